//! `nf diagnose`: where a recording departs from the model the simulation used (Eq. 7 on a
//! level, ideal instrument), which physical effect was left out, its fitted parameters, and
//! the fit and azimuth once it is modelled.
//!
//! The recording's own noise is estimated first (`noise`) and every test is made on columns
//! whitened by it, so the false-alarm rate holds on coloured noise; heavy tails are measured
//! (`tails`) and the outlier test judged under them. Each effect of the catalogue is one type
//! implementing [`Effect`], in a file of its own. The selection (`select`) names effects one
//! at a time; the result averages the models it met (`averaging`) and, for its sigma, the
//! noise models the recording allows; what remains is tested for structure no effect
//! explains (`unexplained`).

mod averaging;
mod data;
mod drift;
mod effect;
mod encoder;
mod final_result;
mod final_shocks;
mod final_sigma;
mod jump;
mod kind;
mod model;
mod noise;
mod nonlinearity;
mod notes;
mod outliers;
mod scale;
mod scan;
mod select;
mod settling;
mod shaft_tilt;
pub(crate) mod tails;
mod thermal;
mod unexplained;
mod whiten;

pub use averaging::Weighted;
pub use effect::{Effect, Param};
pub use kind::Kind;
pub use model::Summary;
pub use noise::SHOCK_RMS;
pub use select::{Finding, Undecided};
pub use thermal::CYCLE_AMPLITUDE;

use crate::noise_calib;
use crate::noise_fit::NoiseChoice;
use crate::recording::Recording;
use crate::tilt::Sensitivity;
use data::Data;
use model::{Model, summary};
use nf_model::noise::NoiseModel;
use select::Selector;
use shaft_tilt::ShaftTilt;
use whiten::Whitener;

/// The share of the false-alarm rate spent on `unexplained`; the catalogue has the rest, so
/// that a recording of the model is named for anything with probability at most `alpha`.
const UNEXPLAINED_SHARE: f64 = 0.2;

#[derive(Debug, Clone)]
pub struct Options {
    /// Family-wise false-alarm rate of each selection step.
    pub alpha: f64,
    pub noise: NoiseChoice,
    /// Bootstrap replicates that calibrate the final sigma under a noise model estimated
    /// from the recording (0: none).
    pub replicates: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            alpha: 0.05,
            noise: NoiseChoice::Estimate,
            replicates: usize::from(noise_calib::REPLICATES),
        }
    }
}

/// One position, in time order, for the plots.
#[derive(Debug, Clone, Copy)]
pub struct Point {
    pub t_s: f64,
    pub gamma_deg: f64,
    /// Residual of Eq. 7 on the raw rates by least squares, deg/h.
    pub before: f64,
    /// `before` less `fitted`, deg/h.
    pub after: f64,
    /// The named effects' fitted contribution (tilt included) less its least-squares part in
    /// Eq. 7's columns, as the residuals `before` hold it, deg/h.
    pub fitted: f64,
    /// Read as struck by a shock where the final is fitted through shocks (weighed down).
    pub struck: bool,
}

#[derive(Debug, Clone)]
pub struct Diagnosis {
    pub alpha: f64,
    pub noise_model: NoiseModel,
    /// The most coloured plausible model, under which encoder harmonics and the slow
    /// amplitude and 2 psi harmonic are judged.
    pub cautious_model: NoiseModel,
    /// The model estimated with a drift in the design, under which drift, jump and
    /// temperature are judged.
    pub drift_model: NoiseModel,
    /// The model estimated again with the named effects' columns in the design (the first
    /// model where none was named, or the noise was given; beside the shocks where the final
    /// was fitted through them): the noise terms named are its.
    pub noise_with_effects: NoiseModel,
    /// Whether the final azimuth was fitted through shocks (heavy-tailed dwell means).
    pub through_shocks: bool,
    /// Whether drift, jump, temperature, encoder harmonics and the 2 psi harmonic were also
    /// asked of the wander test (the noise re-estimated with and without each): up to 2000
    /// positions, whether the noise is estimated or given.
    pub wander_tested: bool,
    pub noise_source: String,
    /// Where the final sigma under the noise came from: `None` where it is the tests' noise
    /// models' (a given model, or one thinned for its estimate).
    pub final_sigma_from: Option<String>,
    /// The factor replicates drawn from the noise scaled the final sigma by (`None`: not
    /// scaled).
    pub sigma_calibration: Option<f64>,
    /// The most likely model's residual degrees of freedom where they alone measured the
    /// noise, white, each model's sigma widened by Student's t (`None`: a noise model's).
    pub residual_dof: Option<usize>,
    /// Whether the noise model was estimated from the recording (not given).
    pub noise_estimated: bool,
    /// Eq. 7 on the raw rates, under the noise model.
    pub baseline: Summary,
    /// Noise terms, catalogue effects and unexplained structure, in the order found.
    pub findings: Vec<Finding>,
    /// Effects found by their own tests but not named, as the run's own wander explains
    /// the recording as well (the wander test's verdict); the notes say so.
    pub undecided: Vec<Undecided>,
    /// The selected model alone.
    pub selected: Summary,
    /// The result: the models met, averaged by their weights, and over the noise models the
    /// recording allows; with the tilt circle's uncertainty.
    pub final_: Summary,
    /// Why the result is no azimuth (`nf fit`'s rule on the final sigma and the selected
    /// model's amplitude); `None` when the Earth rate is resolved.
    pub unresolved: Option<String>,
    pub models: Vec<Weighted>,
    /// What cannot be told apart, and other cautions.
    pub notes: Vec<String>,
    pub points: Vec<Point>,
    /// Where the time went.
    pub timing: Timing,
}

/// Wall time of a diagnosis's parts, s: the noise estimate, the selection (and how many
/// steps it took), and the whole.
#[derive(Debug, Clone, Copy, Default)]
pub struct Timing {
    pub noise_s: f64,
    pub selection_s: f64,
    pub selection_steps: usize,
    pub total_s: f64,
}

/// Positions a diagnosis needs: Eq. 7's three columns, an effect's and the noise's.
pub const MIN_POSITIONS: usize = 8;

/// Diagnoses a recording.
pub fn diagnose(rec: &Recording, opt: &Options) -> Result<Diagnosis, String> {
    rec.require_turning()?;
    rec.require_positions(MIN_POSITIONS, "diagnosing")?;
    let started = std::time::Instant::now();
    let d = Data::new(rec);
    let white = Whitener::identity();
    let tilt = measure_tilt(&d, &white)?;
    let tilt_warning = match &tilt {
        Some(t) => t.warning.clone(),
        None => Some(untested_tilt(rec.latitude_deg)),
    };
    let tilt_share = final_result::TiltShare {
        sigma_arcsec: tilt.as_ref().map_or(0.0, |t| t.sigma_psi_deg * 3600.0),
        sensitivity: tilt.as_ref().map_or(Sensitivity::NONE, |t| t.sensitivity),
    };
    let y: Vec<f64> = match &tilt {
        Some(t) => d.rate.iter().zip(&t.corrections).map(|(r, c)| r - c).collect(),
        None => d.rate.clone(),
    };
    let noise_started = std::time::Instant::now();
    let noise = noise::analyse(&d, &y, &opt.noise, opt.alpha)?;
    let noise_s = noise_started.elapsed().as_secs_f64();
    let w = &noise.whitener;
    let base_model = Model::new(d.base_cols(), d.rate.clone(), w);
    let base = base_model
        .fit()
        .ok_or("the positions do not determine A cos + B sin + C")?;
    let start = Model::new(d.base_cols(), y, w);
    let (tails, rate_resid) = measured_tails(&d, noise.design.clone(), &start.y, w);
    let tilt_fitted = tilt
        .as_ref()
        .map(|t| t.corrections.clone())
        .unwrap_or_else(|| vec![0.0; d.n()]);
    let effects = catalogue(&d, tilt);
    let selection_started = std::time::Instant::now();
    let sel = Selector {
        data: &d,
        whitener: w,
        cautious: &noise.cautious,
        drift: &noise.drift,
        wander: noise.wander.as_ref(),
        effects: &effects,
        tails: tails.law,
        alpha: opt.alpha * (1.0 - UNEXPLAINED_SHARE),
    }
    .run(start)?;
    let selection_s = selection_started.elapsed().as_secs_f64();
    let averaged = averaging::average(&sel.variants).ok_or("no model fits")?;
    let shocks = final_shocks::through(
        &d,
        &sel.model.raw_cols(),
        &sel.model.y,
        &noise.model,
        &opt.noise,
        opt.replicates,
    );
    let result = final_result::Final::new(&d, &sel, &noise, averaged, shocks.as_ref(), tilt_share, opt);
    let (noise_with_effects, mut findings) =
        noise_findings(&d, &sel.model, &noise, shocks.as_ref(), (tails, rate_resid), opt)?;
    findings.extend(sel.findings.iter().cloned());
    findings.extend(unexplained_finding(&d, &sel, &noise, opt.alpha * UNEXPLAINED_SHARE));
    let struck = shocks.as_ref().map_or(&[][..], |s| &s.through.shocks.struck[..]);
    let points = residual_points(&d, &sel, &tilt_fitted, struck);
    Ok(Diagnosis {
        alpha: opt.alpha,
        notes: tilt_warning
            .into_iter()
            .chain(notes::notes(&findings, &sel.rivals, &result.models, &d))
            .chain(notes::undecided(
                &sel.undecided,
                matches!(opt.noise, NoiseChoice::Given(..)),
            ))
            .chain(shocks.as_ref().map(|s| s.note(&d)))
            .collect(),
        noise_model: noise.model,
        cautious_model: noise.cautious_model,
        drift_model: noise.drift_model,
        noise_with_effects,
        wander_tested: noise.wander.is_some(),
        noise_source: noise.source,
        final_sigma_from: match &shocks {
            Some(s) => Some(s.describe()),
            None => result.own.as_ref().map(final_sigma::FinalSigma::describe),
        },
        through_shocks: shocks.is_some(),
        sigma_calibration: match &shocks {
            Some(s) => s.calibration,
            None => result.own.as_ref().and_then(|o| o.calibration).map(|c| c.psi),
        },
        residual_dof: result.own.as_ref().and_then(|o| o.residual_dof),
        noise_estimated: opt.noise == NoiseChoice::Estimate,
        baseline: {
            let plain = summary(&base_model, &base);
            Summary {
                sigma_arcsec: result.baseline_sigma_arcsec.unwrap_or(plain.sigma_arcsec),
                ..plain
            }
        },
        findings,
        undecided: sel.undecided,
        selected: summary(&sel.model, &sel.fit),
        final_: result.summary,
        unresolved: result.unresolved,
        timing: Timing {
            noise_s,
            selection_s,
            selection_steps: sel.steps,
            total_s: started.elapsed().as_secs_f64(),
        },
        models: result.models,
        points,
    })
}

/// What a recording without inclinometer readings cannot show: a shaft tilt turns the Earth
/// rate's vertical part into a first harmonic, moving the azimuth without a residual.
fn untested_tilt(latitude_deg: f64) -> String {
    format!(
        "shaft_tilt: not tested, the recording has no inclinometer readings; a tilt eta moves the azimuth by up to eta tan(lat) ({:.1}\" per 0.01 deg here) and leaves no residual, so nothing here can show it",
        36.0 * latitude_deg.to_radians().tan().abs()
    )
}

/// The shaft tilt from the inclinometer columns, if the recording has them.
fn measure_tilt(d: &Data, white: &Whitener) -> Result<Option<ShaftTilt>, String> {
    ShaftTilt::measure(&d.rec, |corr| {
        let y: Vec<f64> = d.rate.iter().zip(corr).map(|(r, c)| r - c).collect();
        // The exact correction scales with the fitted amplitude: a wild dwell mean must not
        // set it, so the bursts get columns of their own here as in the noise estimate.
        let cols = noise::with_bursts_held_out(d, &d.base_cols(), &y);
        let m = Model::new(cols, y, white);
        let f = m.fit().ok_or("the positions do not determine A cos + B sin + C")?;
        Ok((summary(&m, &f).azimuth_deg, f.coef[1].hypot(f.coef[2])))
    })
}

/// The catalogue's effects, the shaft tilt among them where it was measured.
fn catalogue(d: &Data, tilt: Option<ShaftTilt>) -> Vec<Box<dyn Effect>> {
    let sensitivity = tilt.as_ref().map_or(Sensitivity::NONE, |t| t.sensitivity);
    let mut effects: Vec<Box<dyn Effect>> = vec![
        Box::new(drift::BiasDrift),
        Box::new(jump::BiasJump),
        Box::new(thermal::ThermalDrift::new(d)),
        Box::new(encoder::EncoderError),
        Box::new(scale::ScaleFactor { sensitivity }),
        Box::new(nonlinearity::Nonlinearity),
        Box::new(settling::SettlingTransient),
        Box::new(outliers::Outliers),
    ];
    if let Some(t) = tilt {
        effects.push(Box::new(t));
    }
    effects
}

/// Structure left after the selection, at `level`: unexplained only when no plausible noise
/// model explains it either, nor white noise: whole dwells that scatter more than their
/// quarters say (shocks) make the estimate take flicker, whose whitening then
/// anti-correlates neighbouring residuals.
fn unexplained_finding(d: &Data, sel: &select::Selection, noise: &noise::Noise, level: f64) -> Option<Finding> {
    let (w, white) = (&noise.whitener, Whitener::identity());
    let s = unexplained::test(d, &sel.model, w, level)
        .and_then(|_| unexplained::test(d, &sel.model.rewhiten(&white), &white, level))
        .and_then(|_| unexplained::test(d, &sel.model.rewhiten(&noise.cautious), &noise.cautious, level))?;
    Some(Finding {
        effect: Kind::Unexplained,
        parameters: s.parameters,
        p_value: s.p,
        location: s.location,
        after: summary(&sel.model, &sel.fit),
    })
}

/// The residuals of Eq. 7 and of the selected model per position, with the findings drawn
/// over the former as those residuals hold them. Drawn by least squares, as the simulation's
/// panels are, so that each is centred and `before = after + fitted`: `before` Eq. 7's
/// residuals on the raw rates, `fitted` the findings as the selection fitted them (tilt
/// included) with their share of C, A cos and B sin taken out (a jump's step about its mean),
/// `after` the rest; `struck` the dwells the final read as struck by shocks.
fn residual_points(d: &Data, sel: &select::Selection, tilt_fitted: &[f64], struck: &[usize]) -> Vec<Point> {
    let plain = |y: Vec<f64>| {
        let m = Model::new(d.base_cols(), y, &Whitener::identity());
        m.fit().map_or_else(|| m.y.clone(), |f| m.raw_residuals(&f))
    };
    let before = plain(d.rate.clone());
    let effects: Vec<f64> = sel
        .model
        .effects_fitted(&sel.fit)
        .iter()
        .zip(tilt_fitted)
        .map(|(e, t)| e + t)
        .collect();
    let fitted = plain(effects);
    (0..d.n())
        .map(|i| Point {
            t_s: d.t[i],
            gamma_deg: d.gamma[i],
            before: before[i],
            after: before[i] - fitted[i],
            fitted: fitted[i],
            struck: struck.contains(&i),
        })
        .collect()
}

/// The noise as it is beside the effects named (what the noise terms and the fix report) and
/// its findings, the tails among them. Through shocks, the noise estimated again beside them is
/// the one whose colours are named, and the shocks are the tails' finding; else the noise is
/// estimated again with the named effects' columns, and its tails measured (a jump left out is
/// one large step of a walk's whitening, a tail), or the first estimate's `tails` stand.
fn noise_findings(
    d: &Data,
    selected: &Model,
    noise: &noise::Noise,
    shocks: Option<&final_shocks::FinalShocks>,
    tails: (tails::Tails, Vec<f64>),
    opt: &Options,
) -> Result<(NoiseModel, Vec<Finding>), String> {
    if let Some(s) = shocks {
        let (model, terms, whence) = match &s.through.estimate {
            Some(e) => (
                s.through.model,
                noise::supported(e, opt.alpha).1,
                "estimated again beside the shocks",
            ),
            None => (noise.model, noise.terms.clone(), WHITENED_BY),
        };
        let mut findings = noise::findings(d, &terms, whence);
        findings.push(s.finding(d));
        return Ok((model, findings));
    }
    let effect_cols: Vec<Vec<f64>> = selected
        .cols
        .iter()
        .filter(|c| c.kind.is_some())
        .map(|c| c.raw.clone())
        .collect();
    let after = match opt.noise {
        NoiseChoice::Estimate if !effect_cols.is_empty() => {
            noise::with_effects(d, &selected.y, &effect_cols, opt.alpha)
        }
        _ => None,
    };
    let (model, terms, (tails, rate_resid)) = match after {
        Some(a) => {
            let w = noise.whitening.of(&a.model)?;
            (a.model, a.terms, measured_tails(d, a.design, &selected.y, &w))
        }
        None => (noise.model, noise.terms.clone(), tails),
    };
    let mut findings = noise::findings(d, &terms, WHITENED_BY);
    findings.extend(noise::tails_finding(&tails, &rate_resid, opt.alpha / 2.0));
    Ok((model, findings))
}

/// Where the noise terms were found, when the tests' whitening found them.
const WHITENED_BY: &str = "whitened by this model in every test";

/// The tails of the rates `y` whitened by `w` about a fit of `design`, and the rates'
/// residuals (which size the shocks). The largest is held out by its own (whitened) column:
/// the design's columns would absorb part of a burst and spread the rest over the others,
/// where it reads as a tail.
fn measured_tails(d: &Data, design: Vec<Vec<f64>>, y: &[f64], w: &Whitener) -> (tails::Tails, Vec<f64>) {
    let model = Model::new(design, y.to_vec(), w);
    let Some(f) = model.fit() else {
        return (tails::estimate(&[]), Vec::new());
    };
    let i = tails::largest(&f.resid).unwrap_or(0);
    let held = model.fit_plus(&[w.apply(&d.indicator(i))]);
    let tails = tails::estimate_held_out(&held.map_or_else(|| f.resid.clone(), |h| h.resid), i);
    (tails, model.raw_residuals(&f))
}
