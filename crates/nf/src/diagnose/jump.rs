//! `bias_jump`: a step of the bias between two positions, scanned over the time order. The
//! scan's best step is judged also by the wander test (a random walk is a sum of steps), and
//! its p-value corrected for the n - 4 change points it chose from.

use super::effect::{Change, Effect, Law, Proposal, State, f_test, param};
use super::kind::Kind;
use super::scan::{Shape, scan};

pub struct BiasJump;

impl Effect for BiasJump {
    fn kind(&self) -> Kind {
        Kind::BiasJump
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        let d = s.data;
        let n = d.n();
        if s.is_named(Kind::BiasJump) || n < 10 {
            return Vec::new();
        }
        let step = |j: usize| -> Vec<f64> { (0..n).map(|i| if i >= j { 1.0 } else { 0.0 }).collect() };
        let fits = scan(s.drift, Shape::Step);
        let best = (2..n - 2)
            .filter_map(|j| {
                let big = fits[j]?;
                Some((f_test(s.drift.fit.rss, big.rss, 1, big.dof), j, big))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((p, j, big)) = best else { return Vec::new() };
        let row = &d.rec.rows[j];
        vec![s.wander_judged(
            Proposal {
                kind: Kind::BiasJump,
                p: (p * (n - 4) as f64).min(1.0),
                change: Change::Columns(vec![step(j)]),
                parameters: vec![
                    param("size_dph", big.coef, Some(big.sigma())),
                    param("time_s", (d.t[j - 1] + d.t[j]) / 2.0, None),
                    param("first_index_after", row.index as f64, None),
                ],
                location: format!(
                    "between t = {:.1} s and {:.1} s (before position {})",
                    d.t[j - 1],
                    d.t[j],
                    row.index
                ),
                scanned: 1,
                own_p: None,
            },
            Law::F { scan: n - 4 },
        )]
    }
}
