//! What one recording cannot tell apart, said beside the findings.

use super::averaging::Weighted;
use super::data::Data;
use super::kind::Kind;
use super::select::{Finding, Undecided};

fn corr(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

/// Notes on the findings, the rival explanations met at a step, and the models averaged.
pub fn notes(findings: &[Finding], rivals: &[(Kind, Kind)], models: &[Weighted], d: &Data) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    if d.temp_bridged > 0 {
        out.push(format!(
            "temp_c: {} of the {} dwells have no reading: each bridged from the readings before and after it in time, for the thermal test",
            d.temp_bridged,
            d.n()
        ));
    }
    let named = |k: Kind| findings.iter().any(|f| f.effect == k);
    let rival = |a: Kind, b: Kind| rivals.iter().any(|&(x, y)| (x, y) == (a, b) || (x, y) == (b, a));
    if rival(Kind::BiasDrift, Kind::ThermalDrift)
        && let Some(temp) = &d.temp
    {
        out.push(format!(
            "bias_drift and thermal_drift both explain the recording (the temperature follows time, r = {:.3}): the result averages the two models",
            corr(temp, &d.t)
        ));
    }
    if rival(Kind::Nonlinearity, Kind::EncoderError) {
        out.push("nonlinearity and encoder eccentricity (encoder_error, harmonic 1) both make a second harmonic: with psi fixed they differ only in its phase".into());
    }
    if rival(Kind::BiasJump, Kind::BiasDrift) {
        out.push("bias_jump and bias_drift both move the bias with time: the result averages the two models".into());
    }
    if rival(Kind::EncoderError, Kind::ThermalDrift) {
        out.push("encoder_error and thermal_drift: in a sweep a temperature cycle of k periods per run is the angle's k-th harmonic, which an encoder error in harmonic k - 1 or k + 1 makes too; the temperature column tells them apart only as far as the noise lets it".into());
    }
    out.extend(outweighed(rivals, models));
    if named(Kind::ScaleFactor) {
        out.push(
            "scale_factor: an amplitude off the latitude's prediction is also what a wrong latitude_deg would give"
                .into(),
        );
    }
    if named(Kind::EncoderError) {
        out.push("encoder_error: a genuine third (or second) harmonic of the gyro output would look the same in this recording alone; a second run with the encoder turned against the gyro tells them apart".into());
    }
    let shared: Vec<String> = models
        .iter()
        .filter(|m| m.weight >= 0.05)
        .map(|m| {
            format!(
                "{} {:.5} deg +- {:.2}\" (weight {:.2})",
                m.label, m.summary.azimuth_deg, m.summary.sigma_arcsec, m.weight
            )
        })
        .collect();
    if shared.len() > 1 {
        out.push(format!("models sharing the result: {}", shared.join("; ")));
    }
    out
}

/// The rival explanations that the averaging all but drops (under 5 % of the weight, where
/// "models sharing the result" does not show them), with the azimuth each would give: a
/// significant alternative is said even where the information criterion outweighs it.
fn outweighed(rivals: &[(Kind, Kind)], models: &[Weighted]) -> Vec<String> {
    let mut said: Vec<(Kind, Kind)> = Vec::new();
    let mut out = Vec::new();
    for &(chosen, alt) in rivals {
        if said.contains(&(chosen, alt)) {
            continue;
        }
        said.push((chosen, alt));
        if let Some(m) = models
            .iter()
            .find(|m| m.rival == Some((chosen, alt)) && m.weight < 0.05)
        {
            out.push(format!(
                "{} was significant too where {} was named, but weighs {:.3} in the result: with it instead, psi {:.5} deg +- {:.2}\"",
                alt.name(),
                chosen.name(),
                m.weight,
                m.summary.azimuth_deg,
                m.summary.sigma_arcsec
            ));
        }
    }
    out
}

/// The effects the selection's last step found by their own tests and the wander test held
/// back: said, with the effect's size if it is one, so that a clear trend is not passed over
/// in silence. `given`: the noise model came from a static log, not from this run.
pub fn undecided(held: &[Undecided], given: bool) -> Vec<String> {
    let tell = if given {
        "a longer run can, or one in a balanced visiting order"
    } else {
        "a static log of the gyro can (`nf allan LOG --out gyro.noise`, then `--noise gyro.noise`), or a run in a balanced visiting order"
    };
    held.iter()
        .map(|u| {
            let size: Vec<String> = u
                .parameters
                .iter()
                .map(|p| match p.sigma {
                    Some(s) => format!("{} = {} +- {}", p.name, number(p.value), number(s)),
                    None => format!("{} = {}", p.name, number(p.value)),
                })
                .collect();
            let wander = if u.at_least {
                format!(
                    "p at least {:.1e} by the F law, already at or above the step's level {:.1e}",
                    u.p_value, u.level
                )
            } else {
                format!("p = {:.1e}, the step's level {:.1e}", u.p_value, u.level)
            };
            format!(
                "{} not named: its own test finds it (p = {:.1e}), but with the noise re-estimated with and without it the run's own wander explains the recording as well ({}); if it is one, {}, {}. One run cannot tell them apart: {}",
                u.effect.name(),
                u.own_p,
                wander,
                size.join(", "),
                u.location,
                tell
            )
        })
        .collect()
}

/// A parameter for a person: whole numbers whole, the rest to three decimals (0.1 to 1e5)
/// or four figures.
fn number(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e9 {
        format!("{v:.0}")
    } else if (0.1..1e5).contains(&v.abs()) {
        format!("{v:.3}")
    } else {
        format!("{v:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::Summary;

    fn model(label: &str, rival: Option<(Kind, Kind)>, weight: f64, azimuth_deg: f64) -> Weighted {
        Weighted {
            label: label.into(),
            weight,
            summary: Summary {
                azimuth_deg,
                rss: 1.0,
                sigma_arcsec: 30.0,
            },
            rival,
        }
    }

    #[test]
    fn a_rival_the_averaging_all_but_drops_is_said_with_its_azimuth_once() {
        let (enc, thermal, jump) = (Kind::EncoderError, Kind::ThermalDrift, Kind::BiasJump);
        let models = [
            model("Eq. 7", None, 0.0, 10.0),
            model(
                "thermal_drift instead of encoder_error",
                Some((enc, thermal)),
                0.012,
                10.01,
            ),
            model("encoder_error", None, 0.988, 9.9),
            model("bias_jump instead of encoder_error", Some((enc, jump)), 0.2, 10.02),
        ];
        let rivals = [
            (Kind::EncoderError, Kind::ThermalDrift),
            (Kind::EncoderError, Kind::ThermalDrift),
            // Weighed enough to be among the models sharing the result.
            (Kind::EncoderError, Kind::BiasJump),
            // Met without a model of its own (no columns).
            (Kind::EncoderError, Kind::SettlingTransient),
        ];
        let said = outweighed(&rivals, &models);
        assert_eq!(said.len(), 1, "{said:?}");
        assert!(said[0].starts_with("thermal_drift was significant too where encoder_error was named"));
        assert!(
            said[0].contains("weighs 0.012") && said[0].contains("psi 10.01000 deg"),
            "{}",
            said[0]
        );
    }

    #[test]
    fn a_held_back_effect_says_its_wander_p_value_and_whether_it_is_only_a_bound() {
        let held = |at_least| Undecided {
            effect: Kind::BiasDrift,
            own_p: 1e-4,
            p_value: 4.5e-3,
            at_least,
            level: 4e-3,
            parameters: Vec::new(),
            location: "over the run".into(),
        };
        let drawn = undecided(&[held(false)], false);
        assert!(
            drawn[0].contains("(p = 4.5e-3, the step's level 4.0e-3)"),
            "{}",
            drawn[0]
        );
        let bound = undecided(&[held(true)], false);
        assert!(bound[0].contains("(p at least 4.5e-3 by the F law"), "{}", bound[0]);
    }
}
