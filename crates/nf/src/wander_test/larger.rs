//! The larger designs of the wander test's draws, against the null's whitened design under
//! one start: given columns ([`Nested`]), or a step in time at any of the jump scan's change
//! points ([`Steps`]), each giving the RSS of many rate vectors under the null and the larger
//! design at once.

use crate::gls::Cov;
use std::sync::Arc;

/// A larger design of the draws under one start, beyond the null's basis there.
pub(super) enum Larger<'v> {
    Columns(Nested<'v>),
    Steps(Steps<'v>),
}

impl Larger<'_> {
    /// The RSS of `W` whitened rate vectors side by side under the null and the larger
    /// design; `cov` the start's covariance, whose whitening they are.
    pub(super) fn rss_block<const W: usize>(&self, cov: &Cov, y: &[[f64; W]]) -> [(f64, f64); W] {
        match self {
            Larger::Columns(n) => n.rss_block(y),
            Larger::Steps(s) => s.rss_block(cov, y),
        }
    }
}

/// An orthonormal basis of whitened columns.
#[derive(Debug, Default, PartialEq)]
pub(super) struct Basis(Vec<Vec<f64>>);

impl Basis {
    pub(super) fn of(cols: &[Vec<f64>]) -> Basis {
        Basis::beyond(&Basis::default(), cols)
    }

    pub(super) fn len(&self) -> usize {
        self.0.len()
    }

    /// `y` less its projection on the basis, taken off twice over as the basis was built.
    pub(super) fn residual(&self, y: &[f64]) -> Vec<f64> {
        let mut e = y.to_vec();
        for _ in 0..2 {
            for q in &self.0 {
                let d = dot(q, &e);
                e.iter_mut().zip(q).for_each(|(x, y)| *x -= d * y);
            }
        }
        e
    }

    /// The squared length of `e`'s projection on the basis.
    pub(super) fn along(&self, e: &[f64]) -> f64 {
        self.0.iter().map(|q| dot(q, e).powi(2)).sum()
    }

    /// `cols` made orthonormal to `under` and each other by Gram-Schmidt, twice over for its
    /// accuracy; a column dependent on the others adds nothing.
    pub(super) fn beyond(under: &Basis, cols: &[Vec<f64>]) -> Basis {
        let mut basis = Basis::default();
        for c in cols {
            let mut v = c.clone();
            for _ in 0..2 {
                for b in under.0.iter().chain(&basis.0) {
                    let d = dot(b, &v);
                    v.iter_mut().zip(b).for_each(|(x, y)| *x -= d * y);
                }
            }
            let norm = dot(&v, &v).sqrt();
            if norm > 1e-9 * dot(c, c).sqrt() {
                basis.0.push(v.iter().map(|x| x / norm).collect());
            }
        }
        basis
    }
}

/// The null's basis and the effect's columns beyond it, for the RSS of many rates under
/// both.
pub(super) struct Nested<'v> {
    null: &'v Basis,
    extra: Arc<Basis>,
}

impl<'v> Nested<'v> {
    /// `extra` a basis beyond `null` ([`Basis::beyond`]).
    pub(super) fn new(null: &'v Basis, extra: Arc<Basis>) -> Nested<'v> {
        Nested { null, extra }
    }

    /// The RSS of `W` rate vectors side by side (row `i` their `i`th values), under the
    /// null and under the larger design.
    fn rss_block<const W: usize>(&self, y: &[[f64; W]]) -> [(f64, f64); W] {
        let norm = norm_block(y);
        let mut along = [-0.0; W];
        let mut add = |basis: &Basis| {
            for q in &basis.0 {
                let dot = dot_block(q, y);
                for b in 0..W {
                    along[b] += dot[b].powi(2);
                }
            }
            along
        };
        let small = add(self.null);
        let large = add(&self.extra);
        core::array::from_fn(|b| ((norm[b] - small[b]).max(0.0), (norm[b] - large[b]).max(0.0)))
    }
}

/// A step of the bias in time, `1 (t >= t_j)`, at the best of the change points `j` the jump's
/// scan tries, beyond the null's whitened design: its RSS for a rate vector `y` whitened by
/// `W` is the null's less the largest `((W^T e) . s_j)^2 / |P W s_j|^2`, with `e` the null's
/// residual and `P` the projection off the null's span, every `j` in O(n r) through the
/// adjoint's suffix sums (the rows in time order, as the scan takes them).
pub(super) struct Steps<'v> {
    null: &'v Basis,
    /// `|P W s_j|^2` per change point, 0 where it is not tried.
    norms: Vec<f64>,
}

impl<'v> Steps<'v> {
    /// The steps at change points `tried` (row indices) under `cov`, beyond the null's
    /// basis under it.
    pub(super) fn of(cov: &Cov, null: &'v Basis, tried: std::ops::Range<usize>) -> Steps<'v> {
        let (_, whole) = cov.indicator_and_step_norms();
        let mut norms = whole.clone();
        for back in cov.adjoint_each(&null.0) {
            let mut along = 0.0;
            for j in (0..norms.len()).rev() {
                along += back[j];
                norms[j] -= along * along;
            }
        }
        for (j, (norm, whole)) in norms.iter_mut().zip(&whole).enumerate() {
            // A step (nearly) in the null's span adds nothing.
            if !tried.contains(&j) || *norm <= 1e-9 * whole {
                *norm = 0.0;
            }
        }
        Steps { null, norms }
    }

    fn rss_block<const W: usize>(&self, cov: &Cov, y: &[[f64; W]]) -> [(f64, f64); W] {
        let mut e = y.to_vec();
        for q in &self.null.0 {
            let dot = dot_block(q, &e);
            for (x, row) in q.iter().zip(e.iter_mut()) {
                for b in 0..W {
                    row[b] -= dot[b] * x;
                }
            }
        }
        let small = norm_block(&e);
        let back = cov.adjoint_block(&e);
        let (mut along, mut most) = ([0.0; W], [0.0f64; W]);
        for (row, &norm) in back.iter().zip(&self.norms).rev() {
            for b in 0..W {
                along[b] += row[b];
                if norm > 0.0 {
                    most[b] = most[b].max(along[b] * along[b] / norm);
                }
            }
        }
        core::array::from_fn(|b| (small[b], (small[b] - most[b]).max(0.0)))
    }
}

/// `a . b`, summed in four lanes (which the compiler may keep in one register).
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut lanes = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            lanes[k] += x[k] * y[k];
        }
    }
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
}

/// `q . y` for `W` vectors side by side.
fn dot_block<const W: usize>(q: &[f64], y: &[[f64; W]]) -> [f64; W] {
    let mut dot = [-0.0; W];
    for (x, row) in q.iter().zip(y) {
        for b in 0..W {
            dot[b] += x * row[b];
        }
    }
    dot
}

/// `|y|^2` for `W` vectors side by side.
fn norm_block<const W: usize>(y: &[[f64; W]]) -> [f64; W] {
    let mut norm = [-0.0; W];
    for row in y {
        for b in 0..W {
            norm[b] += row[b] * row[b];
        }
    }
    norm
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gls::WindowSet;
    use nf_model::noise::NoiseModel;
    use nf_model::rng::Rng;

    #[test]
    fn steps_give_the_rss_of_the_best_step_column() {
        let mut rng = Rng::new(3);
        let n = 30;
        let t: Vec<f64> = (0..n).map(|i| 2.0 * i as f64 + rng.uniform(0.0, 0.5)).collect();
        let model = NoiseModel {
            bias_instability_dph: 0.01,
            rrw_dph_rth: 0.05,
            ..NoiseModel::white(0.01, 1.0)
        };
        let cov = WindowSet::new(&t, &vec![1.0; n]).cov(&model).unwrap();
        let null: Vec<Vec<f64>> = [vec![1.0; n], t.iter().map(|v| (v / 9.0).sin()).collect()]
            .iter()
            .map(|c| cov.whiten(c))
            .collect();
        let basis = Basis::of(&null);
        let steps = Steps::of(&cov, &basis, 2..n - 2);
        for _ in 0..5 {
            let y: Vec<[f64; 2]> = (0..n).map(|_| [rng.gauss(), rng.gauss()]).collect();
            let got = steps.rss_block(&cov, &y);
            for b in 0..2 {
                let one: Vec<[f64; 1]> = y.iter().map(|row| [row[b]]).collect();
                let (small, large) = (2..n - 2)
                    .map(|j| {
                        let step: Vec<f64> = (0..n).map(|i| f64::from(u8::from(i >= j))).collect();
                        Nested::new(&basis, Arc::new(Basis::beyond(&basis, &[cov.whiten(&step)]))).rss_block(&one)[0]
                    })
                    .fold((0.0, f64::MAX), |(_, l), (s, x)| (s, l.min(x)));
                let close = |a: f64, e: f64| (a - e).abs() <= 1e-9 * e;
                assert!(
                    close(got[b].0, small) && close(got[b].1, large),
                    "{:?} against {small}, {large}",
                    got[b]
                );
            }
        }
    }
}
