//! `settling_transient`: the first quarter of each dwell after a move departs from the rest.
//! Tested by contrasts within each dwell, so the noise's slow part cancels: the first
//! quarter's offset from the other three (t test on its own scatter) and whether it scatters
//! more than the last quarter does from its three (a sign test: exact for any stationary
//! noise, whose time reversal swaps the two). A dwell at the angle of the one before had no
//! move to settle from: it is left out of the test and of the correction.

use super::effect::{Change, Draws, Effect, Proposal, State, param};
use super::kind::Kind;
use crate::stats::{beta_inc, t_sf2};

pub struct SettlingTransient;

impl Effect for SettlingTransient {
    fn kind(&self) -> Kind {
        Kind::SettlingTransient
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        let Some(all) = &s.data.quarters else { return Vec::new() };
        let moved = s.data.moved();
        let q: Vec<[f64; 4]> = all.iter().zip(&moved).filter(|m| *m.1).map(|m| *m.0).collect();
        let n = q.len();
        if s.is_named(Kind::SettlingTransient) || n < 4 {
            return Vec::new();
        }
        let first: Vec<f64> = q.iter().map(|q| q[0] - (q[1] + q[2] + q[3]) / 3.0).collect();
        let last: Vec<f64> = q.iter().map(|q| q[3] - (q[0] + q[1] + q[2]) / 3.0).collect();
        let mean = first.iter().sum::<f64>() / n as f64;
        let var = first.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let se = (var / n as f64).sqrt();
        let p_mean = if se > 0.0 {
            t_sf2(mean / se, (n - 1) as f64)
        } else {
            1.0
        };
        let wider = first.iter().zip(&last).filter(|(f, l)| f.abs() > l.abs()).count();
        let p_scatter = sign_test(wider, n);
        // The dwell means after a move without their first quarter, with the model's
        // corrections kept.
        let y: Vec<f64> = (0..all.len())
            .map(|i| {
                let q = &all[i];
                let rest = if moved[i] {
                    (q[1] + q[2] + q[3]) / 3.0
                } else {
                    s.data.rate[i]
                };
                s.main.model.y[i] - s.data.rate[i] + rest
            })
            .collect();
        let rms = (first.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
        vec![Proposal {
            kind: Kind::SettlingTransient,
            p: (2.0 * p_mean.min(p_scatter)).min(1.0),
            change: Change::Response(y),
            parameters: vec![
                param("first_quarter_offset_dph", mean, Some(se)),
                param("first_quarter_rms_dph", rms, None),
                param("dwells_first_quarter_wider", wider as f64, None),
            ],
            location: "the first quarter of each dwell".into(),
            scanned: 0,
            own_p: None,
            draws: Draws::No,
        }]
    }
}

/// `P(X >= k)` for `X ~ Binomial(n, 1/2)`.
fn sign_test(k: usize, n: usize) -> f64 {
    if k == 0 {
        1.0
    } else {
        beta_inc(k as f64, (n - k + 1) as f64, 0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::sign_test;

    #[test]
    fn sign_test_is_the_binomial_tail() {
        // P(X >= 8 | n = 10) = (45 + 10 + 1) / 1024.
        assert!((sign_test(8, 10) - 56.0 / 1024.0).abs() < 1e-12);
        assert_eq!(sign_test(0, 10), 1.0);
        assert!((sign_test(10, 10) - 1.0 / 1024.0).abs() < 1e-12);
    }
}
