//! The likelihood-ratio test of columns that a wandering bias can mimic (a drift, a jump, a
//! temperature cycle), with the noise's flicker and random walk estimated under each
//! hypothesis. A test under one plugged-in noise model leans one way: estimated with the
//! columns in the design, the walk is small and its wander is taken for the effect;
//! estimated without them, the walk takes a real effect for wander. Profiled under both,
//! the ratio is calibrated on white noise and finds a drift more often than the plug-in
//! test, but over one run of a few dozen dwells a random walk still passes for a drift
//! (the walk's slowest mode is one number), so `nf diagnose` asks both tests, and reads the
//! ratio of a drift or a temperature against draws from the null rather than the F law, and
//! a jump's best step against the best step's in the draws as well as by the F law.
//!
//! The likelihood is restricted for the constant only: flicker and walk covariances are
//! defined up to a constant (`crate::gls`), which the constant's contrasts do not see, and
//! every design holds the constant, so the likelihoods of two designs compare.

mod draws;
mod larger;

use crate::gls::{Cov, WindowSet};
use crate::linfit;
use crate::quarter_contrasts::{Part, QuarterContrasts, Quarters};
use crate::sample_spread::{SampleSpread, Spread};
use crate::stats::f_sf;
use draws::Draws;
use larger::{Basis, Larger, Nested, Steps};
use nf_model::noise::NoiseModel;
use std::cell::{OnceCell, RefCell};
use std::rc::Rc;
use std::sync::Arc;

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
    cov: Arc<Cov>,
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
    /// `dwells_s`: each dwell's length; `dwell_s` the typical one, the unit of its grid.
    pub fn new(
        t_s: &[f64],
        (dwell_s, dwells_s): (f64, &[f64]),
        quarters: &[Quarters],
        spread: &[Spread],
        models: &[NoiseModel],
    ) -> Option<WanderTest> {
        let mut test = WanderTest {
            windows: WindowSet::new(t_s, dwells_s),
            quarters: QuarterContrasts::new(quarters),
            spread: SampleSpread::new(spread),
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
        let cov = Arc::new(self.windows.cov(&model)?);
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
        let at_starts: Vec<Rc<Visit>> = self
            .starts
            .iter()
            .map(|s| Rc::new(Visit::of(s.clone(), cols, y)))
            .collect();
        let (first, _) = at_starts
            .iter()
            .filter_map(|v| Some((Rc::clone(v), v.loglik(&[])?)))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        let mut null = Null {
            test: self,
            cols: cols.to_vec(),
            y: y.to_vec(),
            best: first,
            loglik: f64::NAN,
            at_starts,
        };
        (null.best, null.loglik) = null.refine(Rc::clone(&null.best), &[])?;
        Some(null)
    }

    /// The observations the likelihood sees: the dwell means' contrasts and the quarters' or
    /// the spread's.
    fn count(&self) -> usize {
        self.windows.count() - 1 + self.quarters.count() + self.spread.count()
    }
}

/// A noise model the null was fitted under (a start, or a model a search visited), and the
/// null's design and rates whitened by it.
struct Visit {
    start: Start,
    cols: Vec<Vec<f64>>,
    y: Vec<f64>,
    /// The null's fit, which every likelihood with more columns extends.
    fit: OnceCell<NullFit>,
    /// The extras met (not yet whitened) and their bases beyond the null's: an effect's
    /// ratio and then its draws ask for the same.
    beyond: RefCell<Vec<Met>>,
}

/// Columns not yet whitened, and their basis beyond a visit's null.
type Met = (Vec<Vec<f64>>, Arc<Basis>);

/// The whitened null design's orthonormal basis and the whitened rates' residual off it.
struct NullFit {
    basis: Basis,
    resid: Vec<f64>,
}

impl Visit {
    fn of(start: Start, cols: &[Vec<f64>], y: &[f64]) -> Visit {
        let raw: Vec<&[f64]> = cols.iter().map(Vec::as_slice).chain([y]).collect();
        let mut cols = start.cov.whiten_each(&raw);
        let y = cols.pop().unwrap_or_default();
        Visit {
            cols,
            y,
            start,
            fit: OnceCell::new(),
            beyond: RefCell::new(Vec::new()),
        }
    }

    fn fit(&self) -> &NullFit {
        self.fit.get_or_init(|| {
            let basis = Basis::of(&self.cols);
            let resid = basis.residual(&self.y);
            NullFit { basis, resid }
        })
    }

    /// `extra`, not yet whitened, whitened and made orthonormal beyond the null's basis.
    fn beyond(&self, extra: &[Vec<f64>]) -> Arc<Basis> {
        if let Some((_, b)) = self.beyond.borrow().iter().find(|(raw, _)| raw.as_slice() == extra) {
            return Arc::clone(b);
        }
        let b = Arc::new(Basis::beyond(&self.fit().basis, &self.start.cov.whiten_each(extra)));
        self.beyond.borrow_mut().push((extra.to_vec(), Arc::clone(&b)));
        b
    }

    /// `extra`'s larger design beyond this whitened null.
    fn larger(&self, extra: &Alternative) -> Larger<'_> {
        let basis = &self.fit().basis;
        match extra {
            Alternative::Columns(cols) => Larger::Columns(Nested::new(basis, self.beyond(cols))),
            Alternative::Step(tried) => Larger::Steps(Steps::of(&self.start.cov, basis, tried.range())),
        }
    }

    /// The log-likelihood with `extra`, not yet whitened, added to the columns; `None` where
    /// a column depends on the others.
    fn loglik(&self, extra: &[Vec<f64>]) -> Option<f64> {
        let fit = self.fit();
        let more = self.beyond(extra);
        if fit.basis.len() < self.cols.len() || more.len() < extra.len() {
            return None;
        }
        self.start.loglik((norm2(&fit.resid) - more.along(&fit.resid)).max(0.0))
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

/// What a drawn ratio tests beyond the null.
#[derive(Debug, Clone, Copy)]
pub enum Alternative<'x> {
    /// These columns.
    Columns(&'x [Vec<f64>]),
    /// A step of the bias at any of these change points in time: the ratio at the best,
    /// whose law under the null takes the scan's choice into account, where a ratio at the
    /// chosen step read against the F law and corrected by Bonferroni over the change points
    /// is near-blind to how a walk, itself a sum of steps, makes one.
    Step(ChangePoints),
}

/// The change points a step is tried at: rows `first..end` in time order, the step taking
/// effect at the row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChangePoints {
    pub first: usize,
    pub end: usize,
}

impl ChangePoints {
    /// Of `n` rows, all but the first two and the last two: a step there is fitted from at
    /// least two dwells on either side.
    pub fn inner(n: usize) -> ChangePoints {
        ChangePoints {
            first: 2,
            end: n.saturating_sub(2).max(2),
        }
    }

    pub fn range(&self) -> std::ops::Range<usize> {
        self.first..self.end
    }

    pub fn count(&self) -> usize {
        self.range().len()
    }
}

/// A fitted null hypothesis of the wander test.
pub struct Null<'a> {
    test: &'a WanderTest,
    cols: Vec<Vec<f64>>,
    y: Vec<f64>,
    /// Its best noise model, where the search under the alternative also starts: the larger
    /// design is then at least as likely.
    best: Rc<Visit>,
    loglik: f64,
    /// Under each of the test's starts.
    at_starts: Vec<Rc<Visit>>,
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
    /// each stopped once `draws::EXCEEDED` have reached it, once the p-value can no longer fall
    /// under `limit`, or at `most`. `None` where the test does not draw.
    pub fn p_drawn(&self, extras: &[Alternative], most: usize, limit: f64) -> Vec<Option<f64>> {
        let none = vec![None; extras.len()];
        if !self.test.draws {
            return none;
        }
        let Some((mean, level)) = self.fitted() else {
            return none;
        };
        // Per extra, per start.
        let bases: Vec<Vec<Larger>> = extras
            .iter()
            .map(|extra| self.at_starts.iter().map(|v| v.larger(extra)).collect())
            .collect();
        let seed = self
            .y
            .iter()
            .fold(self.y.len() as u64, |h, v| h.rotate_left(7) ^ v.to_bits());
        let recorded: Vec<Vec<[f64; 1]>> = self
            .at_starts
            .iter()
            .map(|v| v.y.iter().map(|&v| [v]).collect())
            .collect();
        Draws {
            starts: &self.test.starts,
            bases: &bases,
            mean: &mean,
            sd: level.sqrt(),
            cov: &self.best.start.cov,
        }
        .p_values(|i| recorded[i].clone(), seed, most, limit)
    }

    /// The null's fitted rates and white level, which every draw adds noise of its best
    /// model to.
    fn fitted(&self) -> Option<(Vec<f64>, f64)> {
        let fit = linfit::fit(&self.best.cols, &self.best.y)?;
        let (_, level) = self
            .best
            .start
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

    /// Whether its p-values can be read against draws ([`Null::p_drawn`]).
    pub fn draws(&self) -> bool {
        self.test.draws
    }

    /// Twice the log-likelihood gained by `extra`, each side at its best noise model.
    fn lr(&self, extra: &[Vec<f64>]) -> Option<f64> {
        let best_start = self
            .at_starts
            .iter()
            .filter_map(|v| Some((v, v.loglik(extra)?)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let from = match (best_start, self.best.loglik(extra)) {
            (Some((v, l)), Some(n)) if l > n => v,
            (Some((v, _)), None) => v,
            _ => &self.best,
        };
        let (_, large) = self.refine(Rc::clone(from), extra)?;
        Some((2.0 * (large - self.loglik)).max(0.0))
    }

    /// The model near `from` (in halving steps of B^2 and K^2) most likely for
    /// `y ~ cols + extra`, and its log-likelihood.
    fn refine(&self, from: Rc<Visit>, extra: &[Vec<f64>]) -> Option<(Rc<Visit>, f64)> {
        let mut top = from.loglik(extra)?;
        let mut at = from;
        let mut step = 10f64.powf(0.25);
        for _ in 0..REFINE {
            for (fb, fk) in [(step, 1.0), (1.0 / step, 1.0), (1.0, step), (1.0, 1.0 / step)] {
                let model = &at.start.model;
                let moved = NoiseModel {
                    bias_instability_dph: model.bias_instability_dph * fb.sqrt(),
                    rrw_dph_rth: model.rrw_dph_rth * fk.sqrt(),
                    ..*model
                };
                if same(&moved, model) {
                    continue;
                }
                let Some(start) = self.test.start(moved) else { continue };
                let v = Rc::new(Visit::of(start, &self.cols, &self.y));
                if let Some(l) = v.loglik(extra)
                    && l > top
                {
                    (at, top) = (v, l);
                }
            }
            step = step.sqrt();
        }
        Some((at, top))
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
    larger::dot(v, v)
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
        let test = WanderTest::new(&t, (1.0, &vec![1.0; n]), &[], &[], &models).unwrap();
        let ours: Vec<f64> = models
            .iter()
            .map(|m| Visit::of(test.start(unit(m)).unwrap(), &cols, &y).loglik(&[]).unwrap())
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
        let test = WanderTest::new(&r.t, (1.0, &r.dwells), &r.quarters, &[], &[]).unwrap();
        test.null(&r.cols, &r.y)
            .unwrap()
            .p_value(std::slice::from_ref(&r.t))
            .unwrap()
    }

    #[test]
    fn a_likelihood_with_more_columns_is_the_whole_designs_fitted_afresh() {
        let r = run(40, 0.5, 4e-4, 3);
        let test = WanderTest::new(&r.t, (1.0, &r.dwells), &r.quarters, &[], &[]).unwrap();
        let curve = vec![r.t.clone(), r.t.iter().map(|v| v * v).collect()];
        for start in &test.starts {
            let white: Vec<Vec<f64>> = r.cols.iter().chain(&curve).map(|c| start.cov.whiten(c)).collect();
            let whole = start
                .loglik(linfit::fit(&white, &start.cov.whiten(&r.y)).unwrap().rss)
                .unwrap();
            let ours = Visit::of(start.clone(), &r.cols, &r.y).loglik(&curve).unwrap();
            assert!((ours - whole).abs() < 1e-9 * whole.abs(), "{ours} against {whole}");
        }
        // A column the design holds already adds nothing: no likelihood, as no fit.
        let v = Visit::of(test.starts[0].clone(), &r.cols, &r.y);
        assert_eq!(v.loglik(&[r.cols[0].iter().map(|x| 2.0 * x).collect()]), None);
    }

    #[test]
    fn an_extras_basis_is_made_once_for_its_ratio_and_its_draws() {
        let r = run(40, 0.5, 4e-4, 3);
        let test = WanderTest::new(&r.t, (1.0, &r.dwells), &r.quarters, &[], &[]).unwrap();
        let v = Visit::of(test.starts[0].clone(), &r.cols, &r.y);
        let line = vec![r.t.clone()];
        let square = vec![r.t.iter().map(|x| x * x).collect::<Vec<f64>>()];
        let first = v.beyond(&line);
        assert!(v.loglik(&line).is_some());
        assert!(Arc::ptr_eq(&first, &v.beyond(&line)));
        // Other columns, even of the same shape, get their own.
        assert!(!Arc::ptr_eq(&first, &v.beyond(&square)));
        let fresh = Basis::beyond(&v.fit().basis, &v.start.cov.whiten_each(&square));
        assert_eq!(*v.beyond(&square), fresh);
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
                let test = WanderTest::new(&r.t, (1.0, &r.dwells), &r.quarters, &[], &[])
                    .unwrap()
                    .drawing();
                let null = test.null(&r.cols, &r.y).unwrap();
                f += usize::from(null.p_value(&curve(&r)).unwrap() < level);
                drawn += usize::from(null.p_drawn(&[Alternative::Columns(&curve(&r))], 400, level)[0].unwrap() < level);
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
    fn drawn_against_the_best_step_a_walk_makes_fewer_jumps_and_a_jump_is_still_found() {
        // The jump's scan over change points 2..n-2, read as the F law corrected by
        // Bonferroni, against the best step's ratio in draws of the null.
        let below = |rrw: f64, jump: f64, level: f64| {
            let (mut f, mut drawn) = (0, 0);
            for seed in 0..60 {
                let mut r = run(48, rrw, 0.0, 900 + seed);
                let n = r.y.len();
                let at = n / 2 + (seed % 7) as usize;
                r.y.iter_mut().skip(at).for_each(|v| *v += jump);
                let test = WanderTest::new(&r.t, (1.0, &r.dwells), &r.quarters, &[], &[])
                    .unwrap()
                    .drawing();
                let null = test.null(&r.cols, &r.y).unwrap();
                let tried = ChangePoints::inner(n);
                let scanned = tried
                    .range()
                    .filter_map(|j| {
                        let step: Vec<f64> = (0..n).map(|i| f64::from(u8::from(i >= j))).collect();
                        null.p_value(&[step])
                    })
                    .fold(1.0f64, f64::min);
                f += usize::from(scanned * (tried.count() as f64) < level);
                drawn += usize::from(null.p_drawn(&[Alternative::Step(tried)], 400, level)[0].unwrap() < level);
            }
            println!("rrw {rrw} jump {jump}: below {level}: F and Bonferroni {f}, drawn {drawn} of 60");
            (f, drawn)
        };
        // A walk of about three times a dwell mean's white noise (0.01 deg/h) per dwell.
        let (f, drawn) = below(1.5, 0.0, 0.01);
        assert!(drawn < f && drawn <= 3, "F {f}, drawn {drawn}");
        // A jump of 8 dwell sigmas on white noise.
        let (_, drawn) = below(0.0, 0.08, 0.01);
        assert!(drawn >= 50, "{drawn} of 60 jumps");
    }

    #[test]
    fn draws_stopped_at_the_level_decide_as_all_of_them_would() {
        let curve = |r: &SweepRun| vec![r.t.clone(), r.t.iter().map(|v| v * v).collect()];
        let mut decided = [0, 0];
        for seed in 0..12 {
            let r = run(36, 0.5, 4e-4 * (seed % 3) as f64, 700 + seed);
            let test = WanderTest::new(&r.t, (1.0, &r.dwells), &r.quarters, &[], &[])
                .unwrap()
                .drawing();
            let null = test.null(&r.cols, &r.y).unwrap();
            let all = null.p_drawn(&[Alternative::Columns(&curve(&r))], 400, 1.0)[0].unwrap();
            for level in [0.004, 0.01, 0.05] {
                let stopped = null.p_drawn(&[Alternative::Columns(&curve(&r))], 400, level)[0].unwrap();
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
        let test = WanderTest::new(&r.t, (1.0, &r.dwells), &r.quarters, &[], &[])
            .unwrap()
            .drawing();
        let null = test.null(&r.cols, &r.y).unwrap();
        for limit in [0.004, 1.0] {
            let together = null.p_drawn(&[Alternative::Columns(&line), Alternative::Columns(&curve)], 400, limit);
            let alone = [&line, &curve].map(|x| null.p_drawn(&[Alternative::Columns(x)], 400, limit)[0]);
            assert_eq!(together, alone.to_vec(), "limit {limit}");
        }
    }

    #[test]
    fn the_null_takes_the_walk_the_noise_estimates_designs_would_hide() {
        // Started from white noise alone, the null's search finds the walk on the coarse grid.
        let mut ratios: Vec<f64> = (0..30)
            .map(|s| {
                let r = run(72, 2.0, 0.0, 100 + s);
                let test = WanderTest::new(&r.t, (1.0, &r.dwells), &r.quarters, &[], &[]).unwrap();
                let null = test.null(&r.cols, &r.y).unwrap();
                // The white level of the quarters: 0.02 deg/h over a quarter second.
                let white = 0.02 * 0.25f64.sqrt() / 60.0;
                null.best.start.model.rrw_dph_rth * white / null.best.start.model.arw_deg_rth / 2.0
            })
            .collect();
        ratios.sort_by(f64::total_cmp);
        let median = ratios[ratios.len() / 2];
        assert!((0.3..=3.0).contains(&median), "median K / truth {median}");
    }
}
