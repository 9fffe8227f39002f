//! `bias_drift`: the bias moves with time, linearly or on a curve.

use super::effect::{Effect, Law, Proposal, State, param};
use super::kind::Kind;

pub struct BiasDrift;

impl Effect for BiasDrift {
    fn kind(&self) -> Kind {
        Kind::BiasDrift
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        if s.is_named(Kind::BiasDrift) {
            return Vec::new();
        }
        let d = s.data;
        let h = d.half_span_s;
        let tau = d.tau.clone();
        let tau2: Vec<f64> = tau.iter().map(|v| v * v).collect();
        let linear = s.drift.nested(
            Kind::BiasDrift,
            vec![tau.clone()],
            |l, k| vec![param("rate_dph_per_s", l.coef[k] / h, Some(l.sigma(k) / h))],
            "grows with time over the run".into(),
        );
        let curved = s.drift.nested(
            Kind::BiasDrift,
            vec![tau, tau2],
            |l, k| {
                vec![
                    param("rate_dph_per_s", l.coef[k] / h, Some(l.sigma(k) / h)),
                    param(
                        "rate_dph_per_s2",
                        l.coef[k + 1] / (h * h),
                        Some(l.sigma(k + 1) / (h * h)),
                    ),
                ]
            },
            "curves with time over the run".into(),
        );
        linear
            .into_iter()
            .chain(curved)
            .map(|p| s.wander_judged(p, Law::Drawn))
            .collect()
    }
}
