//! `encoder_error`: an angle error of harmonic k in the encoder. The rate at the true angle
//! `gamma + e(gamma)` is, linearised, `-R sin(gamma + psi) e(gamma)`: harmonics k - 1 and
//! k + 1 of the residuals. k = 2 makes a third harmonic and biases the azimuth. Reported as
//! the reading's error `-e(gamma) = amplitude sin(k gamma + phase)`, the instrument file's.

use super::effect::{Effect, Law, Proposal, State, param};
use super::kind::Kind;
use nf_model::angle::atan2_deg;

pub struct EncoderError;

/// The harmonics of the angle error tested.
const HARMONICS: [u32; 3] = [1, 2, 3];

impl Effect for EncoderError {
    fn kind(&self) -> Kind {
        Kind::EncoderError
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        if s.is_named(Kind::EncoderError) {
            return Vec::new();
        }
        let amp = s.amplitude();
        let psi = s.summary.azimuth_deg;
        let slope: Vec<f64> = s
            .data
            .gamma
            .iter()
            .map(|g| -amp * (g + psi).to_radians().sin())
            .collect();
        HARMONICS
            .iter()
            .filter_map(|&k| {
                let [c, sn] = s.data.harmonic(k);
                let cols = vec![
                    slope.iter().zip(&c).map(|(a, b)| a * b).collect(),
                    slope.iter().zip(&sn).map(|(a, b)| a * b).collect(),
                ];
                let shows = match k {
                    1 => "the second harmonic of the residuals (no azimuth bias)".to_string(),
                    2 => "the third harmonic of the residuals; it biases the azimuth".to_string(),
                    _ => format!("harmonics {} and {} of the residuals", k - 1, k + 1),
                };
                s.cautious
                    .nested(
                        Kind::EncoderError,
                        cols,
                        move |l, i| {
                            let (a, b) = (l.coef[i], l.coef[i + 1]);
                            vec![
                                param("harmonic", k as f64, None),
                                param(
                                    "amplitude_arcsec",
                                    a.hypot(b).to_degrees() * 3600.0,
                                    Some(l.sigma(i).to_degrees() * 3600.0),
                                ),
                                // The reading's error, `-e`, as the instrument file and
                                // the twin give it: amplitude sin(k gamma + phase).
                                param("phase_deg", atan2_deg(-a, -b), None),
                            ]
                        },
                        shows,
                    )
                    .map(|p| s.wander_judged(p, Law::F { scan: 1 }))
            })
            .collect()
    }
}
