//! Concealing a catalogue effect in a case at a named level, sized against the white noise of a
//! dwell mean `s` (or the standard error of the quantity it moves), so that "barely" is at the
//! edge of detection and "clear" unmistakable whatever the instrument.

use super::cases::{Case, DWELL_S, DwellShift};
use crate::diagnose::Kind;
use nf_twin::{BiasJump, EncoderHarmonic, Rng, TempSwing};

/// Magnitude levels, named; [`conceal`] takes an index into them.
pub const LEVELS: [&str; 3] = ["barely", "moderate", "clear"];

/// The index of "moderate" in [`LEVELS`].
pub const MODERATE: usize = 1;

/// Conceals `effect` at `level` (an index into [`LEVELS`]) in the case.
pub fn conceal(c: &mut Case, effect: Kind, level: usize, rng: &mut Rng) {
    let s = c.sigma();
    let n = c.visits() as f64;
    let r = c.amplitude();
    let pick = |v: [f64; 3]| v[level];
    let duration = c.duration_s();
    // Standard error of a harmonic's coefficient, relative to the amplitude.
    let se = s * (2.0 / n).sqrt() / r;
    match effect {
        Kind::BiasDrift => c.twin.bias_drift_dph_per_s = pick([1.5, 4.0, 12.0]) * s / duration,
        Kind::BiasJump => {
            c.twin.bias_jump = Some(BiasJump {
                time_s: rng.uniform(0.3, 0.7) * duration,
                size_dph: pick([1.5, 3.0, 8.0]) * s,
            });
        }
        Kind::ThermalDrift => {
            c.twin.temp_swing = TempSwing {
                amplitude_c: 2.0,
                period_s: duration / rng.uniform(1.5, 3.0),
                phase_deg: 0.0,
            };
            c.twin.bias_temp_dph_per_c = pick([1.0, 2.5, 8.0]) * s / 2.0;
        }
        Kind::ShaftTilt => {
            c.twin.instrument.tilt_deg = pick([0.0006, 0.002, 0.01]);
            c.twin.instrument.tilt_dir_deg = rng.uniform(0.0, 360.0);
        }
        Kind::EncoderError => {
            let arcsec = pick([2.0, 4.0, 12.0]) * s / r * 206_264.8;
            c.twin.encoder_error[0] = EncoderHarmonic {
                harmonic: 2,
                amplitude_arcsec: arcsec,
                phase_deg: rng.uniform(0.0, 360.0),
            };
        }
        Kind::ScaleFactor => {
            let sign = if rng.unit() < 0.5 { -1.0 } else { 1.0 };
            c.twin.instrument.scale = 1.0 + sign * pick([3.0, 5.0, 10.0]) * se;
        }
        Kind::Nonlinearity => c.twin.nonlinearity_per_dph = pick([3.0, 5.0, 10.0]) * 2.0 * se / r,
        Kind::SettlingTransient => {
            // About this many quarter-mean noises of excess in the first quarter of each dwell.
            let quarter_noise = c.twin.noise.white_mean_sd_dph(DWELL_S / 4.0);
            let tau = 0.05;
            c.twin.settle_tau_s = tau;
            c.twin.settle_dph = pick([0.4, 0.8, 2.0]) * quarter_noise * (DWELL_S / 4.0) / tau * (0.1f64 / tau).exp();
        }
        Kind::Outliers => c.dwell_shifts.push(DwellShift {
            visit: (rng.next_u64() % n as u64) as usize,
            dph: pick([4.0, 6.0, 10.0]) * s,
        }),
        _ => unreachable!("{effect} is not in the catalogue"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::Kind;
    use crate::diagnose_eval::cases::{Site, random_case};
    use nf_model::order::Order;

    #[test]
    fn every_catalogue_effect_changes_the_case_and_grows_with_the_level() {
        for effect in Kind::CATALOGUE {
            let mut sizes = Vec::new();
            for (level, name) in LEVELS.iter().enumerate() {
                let plain = random_case(&mut Rng::new(9), &Site::ORDINARY, Order::Sequential);
                let mut c = plain.clone();
                conceal(&mut c, effect, level, &mut Rng::new(1));
                assert!(
                    c.twin != plain.twin || c.dwell_shifts != plain.dwell_shifts,
                    "{effect} at {name}"
                );
                // A rough size: the parameters the effects set, whichever it is.
                let t = &c.twin;
                let size = t.bias_drift_dph_per_s
                    + t.bias_jump.map_or(0.0, |j| j.size_dph)
                    + t.bias_temp_dph_per_c
                    + t.instrument.tilt_deg
                    + t.encoder_error[0].amplitude_arcsec
                    + (t.instrument.scale - 1.0).abs()
                    + t.nonlinearity_per_dph
                    + t.settle_dph
                    + c.dwell_shifts.iter().map(|s| s.dph).sum::<f64>();
                sizes.push(size);
            }
            assert!(sizes[0] < sizes[1] && sizes[1] < sizes[2], "{effect}: {sizes:?}");
        }
    }
}
