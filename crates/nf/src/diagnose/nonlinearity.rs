//! `nonlinearity`: a rate-squared term `k2 rate^2`, a second harmonic locked to `2 psi` with
//! amplitude `k2 R^2 / 2`.

use super::effect::{Effect, Law, Proposal, State, param};
use super::kind::Kind;

pub struct Nonlinearity;

impl Effect for Nonlinearity {
    fn kind(&self) -> Kind {
        Kind::Nonlinearity
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        if s.is_named(Kind::Nonlinearity) {
            return Vec::new();
        }
        let amp = s.amplitude();
        let psi = s.summary.azimuth_deg;
        let col: Vec<f64> = s
            .data
            .gamma
            .iter()
            .map(|g| (2.0 * (g + psi)).to_radians().cos())
            .collect();
        // In a sweep the 2 psi harmonic is two cycles of the run, which the estimate sees
        // between the harmonics it holds; in opposite pairs it is one, the slowest wander.
        let frame = if s.data.slow_in_time(&col) { s.cautious } else { s.main };
        frame
            .nested(
                Kind::Nonlinearity,
                vec![col],
                |l, k| {
                    vec![param(
                        "k2_per_dph",
                        2.0 * l.coef[k] / (amp * amp),
                        Some(2.0 * l.sigma(k) / (amp * amp)),
                    )]
                },
                "a second harmonic locked to 2 psi".into(),
            )
            .into_iter()
            .map(|p| s.wander_judged(p, Law::F { scan: 1 }))
            .collect()
    }
}
