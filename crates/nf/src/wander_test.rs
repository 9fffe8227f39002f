//! The likelihood-ratio test of columns that a wandering bias can mimic (a drift, a jump, a
//! temperature cycle), with the noise's flicker and random walk estimated under each
//! hypothesis. A test under one plugged-in noise model leans one way: estimated with the
//! columns in the design, the walk is small and its wander is taken for the effect;
//! estimated without them, the walk takes a real effect for wander. Profiled under both,
//! the ratio is calibrated on white noise and finds a drift more often than the plug-in
//! test, but over one run of a few dozen dwells a random walk still passes for a drift
//! (the walk's slowest mode is one number), so `nf diagnose` asks both tests.
//!
//! The likelihood is restricted for the constant only: flicker and walk covariances are
//! defined up to a constant (`crate::gls`), which the constant's contrasts do not see, and
//! every design holds the constant, so the likelihoods of two designs compare.

use crate::gls::{Cov, WindowSet};
use crate::linfit;
use crate::quarter_contrasts::{Part, QuarterContrasts};
use crate::stats::f_sf;
use nf_model::noise::NoiseModel;
use std::cell::OnceCell;

/// Halvings of the search step around the best model, from a quarter decade of B^2 and K^2.
const REFINE: usize = 4;

pub struct WanderTest {
    windows: WindowSet,
    quarters: QuarterContrasts,
    starts: Vec<Start>,
}

/// A noise model of white density 1, factored.
#[derive(Clone)]
struct Start {
    model: NoiseModel,
    cov: Cov,
    /// `-2 ln L` less the dwell means' whitened RSS: the covariances' log-determinants (the
    /// constant's contrast taken out) and the quarters' share.
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
    pub fn new(t_s: &[f64], dwell_s: f64, quarters: &[[f64; 4]], models: &[NoiseModel]) -> Option<WanderTest> {
        let mut test = WanderTest {
            windows: WindowSet::new(t_s, &vec![dwell_s; t_s.len()]),
            quarters: QuarterContrasts::new(quarters, dwell_s),
            starts: Vec::new(),
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

    fn start(&self, model: NoiseModel) -> Option<Start> {
        let n = self.windows.count();
        let cov = self.windows.cov(&model)?;
        let ln_ones = norm2(&cov.whiten(&vec![1.0; n])).ln();
        let dwells = Part {
            log_det: cov.log_det() + ln_ones,
            quad: 0.0,
            count: n - 1,
        };
        let fixed = dwells.plus(self.quarters.part(&model)?);
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

    /// The observations the likelihood sees: the dwell means' contrasts and the quarters'.
    fn count(&self) -> usize {
        self.windows.count() - 1 + self.quarters.count()
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
        let count = t.count();
        let lr = (2.0 * (large - self.loglik)).max(0.0);
        let q = extra.len() as f64;
        let dof = count as f64 - (self.cols.len() + extra.len() - 1) as f64;
        if dof <= 0.0 {
            return None;
        }
        let f = ((lr / count as f64).exp() - 1.0) * dof / q;
        Some(f_sf(f, q, dof))
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
        let test = WanderTest::new(&t, 1.0, &[], &models).unwrap();
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
        let test = WanderTest::new(&r.t, 1.0, &r.quarters, &[]).unwrap();
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
    fn the_null_takes_the_walk_the_noise_estimates_designs_would_hide() {
        // Started from white noise alone, the null's search finds the walk on the coarse grid.
        let mut ratios: Vec<f64> = (0..30)
            .map(|s| {
                let r = run(72, 2.0, 0.0, 100 + s);
                let test = WanderTest::new(&r.t, 1.0, &r.quarters, &[]).unwrap();
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
