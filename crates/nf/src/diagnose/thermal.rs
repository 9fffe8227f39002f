//! `thermal_drift`: the bias follows the recorded temperature. Judged under the drift
//! design's noise model, as drift and jump are: the three are rival explanations of one
//! wander of the bias with time, and a rival judged under a more coloured model loses to the
//! others whatever the data say.

use super::effect::{Effect, Law, Proposal, State, param};
use super::kind::Kind;

pub struct ThermalDrift;

impl Effect for ThermalDrift {
    fn kind(&self) -> Kind {
        Kind::ThermalDrift
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        let Some(temp) = &s.data.temp else { return Vec::new() };
        if s.is_named(Kind::ThermalDrift) {
            return Vec::new();
        }
        let mean = temp.iter().sum::<f64>() / temp.len() as f64;
        let dt: Vec<f64> = temp.iter().map(|v| v - mean).collect();
        if dt.iter().all(|v| v.abs() < 1e-6) {
            return Vec::new();
        }
        s.drift
            .nested(
                Kind::ThermalDrift,
                vec![dt],
                |l, k| vec![param("dph_per_degc", l.coef[k], Some(l.sigma(k)))],
                "follows the recorded temperature".into(),
            )
            .into_iter()
            .map(|p| s.wander_judged(p, Law::Drawn))
            .collect()
    }
}
