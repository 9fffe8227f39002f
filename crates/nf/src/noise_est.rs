//! The gyro's noise estimated from one recording, by restricted maximum likelihood: white noise
//! with flicker (bias instability) and rate random walk, or with a first-order Gauss-Markov
//! bias, from
//! - the quarter means of each dwell (the short-time noise: three contrasts per dwell), or
//!   where there are none the spread of its samples ([`crate::sample_spread`]), and
//! - the dwell means in time order, through the residuals of the azimuth fit (the long-time
//!   noise: REML sees only what the fit's columns cannot absorb).
//!
//! The white level is profiled out in closed form; each family's two parameters are searched
//! on a logarithmic grid (zero included for flicker and walk; negligible corners skipped) and
//! the best refined by halving the step. Every grid point keeps its likelihood and its GLS
//! fit, so that a caller can average over the noise models the recording allows instead of
//! trusting one estimate.

use crate::gls::{self, Cov, WindowSet};
use crate::quarter_contrasts::{Part, QuarterContrasts, Quarters};
use crate::sample_spread::{SampleSpread, Spread};
use crate::stats::chi2_sf;
use nf_model::noise::NoiseModel;

/// What the estimate sees of a recording.
#[derive(Debug, Clone)]
pub struct Data<'a> {
    /// Centre of each dwell, s.
    pub t_s: &'a [f64],
    /// The typical dwell's length, s: the units of the search.
    pub dwell_s: f64,
    /// Each dwell's length, s, in `t_s`'s order.
    pub dwells_s: &'a [f64],
    /// The fit's columns and the (corrected) dwell means.
    pub cols: &'a [Vec<f64>],
    pub y: &'a [f64],
    /// Quarter means of the dwells that have them.
    pub quarters: &'a [Quarters],
    /// The samples' spread of the dwells that have it, where no dwell has quarters.
    pub spread: &'a [Spread],
    /// Per dwell, a variance of its mean alone (a shock's) in units of the white density,
    /// so that it scales with the white level the estimate profiles out; `None`: none.
    pub extra: Option<&'a [f64]>,
}

/// One noise model the search looked at: its profile likelihood and GLS fit.
#[derive(Debug, Clone)]
pub struct Candidate {
    pub model: NoiseModel,
    pub loglik: f64,
    /// The full likelihood, the coefficients at their best rather than integrated out (its
    /// white level profiled apart): unlike the restricted one, comparable between designs.
    pub full_loglik: f64,
    /// The fit's coefficients and their covariance under this model.
    pub coef: Vec<f64>,
    pub cov: Vec<Vec<f64>>,
}

/// The estimated model and how it was found.
#[derive(Debug, Clone)]
pub struct Estimate {
    /// The most likely model.
    pub best: Candidate,
    /// The grid's models (equal prior weight in the log of each ratio, and zero).
    pub grid: Vec<Candidate>,
    /// Degrees of freedom the white level was estimated with.
    pub dof: usize,
}

/// A colour term of a noise model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Term {
    Flicker,
    Walk,
    GaussMarkov,
}

/// A colour term whose likelihood-ratio p-value is at least this is left out of the model.
const KEEP: f64 = 0.1;

impl Term {
    pub const ALL: [Term; 3] = [Term::Flicker, Term::Walk, Term::GaussMarkov];

    pub fn absent(self, m: &NoiseModel) -> bool {
        match self {
            Term::Flicker => m.bias_instability_dph == 0.0,
            Term::Walk => m.rrw_dph_rth == 0.0,
            Term::GaussMarkov => m.gm_sigma_dph == 0.0,
        }
    }

    /// Its parameters: the Gauss-Markov term has a size and a time.
    fn dof(self) -> f64 {
        if self == Term::GaussMarkov { 2.0 } else { 1.0 }
    }
}

impl Estimate {
    /// The model the likelihood supports. In each family (flicker with random walk; a
    /// Gauss-Markov bias) a term goes when the likelihood ratio of the family's best against
    /// its best without the term has a p-value of at least [`KEEP`]: a chi-square of the
    /// term's parameters, not the boundary's half, as the best is refined between grid points
    /// and the model without the term is not, which inflates the ratio. Of the families'
    /// reduced models the one with the better likelihood less its parameters (Akaike) is
    /// chosen: over a short run the families stand in for each other, so terms are tested
    /// within theirs. The maximum-likelihood estimate of white noise is coloured half the
    /// time; a colour the likelihood does not support would cost precision for nothing.
    /// Returns the model and the p-values of the terms it has.
    pub fn supported(&self) -> (&Candidate, Vec<(Term, f64)>) {
        self.reduced(false)
    }

    /// As [`Estimate::supported`], but where each of two terms may go given the other and not
    /// both, only the one that matters least goes and the other is tested again alone.
    /// `nf fit`'s; `nf diagnose`'s tests are calibrated on the other.
    pub fn supported_stepwise(&self) -> (&Candidate, Vec<(Term, f64)>) {
        self.reduced(true)
    }

    fn reduced(&self, stepwise: bool) -> (&Candidate, Vec<(Term, f64)>) {
        let all: Vec<&Candidate> = std::iter::once(&self.best).chain(&self.grid).collect();
        let white = |m: &NoiseModel| Term::ALL.iter().all(|t| t.absent(m));
        type Member = fn(&NoiseModel) -> bool;
        let families: [(&[Term], Member); 2] = [
            (&[Term::Flicker, Term::Walk], |m| Term::GaussMarkov.absent(m)),
            (&[Term::GaussMarkov], |m| {
                !Term::GaussMarkov.absent(m) || Term::ALL.iter().all(|t| t.absent(m))
            }),
        ];
        let best = |keep: &dyn Fn(&NoiseModel) -> bool| {
            all.iter()
                .copied()
                .filter(|c| keep(&c.model))
                .max_by(|a, b| a.loglik.total_cmp(&b.loglik))
        };
        // The likelihood-ratio p-value of term `t` in `from` against the best `without` it.
        let test = |t: Term, from: &Candidate, without: Option<&Candidate>| {
            let without = without.map_or(f64::MIN, |c| c.loglik);
            (t, chi2_sf(2.0 * (from.loglik - without).max(0.0), t.dof()))
        };
        let mut choices = Vec::new();
        for (terms, member) in families {
            let Some(top) = best(&member) else { continue };
            let mut tests: Vec<(Term, f64)> = terms
                .iter()
                .filter(|t| !t.absent(&top.model))
                .map(|&t| test(t, top, best(&|m| member(m) && t.absent(m))))
                .collect();
            let mut dropped: Vec<Term> = tests.iter().filter(|(_, p)| *p >= KEEP).map(|(t, _)| *t).collect();
            // Each may go given the other but not both (flicker and a walk both explain a
            // strong wander): the one that matters least goes, and the other is tested
            // against the family without either (white noise was kept with chi-square 82 on
            // 33 dof under a walk 30 times the white noise).
            if stepwise
                && dropped.len() > 1
                && let Some(&(least, _)) = tests.iter().max_by(|a, b| a.1.total_cmp(&b.1))
                && let Some(rest) = best(&|m| member(m) && least.absent(m))
            {
                tests = terms
                    .iter()
                    .filter(|&&t| t != least && !t.absent(&rest.model))
                    .map(|&t| test(t, rest, best(&|m| member(m) && least.absent(m) && t.absent(m))))
                    .collect();
                dropped = std::iter::once(least)
                    .chain(tests.iter().filter(|(_, p)| *p >= KEEP).map(|(t, _)| *t))
                    .collect();
            }
            let Some(reduced) = best(&|m| member(m) && dropped.iter().all(|t| t.absent(m))) else {
                continue;
            };
            let params: f64 = terms
                .iter()
                .filter(|t| !t.absent(&reduced.model))
                .map(|t| t.dof())
                .sum();
            let kept = tests.into_iter().filter(|(t, _)| !t.absent(&reduced.model)).collect();
            choices.push((reduced.loglik - params, reduced, kept));
        }
        let chosen = choices.into_iter().max_by(|a, b| a.0.total_cmp(&b.0));
        chosen.map_or_else(
            || (best(&white).unwrap_or(&self.best), Vec::new()),
            |(_, c, kept)| (c, kept),
        )
    }
}

/// The two families of coloured noise the estimate searches beside white noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Family {
    /// Flicker and rate random walk: ratios `rb` (B^2, per s) and `rk` (K^2 in
    /// (deg/h)^2/s, per s^2) to the white density.
    Wander,
    /// A first-order Gauss-Markov bias: its variance's ratio to the white density (per s)
    /// and its correlation time, s.
    GaussMarkov,
}

/// One model of a family, by its two parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Point {
    family: Family,
    a: f64,
    b: f64,
}

impl Point {
    /// The model with white density 1 ((deg/h)^2 s).
    fn unit_model(&self) -> NoiseModel {
        let white = NoiseModel {
            arw_deg_rth: 1.0 / 60.0,
            ..NoiseModel::WHITE_NONE
        };
        match self.family {
            Family::Wander => NoiseModel {
                bias_instability_dph: self.a.sqrt(),
                rrw_dph_rth: 60.0 * self.b.sqrt(),
                ..white
            },
            Family::GaussMarkov => NoiseModel {
                gm_sigma_dph: self.a.sqrt(),
                gm_tau_s: self.b,
                ..white
            },
        }
    }

    fn scaled(&self, fa: f64, fb: f64) -> Point {
        Point {
            a: self.a * fa,
            b: self.b * fb,
            ..*self
        }
    }
}

/// `m` with every variance multiplied by `w`.
pub(crate) fn scaled(m: &NoiseModel, w: f64) -> NoiseModel {
    let s = w.sqrt();
    NoiseModel {
        arw_deg_rth: m.arw_deg_rth * s,
        bias_instability_dph: m.bias_instability_dph * s,
        rrw_dph_rth: m.rrw_dph_rth * s,
        gm_sigma_dph: m.gm_sigma_dph * s,
        ..*m
    }
}

struct Problem<'a> {
    data: Data<'a>,
    /// The designs estimated at once: `data.cols` first.
    designs: Vec<&'a [Vec<f64>]>,
    quarters: QuarterContrasts,
    spread: SampleSpread,
    /// The dwells, factored under every model looked at.
    windows: WindowSet,
}

impl<'a> Problem<'a> {
    fn new(data: Data<'a>, more: &[&'a [Vec<f64>]]) -> Problem<'a> {
        Problem {
            quarters: QuarterContrasts::new(data.quarters),
            spread: SampleSpread::new(data.spread),
            designs: std::iter::once(data.cols).chain(more.iter().copied()).collect(),
            windows: WindowSet::new(data.t_s, data.dwells_s),
            data,
        }
    }

    /// The median time between consecutive dwells, s.
    fn spacing(&self) -> f64 {
        let mut t = self.data.t_s.to_vec();
        t.sort_by(f64::total_cmp);
        let mut dt: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
        dt.sort_by(f64::total_cmp);
        dt.get(dt.len() / 2)
            .copied()
            .unwrap_or(self.data.dwell_s)
            .max(self.data.dwell_s)
    }

    /// Units that make the ratios dimensionless: flicker against a dwell's white variance,
    /// the random walk over the run against it.
    fn units(&self) -> (f64, f64) {
        let dwell = self.data.dwell_s;
        (1.0 / dwell, 1.0 / (dwell * self.span()))
    }

    /// From the first dwell's centre to the last's, at least a dwell, s.
    fn span(&self) -> f64 {
        let t = self.data.t_s;
        let span = t.iter().fold(0.0f64, |m, &t| m.max(t)) - t.iter().fold(f64::MAX, |m, &t| m.min(t));
        span.max(self.data.dwell_s)
    }

    /// The model at `at` with the white level that maximises the likelihood, for design `k`.
    fn profile(&self, at: Point, k: usize) -> Option<Candidate> {
        let cov = self.cov(at)?;
        self.candidate(at, &cov, self.designs[k])
    }

    /// The covariance of the dwell means at `at`, factored.
    fn cov(&self, at: Point) -> Option<Cov> {
        self.windows.cov_plus(&at.unit_model(), self.data.extra)
    }

    /// The profile under the factored covariance `cov` of `at`.
    fn candidate(&self, at: Point, cov: &Cov, cols: &[Vec<f64>]) -> Option<Candidate> {
        let d = &self.data;
        let m = at.unit_model();
        let g = gls::fit(cols, d.y, cov)?;
        // -2 loglik = N ln W + a + q / W, with the dwell means' REML and the quarter contrasts
        // or the samples' spread.
        let dwells = Part {
            log_det: -2.0 * g.reml_loglik - g.chi2,
            quad: g.chi2,
            count: g.dof,
        };
        let short = self.quarters.part(&m)?.plus(self.spread.part(&m)?);
        let (loglik, w) = dwells.plus(short).profiled()?;
        let full = Part {
            log_det: cov.log_det(),
            quad: g.chi2,
            count: d.y.len(),
        };
        let (full_loglik, _) = full.plus(short).profiled()?;
        Some(Candidate {
            model: scaled(&m, w),
            loglik,
            full_loglik,
            coef: g.coef,
            cov: g.cov.iter().map(|r| r.iter().map(|v| v * w).collect()).collect(),
        })
    }
}

/// A family's grid: the values of its two parameters, and which of them are whole decades
/// (searched first).
struct Grid {
    family: Family,
    a: Vec<f64>,
    b: Vec<f64>,
    coarse_a: Vec<bool>,
    coarse_b: Vec<bool>,
}

/// Half-decade steps of `unit` from 1e-4 to 1e4, and which are whole decades.
fn ratios(unit: f64) -> (Vec<f64>, Vec<bool>) {
    (-8..=8)
        .map(|k| (unit * 10f64.powf(k as f64 / 2.0), k % 2 == 0))
        .unzip()
}

impl Grid {
    /// Flicker and random walk, each ratio zero or from 1e-4 to 1e4 units: 18 x 18.
    fn wander(ub: f64, uk: f64) -> Grid {
        let with_zero = |unit: f64| {
            let (v, c) = ratios(unit);
            (
                std::iter::once(0.0).chain(v).collect(),
                std::iter::once(true).chain(c).collect(),
            )
        };
        let ((a, coarse_a), (b, coarse_b)) = (with_zero(ub), with_zero(uk));
        Grid {
            family: Family::Wander,
            a,
            b,
            coarse_a,
            coarse_b,
        }
    }

    /// White noise alone, as a grid of one model.
    fn white() -> Grid {
        Grid {
            family: Family::Wander,
            a: vec![0.0],
            b: vec![0.0],
            coarse_a: vec![true],
            coarse_b: vec![true],
        }
    }

    /// A Gauss-Markov bias: its variance 1e-4 to 1e4 units, its time in half decades from
    /// three spacings of the dwells to the run. Shorter, it is extra noise of each dwell mean
    /// that flicker's short end makes as well; longer, a walk.
    fn gauss_markov(unit: f64, spacing_s: f64, span_s: f64) -> Grid {
        let (a, coarse_a) = ratios(unit);
        let shortest = 3.0 * spacing_s;
        let (b, coarse_b) = (0..)
            .map(|k| (shortest * 10f64.powf(k as f64 / 2.0), k % 2 == 0))
            .take_while(|&(tau, _)| tau <= span_s.max(shortest))
            .unzip();
        Grid {
            family: Family::GaussMarkov,
            a,
            b,
            coarse_a,
            coarse_b,
        }
    }

    /// A Gauss-Markov bias shorter than [`Grid::gauss_markov`]'s: its time in half decades
    /// from a quarter of a dwell to three spacings. It is the scatter of whole dwells beyond
    /// what their quarters show, white from dwell to dwell: what shocks make.
    fn short_gauss_markov(unit: f64, dwell_s: f64, spacing_s: f64) -> Grid {
        let (a, coarse_a) = ratios(unit);
        let (b, coarse_b) = (0..)
            .map(|k| (dwell_s / 4.0 * 10f64.powf(k as f64 / 2.0), k % 2 == 0))
            .take_while(|&(tau, _)| tau < 3.0 * spacing_s)
            .unzip();
        Grid {
            family: Family::GaussMarkov,
            a,
            b,
            coarse_a,
            coarse_b,
        }
    }

    fn point(&self, i: usize, j: usize) -> Point {
        Point {
            family: self.family,
            a: self.a[i],
            b: self.b[j],
        }
    }

    fn coarse(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.a.len())
            .filter(|&i| self.coarse_a[i])
            .flat_map(move |i| (0..self.b.len()).filter(|&j| self.coarse_b[j]).map(move |j| (i, j)))
    }
}

/// Dwell means beyond this are thinned for an estimate, which then costs what a run of this
/// many does: the slow noise shows in one dwell mean in k over the whole run as well, and the
/// fast in the quarters of every dwell, all of which are kept.
pub const THINNED: usize = 2000;

/// One row in `every` (`every` the least that leaves at most [`THINNED`]), with its rows of
/// each design; a column left with nothing (a burst's indicator on a row not kept) goes. A row
/// that every design gives a column of its own (a burst held out) goes with those columns:
/// the restricted likelihood with a free mean for one row is that of the other rows, at the
/// cost of one column less (a long shocked run holds out a thousand bursts).
pub struct Thinned {
    pub every: usize,
    /// The rows kept, in order.
    pub rows: Vec<usize>,
    pub t_s: Vec<f64>,
    pub y: Vec<f64>,
    pub designs: Vec<Vec<Vec<f64>>>,
}

impl Thinned {
    pub fn new(t_s: &[f64], y: &[f64], designs: &[&[Vec<f64>]]) -> Thinned {
        let every = t_s.len().div_ceil(THINNED).max(1);
        let kept: Vec<usize> = (0..t_s.len()).step_by(every).collect();
        // The one kept row a column is not zero on, if there is just one.
        let own_row = |c: &[f64]| {
            let mut on = kept.iter().filter(|&&i| c[i] != 0.0);
            match (on.next(), on.next()) {
                (Some(&i), None) => Some(i),
                _ => None,
            }
        };
        let owned: Vec<Vec<usize>> = designs
            .iter()
            .map(|cols| cols.iter().filter_map(|c| own_row(c)).collect())
            .collect();
        let rows: Vec<usize> = kept
            .iter()
            .copied()
            .filter(|i| designs.is_empty() || !owned.iter().all(|o| o.contains(i)))
            .collect();
        let keep = |v: &[f64]| -> Vec<f64> { rows.iter().map(|&i| v[i]).collect() };
        Thinned {
            every,
            t_s: keep(t_s),
            y: keep(y),
            designs: designs
                .iter()
                .map(|cols| {
                    cols.iter()
                        .map(|c| keep(c))
                        .filter(|c| c.iter().any(|v| *v != 0.0))
                        .collect()
                })
                .collect(),
            rows,
        }
    }
}

/// A grid point this far below the best log-likelihood weighs under 1e-5 of it: its
/// neighbours are not looked at.
const NEGLIGIBLE: f64 = 12.0;

/// The families of coloured noise an estimate searches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Colours {
    /// Flicker and rate random walk: over a run they stand for any slow wander without
    /// claiming it bounded, so the sigma they give stays honest (`nf fit`).
    FlickerAndWalk,
    /// A Gauss-Markov bias too, to name it (`nf diagnose`). Its time is poorly known from
    /// one run and mostly too short: a sigma averaged over its models is too small (RMS
    /// error/sigma 1.5 in a sequential run under a walk or a Gauss-Markov bias).
    WithGaussMarkov,
    /// Flicker and walk, and a Gauss-Markov bias shorter than three dwell spacings: for
    /// heavy-tailed dwell means (`nf fit`), whose excess over their quarters is shocks, white
    /// from dwell to dwell, which flicker would take for wander.
    WithShocks,
    /// Flicker and walk, and a Gauss-Markov bias shorter than three dwell spacings: for dwell
    /// means that scatter beyond their quarters but not as a wander does (`nf fit`, where that
    /// bias explains the run far better than flicker and walk can).
    WithFastMarkov,
    /// None: as many positions as unknowns leave the dwell means no contrast to show a
    /// colour by, and the quarters or the samples' spread measure the white level alone.
    White,
}

/// Estimates white noise and `colours` from a recording.
pub fn estimate(data: Data<'_>, colours: Colours) -> Option<Estimate> {
    estimate_all(data, &[], colours).into_iter().next().flatten()
}

/// The estimate under `colours` for `data` and for each of `more` designs of the same
/// recording (other columns, the same dwell means): the grid's covariances are factored once
/// for all.
pub fn estimate_all<'a>(data: Data<'a>, more: &[&'a [Vec<f64>]], colours: Colours) -> Vec<Option<Estimate>> {
    let p = Problem::new(data, more);
    let (ub, uk) = p.units();
    let mut grids = vec![match colours {
        Colours::White => Grid::white(),
        _ => Grid::wander(ub, uk),
    }];
    match colours {
        Colours::FlickerAndWalk | Colours::White => {}
        Colours::WithGaussMarkov => grids.push(Grid::gauss_markov(ub, p.spacing(), p.span())),
        Colours::WithShocks | Colours::WithFastMarkov => {
            grids.push(Grid::short_gauss_markov(ub, p.data.dwell_s, p.spacing()))
        }
    }
    let mut cands: Vec<Vec<(Point, Candidate)>> = vec![Vec::new(); p.designs.len()];
    // Whole decades first, then the half decades next to a point that is not negligible for
    // some design, until none is left: a sharp likelihood (a long run) costs a few dozen
    // models, a flat one the whole grid.
    let mut seen: Vec<Vec<Vec<Option<f64>>>> = grids.iter().map(|g| vec![vec![None; g.b.len()]; g.a.len()]).collect();
    let mut next: Vec<(usize, usize, usize)> = grids
        .iter()
        .enumerate()
        .flat_map(|(f, g)| g.coarse().map(move |(i, j)| (f, i, j)))
        .collect();
    while !next.is_empty() {
        for &(f, i, j) in &next {
            let at = grids[f].point(i, j);
            let mut best = f64::MIN;
            if let Some(cov) = p.cov(at) {
                for (k, cols) in p.designs.iter().enumerate() {
                    if let Some(c) = p.candidate(at, &cov, cols) {
                        best = best.max(c.loglik);
                        cands[k].push((at, c));
                    }
                }
            }
            seen[f][i][j] = Some(best);
        }
        let top = seen
            .iter()
            .flatten()
            .flatten()
            .flatten()
            .fold(f64::MIN, |m, &v| m.max(v));
        next = Vec::new();
        for (f, s) in seen.iter().enumerate() {
            let (na, nb) = (s.len(), s[0].len());
            let near = |a: usize, n: usize| a.saturating_sub(1)..=(a + 1).min(n - 1);
            for i in 0..na {
                for j in (0..nb).filter(|&j| s[i][j].is_none()) {
                    if near(i, na).any(|a| near(j, nb).any(|b| s[a][b].is_some_and(|l| l >= top - NEGLIGIBLE))) {
                        next.push((f, i, j));
                    }
                }
            }
        }
    }
    cands.into_iter().enumerate().map(|(k, c)| refine(&p, k, c)).collect()
}

/// The best of design `k`'s grid, refined in log steps, halving from the grid's half decade.
fn refine(p: &Problem, k: usize, cands: Vec<(Point, Candidate)>) -> Option<Estimate> {
    let (mut at, mut best) = cands.iter().max_by(|a, b| a.1.loglik.total_cmp(&b.1.loglik))?.clone();
    let mut step = 10f64.powf(0.5);
    for _ in 0..6 {
        step = step.sqrt();
        for (fa, fb) in [(step, 1.0), (1.0 / step, 1.0), (1.0, step), (1.0, 1.0 / step)] {
            let moved = at.scaled(fa, fb);
            if moved == at {
                continue;
            }
            if let Some(c) = p.profile(moved, k)
                && c.loglik > best.loglik
            {
                (at, best) = (moved, c);
            }
        }
    }
    Some(Estimate {
        best,
        grid: cands.into_iter().map(|c| c.1).collect(),
        dof: p.data.t_s.len() - p.designs[k].len() + p.quarters.count() + p.spread.count(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep_run::{Sweep, SweepRun};

    #[test]
    fn thinning_keeps_one_row_in_k_and_drops_the_columns_it_empties() {
        let n = 3 * THINNED;
        let t: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let ones = vec![1.0; n];
        let burst = |i: usize| (0..n).map(|k| f64::from(u8::from(k == i))).collect::<Vec<f64>>();
        let a = vec![ones.clone(), burst(3000), burst(3001)];
        let b = vec![ones, t.clone()];
        let th = Thinned::new(&t, &t, &[&a, &b]);
        assert_eq!(th.every, 3);
        assert_eq!(th.t_s.len(), THINNED);
        assert_eq!(th.t_s[..3], [0.0, 3.0, 6.0]);
        assert_eq!(th.y, th.t_s);
        assert_eq!(th.designs[0].len(), 2, "the burst on a row not kept goes");
        assert_eq!(th.designs[0][1].iter().sum::<f64>(), 1.0);
        assert_eq!(th.designs[1][1], th.t_s);
        // A burst every design holds out goes with its row.
        let c = vec![vec![1.0; n], burst(3000)];
        let both = Thinned::new(&t, &t, &[&a, &c]);
        assert_eq!(both.t_s.len(), THINNED - 1);
        assert!(!both.t_s.contains(&3000.0) && both.rows.len() == THINNED - 1);
        assert_eq!(both.designs.iter().map(Vec::len).collect::<Vec<_>>(), [1, 1]);
        let short = Thinned::new(&t[..THINNED], &t[..THINNED], &[&[t[..THINNED].to_vec()]]);
        assert_eq!(
            (short.every, short.t_s.len()),
            (1, THINNED),
            "nothing thinned up to THINNED"
        );
    }

    /// Dwell means of a sequential run under white noise, with a random walk of `walk` per
    /// dwell, and their quarters.
    fn run(n: usize, walk: f64, seed: u64) -> SweepRun {
        Sweep {
            n,
            t0_s: 5.0,
            spacing_s: 1.2,
            walk_dph: walk,
            drift_dph_per_s: 0.0,
        }
        .run(seed)
    }

    #[test]
    fn skipping_negligible_corners_finds_the_grid_maximum() {
        for (n, walk, seed) in [(60, 0.0, 1), (400, 0.0, 2), (400, 0.003, 3), (2000, 0.001, 4)] {
            let r = run(n, walk, seed);
            let data = Data {
                t_s: &r.t,
                dwell_s: 1.0,
                dwells_s: &r.dwells,
                cols: &r.cols,
                y: &r.y,
                quarters: &r.quarters,
                spread: &[],
                extra: None,
            };
            let e = estimate_all(data.clone(), &[], Colours::WithGaussMarkov)
                .remove(0)
                .unwrap();
            let grid_best = e.grid.iter().map(|c| c.loglik).fold(f64::MIN, f64::max);
            let p = Problem::new(data, &[]);
            let (ub, uk) = p.units();
            let grids = [Grid::wander(ub, uk), Grid::gauss_markov(ub, p.spacing(), p.span())];
            let points: Vec<Point> = grids
                .iter()
                .flat_map(|g| (0..g.a.len()).flat_map(move |i| (0..g.b.len()).map(move |j| g.point(i, j))))
                .collect();
            let whole = points
                .iter()
                .filter_map(|&at| p.profile(at, 0))
                .map(|c| c.loglik)
                .fold(f64::MIN, f64::max);
            assert!(
                (grid_best - whole).abs() < 1e-9 * whole.abs(),
                "n {n}: {grid_best} vs {whole}"
            );
            assert!(e.grid.len() < points.len(), "n {n}: {} models", e.grid.len());
            println!("n {n}, walk {walk}: {} of {} grid models", e.grid.len(), points.len());
        }
    }
}
