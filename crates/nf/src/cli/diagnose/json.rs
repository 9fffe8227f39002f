//! The JSON of `nf diagnose --json` (a recording; the suite's is `diagnose_eval::json`).
//!
//! The fields of each struct are in alphabetical order, the order the keys have always had.

use super::super::diagnose_sim::{self, SimJson};
use crate::diagnose::{Diagnosis, Finding, Param, Summary, Undecided};
use crate::sim_compare::SimReport;
use nf_model::noise::NoiseModel;
use serde::Serialize;
use std::collections::BTreeMap;

/// The diagnosis: the noise model, the baseline fit, each finding, and the result.
#[derive(Serialize)]
pub(super) struct DiagnosisJson<'a> {
    /// Family-wise false-alarm rate of each selection step.
    alpha: f64,
    /// Eq. 7 on the raw rates, under the noise model.
    baseline: SummaryJson,
    /// Whether the Earth rate is resolved; without it the final has no azimuth.
    earth_rate_resolved: bool,
    /// The result: the models met, averaged by their weights, and over the noise models the
    /// recording allows; its azimuth is null when the Earth rate is not resolved.
    #[serde(rename = "final")]
    final_: SummaryJson,
    /// Noise terms, catalogue effects and unexplained structure, in the order found.
    findings: Vec<FindingJson<'a>>,
    /// The models met and their weights.
    models: Vec<ModelJson<'a>>,
    /// The gyro noise model.
    noise_model: NoiseModelJson<'a>,
    /// Why the Earth rate is not resolved; null when it is.
    not_resolved_because: Option<&'a str>,
    /// What cannot be told apart, and other cautions.
    notes: &'a [String],
    /// The selected model alone.
    selected: SummaryJson,
    /// The comparison with the instrument file of --sim; only with --sim.
    #[serde(skip_serializing_if = "Option::is_none")]
    simulation: Option<SimJson<'a>>,
    /// Effects their own tests find but the wander test holds back: not named, as the run's
    /// own wander explains the recording as well.
    undecided: Vec<UndecidedJson<'a>>,
}

/// An effect not named for the run's own wander.
#[derive(Serialize)]
struct UndecidedJson<'a> {
    /// The effect's name.
    effect: &'static str,
    /// Its own test's p-value.
    own_p_value: f64,
    /// The wander test's p-value (the noise re-estimated with and without it).
    p_value: f64,
    /// Whether `p_value` is the F law's lower bound of it (draws of the null not made, as
    /// it already reached `level`).
    p_value_is_lower_bound: bool,
    /// The selection step's level, which the wander test's p-value did not get under.
    level: f64,
    /// Its size by name, if it is one.
    parameters: BTreeMap<&'a str, ParamJson>,
    /// Where in the recording it would show.
    #[serde(rename = "where")]
    location: &'a str,
}

/// Azimuth and uncertainty of a fit.
#[derive(Serialize)]
struct SummaryJson {
    /// Azimuth psi, deg.
    azimuth_deg: Option<f64>,
    /// Residual sum of squares of this fit's residuals in rate units, (deg/h)^2. Under a
    /// coloured noise model the fit is GLS, which leaves the slow wander in its residuals: more
    /// than white least squares' (`nf fit`'s `rss`).
    rss: f64,
    /// 1-sigma uncertainty of psi, arcsec.
    sigma_arcsec: f64,
}

impl From<&Summary> for SummaryJson {
    fn from(s: &Summary) -> SummaryJson {
        SummaryJson {
            azimuth_deg: Some(s.azimuth_deg),
            rss: s.rss,
            sigma_arcsec: s.sigma_arcsec,
        }
    }
}

/// One finding.
#[derive(Serialize)]
struct FindingJson<'a> {
    /// The fit with it; null for a noise term.
    after: Option<SummaryJson>,
    /// The effect's name.
    effect: &'static str,
    /// Whether it is a noise term rather than an effect in the fit.
    noise: bool,
    /// Bonferroni-adjusted p-value of the test that found it.
    p_value: f64,
    /// Its parameters by name.
    parameters: BTreeMap<&'a str, ParamJson>,
    /// Where in the recording it shows.
    #[serde(rename = "where")]
    location: &'a str,
}

/// A parameter, in the unit its name ends with.
#[derive(Serialize)]
struct ParamJson {
    /// Standard error; null where the fit gives none.
    sigma: Option<f64>,
    /// The fitted value.
    value: f64,
}

/// One of the models met, with its weight in the result.
#[derive(Serialize)]
struct ModelJson<'a> {
    /// Azimuth psi, deg.
    azimuth_deg: f64,
    /// The model's effects.
    model: &'a str,
    /// 1-sigma uncertainty of psi, arcsec.
    sigma_arcsec: f64,
    /// Its weight in the average (dimensionless, the weights sum to 1).
    weight: f64,
}

/// The gyro noise model, and the two under which some effects are judged.
#[derive(Serialize)]
struct NoiseModelJson<'a> {
    /// Angle random walk N, deg/sqrt(h).
    arw_deg_rth: f64,
    /// Bias instability B, deg/h.
    bias_instability_dph: f64,
    /// The most coloured plausible model: encoder harmonics and the slow amplitude and 2 psi
    /// harmonic are judged under it.
    cautious: ColouredJson,
    /// Rate random walk K, deg/h/sqrt(h).
    rrw_dph_rth: f64,
    /// Where the model came from.
    source: &'a str,
    /// Where the final sigma under the noise came from (null: the tests' noise models).
    final_sigma_from: Option<&'a str>,
    /// The factor a parametric bootstrap scaled the final sigma by (null: not scaled).
    sigma_calibration: Option<f64>,
    /// The most likely model's residual degrees of freedom where they alone measured the
    /// noise (null: a noise model did): white, each sigma widened by Student's t.
    residual_dof: Option<usize>,
    /// The model estimated with a drift: drift, jump and temperature are judged under it.
    with_drift: ColouredJson,
    /// The model estimated again with the named effects in the design: the noise terms named
    /// are its, and `--fix` writes it.
    with_effects: ColouredJson,
    /// Whether drift, jump, temperature, encoder harmonics and the 2 psi harmonic were also
    /// judged with the noise re-estimated with and without each (a likelihood ratio; named
    /// only when both tests find them).
    wander_tested: bool,
}

/// The coloured terms of a noise model.
#[derive(Serialize)]
struct ColouredJson {
    /// Bias instability B, deg/h.
    bias_instability_dph: f64,
    /// Rate random walk K, deg/h/sqrt(h).
    rrw_dph_rth: f64,
}

impl From<&NoiseModel> for ColouredJson {
    fn from(m: &NoiseModel) -> ColouredJson {
        ColouredJson {
            bias_instability_dph: m.bias_instability_dph,
            rrw_dph_rth: m.rrw_dph_rth,
        }
    }
}

fn finding_json(f: &Finding) -> FindingJson<'_> {
    FindingJson {
        after: (!f.effect.is_noise()).then(|| (&f.after).into()),
        effect: f.effect.name(),
        noise: f.effect.is_noise(),
        p_value: f.p_value,
        parameters: parameters_json(&f.parameters),
        location: &f.location,
    }
}

fn undecided_json(u: &Undecided) -> UndecidedJson<'_> {
    UndecidedJson {
        effect: u.effect.name(),
        own_p_value: u.own_p,
        p_value: u.p_value,
        p_value_is_lower_bound: u.at_least,
        level: u.level,
        parameters: parameters_json(&u.parameters),
        location: &u.location,
    }
}

fn parameters_json(ps: &[Param]) -> BTreeMap<&str, ParamJson> {
    ps.iter()
        .map(|p| {
            let j = ParamJson {
                sigma: p.sigma,
                value: p.value,
            };
            (p.name.as_str(), j)
        })
        .collect()
}

pub(super) fn diagnosis_json<'a>(d: &'a Diagnosis, sim: Option<&'a SimReport>) -> DiagnosisJson<'a> {
    let m = &d.noise_model;
    DiagnosisJson {
        alpha: d.alpha,
        baseline: (&d.baseline).into(),
        earth_rate_resolved: d.unresolved.is_none(),
        final_: SummaryJson {
            azimuth_deg: d.unresolved.is_none().then_some(d.final_.azimuth_deg),
            ..(&d.final_).into()
        },
        findings: d.findings.iter().map(finding_json).collect(),
        models: d
            .models
            .iter()
            .map(|w| ModelJson {
                azimuth_deg: w.summary.azimuth_deg,
                model: &w.label,
                sigma_arcsec: w.summary.sigma_arcsec,
                weight: w.weight,
            })
            .collect(),
        noise_model: NoiseModelJson {
            arw_deg_rth: m.arw_deg_rth,
            bias_instability_dph: m.bias_instability_dph,
            cautious: (&d.cautious_model).into(),
            rrw_dph_rth: m.rrw_dph_rth,
            source: &d.noise_source,
            final_sigma_from: d.final_sigma_from.as_deref(),
            sigma_calibration: d.sigma_calibration,
            residual_dof: d.residual_dof,
            with_drift: (&d.drift_model).into(),
            with_effects: (&d.noise_with_effects).into(),
            wander_tested: d.wander_tested,
        },
        not_resolved_because: d.unresolved.as_deref(),
        notes: &d.notes,
        selected: (&d.selected).into(),
        simulation: sim.map(diagnose_sim::json),
        undecided: d.undecided.iter().map(undecided_json).collect(),
    }
}
