//! The likelihood-ratio test of columns that a wandering bias can mimic (a drift, a jump, a
//! temperature cycle), with the noise's flicker and random walk estimated under each
//! hypothesis. A test under one plugged-in noise model leans one way: estimated with the
//! columns in the design, the walk is small and its wander is taken for the effect;
//! estimated without them, the walk takes a real effect for wander. Profiled under both,
//! the ratio is calibrated on white noise and finds a drift more often than the plug-in
//! test, but over one run of a few dozen dwells a random walk still passes for a drift
//! (the walk's slowest mode is one number), so `nf diagnose` asks both tests, and reads the
//! ratio of a drift or a temperature against draws from the null rather than the F law.
//!
//! The likelihood is restricted for the constant only: flicker and walk covariances are
//! defined up to a constant (`crate::gls`), which the constant's contrasts do not see, and
//! every design holds the constant, so the likelihoods of two designs compare.

use crate::gls::{Cov, WindowSet};
use crate::linfit;
use crate::quarter_contrasts::{Part, QuarterContrasts};
use crate::sample_spread::{SampleSpread, Spread};
use crate::stats::f_sf;
use nf_model::noise::NoiseModel;
use std::cell::OnceCell;

/// Draws of the null that reach the recording's likelihood ratio before the drawn p-value
/// stops: it is then near 10 / draws, too large to matter.
const EXCEEDED: usize = 10;

/// Draws of the null made side by side: each factor's generators, too large for the cache
/// over 20-30 starts, are then read once for all of them.
const BLOCK: usize = 16;

/// Halvings of the search step around the best model, from a quarter decade of B^2 and K^2.
const REFINE: usize = 4;

pub struct WanderTest {
    windows: WindowSet,
    quarters: QuarterContrasts,
    spread: SampleSpread,
    starts: Vec<Start>,
    /// Whether a ratio may be read against draws of the null ([`Null::p_drawn`]).
    draws: bool,
}

/// A noise model of white density 1, factored.
#[derive(Clone)]
struct Start {
    model: NoiseModel,
    cov: Cov,
    /// `-2 ln L` less the dwell means' whitened RSS: the covariances' log-determinants (the
    /// constant's contrast taken out) and the share of the quarters or the samples' spread.
    fixed: Part,
}

impl Start {
    fn loglik(&self, rss: f64) -> Option<f64> {
        let fit = Part {
            log_det: 0.0,
            quad: rss,
            count: 0,
        };
        self.fixed.plus(fit).profiled().map(|(l, _)| l)
    }
}

impl WanderTest {
    /// `models`: flicker-and-walk models the recording allows (any white level), the starts of
    /// each search beside white noise. `None` when none of them is usable.
    pub fn new(
        t_s: &[f64],
        dwell_s: f64,
        quarters: &[[f64; 4]],
        spread: &[Spread],
        models: &[NoiseModel],
    ) -> Option<WanderTest> {
        let mut test = WanderTest {
            windows: WindowSet::new(t_s, &vec![dwell_s; t_s.len()]),
            quarters: QuarterContrasts::new(quarters, dwell_s),
            spread: SampleSpread::new(spread, dwell_s),
            starts: Vec::new(),
            draws: false,
        };
        let white = NoiseModel {
            arw_deg_rth: 1.0 / 60.0,
            ..NoiseModel::WHITE_NONE
        };
        let span_s = t_s.iter().fold(f64::MIN, |a, &b| a.max(b)) - t_s.iter().fold(f64::MAX, |a, &b| a.min(b));
        let grid = coarse_grid(dwell_s, span_s.max(dwell_s));
        for m in std::iter::once(&white)
            .chain(&grid)
            .chain(models)
            .filter(|m| m.gm_sigma_dph == 0.0 && m.arw_deg_rth > 0.0)
        {
            let u = unit(m);
            if !test.starts.iter().any(|s| same(&s.model, &u))
                && let Some(s) = test.start(u)
            {
                test.starts.push(s);
            }
        }
        (!test.starts.is_empty()).then_some(test)
    }

    /// The test with its ratios read against draws of the null, where the noise is
    /// estimated from this run alone. A model given from a static log bounds the wander;
    /// the draws would take the null's from this run (a drift on white noise told white
    /// was named in 1 of 20 runs instead of 12 or more).
    pub fn drawing(self) -> WanderTest {
        WanderTest { draws: true, ..self }
    }

    fn start(&self, model: NoiseModel) -> Option<Start> {
        let n = self.windows.count();
        let cov = self.windows.cov(&model)?;
        let ln_ones = norm2(&cov.whiten(&vec![1.0; n])).ln();
        let dwells = Part {
            log_det: cov.log_det() + ln_ones,
            quad: 0.0,
            count: n - 1,
        };
        let fixed = dwells.plus(self.quarters.part(&model)?).plus(self.spread.part(&model)?);
        Some(Start { model, cov, fixed })
    }

    /// The null hypothesis `y ~ cols` (`cols` holding the constant) at its best noise model,
    /// against which effects are then tested. Every start keeps its whitened design.
    pub fn null<'a>(&'a self, cols: &[Vec<f64>], y: &[f64]) -> Option<Null<'a>> {
        let whitened: Vec<Whitened> = self
            .starts
            .iter()
            .map(|s| Whitened {
                cols: cols.iter().map(|c| s.cov.whiten(c)).collect(),
                y: s.cov.whiten(y),
            })
            .collect();
        let at = |i: usize, extra: &[Vec<f64>]| whitened[i].loglik(&self.starts[i], extra);
        let (first, _) = (0..self.starts.len())
            .filter_map(|i| Some((i, at(i, &[])?)))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        let (best, loglik) = self.refine(self.starts[first].clone(), cols, y, &[])?;
        Some(Null {
            test: self,
            cols: cols.to_vec(),
            y: y.to_vec(),
            whitened,
            best,
            loglik,
        })
    }

    /// The observations the likelihood sees: the dwell means' contrasts and the quarters' or
    /// the spread's.
    fn count(&self) -> usize {
        self.windows.count() - 1 + self.quarters.count() + self.spread.count()
    }

    /// The log-likelihood of `y ~ cols + extra` under `s`.
    fn loglik(&self, s: &Start, cols: &[Vec<f64>], y: &[f64], extra: &[Vec<f64>]) -> Option<f64> {
        let white: Vec<Vec<f64>> = cols.iter().chain(extra).map(|c| s.cov.whiten(c)).collect();
        s.loglik(linfit::fit(&white, &s.cov.whiten(y))?.rss)
    }

    /// The model near `from` (in halving steps of B^2 and K^2) most likely for
    /// `y ~ cols + extra`, and its log-likelihood.
    fn refine(&self, from: Start, cols: &[Vec<f64>], y: &[f64], extra: &[Vec<f64>]) -> Option<(Start, f64)> {
        let loglik = |s: &Start| self.loglik(s, cols, y, extra);
        let mut top = loglik(&from)?;
        let mut at = from;
        let mut step = 10f64.powf(0.25);
        for _ in 0..REFINE {
            for (fb, fk) in [(step, 1.0), (1.0 / step, 1.0), (1.0, step), (1.0, 1.0 / step)] {
                let moved = NoiseModel {
                    bias_instability_dph: at.model.bias_instability_dph * fb.sqrt(),
                    rrw_dph_rth: at.model.rrw_dph_rth * fk.sqrt(),
                    ..at.model
                };
                if same(&moved, &at.model) {
                    continue;
                }
                let Some(s) = self.start(moved) else { continue };
                if let Some(l) = loglik(&s)
                    && l > top
                {
                    (at, top) = (s, l);
                }
            }
            step = step.sqrt();
        }
        Some((at, top))
    }
}

/// An orthonormal basis of whitened columns.
#[derive(Default)]
struct Basis(Vec<Vec<f64>>);

impl Basis {
    /// `cols` added by Gram-Schmidt, twice over for its accuracy; a column dependent on the
    /// others adds nothing.
    fn extend(&mut self, cols: &[Vec<f64>]) {
        for c in cols {
            let mut v = c.clone();
            for _ in 0..2 {
                for b in &self.0 {
                    let d: f64 = b.iter().zip(&v).map(|(x, y)| x * y).sum();
                    v.iter_mut().zip(b).for_each(|(x, y)| *x -= d * y);
                }
            }
            let norm = norm2(&v).sqrt();
            if norm > 1e-9 * norm2(c).sqrt() {
                self.0.push(v.iter().map(|x| x / norm).collect());
            }
        }
    }
}

/// The null's whitened design and the effect's columns beyond it, for the RSS of many
/// rates under both: one basis, the null's span its first `small` vectors.
struct Nested {
    basis: Basis,
    small: usize,
}

impl Nested {
    fn of(null: &[Vec<f64>], extra: &[Vec<f64>]) -> Nested {
        let mut basis = Basis::default();
        basis.extend(null);
        let small = basis.0.len();
        basis.extend(extra);
        Nested { basis, small }
    }

    /// The RSS of `W` rate vectors side by side (row `i` their `i`th values), under the
    /// null and under the larger design.
    fn rss_block<const W: usize>(&self, y: &[[f64; W]]) -> [(f64, f64); W] {
        let mut norm = [-0.0; W];
        for row in y {
            for b in 0..W {
                norm[b] += row[b] * row[b];
            }
        }
        let (mut along, mut small) = ([-0.0; W], [-0.0; W]);
        for (k, q) in self.basis.0.iter().enumerate() {
            if k == self.small {
                small = along;
            }
            let mut dot = [-0.0; W];
            for (x, row) in q.iter().zip(y) {
                for b in 0..W {
                    dot[b] += x * row[b];
                }
            }
            for b in 0..W {
                along[b] += dot[b].powi(2);
            }
        }
        if self.small == self.basis.0.len() {
            small = along;
        }
        core::array::from_fn(|b| ((norm[b] - small[b]).max(0.0), (norm[b] - along[b]).max(0.0)))
    }
}

/// Twice the log-likelihood gained by each extra (`bases[e]`, per start) for `W` rate
/// vectors whitened under start `i` by `white(i)`, each side at its best start; extras not
/// `live` are skipped. Each start's whitening serves every extra.
fn ratios<const W: usize>(
    starts: &[Start],
    bases: &[Vec<Nested>],
    white: impl Fn(usize) -> Vec<[f64; W]>,
    live: &[bool],
) -> Vec<[Option<f64>; W]> {
    let mut best = vec![[Some((f64::MIN, f64::MIN)); W]; bases.len()];
    for (i, start) in starts.iter().enumerate() {
        let w = white(i);
        for (e, best) in best.iter_mut().enumerate().filter(|(e, _)| live[*e]) {
            for (b, rss) in bases[e][i].rss_block(&w).into_iter().enumerate() {
                best[b] = best[b]
                    .zip(start.loglik(rss.0))
                    .zip(start.loglik(rss.1))
                    .map(|(((small, large), l0), l1)| (small.max(l0), large.max(l1)));
            }
        }
    }
    best.into_iter()
        .map(|b| b.map(|b| b.map(|(small, large)| (2.0 * (large - small)).max(0.0))))
        .collect()
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

/// A start's whitening of the null's design and rates.
struct Whitened {
    cols: Vec<Vec<f64>>,
    y: Vec<f64>,
}

impl Whitened {
    /// The log-likelihood under `s` (whose whitening this is) with `extra`, already
    /// whitened, added to the columns.
    fn loglik(&self, s: &Start, extra: &[Vec<f64>]) -> Option<f64> {
        let mut cols = self.cols.clone();
        cols.extend(extra.iter().cloned());
        s.loglik(linfit::fit(&cols, &self.y)?.rss)
    }
}

/// A null hypothesis fitted when it is first asked for: most selection steps find no effect
/// below their level, and then nothing asks.
pub struct LazyNull<'a> {
    test: Option<&'a WanderTest>,
    cols: Vec<Vec<f64>>,
    y: Vec<f64>,
    null: OnceCell<Option<Null<'a>>>,
}

impl<'a> LazyNull<'a> {
    /// `y ~ cols` under `test`; never fitted without one.
    pub fn new(test: Option<&'a WanderTest>, cols: Vec<Vec<f64>>, y: Vec<f64>) -> Self {
        LazyNull {
            test,
            cols,
            y,
            null: OnceCell::new(),
        }
    }

    pub fn get(&self) -> Option<&Null<'a>> {
        self.null.get_or_init(|| self.test?.null(&self.cols, &self.y)).as_ref()
    }
}

/// A fitted null hypothesis of the wander test.
pub struct Null<'a> {
    test: &'a WanderTest,
    cols: Vec<Vec<f64>>,
    y: Vec<f64>,
    whitened: Vec<Whitened>,
    /// Its best noise model, where the search under the alternative also starts: the larger
    /// design is then at least as likely.
    best: Start,
    loglik: f64,
}

impl Null<'_> {
    /// The p-value of `extra` added to the null's columns: the likelihood ratio, each side at
    /// its best noise model, read as an F statistic of the dwell means' and quarter
    /// contrasts' degrees of freedom.
    pub fn p_value(&self, extra: &[Vec<f64>]) -> Option<f64> {
        let lr = self.lr(extra)?;
        self.f_p(lr, extra.len())
    }

    /// The likelihood ratio read as an F statistic of the dwell means' and quarter
    /// contrasts' degrees of freedom.
    fn f_p(&self, lr: f64, q: usize) -> Option<f64> {
        let count = self.test.count();
        let dof = count as f64 - (self.cols.len() + q - 1) as f64;
        if dof <= 0.0 {
            return None;
        }
        let f = ((lr / count as f64).exp() - 1.0) * dof / q as f64;
        Some(f_sf(f, q as f64, dof))
    }

    /// The p-value of `extra` from rates drawn from the null's fit and noise model (the
    /// quarters or spread kept): the share of draws whose likelihood ratio reaches the recording's. A
    /// walk's slow wander is one number in one run, so the ratio's law under it is far from
    /// the F law: under a walk of about a dwell mean's noise per dwell, a curve's F p-value
    /// was below 0.01 in 19 of 60 runs of 36 dwells, the drawn one in 1. The ratio here is
    /// each side's best over the starts (not refined), the recording's as the draws'; each
    /// start's designs are factored once. One p-value per extra, all from the same draws,
    /// each stopped once `EXCEEDED` have reached it, once the p-value can no longer fall
    /// under `limit`, or at `most`. `None` where the test does not draw.
    pub fn p_drawn(&self, extras: &[&[Vec<f64>]], most: usize, limit: f64) -> Vec<Option<f64>> {
        let none = vec![None; extras.len()];
        if !self.test.draws {
            return none;
        }
        let starts = &self.test.starts;
        // Per extra, per start.
        let bases: Vec<Vec<Nested>> = extras
            .iter()
            .map(|extra| {
                starts
                    .iter()
                    .zip(&self.whitened)
                    .map(|(s, w)| {
                        let extra: Vec<Vec<f64>> = extra.iter().map(|c| s.cov.whiten(c)).collect();
                        Nested::of(&w.cols, &extra)
                    })
                    .collect()
            })
            .collect();
        let observed: Vec<[Option<f64>; 1]> = ratios(
            starts,
            &bases,
            |i| self.whitened[i].y.iter().map(|&v| [v]).collect(),
            &vec![true; extras.len()],
        );
        let Some((mean, level)) = self.fitted() else {
            return none;
        };
        let mut tallies: Vec<Tally> = observed.iter().map(|[o]| Tally::new(*o, most, limit)).collect();
        let seed = self
            .y
            .iter()
            .fold(self.y.len() as u64, |h, v| h.rotate_left(7) ^ v.to_bits());
        let mut rng = nf_model::rng::Rng::new(seed);
        while tallies.iter().any(Tally::drawing) {
            let mut z = vec![[0.0; BLOCK]; mean.len()];
            for b in 0..BLOCK {
                z.iter_mut().for_each(|row| row[b] = rng.gauss());
            }
            let noise = self.best.cov.colour_block(&z);
            let y: Vec<[f64; BLOCK]> = mean
                .iter()
                .zip(&noise)
                .map(|(m, e)| e.map(|e| m + level.sqrt() * e))
                .collect();
            let live: Vec<bool> = tallies.iter().map(Tally::drawing).collect();
            let drawn: Vec<[Option<f64>; BLOCK]> = ratios(starts, &bases, |i| starts[i].cov.whiten_block(&y), &live);
            for (t, r) in tallies.iter_mut().zip(drawn) {
                r.into_iter().for_each(|l| t.take(l));
            }
        }
        tallies.iter().map(Tally::p).collect()
    }

    /// The null's fitted rates and white level, which every draw adds noise of its best
    /// model to.
    fn fitted(&self) -> Option<(Vec<f64>, f64)> {
        let s = &self.best;
        let white: Vec<Vec<f64>> = self.cols.iter().map(|c| s.cov.whiten(c)).collect();
        let fit = linfit::fit(&white, &s.cov.whiten(&self.y))?;
        let (_, level) = s
            .fixed
            .plus(Part {
                log_det: 0.0,
                quad: fit.rss,
                count: 0,
            })
            .profiled()?;
        let mean = (0..self.y.len())
            .map(|i| self.cols.iter().zip(&fit.coef).map(|(c, b)| c[i] * b).sum())
            .collect();
        Some((mean, level))
    }

    /// Twice the log-likelihood gained by `extra`, each side at its best noise model.
    fn lr(&self, extra: &[Vec<f64>]) -> Option<f64> {
        let t = self.test;
        let best_start = (0..t.starts.len())
            .filter_map(|i| {
                let s = &t.starts[i];
                let white: Vec<Vec<f64>> = extra.iter().map(|c| s.cov.whiten(c)).collect();
                Some((&t.starts[i], self.whitened[i].loglik(s, &white)?))
            })
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let at_null = t.loglik(&self.best, &self.cols, &self.y, extra);
        let from = match (best_start, at_null) {
            (Some((s, l)), Some(n)) if l > n => s,
            (Some((s, _)), None) => s,
            _ => &self.best,
        };
        let (_, large) = t.refine(from.clone(), &self.cols, &self.y, extra)?;
        Some((2.0 * (large - self.loglik)).max(0.0))
    }
}

/// Flicker and walk of white density 1 on whole decades of their ratios to it (as
/// `noise_est` searches first), each zero or 1e-4 to 1e4 units: flicker against a dwell's
/// white variance, the walk over the run against it. The null's maximum can lie far from the
/// noise estimates', whose designs hold columns (temperature, harmonics, a drift) that take
/// up the slow wander.
fn coarse_grid(dwell_s: f64, span_s: f64) -> Vec<NoiseModel> {
    let model = |rb: f64, rk: f64| NoiseModel {
        arw_deg_rth: 1.0 / 60.0,
        bias_instability_dph: (rb / dwell_s).sqrt(),
        rrw_dph_rth: 60.0 * (rk / (dwell_s * span_s)).sqrt(),
        ..NoiseModel::WHITE_NONE
    };
    (-4..=4)
        .map(|k| 10f64.powi(k))
        .flat_map(|r| [model(r, 0.0), model(0.0, r)])
        .collect()
}

/// `m` scaled to white density 1 ((deg/h)^2 s), as the likelihood profiles the level out.
fn unit(m: &NoiseModel) -> NoiseModel {
    let s = 1.0 / (60.0 * m.arw_deg_rth);
    NoiseModel {
        arw_deg_rth: 1.0 / 60.0,
        bias_instability_dph: m.bias_instability_dph * s,
        rrw_dph_rth: m.rrw_dph_rth * s,
        ..*m
    }
}

fn same(a: &NoiseModel, b: &NoiseModel) -> bool {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * x.abs().max(y.abs());
    close(a.bias_instability_dph, b.bias_instability_dph) && close(a.rrw_dph_rth, b.rrw_dph_rth)
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gls::window_covariance;
    use crate::sweep_run::{Sweep, SweepRun};
    use nf_model::rng::Rng;

    /// Dwell centres 1.35 s apart, 1 s dwells.
    fn times(n: usize) -> Vec<f64> {
        (0..n).map(|i| 0.5 + 1.35 * i as f64).collect()
    }

    fn walk(rrw: f64) -> NoiseModel {
        NoiseModel {
            arw_deg_rth: 1.0 / 60.0,
            rrw_dph_rth: rrw,
            ..NoiseModel::WHITE_NONE
        }
    }

    /// Orthonormal contrasts of n values, orthogonal to their mean (Helmert), as columns.
    fn contrasts(n: usize) -> Vec<Vec<f64>> {
        (1..n)
            .map(|k| {
                let s = ((k * (k + 1)) as f64).sqrt();
                (0..n)
                    .map(|i| match i.cmp(&k) {
                        std::cmp::Ordering::Less => 1.0 / s,
                        std::cmp::Ordering::Equal => -(k as f64) / s,
                        std::cmp::Ordering::Greater => 0.0,
                    })
                    .collect()
            })
            .collect()
    }

    /// The likelihood of the contrasts `K^T y` under `K^T V K`, V the exact dense covariance
    /// of the windows: what the test's restricted likelihood is, up to a constant.
    fn reference(m: &NoiseModel, t: &[f64], cols: &[Vec<f64>], y: &[f64]) -> f64 {
        let n = t.len();
        let v = window_covariance(m, t, &vec![1.0; n]);
        let k = contrasts(n);
        let q = n - 1;
        let mut sigma = vec![0.0; q * q];
        for a in 0..q {
            for b in 0..q {
                sigma[a * q + b] = (0..n)
                    .flat_map(|i| (0..n).map(move |j| (i, j)))
                    .map(|(i, j)| k[a][i] * v[i * n + j] * k[b][j])
                    .sum();
            }
        }
        let project = |x: &[f64]| -> Vec<f64> { k.iter().map(|c| c.iter().zip(x).map(|(a, b)| a * b).sum()).collect() };
        let cov = Cov::exact(&sigma, q).unwrap();
        let white: Vec<Vec<f64>> = cols.iter().skip(1).map(|c| cov.whiten(&project(c))).collect();
        let rss = linfit::fit(&white, &cov.whiten(&project(y))).unwrap().rss;
        let w = rss / q as f64;
        -0.5 * (q as f64 * w.ln() + cov.log_det() + q as f64)
    }

    #[test]
    fn the_restricted_likelihood_is_that_of_the_contrasts_whatever_constant_the_covariance_carries() {
        let n = 14;
        let t = times(n);
        let mut rng = Rng::new(7);
        let cols = vec![vec![1.0; n], t.iter().map(|v| (v / 5.0).cos()).collect()];
        let y: Vec<f64> = (0..n).map(|i| 0.3 * cols[1][i] + 0.01 * rng.gauss()).collect();
        let models = [walk(0.0), walk(0.5), walk(5.0)];
        let test = WanderTest::new(&t, 1.0, &[], &[], &models).unwrap();
        let ours: Vec<f64> = models
            .iter()
            .map(|m| test.loglik(&test.start(unit(m)).unwrap(), &cols, &y, &[]).unwrap())
            .collect();
        let theirs: Vec<f64> = models.iter().map(|m| reference(m, &t, &cols, &y)).collect();
        for i in 1..models.len() {
            let (a, b) = (ours[i] - ours[0], theirs[i] - theirs[0]);
            assert!((a - b).abs() < 1e-6 * (1.0 + b.abs()), "model {i}: {a} against {b}");
        }
    }

    /// A sequential run of dwells 1.35 s apart, its bias walking by `rrw` deg/h/sqrt(h) and
    /// drifting by `drift` deg/h per s.
    fn run(n: usize, rrw: f64, drift: f64, seed: u64) -> SweepRun {
        Sweep {
            n,
            t0_s: 0.5,
            spacing_s: 1.35,
            walk_dph: rrw * (1.35f64 / 3600.0).sqrt(),
            drift_dph_per_s: drift,
        }
        .run(seed)
    }

    fn p_of(n: usize, rrw: f64, drift: f64, seed: u64) -> f64 {
        let r = run(n, rrw, drift, seed);
        let test = WanderTest::new(&r.t, 1.0, &r.quarters, &[], &[]).unwrap();
        test.null(&r.cols, &r.y)
            .unwrap()
            .p_value(std::slice::from_ref(&r.t))
            .unwrap()
    }

    #[test]
    fn on_white_noise_its_p_values_are_uniform() {
        let p: Vec<f64> = (0..300).map(|s| p_of(48, 0.0, 0.0, s)).collect();
        let share = |a: f64| p.iter().filter(|&&v| v < a).count() as f64 / p.len() as f64;
        println!("below 0.05: {}, below 0.2: {}", share(0.05), share(0.2));
        assert!((0.02..=0.09).contains(&share(0.05)), "{}", share(0.05));
        assert!((0.13..=0.28).contains(&share(0.2)), "{}", share(0.2));
    }

    #[test]
    fn a_drift_on_white_noise_is_found() {
        // 0.0015 deg/h per s over 64 s: 0.095 deg/h, 9.5 times a dwell mean's white noise.
        let found = (0..40).filter(|&s| p_of(48, 0.0, 1.5e-3, s) < 1e-3).count();
        assert!(found >= 36, "{found} of 40");
    }

    #[test]
    fn drawn_from_the_null_a_walk_passes_for_a_curve_at_the_level_and_a_drift_is_still_found() {
        let curve = |r: &SweepRun| vec![r.t.clone(), r.t.iter().map(|v| v * v).collect()];
        let below = |n: usize, rrw: f64, drift: f64, level: f64| {
            let (mut f, mut drawn) = (0, 0);
            for seed in 0..60 {
                let r = run(n, rrw, drift, 500 + seed);
                let test = WanderTest::new(&r.t, 1.0, &r.quarters, &[], &[]).unwrap().drawing();
                let null = test.null(&r.cols, &r.y).unwrap();
                f += usize::from(null.p_value(&curve(&r)).unwrap() < level);
                drawn += usize::from(null.p_drawn(&[&curve(&r)], 400, level)[0].unwrap() < level);
            }
            println!("n {n} rrw {rrw} drift {drift}: below {level}: F {f}, drawn {drawn} of 60");
            (f, drawn)
        };
        // A walk of about a dwell mean's white noise per dwell.
        let (f, drawn) = below(36, 0.5, 0.0, 0.01);
        assert!(f >= 10 && drawn <= 3, "F {f}, drawn {drawn}");
        let (_, drawn) = below(72, 0.0, 1.5e-3, 0.01);
        assert!(drawn >= 50, "{drawn} of 60 drifts");
    }

    #[test]
    fn draws_stopped_at_the_level_decide_as_all_of_them_would() {
        let curve = |r: &SweepRun| vec![r.t.clone(), r.t.iter().map(|v| v * v).collect()];
        let mut decided = [0, 0];
        for seed in 0..12 {
            let r = run(36, 0.5, 4e-4 * (seed % 3) as f64, 700 + seed);
            let test = WanderTest::new(&r.t, 1.0, &r.quarters, &[], &[]).unwrap().drawing();
            let null = test.null(&r.cols, &r.y).unwrap();
            let all = null.p_drawn(&[&curve(&r)], 400, 1.0)[0].unwrap();
            for level in [0.004, 0.01, 0.05] {
                let stopped = null.p_drawn(&[&curve(&r)], 400, level)[0].unwrap();
                assert_eq!(
                    stopped < level,
                    all < level,
                    "seed {seed} level {level}: {stopped} and {all}"
                );
                if stopped < level {
                    assert_eq!(stopped, all, "seed {seed}");
                }
                decided[usize::from(all < level)] += 1;
            }
        }
        assert!(decided[0] > 0 && decided[1] > 0, "{decided:?}");
    }

    #[test]
    fn extras_drawn_together_get_what_each_gets_alone() {
        let r = run(36, 0.5, 4e-4, 9);
        let line = vec![r.t.clone()];
        let curve = vec![r.t.clone(), r.t.iter().map(|v| v * v).collect()];
        let test = WanderTest::new(&r.t, 1.0, &r.quarters, &[], &[]).unwrap().drawing();
        let null = test.null(&r.cols, &r.y).unwrap();
        for limit in [0.004, 1.0] {
            let together = null.p_drawn(&[&line, &curve], 400, limit);
            let alone = [&line, &curve].map(|x| null.p_drawn(&[x], 400, limit)[0]);
            assert_eq!(together, alone.to_vec(), "limit {limit}");
        }
    }

    #[test]
    fn the_null_takes_the_walk_the_noise_estimates_designs_would_hide() {
        // Started from white noise alone, the null's search finds the walk on the coarse grid.
        let mut ratios: Vec<f64> = (0..30)
            .map(|s| {
                let r = run(72, 2.0, 0.0, 100 + s);
                let test = WanderTest::new(&r.t, 1.0, &r.quarters, &[], &[]).unwrap();
                let null = test.null(&r.cols, &r.y).unwrap();
                // The white level of the quarters: 0.02 deg/h over a quarter second.
                let white = 0.02 * 0.25f64.sqrt() / 60.0;
                null.best.model.rrw_dph_rth * white / null.best.model.arw_deg_rth / 2.0
            })
            .collect();
        ratios.sort_by(f64::total_cmp);
        let median = ratios[ratios.len() / 2];
        assert!((0.3..=3.0).contains(&median), "median K / truth {median}");
    }
}
