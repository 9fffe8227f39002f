//! `bias_drift`: the bias moves with time, linearly or on a curve. Once a line is named, the
//! curve beyond it is still asked: in a sweep a curve is mostly the first harmonic of the
//! angle, so a line alone leaves the rest of it in the azimuth (a curve of 5 dwell-mean
//! sigmas over a 48-position sweep: the line's final 3 to 5 of its sigmas off).

use super::data::Data;
use super::effect::{Effect, Extension, Law, Proposal, State, param};
use super::kind::Kind;
use super::model::Model;
use crate::linfit::Ls;

pub struct BiasDrift;

impl Effect for BiasDrift {
    fn kind(&self) -> Kind {
        Kind::BiasDrift
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        let d = s.data;
        let h = d.half_span_s;
        let tau = d.tau.clone();
        let tau2: Vec<f64> = tau.iter().map(|v| v * v).collect();
        let curve = |l: &Ls, line: usize, k: usize| {
            vec![
                param("rate_dph_per_s", l.coef[line] / h, Some(l.sigma(line) / h)),
                param("rate_dph_per_s2", l.coef[k] / (h * h), Some(l.sigma(k) / (h * h))),
            ]
        };
        if s.is_named(Kind::BiasDrift) {
            let Some((line, ext)) = beyond_line(d, &s.drift.model) else {
                return Vec::new();
            };
            let beyond = s.drift.nested(
                Kind::BiasDrift,
                ext.cols,
                |l, k| curve(l, line, k),
                "curves with time over the run (beyond the line)".into(),
            );
            return beyond.into_iter().map(|p| s.wander_judged(p, Law::Drawn)).collect();
        }
        let linear = s.drift.nested(
            Kind::BiasDrift,
            vec![tau.clone()],
            |l, k| vec![param("rate_dph_per_s", l.coef[k] / h, Some(l.sigma(k) / h))],
            "grows with time over the run".into(),
        );
        let curved = s.drift.nested(
            Kind::BiasDrift,
            vec![tau, tau2],
            |l, k| curve(l, k, k + 1),
            "curves with time over the run".into(),
        );
        linear
            .into_iter()
            .chain(curved)
            .map(|p| s.wander_judged(p, Law::Drawn))
            .collect()
    }

    fn extension(&self, d: &Data, m: &Model) -> Option<Extension> {
        beyond_line(d, m).map(|(_, ext)| ext)
    }
}

/// Where `m` has the line and not the curve: the line's column and the curve's.
fn beyond_line(d: &Data, m: &Model) -> Option<(usize, Extension)> {
    let tau2: Vec<f64> = d.tau.iter().map(|v| v * v).collect();
    let at = |c: &[f64]| m.cols.iter().position(|x| x.raw == c);
    match (at(&d.tau), at(&tau2)) {
        (Some(line), None) => Some((
            line,
            Extension {
                form: "curved",
                cols: vec![tau2],
            },
        )),
        _ => None,
    }
}
