//! The covariance of Allan points under a noise model, built from each term's lag grids at
//! unit size: the second differences' covariances are linear in the terms' variances, so the
//! many models an Allan fit weighs its points by cost one set of lag sums per term.

use crate::allan::Point;
use crate::allan_fit::Term;
use crate::allan_model::{LagGrid, Sampling};
use crate::allan_removed::Removed;
use nf_model::noise::NoiseModel;
use std::cell::RefCell;
use std::rc::Rc;

pub struct PointCov<'a> {
    points: &'a [Point],
    sampling: Sampling,
    lens: &'a [usize],
    /// What was fitted out of the series before its Allan variance.
    removed: Option<&'a Removed>,
    /// Each term's grids at unit size, for every pair of points (row-major, i <= j).
    units: RefCell<Vec<(Term, Rc<Vec<LagGrid>>)>>,
    /// Each term's expected Allan variance at unit size, at every point.
    expected: RefCell<Vec<(Term, Rc<Vec<f64>>)>>,
}

impl<'a> PointCov<'a> {
    /// `removed` counts only for one segment of its length.
    pub fn new(
        points: &'a [Point],
        sampling: Sampling,
        lens: &'a [usize],
        removed: Option<&'a Removed>,
    ) -> PointCov<'a> {
        let removed = removed.filter(|r| lens == [r.values()]);
        PointCov {
            points,
            sampling,
            lens,
            removed,
            units: RefCell::new(Vec::new()),
            expected: RefCell::new(Vec::new()),
        }
    }

    /// A term's expected Allan variance at unit size at every point: a fit's column, the same
    /// in every pass and every support tried.
    pub fn expected(&self, term: Term) -> Rc<Vec<f64>> {
        if let Some((_, e)) = self.expected.borrow().iter().find(|(t, _)| *t == term) {
            return e.clone();
        }
        let unit = term.unit();
        let mut e: Vec<f64> = self
            .points
            .iter()
            .map(|p| match term {
                Term::Ramp => ramp_avar(self.sampling, p.m),
                _ => self.sampling.expected_avar(&unit, p.m),
            })
            .collect();
        if let (Some(r), false) = (self.removed, term == Term::Ramp) {
            let ms: Vec<usize> = self.points.iter().map(|p| p.m).collect();
            for (x, lost) in e.iter_mut().zip(r.loss(&unit, self.sampling, &ms)) {
                *x = (*x - lost).max(0.0);
            }
        }
        let e = Rc::new(e);
        self.expected.borrow_mut().push((term, e.clone()));
        e
    }

    /// The variance under `model` of the mean of every difference of consecutive cluster means
    /// a point's estimate averages (what a ramp's cross term scales). The sum telescopes to the
    /// last `m` cluster means less the first: `m / M` times the difference of two means of
    /// `m` values `M` values apart, `M` the differences in the longest segment (each mean
    /// taken as a plain window rather than the sum's triangle).
    pub fn mean_difference_var(&self, model: &NoiseModel) -> Vec<f64> {
        let longest = self.lens.iter().copied().max().unwrap_or(0);
        self.points
            .iter()
            .map(|p| {
                let terms = (longest + 1).saturating_sub(2 * p.m).max(p.m) as f64;
                let apart = Sampling {
                    step_s: terms * self.sampling.step_s,
                    window_s: p.m as f64 * self.sampling.step_s,
                };
                let share = p.m as f64 / terms;
                share * share * 2.0 * apart.expected_avar(model, 1)
            })
            .collect()
    }

    /// The expected Allan variance under `model` at every point.
    pub fn expected_of(&self, model: &NoiseModel) -> Vec<f64> {
        let mut e = vec![0.0; self.points.len()];
        for (t, size) in Term::sizes(model) {
            for (x, u) in e.iter_mut().zip(self.expected(t).iter()) {
                *x += size * size * u;
            }
        }
        e
    }

    /// The points' covariance under `model`, n x n row-major.
    pub fn of(&self, model: &NoiseModel) -> Vec<f64> {
        let n = self.points.len();
        let terms: Vec<(Rc<Vec<LagGrid>>, f64)> = Term::sizes(model)
            .into_iter()
            .map(|(t, size)| (self.unit(t), size * size))
            .collect();
        let mut sigma = vec![0.0; n * n];
        let Some((first, _)) = terms.first() else { return sigma };
        for (k, (i, j)) in self.pairs().enumerate() {
            let mut g = first[k].zero();
            for (unit, var) in &terms {
                g.add_scaled(&unit[k], *var);
            }
            let v = self.sampling.pooled_cov(&g, self.lens);
            sigma[i * n + j] = v;
            sigma[j * n + i] = v;
        }
        sigma
    }

    fn pairs(&self) -> impl Iterator<Item = (usize, usize)> + use<> {
        let n = self.points.len();
        (0..n).flat_map(move |i| (i..n).map(move |j| (i, j)))
    }

    fn unit(&self, term: Term) -> Rc<Vec<LagGrid>> {
        if let Some((_, u)) = self.units.borrow().iter().find(|(t, _)| *t == term) {
            return u.clone();
        }
        let model = term.unit();
        let m = |i: usize| self.points[i].m;
        let pairs: Vec<(usize, usize)> = self.pairs().map(|(i, j)| (m(i), m(j))).collect();
        let u: Rc<Vec<LagGrid>> = Rc::new(self.sampling.lag_grids(&model, &pairs));
        self.units.borrow_mut().push((term, u.clone()));
        u
    }
}

/// The Allan variance a rate ramp of 1 deg/h per hour gives at factor `m`: consecutive means
/// of `m` values lie `m` steps apart, so their difference is the ramp times that time.
fn ramp_avar(sampling: Sampling, m: usize) -> f64 {
    let dt_h = m as f64 * sampling.step_s / 3600.0;
    0.5 * dt_h * dt_h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::allan::octaves;

    #[test]
    fn the_sum_of_unit_terms_is_the_model_s_covariance() {
        let sampling = Sampling::contiguous(0.01);
        let lens = [200_000];
        let points: Vec<Point> = octaves(200_000)
            .into_iter()
            .map(|m| Point {
                m,
                tau_s: m as f64 * 0.01,
                avar: 1.0,
                terms: 200_001 - 2 * m,
                clusters: 200_000 / m,
            })
            .collect();
        let model = NoiseModel {
            arw_deg_rth: 0.3,
            bias_instability_dph: 2.0,
            rrw_dph_rth: 5.0,
            quantization_arcsec: 0.5,
            gm_sigma_dph: 4.0,
            gm_tau_s: 3.0,
            ..NoiseModel::WHITE_NONE
        };
        let cov = PointCov::new(&points, sampling, &lens, None);
        let sum = cov.of(&model);
        let n = points.len();
        for i in 0..n {
            for j in 0..n {
                let direct = sampling.avar_cov(&model, points[i].m, points[j].m, &lens);
                assert!(
                    (sum[i * n + j] - direct).abs() <= 1e-9 * direct.abs().max(1e-300),
                    "({i}, {j})"
                );
            }
        }
    }
}
