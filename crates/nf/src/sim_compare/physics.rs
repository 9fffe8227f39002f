//! Which physics the simulation lacks: each catalogue effect and noise property the
//! recording's diagnosis names, against the instrument file's value of it; and what a
//! diagnosis of the simulation names that the recording's does not.

use super::compare::Comparison;
use super::profile::Quantity;
use crate::diagnose::{CYCLE_AMPLITUDE, Diagnosis, Finding, Kind, Param, SHOCK_RMS};
use crate::instrument_file::InstrumentFile;
use crate::recording::Recording;
use nf_model::noise::NoiseModel;
use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The recording has it, the simulation has none of it.
    Missing,
    /// Both have it, of different sizes.
    Different,
    /// Both have it, of the same size within the recording's uncertainty.
    Modelled,
    /// The simulation has it at a size the recording would show, and the recording does not.
    OnlyInSimulation,
    /// A colour of noise the recording names that the simulation has as another colour, its
    /// noise over the run the recording's.
    Equivalent,
}

impl Verdict {
    /// Whether the file should change.
    pub fn needs_change(self) -> bool {
        matches!(self, Verdict::Missing | Verdict::Different | Verdict::OnlyInSimulation)
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Verdict::Missing => "missing from the simulation",
            Verdict::Different => "in both, of a different size",
            Verdict::Modelled => "in both, the same within its uncertainty",
            Verdict::OnlyInSimulation => "in the simulation at a size the recording would show, not shown by it",
            Verdict::Equivalent => "in the simulation as another colour, whose noise over the run is the recording's",
        })
    }
}

/// One effect, as the recording shows it and as the file has it.
#[derive(Debug, Clone, PartialEq)]
pub struct Physics {
    pub kind: Kind,
    pub verdict: Verdict,
    /// The parameter compared, with the recording's value and uncertainty.
    pub parameter: Param,
    pub simulated: f64,
    /// Every parameter the recording's diagnosis fitted (those of the simulation's for
    /// `OnlyInSimulation`).
    pub found: Vec<Param>,
}

pub fn param<'a>(f: &'a [Param], name: &str) -> Option<&'a Param> {
    f.iter().find(|p| p.name == name)
}

/// Mean offset of a dwell's first quarter from its other three under the file's settling.
pub fn settling_offset(file: &InstrumentFile, dwell_s: f64) -> f64 {
    let (size, tau, s) = (file.settling.size_dph, file.settling.tau_s, file.run.settle_s);
    let mean_over = |a: f64, b: f64| size * tau * ((-a / tau).exp() - (-b / tau).exp()) / (b - a);
    let q = dwell_s / 4.0;
    mean_over(s, s + q) - mean_over(s + q, s + dwell_s)
}

/// The RMS shift the file's shocks give a dwell mean, deg/h.
pub fn shock_rms(file: &InstrumentFile, dwell_s: f64) -> f64 {
    file.shocks.map_or(0.0, |s| {
        let w = s.twin().per_window(dwell_s);
        w.share.sqrt() * w.shift_dph
    })
}

/// The run's middle time, s (where the diagnosis takes the drift's slope).
pub fn middle_s(rec: &Recording) -> f64 {
    let (lo, hi) = rec.rows.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
        (lo.min(r.t_s), hi.max(r.t_s))
    });
    (lo + hi) / 2.0
}

/// The parameter compared for `kind` and the file's value of it; `None` for kinds a file
/// does not describe by one number.
fn simulated(
    kind: Kind,
    found: &[Param],
    file: &InstrumentFile,
    rec: &Recording,
    dwell_s: f64,
    origin_s: f64,
) -> Option<(&'static str, f64)> {
    let harmonic = param(found, "harmonic").map_or(0, |p| p.value as u8);
    Some(match kind {
        Kind::BiasDrift => (
            "rate_dph_per_s",
            file.drift.linear_dph_per_s + 2.0 * file.drift.quadratic_dph_per_s2 * (middle_s(rec) + origin_s),
        ),
        Kind::BiasJump => ("size_dph", file.jump.map_or(0.0, |j| j.size_dph)),
        // Without a recorded temperature the bias's cycle in time is what was found.
        Kind::ThermalDrift if param(found, CYCLE_AMPLITUDE).is_some() => (
            CYCLE_AMPLITUDE,
            (file.temperature.bias_dph_per_c * file.temperature.swing_c).abs(),
        ),
        Kind::ThermalDrift => ("dph_per_degc", file.temperature.bias_dph_per_c),
        Kind::ShaftTilt => ("tilt_deg", file.shaft.tilt_deg),
        Kind::EncoderError => (
            "amplitude_arcsec",
            file.encoder
                .error
                .iter()
                .filter(|e| e.harmonic == harmonic)
                .map(|e| e.amplitude_arcsec)
                .fold(0.0, |a, b| a + b),
        ),
        Kind::ScaleFactor => ("scale", file.gyro.scale),
        Kind::Nonlinearity => ("k2_per_dph", file.gyro.nonlinearity_per_dph),
        Kind::SettlingTransient => ("first_quarter_offset_dph", settling_offset(file, dwell_s)),
        Kind::Outliers => {
            let t = param(found, "index")
                .and_then(|i| rec.rows.iter().find(|r| r.index as f64 == i.value))
                .map_or(f64::NAN, |r| r.t_s + origin_s);
            let size = file
                .disturbance
                .iter()
                .filter(|d| (d.from_s..d.to_s).contains(&t))
                .map(|d| d.size_dph)
                .fold(0.0, |a, b| a + b);
            ("size_dph", size)
        }
        Kind::BiasInstability => ("bias_instability_dph", file.noise.bias_instability_dph),
        Kind::RateRandomWalk => ("rrw_dph_rth", file.noise.rrw_dph_rth),
        Kind::CorrelatedNoise => ("gm_sigma_dph", file.noise.gm_sigma_dph),
        // The samples' Student-t averages out over a dwell: the dwell means' tails are shocks.
        Kind::HeavyTails => (SHOCK_RMS, shock_rms(file, dwell_s)),
        Kind::Unexplained => return None,
    })
}

/// The size of an effect whose compared parameter is `v`: a scale of 1 is none.
fn size(kind: Kind, v: f64) -> f64 {
    if kind == Kind::ScaleFactor { v - 1.0 } else { v }
}

/// Whether `found` and the file's `sim` agree: within 3 sigma, or the profile range of a
/// noise term, or 20 % where the diagnosis gives no uncertainty.
fn agrees(kind: Kind, p: &Param, found: &[Param], sim: f64) -> bool {
    if kind == Kind::HeavyTails {
        // A few shifted dwells size the shocks: within a factor of two.
        return sim > 0.0 && (0.5..=2.0).contains(&(p.value / sim));
    }
    let lo = param(found, &format!("{}_lo", p.name));
    let hi = param(found, &format!("{}_hi", p.name));
    if let (Some(lo), Some(hi)) = (lo, hi) {
        return (lo.value..=hi.value).contains(&sim);
    }
    let tol = p.sigma.map_or(0.2 * p.value.abs(), |s| 3.0 * s);
    (p.value - sim).abs() <= tol
}

/// The verdict on a finding of the recording against the file's `sim`. A finding is
/// significant: a file without the term lacks it, whatever range of sizes the finding's
/// profile allows (a noise term's can reach down to none).
fn verdict(kind: Kind, p: &Param, found: &[Param], sim: f64) -> Verdict {
    if size(kind, sim) == 0.0 {
        Verdict::Missing
    } else if agrees(kind, p, found, sim) {
        Verdict::Modelled
    } else {
        Verdict::Different
    }
}

/// The recording's noise: the estimate made with the named effects in the design, as a
/// strong drift or jump otherwise passes for a random walk.
pub fn noise_of(diag: &Diagnosis) -> NoiseModel {
    diag.noise_with_effects
}

/// A noise term of the recording's noise model: `None` when the model has none of it.
fn noise_term(kind: Kind, diag: &Diagnosis, f: &Finding) -> Option<Vec<Param>> {
    let m = noise_of(diag);
    let v = match kind {
        Kind::BiasInstability => m.bias_instability_dph,
        Kind::RateRandomWalk => m.rrw_dph_rth,
        Kind::CorrelatedNoise => m.gm_sigma_dph,
        _ => return Some(f.parameters.clone()),
    };
    if m == diag.noise_model {
        return Some(f.parameters.clone());
    }
    // The finding's profile range belongs to the other model: a factor of two instead.
    let name = match kind {
        Kind::BiasInstability => "bias_instability_dph",
        Kind::CorrelatedNoise => "gm_sigma_dph",
        _ => "rrw_dph_rth",
    };
    (v > 0.0).then(|| {
        vec![
            Param {
                name: name.into(),
                value: v,
                sigma: None,
            },
            Param {
                name: format!("{name}_lo"),
                value: v / 2.0,
                sigma: None,
            },
            Param {
                name: format!("{name}_hi"),
                value: v * 2.0,
                sigma: None,
            },
        ]
    })
}

/// An effect the simulation has this many of its standard errors (as a replay's diagnosis
/// fits it) would be named in the recording too: its absence there contradicts the file.
const SHOWN_SIGMAS: f64 = 5.0;

/// Whether the recording's diagnosis found `kind` without naming it: as a rival of what it
/// named, or held back by the noise's wander.
fn shown_otherwise(diag: &Diagnosis, kind: Kind) -> bool {
    diag.undecided.iter().any(|u| u.effect == kind)
        || diag.models.iter().any(|m| m.rival.is_some_and(|(_, alt)| alt == kind))
}

/// Whether `kind` is a colour of noise and the file has another.
fn other_colour(kind: Kind, file: &InstrumentFile) -> bool {
    let n = &file.noise;
    let colours = [
        (Kind::BiasInstability, n.bias_instability_dph),
        (Kind::RateRandomWalk, n.rrw_dph_rth),
        (Kind::CorrelatedNoise, n.gm_sigma_dph),
    ];
    colours.iter().any(|&(k, _)| k == kind) && colours.iter().any(|&(k, v)| k != kind && v > 0.0)
}

/// The noise of the dwell means over the run, where colour shows.
fn over_the_run(q: Quantity) -> bool {
    matches!(q, Quantity::ResidualSd | Quantity::Allan(_))
}

/// The effects the recording shows, judged against the file, then those only `sim_diags`
/// (diagnoses of replays of the file) show at a size the recording would show too, where the
/// recording departs from the replays somewhere. A colour the file lacks by name but has as
/// another, where `before` (the recording against replays of the file) finds their noise over
/// the run alike, is equivalent: one run tells flicker, a walk and a Gauss-Markov bias apart
/// only so far.
/// `origin_s` is where the run starts on the file's clock.
pub fn judge(
    rec: &Recording,
    diag: &Diagnosis,
    file: &InstrumentFile,
    sim_diags: &[Diagnosis],
    before: &Comparison,
    dwell_s: f64,
    origin_s: f64,
) -> Vec<Physics> {
    let noise_alike = !before.any(over_the_run);
    let mut out: Vec<Physics> = diag
        .findings
        .iter()
        .filter_map(|f: &Finding| {
            let found = noise_term(f.effect, diag, f)?;
            let (name, sim) = simulated(f.effect, &found, file, rec, dwell_s, origin_s)?;
            let p = param(&found, name)?.clone();
            let verdict = match verdict(f.effect, &p, &found, sim) {
                Verdict::Missing if noise_alike && other_colour(f.effect, file) => Verdict::Equivalent,
                v => v,
            };
            Some(Physics {
                kind: f.effect,
                verdict,
                parameter: p,
                simulated: sim,
                found,
            })
        })
        .collect();
    for f in sim_diags.iter().flat_map(|d| &d.findings) {
        if out.iter().any(|p| p.kind == f.effect) || diag.findings.iter().any(|g| g.effect == f.effect) {
            continue;
        }
        // A finding of the replay that the file has none of is the replay's false alarm.
        let Some((name, sim)) =
            simulated(f.effect, &f.parameters, file, rec, dwell_s, origin_s).filter(|s| size(f.effect, s.1) != 0.0)
        else {
            continue;
        };
        // One run misses an effect near its threshold: not named is no evidence against it;
        // nor is it where the recording found it but named a rival, or the noise's wander
        // held it back, or where the recording agrees with the file's replays in every
        // quantity. A colour of noise is judged by the noise's profile instead.
        let sigma = param(&f.parameters, name).and_then(|p| p.sigma);
        let colour = f.effect.is_noise() && f.effect != Kind::HeavyTails;
        if colour
            || before.mismatches() == 0
            || sigma.is_some_and(|s| size(f.effect, sim).abs() < SHOWN_SIGMAS * s)
            || shown_otherwise(diag, f.effect)
        {
            continue;
        }
        out.push(Physics {
            kind: f.effect,
            verdict: Verdict::OnlyInSimulation,
            parameter: crate::diagnose::Param {
                name: name.into(),
                value: 0.0,
                sigma: None,
            },
            simulated: sim,
            found: f.parameters.clone(),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_colour_of_noise_can_stand_for_another() {
        let mut file = InstrumentFile::default();
        file.noise.bias_instability_dph = 0.01;
        assert!(other_colour(Kind::CorrelatedNoise, &file));
        assert!(other_colour(Kind::RateRandomWalk, &file));
        assert!(!other_colour(Kind::BiasInstability, &file), "the same colour");
        for kind in [Kind::BiasDrift, Kind::HeavyTails, Kind::Outliers] {
            assert!(!other_colour(kind, &file), "{kind:?}");
        }
    }

    #[test]
    fn a_term_found_is_missing_from_a_file_without_it_even_where_its_range_reaches_none() {
        let at = |name: &str, value: f64| Param {
            name: name.into(),
            value,
            sigma: None,
        };
        let found = [
            at("gm_sigma_dph", 0.016),
            at("gm_sigma_dph_lo", 0.0),
            at("gm_sigma_dph_hi", 0.03),
        ];
        let v = |sim: f64| verdict(Kind::CorrelatedNoise, &found[0], &found, sim);
        assert_eq!(v(0.0), Verdict::Missing);
        assert_eq!(v(0.02), Verdict::Modelled);
        assert_eq!(v(0.1), Verdict::Different);
    }
}
