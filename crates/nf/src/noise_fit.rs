//! The azimuth by generalised least squares under a gyro noise model, given or estimated from
//! the recording, and the check that the Earth rate was resolved at all.

use crate::diagnose::tails;
use crate::dwells;
use crate::gls::{self, WindowSet};
use crate::linfit;
use crate::noise_calib::{self, Calibration, Verdict};
use crate::noise_est::{self, Candidate, Colours, Data, Estimate, Thinned, scaled};
use crate::quarter_contrasts;
use crate::recording::{Recording, Row};
use crate::sample_spread;
use crate::shock_fit::{self, ShockFit};
use crate::student_fit;
use nf_model::angle::{atan2_deg, wrap_180, wrap_360};
use nf_model::fit::{FitConfig, design_row};
use nf_model::noise::NoiseModel;
use nf_model::uncertainty;

/// Where the noise model comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum NoiseChoice {
    /// Estimated from the recording (quarters and the residual sequence).
    Estimate,
    /// Given by the user (a file or flags), named for the report.
    Given(NoiseModel, String),
}

/// How the noise model was obtained, for the report.
#[derive(Debug, Clone, PartialEq)]
pub enum NoiseSource {
    Estimated {
        dof: usize,
        from_quarters: usize,
        /// Dwells whose samples' spread the estimate used (none where there are quarters).
        from_spread: usize,
        /// Where the samples' spread disagreed with the dwell means and was left out: their
        /// variance over the one it gives ([`sample_spread::Checked`]).
        spread_refused: Option<f64>,
        /// The estimate saw one dwell mean in this many (1: all of them).
        one_in: usize,
        /// The parametric bootstrap that scaled the sigmas, when it could be run.
        calibration: Option<Calibration>,
        /// The colour families searched (shocks: heavy-tailed dwell means).
        colours: Colours,
    },
    /// White at the level of the residuals alone, too few to tell a colour by or to
    /// calibrate by replicates: the sigmas are Student's t half-widths ([`student_fit`]).
    Residuals {
        dof: usize,
        /// The sigma over the least-squares one, and the 68.27 % half-width in sigmas.
        widening: f64,
        one_sigma: f64,
        spread_refused: Option<f64>,
    },
    /// Given by the user; `scatter` the dwell means' whitened chi2 over its degrees of
    /// freedom where it is beyond what the model allows ([`beyond_given`]), which then
    /// widens the sigmas by its root.
    Given {
        name: String,
        scatter: Option<f64>,
        chi2: f64,
        dof: usize,
    },
}

/// A given model's chi2 beyond this p is not chance: the recording is noisier than it says.
const GIVEN_P: f64 = 1e-3;

/// The dwell means' scatter over the given model's variance (`chi2 / dof`) where the model
/// cannot explain it (p under [`GIVEN_P`]). A noise file of another gyro, or scaled
/// otherwise than the recording, gave a sigma of 0.37" for an error of 29.5" with its chi2
/// of 598 367 on 69 dof only printed (an outside audit; RMS error/sigma 98.6 over 40 runs
/// with the file a hundred times small, 3.47 with it three times small).
pub fn beyond_given(chi2: f64, dof: usize) -> Option<f64> {
    (dof > 0 && chi2 > dof as f64 && crate::stats::chi2_sf(chi2, dof as f64) < GIVEN_P).then(|| chi2 / dof as f64)
}

impl NoiseSource {
    pub fn describe(&self) -> String {
        match self {
            NoiseSource::Estimated {
                dof,
                from_quarters,
                from_spread,
                spread_refused,
                one_in,
                calibration,
                colours,
            } => {
                let from = match (from_quarters, from_spread, spread_refused) {
                    (0, 0, Some(r)) => format!("{}; ", spread_left_out(*r)),
                    (0, 0, None) => String::new(),
                    (0, s, _) => format!("the samples' spread in {s} dwells and "),
                    (q, _, _) => format!("quarter means of {q} dwells and "),
                };
                let calibrated = match calibration {
                    Some(c) => format!(
                        "; sigma scaled by {:.2} as {} replicates drawn from the estimate showed",
                        c.psi, c.replicates
                    ),
                    None if *one_in > 1 => format!(
                        "; sigma not calibrated by replicates (past {} positions, as in `nf diagnose`)",
                        noise_est::THINNED
                    ),
                    None => "; sigma not calibrated by replicates".into(),
                };
                let means = match one_in {
                    1 => "the dwell means".to_string(),
                    k => format!("one in {k} of the dwell means"),
                };
                let shocks = match colours {
                    Colours::WithShocks => {
                        "; the dwell means are heavy-tailed: read as shocks (a Gauss-Markov bias shorter than three dwell spacings searched too), not as wander, and each dwell weighed by how likely a shock struck it"
                    }
                    Colours::WithFastMarkov => {
                        "; the dwell means scatter beyond their quarters but do not wander as flicker would: a Gauss-Markov bias shorter than three dwell spacings searched too"
                    }
                    Colours::White => {
                        "; white: as many positions as unknowns leave the dwell means no contrast to show a colour by, so the noise between dwells is taken to be what their insides show"
                    }
                    _ => "",
                };
                format!(
                    "estimated from the recording ({from}REML on {means} in time order, {dof} dof){calibrated}{shocks}"
                )
            }
            NoiseSource::Residuals {
                dof,
                widening,
                one_sigma,
                spread_refused,
            } => {
                let refused = spread_refused.map_or(String::new(), |r| format!("; {}", spread_left_out(r)));
                // Student's t has a finite variance, nu / (nu - 2), from 3 dof on.
                let tails = match dof {
                    0..=2 => "which has no finite variance".to_string(),
                    _ => format!(
                        "whose variance is {:.2} times the normal's",
                        *dof as f64 / (*dof as f64 - 2.0)
                    ),
                };
                format!(
                    "white at the level of the dwell means' residuals alone ({dof} dof: too few to tell a colour by, and no quarter means or samples' spread{refused}); the azimuth's error follows Student's t of {dof} dof, {tails}: sigma is {widening:.2} times the least-squares one, so that 95 % of such errors lie within 1.96 sigma (68 % within {one_sigma:.2} sigma); quarter means, the samples' spread or a noise model (`--noise`) would measure the noise"
                )
            }
            NoiseSource::Given {
                name, scatter: None, ..
            } => format!("given: {name}"),
            NoiseSource::Given {
                name,
                scatter: Some(r),
                chi2,
                dof,
            } => format!(
                "given: {name}; it does NOT describe this recording: the dwell means scatter {r:.3} times the variance it gives them (chi2 {chi2:.1} on {dof} dof, p < {GIVEN_P}): another gyro, another scaling or units, or an effect in the recording (nf diagnose tells which); the sigma is widened {:.2} times, the root of that scatter",
                r.sqrt()
            ),
        }
    }
}

/// Why the samples' spread was left out: `r`, the dwell means' variance over the one it gives.
fn spread_left_out(r: f64) -> String {
    format!(
        "the samples' spread left out: the dwell means scatter {r:.3} times the variance it gives a dwell mean, more than chance allows (is `rate_sd_dph` the samples' standard deviation, in deg/h?)"
    )
}

/// The GLS azimuth.
#[derive(Debug, Clone)]
pub struct NoiseFit {
    pub model: NoiseModel,
    pub source: NoiseSource,
    /// The typical dwell length the covariance assumes, and where it came from.
    pub dwell_s: f64,
    pub dwell_from: &'static str,
    /// The shortest and longest dwell, where the rows' samples make them differ.
    pub dwell_range_s: Option<(f64, f64)>,
    pub psi_deg: f64,
    pub sigma_psi_deg: f64,
    /// How many times the azimuth's sigma exceeds GLS under `model` alone: the spread of the
    /// noise models the recording allows and the replicates' calibration (1 when given).
    pub widening: f64,
    pub amplitude_dph: f64,
    pub sigma_amplitude_dph: f64,
    pub offset_dph: f64,
    /// Whitened residual sum of squares and its degrees of freedom: about `dof` when the noise
    /// model describes the recording.
    pub chi2: f64,
    pub dof: usize,
    /// The shocks the fit weighed the dwells through, where the dwell means are heavy-tailed.
    pub shocks: Option<Shocks>,
}

/// Shocks in a recording: the share of dwells struck, the sd of a shock's shift, and the
/// lines of the dwells more likely struck than not.
#[derive(Debug, Clone, PartialEq)]
pub struct Shocks {
    pub share: f64,
    pub shift_dph: f64,
    pub struck: Vec<usize>,
}

/// Fits `y` (the rates with the tilt correction removed) by GLS.
/// An estimated noise model's sigma is calibrated by `replicates` bootstrap replicates (none:
/// not calibrated).
pub fn fit(
    rec: &Recording,
    y: &[f64],
    cfg: &FitConfig<f64>,
    choice: &NoiseChoice,
    replicates: usize,
) -> Result<NoiseFit, String> {
    let n = rec.rows.len();
    let t0 = rec.rows[0].t_s;
    let rows: Vec<_> = rec
        .rows
        .iter()
        .map(|r| design_row(cfg, r.encoder_deg, (r.t_s - t0) / cfg.t_scale_s))
        .collect();
    let p = cfg.terms().ok_or("bad fit configuration")?;
    let cols: Vec<Vec<f64>> = (0..p).map(|k| rows.iter().map(|r| r[k]).collect()).collect();
    let t: Vec<f64> = rec.rows.iter().map(|r| r.t_s).collect();
    let dw = dwells::of(rec);
    let (dwell_s, dwell_from) = (dw.nominal_s, dw.from);
    let rows_dwells = || rec.rows.iter().zip(dw.each_s.iter().copied());
    let quarters = quarter_contrasts::of_rows(rows_dwells());
    let sample_spread::Checked {
        spreads: spread,
        refused_ratio,
    } = sample_spread::checked(sample_spread::of_rows(rows_dwells(), || n.saturating_sub(p)), &cols, y);
    // As many positions as unknowns leave the noise to a given model or to the dwells' insides.
    let within = !quarters.is_empty() || !spread.is_empty() || matches!(choice, NoiseChoice::Given(..));
    if n < p || (n == p && !within) {
        return Err(format!(
            "{n} positions for {p} unknowns: no degrees of freedom are left to measure the noise by, so the azimuth's uncertainty is undefined; the fit needs at least {}",
            p + 1
        ));
    }
    if !within && n - p <= student_fit::MOST_DOF {
        // Each dwell mean weighed by its length: the same Student's t, of the weighted fit.
        let root: Vec<f64> = dw.each_s.iter().map(|d| (d / dwell_s).sqrt()).collect();
        let weigh = |v: &[f64]| -> Vec<f64> { v.iter().zip(&root).map(|(a, w)| a * w).collect() };
        let cols: Vec<Vec<f64>> = cols.iter().map(|c| weigh(c)).collect();
        let mut f = student(&cols, &weigh(y), dwell_s, dwell_from, refused_ratio)?;
        f.dwell_range_s = dw.range_s();
        return Ok(f);
    }
    let windows = WindowSet::new(&t, &dw.each_s);
    let data = Data {
        t_s: &t,
        dwell_s,
        dwells_s: &dw.each_s,
        cols: &cols,
        y,
        quarters: &quarters,
        spread: &spread,
        extra: None,
    };
    let colours = match n == p {
        true => Colours::White,
        false => colours_of(&data, matches!(choice, NoiseChoice::Estimate)),
    };
    let (model, source, v, carried) = match choice {
        NoiseChoice::Given(m, s) => {
            let cov = windows.cov(m).ok_or_else(|| {
                format!("the noise model given ({s}) makes no covariance of the dwell means: its terms are all zero or too small")
            })?;
            let g = gls::fit(&cols, y, &cov).ok_or("the positions do not determine the fit's terms")?;
            // Heavy-tailed dwell means are fitted through as shocks, whose scatter is theirs.
            let scatter = beyond_given(g.chi2, g.dof).filter(|_| colours != Colours::WithShocks);
            let w = scatter.unwrap_or(1.0);
            let scaled: Vec<Vec<f64>> = g.cov.iter().map(|r| r.iter().map(|c| c * w).collect()).collect();
            let source = NoiseSource::Given {
                name: s.clone(),
                scatter,
                chi2: g.chi2,
                dof: g.dof,
            };
            (*m, source, azimuth(&g.coef, &scaled), (w.sqrt(), w.sqrt()))
        }
        NoiseChoice::Estimate => {
            let g = gaussian(&data, colours, replicates)?;
            let source = NoiseSource::Estimated {
                dof: g.dof,
                from_quarters: quarters.len(),
                from_spread: spread.len(),
                spread_refused: refused_ratio,
                one_in: g.one_in,
                calibration: g.calibration,
                colours,
            };
            (g.judged.model, source, g.verdict, g.carried())
        }
    };
    // The whitened residuals of the chosen model tell whether it describes the recording.
    let cov = windows
        .cov(&model)
        .ok_or("the noise model gives no usable covariance (all terms zero?)")?;
    let g = gls::fit(&cols, y, &cov).ok_or("the positions do not determine the fit's terms")?;
    // Heavy-tailed dwell means: each weighed by how likely a shock struck it.
    let through = (colours == Colours::WithShocks)
        .then(|| through(&data, &windows, &model, choice, &rec.rows, carried))
        .flatten();
    let (v, g, model, shocks) = match through {
        Some(th) => {
            let v = th.verdict;
            let shocks = Shocks {
                share: th.shocks.share,
                shift_dph: th.shocks.shift_dph,
                struck: th.shocks.struck.iter().map(|&i| rec.rows[i].line).collect(),
            };
            (v, th.gls, th.model, Some(shocks))
        }
        None => (v, g, model, None),
    };
    Ok(NoiseFit {
        model,
        source,
        dwell_s,
        dwell_from,
        dwell_range_s: dw.range_s(),
        psi_deg: wrap_360(v.psi_deg),
        sigma_psi_deg: v.sigma_psi_deg,
        widening: carried.0,
        amplitude_dph: v.amplitude_dph,
        sigma_amplitude_dph: v.sigma_amplitude_dph,
        offset_dph: g.coef[0],
        chi2: g.chi2,
        dof: g.dof,
        shocks,
    })
}

/// The fit of a run whose residuals alone, one to five of them, measure the noise.
fn student(
    cols: &[Vec<f64>],
    y: &[f64],
    dwell_s: f64,
    dwell_from: &'static str,
    spread_refused: Option<f64>,
) -> Result<NoiseFit, &'static str> {
    let f = student_fit::fit(cols, y).ok_or("the positions do not determine the fit's terms")?;
    Ok(NoiseFit {
        model: NoiseModel::white(f.level_dph, dwell_s),
        source: NoiseSource::Residuals {
            dof: f.dof,
            widening: f.widening,
            one_sigma: f.one_sigma,
            spread_refused,
        },
        dwell_s,
        dwell_from,
        dwell_range_s: None,
        psi_deg: wrap_360(f.verdict.psi_deg),
        sigma_psi_deg: f.verdict.sigma_psi_deg,
        widening: f.widening,
        amplitude_dph: f.verdict.amplitude_dph,
        sigma_amplitude_dph: f.verdict.sigma_amplitude_dph,
        offset_dph: f.coef[0],
        chi2: f.chi2,
        dof: f.dof,
        shocks: None,
    })
}

/// A fit through shocks: the azimuth, the noise model, the fit's GLS and the shocks.
pub(crate) struct Through {
    pub verdict: Verdict,
    pub model: NoiseModel,
    pub gls: gls::Gls,
    pub shocks: ShockFit,
    /// The noise estimated again beside the shocks (`None`: the model was given).
    pub estimate: Option<Estimate>,
    /// What the azimuth's sigma carries beyond this fit's own ([`Gaussian::carried`]).
    pub carried: f64,
}

/// The fit of `data` through shocks, from the Gaussian fit's noise `model` and how it was
/// chosen: a given model keeps its terms and scale, and only the shocks are fitted beside it;
/// an estimated one is estimated again beside them ([`through_shocks`]). `rows` are the
/// recording's, in `data`'s order. `None` where no dwell stands out.
pub(crate) fn through(
    data: &Data<'_>,
    windows: &WindowSet,
    model: &NoiseModel,
    choice: &NoiseChoice,
    rows: &[Row],
    carried: (f64, f64),
) -> Option<Through> {
    let th = match choice {
        NoiseChoice::Given(..) => shock_fit::fit(windows, model, false, data.cols, data.y).map(|sf| Through {
            verdict: azimuth(&sf.gls.coef, &sf.gls.cov),
            model: *model,
            gls: sf.gls.clone(),
            shocks: sf,
            estimate: None,
            carried: 1.0,
        }),
        NoiseChoice::Estimate => through_shocks(data, windows, model, rows),
    }?;
    let v = th.verdict;
    Some(Through {
        verdict: Verdict {
            sigma_psi_deg: v.sigma_psi_deg * carried.0,
            sigma_amplitude_dph: v.sigma_amplitude_dph * carried.1,
            ..v
        },
        carried: carried.0,
        ..th
    })
}

/// The noise estimated from the recording by the Gaussian likelihood: the supported model,
/// its verdict (with the grid's spread) calibrated by replicates, and the estimate's size.
pub(crate) struct Gaussian {
    pub judged: Judged,
    pub calibration: Option<Calibration>,
    pub verdict: Verdict,
    pub dof: usize,
    pub one_in: usize,
}

/// The Gaussian estimate of `data` under `colours`, its sigma calibrated by `replicates`
/// replicates drawn from the supported model and fitted the same way.
pub(crate) fn gaussian(data: &Data<'_>, colours: Colours, replicates: usize) -> Result<Gaussian, &'static str> {
    let (e, one_in) =
        estimate(data.clone(), colours).ok_or("the noise model could not be estimated from the recording")?;
    let j = judge(&e).ok_or("no noise model fits")?;
    let judge_replica = |d: Data<'_>| estimate(d, colours).and_then(|(e, _)| judge(&e)).map(|j| j.verdict);
    // As `nf diagnose`'s: a run thinned for its noise estimate is not calibrated (its
    // replicates would cost a minute at 10^5 positions).
    let replicates = if one_in > 1 { 0 } else { replicates };
    let calibration = noise_calib::calibrate(data, &j.model, &j.coef, &j.verdict, replicates, judge_replica);
    Ok(Gaussian {
        verdict: j.verdict.calibrated(calibration),
        judged: j,
        calibration,
        dof: e.dof,
        one_in,
    })
}

impl Gaussian {
    /// What the sigmas carry beyond the supported model's own GLS (the spread of the noise
    /// models the recording allows, the replicates' calibration): a fit through shocks keeps
    /// it.
    pub fn carried(&self) -> (f64, f64) {
        let (v, own) = (&self.verdict, &self.judged.own);
        (
            (v.sigma_psi_deg / own.sigma_psi_deg).max(1.0),
            (v.sigma_amplitude_dph / own.sigma_amplitude_dph).max(1.0),
        )
    }
}

/// Rounds of the shocks' EM and the noise estimate in turn.
const ROUNDS: usize = 3;

/// The fit through shocks with the noise estimated beside them: the shocks' EM under the
/// noise model, then the noise (flicker and walk) estimated again with each dwell's share of
/// the shocks in its variance and the struck dwells' quarters left out (a shock within a dwell
/// is not the gyro's short-time noise), in turn. The Gaussian estimate took the shocks for a
/// short Gauss-Markov bias, and with it for the only colour: its flicker would be lost.
fn through_shocks(data: &Data<'_>, windows: &WindowSet, gaussian: &NoiseModel, rows: &[Row]) -> Option<Through> {
    let mut model = NoiseModel {
        gm_sigma_dph: 0.0,
        ..*gaussian
    };
    let mut last: Option<Through> = None;
    for round in 0..ROUNDS {
        // The first round scales the Gaussian model to the calm dwells; the later ones keep
        // the estimate's level. A round that fails leaves the last one's fit.
        let Some(next) = shock_round(data, windows, &model, round == 0, rows) else {
            break;
        };
        model = next.model;
        last = Some(next);
    }
    last
}

/// One round of [`through_shocks`] from `model`.
fn shock_round(
    data: &Data<'_>,
    windows: &WindowSet,
    model: &NoiseModel,
    rescale: bool,
    rows: &[Row],
) -> Option<Through> {
    let sf = shock_fit::fit(windows, model, rescale, data.cols, data.y)?;
    let white = scaled(model, sf.scale).white_dph_rts().powi(2);
    if white.is_nan() || white <= 0.0 {
        return None;
    }
    let relative: Vec<f64> = sf.extra.iter().map(|e| e / white).collect();
    let unstruck = rows
        .iter()
        .zip(data.dwells_s.iter().copied())
        .enumerate()
        .filter(|(i, _)| !sf.struck.contains(i))
        .map(|(_, r)| r);
    let quarters = quarter_contrasts::of_rows(unstruck.clone());
    let spread = match data.spread {
        [] => Vec::new(),
        _ => sample_spread::of_rows(unstruck, || 0),
    };
    let (e, _) = estimate(
        Data {
            quarters: &quarters,
            spread: &spread,
            extra: Some(&relative),
            ..data.clone()
        },
        Colours::FlickerAndWalk,
    )?;
    let j = judge(&e)?;
    let absolute: Vec<f64> = relative.iter().map(|r| r * j.model.white_dph_rts().powi(2)).collect();
    let gls = gls::fit(data.cols, data.y, &windows.cov_plus(&j.model, Some(&absolute))?)?;
    Some(Through {
        verdict: j.verdict,
        model: j.model,
        gls,
        shocks: sf,
        estimate: Some(e),
        carried: 1.0,
    })
}

/// The noise estimate and how thinned it was (one dwell mean in k). Past
/// [`noise_est::THINNED`] rows the noise is estimated from one dwell mean in k (and its
/// extra variance) and every quarter, and the models that carry weight are refitted on every
/// row: the azimuth comes from their fits.
fn estimate(data: Data<'_>, colours: Colours) -> Option<(Estimate, usize)> {
    if data.t_s.len() <= noise_est::THINNED {
        return noise_est::estimate(data, colours).map(|e| (e, 1));
    }
    let th = Thinned::new(data.t_s, data.y, &[data.cols]);
    let extra: Option<Vec<f64>> = data.extra.map(|x| th.rows.iter().map(|&i| x[i]).collect());
    let dwells: Vec<f64> = th.rows.iter().map(|&i| data.dwells_s[i]).collect();
    let e = noise_est::estimate(
        Data {
            t_s: &th.t_s,
            dwells_s: &dwells,
            y: &th.y,
            cols: &th.designs[0],
            extra: extra.as_deref(),
            ..data.clone()
        },
        colours,
    )?;
    let windows = WindowSet::new(data.t_s, data.dwells_s);
    let refit = |c: Candidate| -> Option<Candidate> {
        let white = c.model.white_dph_rts().powi(2);
        let absolute: Option<Vec<f64>> = data.extra.map(|x| x.iter().map(|r| r * white).collect());
        let g = gls::fit(data.cols, data.y, &windows.cov_plus(&c.model, absolute.as_deref())?)?;
        Some(Candidate {
            coef: g.coef,
            cov: g.cov,
            ..c
        })
    };
    // Against the grid's own best: the refined best may stand far above every grid model.
    let top = e.grid.iter().map(|c| c.loglik).fold(f64::MIN, f64::max);
    let e = Estimate {
        best: refit(e.best)?,
        grid: e
            .grid
            .into_iter()
            .filter(|c| c.loglik - top > NEGLIGIBLE.ln())
            .filter_map(refit)
            .collect(),
        dof: e.dof,
    };
    Some((e, th.every))
}

/// Heavy-tailed dwell means (their least-squares residuals' tails beat the normal at
/// [`SHOCK_TAILS`]) are shocks: the short Gauss-Markov family joins flicker and walk, so that
/// their scatter beyond the quarters is not taken for wander. Gaussian ones whose scatter a
/// short Gauss-Markov bias explains by [`FAST_MARKOV_GATE`] better than flicker and walk do
/// get that family too, where the noise is `estimated` (a given model has its own terms).
fn colours_of(data: &Data, estimated: bool) -> Colours {
    if shock_tails(data.cols, data.y).is_some() {
        Colours::WithShocks
    } else if estimated && fast_markov_shows(data) {
        Colours::WithFastMarkov
    } else {
        Colours::FlickerAndWalk
    }
}

/// Whether a Gauss-Markov bias shorter than three dwell spacings beats flicker and walk by
/// [`FAST_MARKOV_GATE`]: then its family is searched beside them.
pub(crate) fn fast_markov_shows(data: &Data) -> bool {
    fast_markov_margin(data).is_some_and(|m| m >= FAST_MARKOV_GATE)
}

/// How far the best model with a Gauss-Markov bias shorter than three dwell spacings beats
/// the best of flicker and walk, in log-likelihood. Not looked for past [`noise_est::THINNED`]
/// positions, whose estimate is thinned.
fn fast_markov_margin(data: &Data) -> Option<f64> {
    if data.t_s.len() > noise_est::THINNED {
        return None;
    }
    let e = noise_est::estimate(data.clone(), Colours::WithFastMarkov)?;
    let best = |markov: bool| {
        std::iter::once(&e.best)
            .chain(&e.grid)
            .filter(|c| noise_est::Term::GaussMarkov.absent(&c.model) != markov)
            .map(|c| c.loglik)
            .fold(f64::MIN, f64::max)
    };
    Some(best(true) - best(false))
}

/// The margin by which a short Gauss-Markov bias must beat flicker and walk to be searched.
/// Such a bias (a sensor's correlation over a second or two, 0.05 deg/h of it on 2 s dwells)
/// makes the dwell means scatter beyond their quarters, which flicker explains only with a
/// wander at the run's own frequency that is not there (an outside audit: sigma 459" for an
/// error of 100"). Searched on any evidence, it took real MEMS sweeps' wander for it and made
/// their sigma too small (docs/noise.md), where it was a few units better at most.
const FAST_MARKOV_GATE: f64 = 5.0;

/// The tails of the least-squares residuals of `y ~ cols` where a Student-t explains them
/// better than the normal, at [`SHOCK_TAILS`].
pub(crate) fn shock_tails(cols: &[Vec<f64>], y: &[f64]) -> Option<tails::Tails> {
    linfit::fit(cols, y)
        .map(|ls| tails::estimate(&ls.resid))
        .filter(|t| t.heavy(SHOCK_TAILS))
}

/// The level of the tails' test that lets the shocks' family in.
const SHOCK_TAILS: f64 = 0.01;

/// A grid model under this share of the grid's best likelihood is not refitted on every row.
const NEGLIGIBLE: f64 = 1e-3;

/// What the estimate makes of a recording: the model the likelihood supports, its fit's
/// coefficients and azimuth, and the variance of the most likely model plus the spread of the
/// grid models' azimuths about the chosen one (weighted by their likelihood), which carries
/// how poorly one recording pins its noise down.
pub(crate) struct Judged {
    pub model: NoiseModel,
    coef: Vec<f64>,
    verdict: Verdict,
    /// The supported model's own GLS verdict.
    own: Verdict,
}

fn judge(e: &Estimate) -> Option<Judged> {
    // The azimuth of the supported model: on white noise, least squares (the Cramer-Rao bound).
    let (supported, _) = e.supported_stepwise();
    let chosen = azimuth(&supported.coef, &supported.cov);
    let top = e.best.loglik;
    let per: Vec<(f64, Verdict)> = e
        .grid
        .iter()
        .map(|c| ((c.loglik - top).exp(), azimuth(&c.coef, &c.cov)))
        .collect();
    let total: f64 = per.iter().map(|f| f.0).sum();
    let mean = |f: &dyn Fn(&Verdict) -> f64| per.iter().map(|(w, a)| w / total * f(a)).sum::<f64>();
    let best = &per.iter().max_by(|a, b| a.0.total_cmp(&b.0))?.1;
    let var_psi = best.sigma_psi_deg.powi(2) + mean(&|a| wrap_180(a.psi_deg - chosen.psi_deg).powi(2));
    let var_amp = best.sigma_amplitude_dph.powi(2) + mean(&|a| (a.amplitude_dph - chosen.amplitude_dph).powi(2));
    Some(Judged {
        model: supported.model,
        coef: supported.coef.clone(),
        verdict: Verdict {
            sigma_psi_deg: var_psi.sqrt(),
            sigma_amplitude_dph: var_amp.sqrt(),
            ..chosen
        },
        own: chosen,
    })
}

/// Azimuth and amplitude of one fit's `C, A, B` (first of its terms) and their covariance.
pub(crate) fn azimuth(coef: &[f64], cov: &[Vec<f64>]) -> Verdict {
    let (a, b) = (coef[1], coef[2]);
    let r2 = a * a + b * b;
    let (vaa, vbb, vab) = (cov[1][1], cov[2][2], cov[1][2]);
    let var_psi = (b * b * vaa + a * a * vbb - 2.0 * a * b * vab) / (r2 * r2);
    let var_amp = (a * a * vaa + b * b * vbb + 2.0 * a * b * vab) / r2;
    Verdict {
        psi_deg: atan2_deg(-b, a),
        sigma_psi_deg: var_psi.max(0.0).sqrt().to_degrees(),
        amplitude_dph: r2.sqrt(),
        sigma_amplitude_dph: var_amp.max(0.0).sqrt(),
    }
}

impl NoiseFit {
    /// Why the Earth rate is not resolved, if it is not ([`unresolved`]).
    pub fn unresolved(&self, predicted_dph: f64) -> Option<String> {
        unresolved(
            self.sigma_psi_deg,
            self.amplitude_dph,
            self.sigma_amplitude_dph,
            predicted_dph,
        )
    }
}

/// Why the Earth rate is not resolved, if it is not: the azimuth's sigma is tens of degrees,
/// or the amplitude is inconsistent with `WE cos(lat)` (`predicted_dph`).
pub fn unresolved(sigma_deg: f64, amplitude_dph: f64, sigma_amplitude_dph: f64, predicted_dph: f64) -> Option<String> {
    if sigma_deg.is_nan() || sigma_deg >= uncertainty::RESOLVED_SIGMA_DEG {
        return Some(format!(
            "the azimuth's uncertainty is {sigma_deg:.1} deg: the gyro noise hides the Earth rate"
        ));
    }
    let ratio = amplitude_dph / predicted_dph;
    if !uncertainty::amplitude_is_earth_rate(amplitude_dph, sigma_amplitude_dph, predicted_dph) {
        let times = if (0.01..100.0).contains(&ratio) {
            format!("{ratio:.2}")
        } else {
            format!("{ratio:.3e}")
        };
        return Some(format!(
            "the first-harmonic amplitude {amplitude_dph:.5} deg/h is {times} times the Earth rate's {predicted_dph:.5} deg/h at this latitude{}",
            unit_slip(ratio)
        ));
    }
    None
}

/// A rate unit that would explain an amplitude `ratio` times the Earth rate's (within 20 %):
/// rates written in deg/s, rad/s or arcsec/h where the format has deg/h.
fn unit_slip(ratio: f64) -> &'static str {
    let per_s: f64 = 1.0 / 3600.0;
    [
        (
            per_s,
            " (1/3600 of it: as if rate_dph held deg/s; the format's rates are deg/h)",
        ),
        (
            per_s.to_radians(),
            " (as if rate_dph held rad/s; the format's rates are deg/h)",
        ),
        (
            3600.0,
            " (3600 times it: as if rate_dph held arcsec/h; the format's rates are deg/h)",
        ),
    ]
    .into_iter()
    .find(|(f, _)| (ratio / f - 1.0).abs() < 0.2)
    .map_or("", |(_, why)| why)
}

/// Up to ten line numbers, and how many more.
pub fn lines_text(lines: &[usize]) -> String {
    let shown: Vec<String> = lines.iter().take(10).map(|l| l.to_string()).collect();
    match lines.len() {
        0 => "none".into(),
        k if k > 10 => format!("{}, and {} more", shown.join(", "), k - 10),
        _ => shown.join(", "),
    }
}

#[cfg(test)]
mod tests {
    use super::unresolved;

    #[test]
    fn an_amplitude_off_by_a_units_factor_names_the_unit() {
        let earth = 10.63559;
        let why = |amplitude: f64| unresolved(0.01, amplitude, 1e-3 * amplitude, earth);
        assert_eq!(why(earth * 1.02), None);
        for (amplitude, unit) in [
            (earth / 3600.0, "deg/s"),
            (earth / 3600.0 * 1.1, "deg/s"),
            ((earth / 3600.0).to_radians(), "rad/s"),
            (earth * 3600.0, "arcsec/h"),
        ] {
            let w = why(amplitude).unwrap();
            assert!(w.contains(&format!("held {unit}")), "{amplitude}: {w}");
        }
        // A latitude that is wrong, not a unit: the ratio alone.
        let w = why(earth * 0.2).unwrap();
        assert!(w.contains(" 0.20 times") && !w.contains("held"), "{w}");
        assert!(why(earth / 3600.0).unwrap().contains(" 2.778e-4 times"));
    }
}
