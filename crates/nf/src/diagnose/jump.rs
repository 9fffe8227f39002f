//! `bias_jump`: a step of the bias between two positions, scanned over the time order. The
//! scan's best step is judged also by the wander test (a random walk is a sum of steps): by
//! the F law, corrected for the change points it chose from, and where the null draws,
//! also against the best step's ratio in its draws. A jump falls inside a
//! dwell as often as not: that dwell's mean then holds part of it, and under a coloured
//! whitening, which weighs the neighbouring dwells most, a step at a boundary sizes it short
//! (0.83-0.89 of it in twin runs). So the chosen step is then let fall inside either
//! neighbouring dwell, at a quarter, a half or three quarters of it.

use super::effect::{Change, Draws, Effect, Law, Proposal, State, f_test, param};
use super::kind::Kind;
use super::scan::{Shape, scan};
use crate::wander_test::ChangePoints;

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
        let fits = scan(s.drift, Shape::Step);
        let tried = ChangePoints::inner(n);
        let best = tried
            .range()
            .filter_map(|j| {
                let big = fits[j]?;
                Some((f_test(s.drift.fit.rss, big.rss, 1, big.dof), j, big))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((p, j, big)) = best else { return Vec::new() };
        let at = within(s, j).unwrap_or(Within {
            col: step_column(n, j, 1.0),
            size: (big.coef, big.sigma()),
            dwell: None,
        });
        let row = &d.rec.rows[j];
        let (time_s, location) = match at.dwell {
            None => (
                (d.t[j - 1] + d.t[j]) / 2.0,
                format!(
                    "between t = {:.1} s and {:.1} s (before position {})",
                    d.t[j - 1],
                    d.t[j],
                    row.index
                ),
            ),
            Some((k, after)) => {
                let dwell_s = crate::dwells::of(&d.rec).each_s[k];
                (
                    d.t[k] + dwell_s * (0.5 - after),
                    format!(
                        "within the dwell at t = {:.1} s (position {}), its last {:.0} % after the step",
                        d.t[k],
                        d.rec.rows[k].index,
                        100.0 * after
                    ),
                )
            }
        };
        vec![s.wander_judged(
            Proposal {
                kind: Kind::BiasJump,
                p: (p * tried.count() as f64).min(1.0),
                change: Change::Columns(vec![at.col]),
                parameters: vec![
                    param("size_dph", at.size.0, Some(at.size.1)),
                    param("time_s", time_s, None),
                    param("first_index_after", row.index as f64, None),
                ],
                location,
                scanned: 1,
                own_p: None,
                draws: Draws::No,
            },
            Law::DrawnStep { tried },
        )]
    }
}

/// The step placed best: its column, its size and sigma (deg/h), and the dwell it falls
/// inside with the share of it after the step (`None`: between dwells).
struct Within {
    col: Vec<f64>,
    size: (f64, f64),
    dwell: Option<(usize, f64)>,
}

/// The step at boundary `j`, or inside dwell `j - 1` or `j`, whichever fits best.
fn within(s: &State, j: usize) -> Option<Within> {
    let n = s.data.n();
    let frame = s.drift;
    let candidates = std::iter::once((j, 1.0, None)).chain(
        [j - 1, j]
            .into_iter()
            .flat_map(|k| [0.25, 0.5, 0.75].map(|after| (k, after, Some((k, after))))),
    );
    candidates
        .filter_map(|(k, after, dwell)| {
            let col = step_column(n, k, after);
            let ls = frame.model.fit_plus(&[frame.whitener.apply(&col)])?;
            let last = ls.coef.len() - 1;
            let size = (ls.coef[last], ls.sigma(last));
            Some((ls.rss, Within { col, size, dwell }))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, w)| w)
}

/// A step of 1 over `n` positions: 0 before position `k`, 1 after it, and `after` (the share
/// of its dwell after the step) at it.
fn step_column(n: usize, k: usize, after: f64) -> Vec<f64> {
    (0..n)
        .map(|i| match i.cmp(&k) {
            std::cmp::Ordering::Less => 0.0,
            std::cmp::Ordering::Equal => after,
            std::cmp::Ordering::Greater => 1.0,
        })
        .collect()
}
