//! The draws of the null behind [`super::Null::p_drawn`]: rates from the null's fit plus noise
//! of its best model, each extra's likelihood ratio read as each side's best over the
//! starts, tallied against the recording's.

use super::Start;
use super::larger::Larger;
use crate::gls::Cov;
use nf_model::rng::Rng;

/// Draws of the null that reach the recording's likelihood ratio before the drawn p-value
/// stops: it is then near 10 / draws, too large to matter.
pub(super) const EXCEEDED: usize = 10;

/// Draws of the null made side by side: each factor's generators, too large for the cache
/// over 20-30 starts, are then read once for all of them.
const BLOCK: usize = 16;

/// The first block of draws, smaller: where the recording's ratio is well within the null's
/// law, a few draws reach it and end the drawing.
const FIRST_BLOCK: usize = 8;

/// How far below the recording's best log-likelihood a start is still read under in the
/// draws ([`needed`]).
const NEAR: f64 = 20.0;

/// The log-likelihoods of `W` rate vectors under one start, the null's and the larger
/// design's; `None` where one failed.
type AtStart<const W: usize> = [Option<(f64, f64)>; W];

/// Below this many rows times starts read, the starts are taken on one core: the threads
/// would cost more than they save.
const ON_CORES: usize = 4000;

/// Each extra's log-likelihoods under the null and the larger design (`bases[e]`, per start)
/// for `W` vectors of `rows` rates whitened under start `i` by `white(i)`, at the starts it `uses`
/// (elsewhere `None`, as where a likelihood failed). Each start's whitening serves every
/// extra; the starts are spread over the cores.
fn logliks<const W: usize>(
    starts: &[Start],
    bases: &[Vec<Larger>],
    rows: usize,
    white: impl Fn(usize) -> Vec<[f64; W]> + Sync,
    uses: &[Vec<bool>],
) -> Vec<Vec<AtStart<W>>> {
    let used: Vec<usize> = (0..starts.len()).filter(|&i| uses.iter().any(|u| u[i])).collect();
    let at_start = |k: usize| {
        let (i, start) = (used[k], &starts[used[k]]);
        let w = white(i);
        let per_extra: Vec<(usize, AtStart<W>)> = (0..bases.len())
            .filter(|&e| uses[e][i])
            .map(|e| {
                let rss = bases[e][i].rss_block(&start.cov, &w);
                (
                    e,
                    rss.map(|(small, large)| start.loglik(small).zip(start.loglik(large))),
                )
            })
            .collect();
        (i, per_extra)
    };
    let each = if rows * used.len() >= ON_CORES {
        crate::cores::each(used.len(), at_start)
    } else {
        (0..used.len()).map(at_start).collect()
    };
    let mut out = vec![vec![[None; W]; starts.len()]; bases.len()];
    for (i, per_extra) in each {
        for (e, at) in per_extra {
            out[e][i] = at;
        }
    }
    out
}

/// Twice the log-likelihood gained, each side at its best of the starts `used`; `None`
/// where a likelihood failed at one of them.
fn ratio<const W: usize>(at: &[AtStart<W>], used: &[bool]) -> [Option<f64>; W] {
    core::array::from_fn(|b| {
        let mut best = Some((f64::MIN, f64::MIN));
        for (l, _) in at.iter().zip(used).filter(|(_, u)| **u) {
            best = best
                .zip(l[b])
                .map(|((small, large), (l0, l1))| (small.max(l0), large.max(l1)));
        }
        best.map(|(small, large)| (2.0 * (large - small)).max(0.0))
    })
}

/// The starts an extra's draws are read under, from its log-likelihoods on the recording:
/// those within `NEAR` of the best on either side. Draws of the null's best model peak
/// where the recording does; a start the recording puts e^20 below the best would have to
/// gain that on a draw.
fn needed(at: &[AtStart<1>]) -> Vec<bool> {
    let best = at
        .iter()
        .filter_map(|[l]| *l)
        .fold((f64::MIN, f64::MIN), |(s, g), (l0, l1)| (s.max(l0), g.max(l1)));
    // A failed likelihood is kept: it ends the draws as before.
    at.iter()
        .map(|[l]| l.is_none_or(|(l0, l1)| l0 >= best.0 - NEAR || l1 >= best.1 - NEAR))
        .collect()
}

/// The draws of the null for [`super::Null::p_drawn`]: its fitted rates, plus its best noise
/// model's colouring of unit normals times `sd`.
pub(super) struct Draws<'a> {
    pub starts: &'a [Start],
    /// Each extra's larger design, per start.
    pub bases: &'a [Vec<Larger<'a>>],
    pub mean: &'a [f64],
    pub sd: f64,
    pub cov: &'a Cov,
}

impl Draws<'_> {
    /// Each extra's p-value: the share of draws whose likelihood ratio reaches the
    /// recording's (`recorded(i)`: its rates whitened under start `i`), each stopped once
    /// `EXCEEDED` have reached it, once it can no longer fall under `limit`, or at `most`.
    pub(super) fn p_values(
        &self,
        recorded: impl Fn(usize) -> Vec<[f64; 1]> + Sync,
        seed: u64,
        most: usize,
        limit: f64,
    ) -> Vec<Option<f64>> {
        let every = vec![vec![true; self.starts.len()]; self.bases.len()];
        let on_recording = logliks(self.starts, self.bases, self.mean.len(), recorded, &every);
        let needed: Vec<Vec<bool>> = on_recording.iter().map(|at| needed(at)).collect();
        let mut tallies: Vec<Tally> = on_recording
            .iter()
            .zip(&every)
            .map(|(at, used)| Tally::new(ratio(at, used)[0], most, limit))
            .collect();
        let mut rng = Rng::new(seed);
        if tallies.iter().any(Tally::drawing) {
            self.block::<FIRST_BLOCK>(&mut rng, &needed, &mut tallies);
        }
        while tallies.iter().any(Tally::drawing) {
            self.block::<BLOCK>(&mut rng, &needed, &mut tallies);
        }
        tallies.iter().map(Tally::p).collect()
    }

    /// `W` draws side by side, taken by the tallies still drawing, each read under the
    /// starts its extra needs. Each draw reads its own run of `rng`, so the tallies see the
    /// same draws whatever the block.
    fn block<const W: usize>(&self, rng: &mut Rng, needed: &[Vec<bool>], tallies: &mut [Tally]) {
        let mut z = vec![[0.0; W]; self.mean.len()];
        for b in 0..W {
            z.iter_mut().for_each(|row| row[b] = rng.gauss());
        }
        let noise = self.cov.colour_block(&z);
        let y: Vec<[f64; W]> = self
            .mean
            .iter()
            .zip(&noise)
            .map(|(m, e)| e.map(|e| m + self.sd * e))
            .collect();
        let uses: Vec<Vec<bool>> = tallies
            .iter()
            .zip(needed)
            .map(|(t, n)| n.iter().map(|&u| u && t.drawing()).collect())
            .collect();
        let at = logliks(
            self.starts,
            self.bases,
            self.mean.len(),
            |i| self.starts[i].cov.whiten_block(&y),
            &uses,
        );
        for ((t, at), u) in tallies.iter_mut().zip(&at).zip(&uses) {
            ratio(at, u).into_iter().for_each(|l| t.take(l));
        }
    }
}

/// One extra's draws so far: how many reached the recording's ratio, and why they stopped.
struct Tally {
    /// The recording's ratio; `None` where a likelihood failed, which ends the draws.
    observed: Option<f64>,
    drawn: usize,
    reached: usize,
    most: usize,
    limit: f64,
}

impl Tally {
    fn new(observed: Option<f64>, most: usize, limit: f64) -> Tally {
        Tally {
            observed,
            drawn: 0,
            reached: 0,
            most,
            limit,
        }
    }

    /// Until `EXCEEDED` have reached the ratio, the p-value can no longer fall under the
    /// limit, or at `most`.
    fn drawing(&self) -> bool {
        self.observed.is_some()
            && self.drawn < self.most
            && self.reached < EXCEEDED
            && ((1 + self.reached) as f64) < self.limit * (1 + self.most) as f64
    }

    /// The next draw's ratio, taken while drawing.
    fn take(&mut self, ratio: Option<f64>) {
        if !self.drawing() {
            return;
        }
        match (ratio, self.observed) {
            (Some(l), Some(o)) => {
                self.drawn += 1;
                self.reached += usize::from(l >= o);
            }
            _ => self.observed = None,
        }
    }

    fn p(&self) -> Option<f64> {
        self.observed
            .map(|_| (1 + self.reached) as f64 / (1 + self.drawn) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_draw_is_read_under_the_starts_near_the_recordings_best_on_either_side() {
        let at = [
            [Some((100.0, 110.0))],
            [Some((85.0, 70.0))],
            [Some((60.0, 95.0))],
            [Some((60.0, 70.0))],
            [None],
            [Some((79.9, 89.9))],
        ];
        assert_eq!(needed(&at), [true, true, true, false, true, false]);
    }

    #[test]
    fn the_ratio_is_each_sides_best_over_the_starts_used() {
        let at = [[Some((100.0, 104.0))], [Some((101.0, 103.0))], [Some((90.0, 120.0))]];
        assert_eq!(ratio(&at, &[true, true, false]), [Some(6.0)]);
        assert_eq!(ratio(&at, &[true, true, true]), [Some(38.0)]);
        assert_eq!(ratio(&at, &[false, false, false]), [Some(0.0)]);
        let failed = [[Some((100.0, 104.0))], [None]];
        assert_eq!(ratio(&failed, &[true, false]), [Some(8.0)]);
        assert_eq!(ratio(&failed, &[true, true]), [None]);
    }
}
