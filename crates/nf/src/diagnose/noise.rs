//! The recording's own noise, before any effect is tested: white noise with flicker (bias
//! instability) and rate random walk, or with a Gauss-Markov bias, estimated by REML
//! (`crate::noise_est`) from the quarter means and the dwell means in time order (one in k of
//! them past `noise_est::THINNED` positions). The REML
//! design holds the effects that noise cannot make (temperature, harmonics 2-4 of the angle),
//! so that they are not taken for noise. It does not hold a drift: over one run a drift and a
//! rate random walk are the same wander, and the null hypothesis of every test is that the
//! wander is noise. Colour that the likelihood needs is itself a finding, with its Allan
//! parameters.

use super::data::Data;
use super::effect::{Param, param};
use super::kind::Kind;
use super::model::Summary;
use super::select::Finding;
use super::tails::{Tails, shock_mix};
use super::whiten::Whitener;
use crate::dwells;
use crate::gls::WindowSet;
use crate::linfit;
use crate::noise_est::{self, Candidate, THINNED, Term, Thinned};
use crate::noise_fit::NoiseChoice;
use crate::quarter_contrasts::{self, Quarters};
use crate::sample_spread::{self, Spread};
use crate::wander_test::WanderTest;
use nf_model::noise::NoiseModel;

/// Log-likelihood below the best that a noise model may lie and still count as plausible:
/// half the 68 % point of a chi-square of 1 dof (one sigma).
const PLAUSIBLE: f64 = 0.5;

/// The flicker-and-walk models of each noise estimate, the most likely first, that start the
/// wander test's searches (each search then refines its best).
const WANDER_STARTS: usize = 10;

/// A property of the noise the likelihood needs.
#[derive(Clone)]
pub struct NoiseTerm {
    pub kind: Kind,
    pub p: f64,
    pub parameters: Vec<Param>,
}

pub struct Noise {
    pub model: NoiseModel,
    pub whitener: Whitener,
    /// The most coloured model within one sigma of the likelihood's best, and its whitening.
    pub cautious_model: NoiseModel,
    pub cautious: Whitener,
    /// The most likely model with a drift in the design: for the tests of drift and jump.
    pub drift_model: NoiseModel,
    pub drift: Whitener,
    /// The test of the effects a wandering bias can mimic with the noise estimated under each
    /// hypothesis; `None` when the noise was given or the run is thinned for its estimate.
    pub wander: Option<WanderTest>,
    /// The noise models the recording allows, with their likelihood weights (summing to 1),
    /// for the final sigma: factored one at a time, as a long recording's factor is large.
    pub plausible: Vec<(f64, NoiseModel)>,
    pub source: String,
    pub terms: Vec<NoiseTerm>,
    /// The columns the noise was estimated under, for the test of its tails.
    pub design: Vec<Vec<f64>>,
    pub whitening: Whitening,
}

/// The whitening of the recording's dwell means under any noise model.
pub struct Whitening {
    windows: WindowSet,
}

impl Whitening {
    pub fn of(&self, m: &NoiseModel) -> Result<Whitener, String> {
        if !m.is_coloured() {
            return Ok(Whitener::identity());
        }
        self.windows
            .cov(m)
            .map(Whitener::of)
            .ok_or_else(|| "the noise model gives no usable covariance".to_string())
    }
}

/// The effects noise cannot make, as far as the positions allow: a third of them.
fn design(d: &Data) -> Vec<Vec<f64>> {
    let mut cols = d.base_cols();
    let mut groups: Vec<Vec<Vec<f64>>> = Vec::new();
    if let Some(temp) = &d.temp {
        let m = temp.iter().sum::<f64>() / temp.len() as f64;
        if temp.iter().any(|v| (v - m).abs() > 1e-6) {
            groups.push(vec![temp.iter().map(|v| v - m).collect()]);
        }
    }
    groups.extend((2..=4).map(|k| d.harmonic(k).to_vec()));
    for g in groups {
        // On few distinct angles a harmonic aliases onto a lower one or vanishes.
        let mut with = cols.clone();
        for c in g {
            if independent(&with, &c) {
                with.push(c);
            }
        }
        if with.len() <= d.n() / 3 {
            cols = with;
        }
    }
    cols
}

/// A given model named, and said not to describe the recording where Eq. 7's residuals
/// scatter beyond it (`nf fit` then widens its sigma by the root of that scatter): the tests
/// and sigmas here whiten by its shape and take the level the recording shows, so a file
/// scaled otherwise than the recording leaves them as they are, and would pass unremarked.
fn given_source(whitening: &Whitening, d: &Data, y: &[f64], m: &NoiseModel, label: &str) -> String {
    let beyond = whitening
        .windows
        .cov(m)
        .and_then(|c| crate::gls::fit(&d.base_cols(), y, &c))
        .and_then(|g| crate::noise_fit::beyond_given(g.chi2, g.dof).map(|r| (r, g.chi2, g.dof)));
    match beyond {
        None => format!("given: {label}"),
        Some((r, chi2, dof)) => format!(
            "given: {label}; it does NOT describe this recording: Eq. 7's residuals scatter {r:.3} times the variance it gives them (chi2 {chi2:.1} on {dof} dof): another gyro, another scaling or units, or an effect in the recording; the tests and sigmas here take its shape at the level the recording shows"
        ),
    }
}

/// Whether `c` has a part that `cols` cannot make.
fn independent(cols: &[Vec<f64>], c: &[f64]) -> bool {
    let norm: f64 = c.iter().map(|v| v * v).sum();
    linfit::fit(cols, c).is_some_and(|ls| ls.rss > 1e-9 * norm)
}

/// Estimates (or takes) the noise model of `y`, the rates less the tilt correction.
pub fn analyse(d: &Data, y: &[f64], choice: &NoiseChoice, alpha: f64) -> Result<Noise, String> {
    let cols = design(d);
    let short = short_time(d);
    let (dwells, quarters) = ((short.dwell_s, short.dwells_s.as_slice()), &short.quarters);
    let n = d.n();
    let whitening = Whitening {
        windows: WindowSet::new(&d.t, &short.dwells_s),
    };
    let whitener_of = |m: &NoiseModel| whitening.of(m);
    if let NoiseChoice::Given(m, label) = choice {
        let given = whitener_of(m)?;
        // A model from a static log is the gyro's there; this run's wander at its own
        // frequency can differ, so the effects it can mimic are also asked of the wander
        // test, started from the given model too.
        let wander = (n <= THINNED)
            .then(|| WanderTest::new(&d.t, dwells, quarters, &short.spread, &[*m]))
            .flatten();
        return Ok(Noise {
            model: *m,
            whitener: given.clone(),
            cautious_model: *m,
            cautious: given.clone(),
            drift_model: *m,
            drift: given.clone(),
            wander,
            plausible: vec![(1.0, *m)],
            source: given_source(&whitening, d, y, m, label),
            terms: Vec::new(),
            design: cols,
            whitening,
        });
    }
    let robust = with_bursts_held_out(d, &cols, y);
    // With a drift in the design too: the wander a random walk makes beyond a smooth curve,
    // under which a drift or a jump is judged (below).
    let mut drifting = robust.clone();
    drifting.extend([d.tau.clone(), d.tau.iter().map(|v| v * v).collect()]);
    let (both, every, used) = estimates(d, y, &short, &[&robust, &drifting]);
    let mut both = both.into_iter();
    let (e, with_drift) = (both.next().flatten(), both.next().flatten());
    let e = e.ok_or("the noise could not be estimated from the recording")?;
    // Without the colour the likelihood does not support, which would cost every test power.
    let (model, terms) = supported(&e, alpha);
    let cautious_model = most_coloured(d, &e, model);
    // The most likely model with a drift in the design. Its upper bound would be too
    // cautious: beyond a curve, a modest random walk is hard to exclude. Flicker and walk
    // only: a Gauss-Markov bias claims the wander bounded, and a drift judged under it is
    // named wherever the run is longer than its time.
    let drift_model = with_drift.as_ref().map_or(cautious_model, |e| {
        flicker_and_walk(e)
            .max_by(|a, b| a.loglik.total_cmp(&b.loglik))
            .map_or(e.best.model, |c| c.model)
    });
    let wander = if every > 1 {
        None
    } else {
        let near = |e: &noise_est::Estimate| {
            let mut wander: Vec<&Candidate> = flicker_and_walk(e).collect();
            wander.sort_by(|a, b| b.loglik.total_cmp(&a.loglik));
            wander
                .into_iter()
                .take(WANDER_STARTS)
                .map(|c| c.model)
                .collect::<Vec<_>>()
        };
        let mut starts = near(&e);
        starts.extend(with_drift.as_ref().map(near).unwrap_or_default());
        WanderTest::new(&d.t, dwells, quarters, &short.spread, &starts).map(WanderTest::drawing)
    };
    Ok(Noise {
        wander,
        plausible: plausible(&e),
        drift_model,
        drift: whitener_of(&drift_model)?,
        whitener: whitener_of(&model)?,
        cautious: whitener_of(&cautious_model)?,
        cautious_model,
        source: format!(
            "estimated from the recording (REML on {} dwell means in time order{}, {} dof)",
            match (every, n.div_ceil(every) - used) {
                (1, 0) => n.to_string(),
                (1, held) => format!("{used} of the {n} ({held} held out as bursts)"),
                (_, 0) => format!("{used} of the {n} (one in {every})"),
                (_, held) => format!("{used} of the {n} (one in {every}, {held} held out as bursts)"),
            },
            match (quarters.len(), short.spread.len()) {
                (0, 0) => String::new(),
                (0, s) => format!(" and the samples' spread in {s} dwells"),
                (q, _) => format!(" and the quarter means of {q} dwells"),
            },
            e.dof
        ),
        model,
        terms,
        design: cols,
        whitening,
    })
}

/// The dwells, and what shows the short-time noise inside them, as `nf fit` takes them: the
/// quarter means of whichever dwells have them, else the samples' spread.
pub(super) struct ShortTime {
    /// The typical dwell and each one, s.
    pub dwell_s: f64,
    pub dwells_s: Vec<f64>,
    pub quarters: Vec<Quarters>,
    pub spread: Vec<Spread>,
}

pub(super) fn short_time(d: &Data) -> ShortTime {
    let dw = dwells::of(&d.rec);
    let rows = || d.rec.rows.iter().zip(dw.each_s.iter().copied());
    ShortTime {
        quarters: quarter_contrasts::of_rows(rows()),
        spread: sample_spread::of_rows(rows(), || d.n().saturating_sub(design(d).len())),
        dwell_s: dw.nominal_s,
        dwells_s: dw.each_s,
    }
}

/// The REML estimate of `y` under each of `designs` (white noise with flicker and walk, or a
/// Gauss-Markov bias), from one dwell mean in `every` past `THINNED` positions; `every` and
/// the dwell means used (bursts every design holds out leave the series).
fn estimates(
    d: &Data,
    y: &[f64],
    short: &ShortTime,
    designs: &[&[Vec<f64>]],
) -> (Vec<Option<noise_est::Estimate>>, usize, usize) {
    let thinned = Thinned::new(&d.t, y, designs);
    let more: Vec<&[Vec<f64>]> = thinned.designs[1..].iter().map(Vec::as_slice).collect();
    let dwells: Vec<f64> = thinned.rows.iter().map(|&i| short.dwells_s[i]).collect();
    let e = noise_est::estimate_all(
        noise_est::Data {
            t_s: &thinned.t_s,
            dwell_s: short.dwell_s,
            dwells_s: &dwells,
            cols: &thinned.designs[0],
            y: &thinned.y,
            quarters: &short.quarters,
            spread: &short.spread,
            extra: None,
        },
        &more,
        noise_est::Colours::WithGaussMarkov,
    );
    (e, thinned.every, thinned.t_s.len())
}

/// The model the likelihood supports, and its colour terms significant at `alpha` (over the
/// three) as findings.
pub(super) fn supported(e: &noise_est::Estimate, alpha: f64) -> (NoiseModel, Vec<NoiseTerm>) {
    let (chosen, tests) = e.supported();
    let model = chosen.model;
    let terms = tests
        .into_iter()
        .filter(|&(_, p)| p < alpha / Term::ALL.len() as f64)
        .map(|(term, p)| NoiseTerm {
            kind: kind_of(term),
            p,
            parameters: allan_parameters(&model, &e.grid, chosen.loglik),
        })
        .collect();
    (model, terms)
}

/// The noise estimated again once the selection is done, with the named effects' columns in
/// the design: the first estimate, before any effect was known, sees a jump or a drift as
/// wander, and its colour terms would name a random walk beside the jump that made it. `None`
/// where the estimate fails (the first one then stands).
pub fn with_effects(d: &Data, y: &[f64], effects: &[Vec<f64>], alpha: f64) -> Option<AfterEffects> {
    let mut cols = design(d);
    for c in effects {
        if cols.len() < d.n() / 3 && independent(&cols, c) {
            cols.push(c.clone());
        }
    }
    let robust = with_bursts_held_out(d, &cols, y);
    let (mut e, _, _) = estimates(d, y, &short_time(d), &[&robust]);
    let (model, terms) = supported(&e.pop().flatten()?, alpha);
    Some(AfterEffects {
        model,
        terms,
        design: cols,
    })
}

/// The noise estimated with the named effects in the design.
pub struct AfterEffects {
    pub model: NoiseModel,
    pub terms: Vec<NoiseTerm>,
    /// The design it was estimated with (the effects that add to it), for the tails.
    pub design: Vec<Vec<f64>>,
}

/// The flicker and walk models of the grid that carry at least 1 % of the best one's
/// likelihood, weighted by it (a Gauss-Markov model's sigma is too small when averaged: see
/// [`noise_est::Colours`]).
fn plausible(e: &noise_est::Estimate) -> Vec<(f64, NoiseModel)> {
    plausible_candidates(e, false)
        .into_iter()
        .map(|(w, c)| (w, c.model))
        .collect()
}

/// [`plausible`]'s models with their fits, the most likely first; the Gauss-Markov ones too
/// where `markov` (a short one, searched where it shows: `noise_fit::fast_markov_shows`).
pub(super) fn plausible_candidates(e: &noise_est::Estimate, markov: bool) -> Vec<(f64, &Candidate)> {
    let wander = || {
        std::iter::once(&e.best)
            .chain(&e.grid)
            .filter(move |c| markov || Term::GaussMarkov.absent(&c.model))
    };
    let top = wander().map(|c| c.loglik).fold(f64::MIN, f64::max);
    let kept: Vec<(f64, &Candidate)> = wander()
        .map(|c| ((c.loglik - top).exp(), c))
        .filter(|(w, _)| *w >= 0.01)
        .collect();
    let total: f64 = kept.iter().map(|k| k.0).sum();
    kept.into_iter().map(|(w, c)| (w / total, c)).collect()
}

/// The estimate's models without a Gauss-Markov term, its best first.
fn flicker_and_walk(e: &noise_est::Estimate) -> impl Iterator<Item = &Candidate> {
    std::iter::once(&e.best)
        .chain(&e.grid)
        .filter(|c| Term::GaussMarkov.absent(&c.model))
}

/// The model within one sigma of the likelihood's best that wanders most over the run.
fn most_coloured(d: &Data, e: &noise_est::Estimate, fallback: NoiseModel) -> NoiseModel {
    let span_h = 2.0 * d.half_span_s / 3600.0;
    let wander =
        |m: &NoiseModel| m.bias_instability_dph.powi(2) + m.rrw_dph_rth.powi(2) * span_h / 3.0 + m.gm_sigma_dph.powi(2);
    std::iter::once(&e.best)
        .chain(&e.grid)
        .filter(|c| c.loglik >= e.best.loglik - PLAUSIBLE)
        .max_by(|a, b| wander(&a.model).total_cmp(&wander(&b.model)))
        .map_or(fallback, |c| c.model)
}

/// Dwell means far outside the rest (five robust sigmas of the residuals) get a
/// column of their own, so that a burst is not taken for flicker: one spike raises the scatter
/// of the dwell means above what the quarters show, which is what flicker does.
pub(super) fn with_bursts_held_out(d: &Data, cols: &[Vec<f64>], y: &[f64]) -> Vec<Vec<f64>> {
    let mut out = cols.to_vec();
    // Against a smooth curve in time: a drift is not a string of bursts.
    let mut smooth = cols.to_vec();
    smooth.extend([d.tau.clone(), d.tau.iter().map(|v| v * v).collect()]);
    let Some(ls) = linfit::fit(&smooth, y) else { return out };
    let sigma = crate::stats::robust_sigma(ls.resid.iter().copied());
    let bursts = (0..d.n()).filter(|&i| ls.resid[i].abs() > 5.0 * sigma);
    out.extend(bursts.take(d.n() / 10).map(|i| d.indicator(i)));
    out
}

/// The finding that names a colour term.
fn kind_of(t: Term) -> Kind {
    match t {
        Term::Flicker => Kind::BiasInstability,
        Term::Walk => Kind::RateRandomWalk,
        Term::GaussMarkov => Kind::CorrelatedNoise,
    }
}

/// N, B and K of the estimate (and a Gauss-Markov term's size and time where it has one),
/// each with the range of the grid models within half a unit of log-likelihood of the best
/// (a profile interval of about one sigma).
fn allan_parameters(m: &NoiseModel, grid: &[Candidate], top: f64) -> Vec<Param> {
    let near: Vec<&NoiseModel> = grid
        .iter()
        .filter(|c| c.loglik >= top - 0.5)
        .map(|c| &c.model)
        .collect();
    let mut out = Vec::new();
    for (name, value, get) in [
        (
            "arw_deg_rth",
            m.arw_deg_rth,
            (|m: &NoiseModel| m.arw_deg_rth) as fn(&NoiseModel) -> f64,
        ),
        ("bias_instability_dph", m.bias_instability_dph, |m| {
            m.bias_instability_dph
        }),
        ("rrw_dph_rth", m.rrw_dph_rth, |m| m.rrw_dph_rth),
        ("gm_sigma_dph", m.gm_sigma_dph, |m| m.gm_sigma_dph),
        ("gm_tau_s", m.gm_tau_s, |m| m.gm_tau_s),
    ]
    .into_iter()
    .filter(|(name, _, _)| m.gm_sigma_dph > 0.0 || !name.starts_with("gm_"))
    {
        out.push(param(name, value, None));
        let lo = near.iter().map(|m| get(m)).fold(value, f64::min);
        let hi = near.iter().map(|m| get(m)).fold(value, f64::max);
        out.push(param(&format!("{name}_lo"), lo, None));
        out.push(param(&format!("{name}_hi"), hi, None));
    }
    out
}

/// The RMS shift shocks give a dwell mean, deg/h: a heavy-tails finding's size.
pub const SHOCK_RMS: &str = "shock_rms_dph";

/// A noise finding's `after`: it changes no fit.
pub(super) const NO_FIT: Summary = Summary {
    azimuth_deg: f64::NAN,
    rss: f64::NAN,
    sigma_arcsec: f64::NAN,
};

/// The noise terms as findings, found by `whence` in the dwell means (and the quarter means,
/// where `d` has them).
pub fn findings(d: &Data, terms: &[NoiseTerm], whence: &str) -> Vec<Finding> {
    let seen_in = if d.rec.rows.iter().any(|r| r.quarters_dph.is_some()) {
        "the dwell means in time order and the quarter means"
    } else {
        "the dwell means in time order"
    };
    terms
        .iter()
        .map(|t| Finding {
            effect: t.kind,
            parameters: t.parameters.clone(),
            p_value: t.p,
            location: format!("{seen_in}: {whence}"),
            after: NO_FIT,
        })
        .collect()
}

/// The tails as a finding where they are heavy at `level`. `rate_resid`, the rates' residuals
/// of the fit the tails were judged on, size the shocks.
pub fn tails_finding(tails: &Tails, rate_resid: &[f64], level: f64) -> Option<Finding> {
    if !tails.heavy(level) {
        return None;
    }
    let mut parameters = vec![param("student_t_dof", tails.dof, None)];
    if let Some(m) = shock_mix(rate_resid) {
        parameters.extend([
            param("shock_share", m.share, None),
            param("shock_shift_dph", m.shift, None),
            param(SHOCK_RMS, m.share.sqrt() * m.shift, None),
        ]);
    }
    Some(Finding {
        effect: Kind::HeavyTails,
        parameters,
        p_value: tails.p,
        location: "the whitened residuals: the outlier test is judged under every tail they allow".into(),
        after: NO_FIT,
    })
}
