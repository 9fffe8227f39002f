//! Generalised least squares under a gyro noise model: the covariance of the dwell means comes
//! from `nf_model::noise`, is factored by Cholesky, and the whitened problem goes to the host's
//! one least-squares solver ([`crate::linfit`]).
//!
//! Flicker and random walk give covariances defined up to a constant (see `nf_model::noise`).
//! A constant `c 1 1^T` added to the covariance changes neither the GLS estimate of any
//! coefficient other than the constant's nor its covariance, nor the restricted likelihood,
//! when the design has a constant column (Rao's condition): so one is added to make the
//! matrix positive definite.

use crate::linfit;
use crate::semisep::{Semisep, Windows};
use nf_model::noise::NoiseModel;
use std::sync::Arc;

/// A symmetric positive definite matrix, factored.
#[derive(Debug, Clone)]
pub struct Cov {
    factor: Factor,
}

#[derive(Debug, Clone)]
enum Factor {
    /// Lower Cholesky factor `L` with `L L^T = Sigma`, n x n row-major.
    Dense { n: usize, chol: Vec<f64> },
    /// Dwell means of windows apart: O(n) to factor and to whiten.
    Windows(Semisep),
}

/// `map` applied to each of the `W` vectors of a block.
fn by_columns<const W: usize>(block: &[[f64; W]], map: impl Fn(&[f64]) -> Vec<f64>) -> Vec<[f64; W]> {
    let mut out = vec![[0.0; W]; block.len()];
    for b in 0..W {
        let column: Vec<f64> = block.iter().map(|row| row[b]).collect();
        for (row, v) in out.iter_mut().zip(map(&column)) {
            row[b] = v;
        }
    }
    out
}

/// What [`Cov::each`] does to each vector.
#[derive(Clone, Copy)]
enum Op {
    Whiten,
    Adjoint,
}

/// Windows beyond which the dense fallback of [`Cov::of_windows`] is refused: its n x n matrix
/// would take more than 32 MB, and the outlier and jump scans under it minutes.
const DENSE_LIMIT: usize = 2000;

/// The covariance of window means of the gyro rate: centres `t_s`, lengths `dwell_s`.
pub(crate) fn window_covariance(model: &NoiseModel, t_s: &[f64], dwell_s: &[f64]) -> Vec<f64> {
    let n = t_s.len();
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let v = model.mean_cov(t_s[j] - t_s[i], dwell_s[i], dwell_s[j], i == j);
            m[i * n + j] = v;
            m[j * n + i] = v;
        }
    }
    m
}

impl Cov {
    /// The covariance of the means of windows centred at `t_s`, of lengths `dwell_s`, under
    /// `model`: semiseparable when the windows are apart, as they are in a recording; dense
    /// (exact flicker, O(n^3)) when they overlap, up to [`DENSE_LIMIT`] windows. Defined up
    /// to a constant, like [`window_covariance`]: for designs with a constant column.
    pub fn of_windows(model: &NoiseModel, t_s: &[f64], dwell_s: &[f64]) -> Option<Cov> {
        WindowSet::new(t_s, dwell_s).cov(model)
    }

    pub fn semiseparable(s: Semisep) -> Cov {
        Cov {
            factor: Factor::Windows(s),
        }
    }

    /// Factors `sigma` (n x n, row-major), first adding a constant to every element that makes
    /// a generalised covariance positive definite. `None` if it cannot be made so.
    pub fn new(sigma: &[f64], n: usize) -> Option<Cov> {
        let scale = sigma.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        if !(scale.is_finite() && scale > 0.0) {
            return None;
        }
        let mut shift = 0.0;
        for _ in 0..6 {
            if let Some(chol) = cholesky(sigma, n, shift) {
                return Some(Cov::dense(n, chol));
            }
            shift = if shift == 0.0 { 4.0 * scale } else { shift * 10.0 };
        }
        None
    }

    /// Factors a true covariance as it is, with no constant added; `None` if it is not
    /// positive definite.
    pub fn exact(sigma: &[f64], n: usize) -> Option<Cov> {
        cholesky(sigma, n, 0.0).map(|chol| Cov::dense(n, chol))
    }

    fn dense(n: usize, chol: Vec<f64>) -> Cov {
        Cov {
            factor: Factor::Dense { n, chol },
        }
    }

    /// A whitening of `v`: `W v` with `W^T W = Sigma^-1` (`L^-1 v` for the dense factor).
    pub fn whiten(&self, v: &[f64]) -> Vec<f64> {
        match &self.factor {
            Factor::Dense { n, chol } => {
                let n = *n;
                let mut out = vec![0.0; n];
                for i in 0..n {
                    let s: f64 = (0..i).map(|k| chol[i * n + k] * out[k]).sum();
                    out[i] = (v[i] - s) / chol[i * n + i];
                }
                out
            }
            Factor::Windows(s) => s.whiten(v),
        }
    }

    /// `W^-1 z`, the inverse of [`Cov::whiten`]: from independent unit normals `z`, a draw
    /// with this covariance (up to the constant a generalised covariance leaves free).
    pub fn colour(&self, z: &[f64]) -> Vec<f64> {
        match &self.factor {
            Factor::Dense { n, chol } => (0..*n).map(|i| (0..=i).map(|k| chol[i * n + k] * z[k]).sum()).collect(),
            Factor::Windows(s) => s.colour(z),
        }
    }

    /// [`Cov::whiten`] of `W` vectors side by side (row `i` holds their `i`th values).
    pub fn whiten_block<const W: usize>(&self, v: &[[f64; W]]) -> Vec<[f64; W]> {
        match &self.factor {
            Factor::Dense { .. } => by_columns(v, |c| self.whiten(c)),
            Factor::Windows(s) => s.whiten_block(v),
        }
    }

    /// [`Cov::whiten`] of each of `vs`, four side by side ([`Cov::whiten_block`]): the same
    /// arithmetic, each factor read once per four.
    pub fn whiten_each<V: AsRef<[f64]>>(&self, vs: &[V]) -> Vec<Vec<f64>> {
        self.each(Op::Whiten, vs)
    }

    /// [`Cov::adjoint`] of each of `vs`, as [`Cov::whiten_each`].
    pub fn adjoint_each<V: AsRef<[f64]>>(&self, vs: &[V]) -> Vec<Vec<f64>> {
        self.each(Op::Adjoint, vs)
    }

    fn each<V: AsRef<[f64]>>(&self, op: Op, vs: &[V]) -> Vec<Vec<f64>> {
        let mut out = Vec::with_capacity(vs.len());
        for chunk in vs.chunks(4) {
            match chunk.len() {
                4 => out.extend(self.side_by_side::<4, V>(op, chunk)),
                3 => out.extend(self.side_by_side::<3, V>(op, chunk)),
                2 => out.extend(self.side_by_side::<2, V>(op, chunk)),
                _ => out.extend(self.side_by_side::<1, V>(op, chunk)),
            }
        }
        out
    }

    fn side_by_side<const W: usize, V: AsRef<[f64]>>(&self, op: Op, vs: &[V]) -> Vec<Vec<f64>> {
        let n = vs.first().map_or(0, |v| v.as_ref().len());
        let block: Vec<[f64; W]> = (0..n).map(|i| core::array::from_fn(|b| vs[b].as_ref()[i])).collect();
        let done = match op {
            Op::Whiten => self.whiten_block(&block),
            Op::Adjoint => self.adjoint_block(&block),
        };
        (0..W).map(|b| done.iter().map(|row| row[b]).collect()).collect()
    }

    /// [`Cov::colour`] of `W` vectors side by side.
    pub fn colour_block<const W: usize>(&self, z: &[[f64; W]]) -> Vec<[f64; W]> {
        match &self.factor {
            Factor::Dense { .. } => by_columns(z, |c| self.colour(c)),
            Factor::Windows(s) => s.colour_block(z),
        }
    }

    /// `W^T v`, the adjoint of [`Cov::whiten`].
    pub fn adjoint(&self, v: &[f64]) -> Vec<f64> {
        match &self.factor {
            Factor::Dense { n, chol } => {
                let n = *n;
                let mut out = vec![0.0; n];
                for i in (0..n).rev() {
                    let s: f64 = (i + 1..n).map(|k| chol[k * n + i] * out[k]).sum();
                    out[i] = (v[i] - s) / chol[i * n + i];
                }
                out
            }
            Factor::Windows(s) => s.adjoint(v),
        }
    }

    /// [`Cov::adjoint`] of `W` vectors side by side.
    pub fn adjoint_block<const W: usize>(&self, v: &[[f64; W]]) -> Vec<[f64; W]> {
        match &self.factor {
            Factor::Dense { .. } => by_columns(v, |c| self.adjoint(c)),
            Factor::Windows(s) => s.adjoint_block(v),
        }
    }

    /// `|W e_i|^2` and `|W s_i|^2` for every row `i`, `s_i` the step that is 1 from row `i`
    /// on, the rows in time order.
    pub fn indicator_and_step_norms(&self) -> (Vec<f64>, Vec<f64>) {
        match &self.factor {
            Factor::Dense { n, .. } => {
                let norm = |x: Vec<f64>| self.whiten(&x).iter().map(|v| v * v).sum::<f64>();
                let cut = |i: usize, step: bool| (0..*n).map(move |k| f64::from(u8::from(k == i || (step && k > i))));
                (0..*n)
                    .map(|i| (norm(cut(i, false).collect()), norm(cut(i, true).collect())))
                    .unzip()
            }
            Factor::Windows(s) => s.indicator_and_step_norms(),
        }
    }

    /// `ln det Sigma`.
    pub fn log_det(&self) -> f64 {
        match &self.factor {
            Factor::Dense { n, chol } => (0..*n).map(|i| 2.0 * chol[i * n + i].ln()).sum(),
            Factor::Windows(s) => s.log_det(),
        }
    }
}

fn cholesky(a: &[f64], n: usize, shift: f64) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let s: f64 = (0..j).map(|k| l[i * n + k] * l[j * n + k]).sum();
            let v = a[i * n + j] + shift - s;
            if i == j {
                if v.is_nan() || v <= 0.0 {
                    return None;
                }
                l[i * n + i] = v.sqrt();
            } else {
                l[i * n + j] = v / l[j * n + j];
            }
        }
    }
    Some(l)
}

/// Windows whose covariance is wanted under several noise models: what the models share
/// (flicker's ladder, every window's gains and decays) is worked out once.
pub struct WindowSet {
    t_s: Vec<f64>,
    dwell_s: Vec<f64>,
    /// `None` when the windows overlap or are not usable.
    shared: Option<Arc<Windows>>,
}

impl WindowSet {
    pub fn new(t_s: &[f64], dwell_s: &[f64]) -> WindowSet {
        WindowSet {
            shared: Windows::new(t_s, dwell_s).map(Arc::new),
            t_s: t_s.to_vec(),
            dwell_s: dwell_s.to_vec(),
        }
    }

    /// How many windows there are.
    pub fn count(&self) -> usize {
        self.t_s.len()
    }

    /// [`Cov::of_windows`] of these windows under `model`.
    pub fn cov(&self, model: &NoiseModel) -> Option<Cov> {
        self.cov_plus(model, None)
    }

    /// [`WindowSet::cov`] with `extra[i]` added to window `i`'s variance: a disturbance of
    /// that window's mean alone.
    pub fn cov_plus(&self, model: &NoiseModel, extra: Option<&[f64]>) -> Option<Cov> {
        let n = self.t_s.len();
        match self.shared.as_ref().and_then(|w| w.factor(model, extra)) {
            Some(s) => Some(Cov::semiseparable(s)),
            None if n <= DENSE_LIMIT => {
                let mut m = window_covariance(model, &self.t_s, &self.dwell_s);
                for (i, e) in extra.into_iter().flatten().enumerate() {
                    m[i * n + i] += e;
                }
                Cov::new(&m, n)
            }
            None => None,
        }
    }
}

/// A GLS fit.
#[derive(Debug, Clone)]
pub struct Gls {
    pub coef: Vec<f64>,
    /// Covariance of the coefficients under the noise model (not rescaled by the residuals).
    pub cov: Vec<Vec<f64>>,
    /// `y - X beta`, unwhitened.
    pub resid: Vec<f64>,
    /// Whitened residual sum of squares: chi-square with `dof` degrees of freedom if the
    /// model is right.
    pub chi2: f64,
    pub dof: usize,
    /// Restricted (REML) log-likelihood, up to a constant that depends only on the design.
    pub reml_loglik: f64,
}

/// GLS of `y ~ cols` under the factored covariance `cov`; `None` when the columns are dependent.
pub fn fit(cols: &[Vec<f64>], y: &[f64], cov: &Cov) -> Option<Gls> {
    let wcols: Vec<Vec<f64>> = cols.iter().map(|c| cov.whiten(c)).collect();
    let ls = linfit::fit_exact(&wcols, &cov.whiten(y))?;
    let resid = (0..y.len())
        .map(|i| y[i] - cols.iter().zip(&ls.coef).map(|(c, b)| c[i] * b).sum::<f64>())
        .collect();
    // ln det(X^T Sigma^-1 X) = -ln det of the unit covariance.
    let log_det_info = -log_det_spd(&ls.cov_unit)?;
    Some(Gls {
        reml_loglik: -0.5 * (cov.log_det() + log_det_info + ls.rss),
        coef: ls.coef,
        cov: ls.cov_unit,
        resid,
        chi2: ls.rss,
        dof: ls.dof,
    })
}

fn log_det_spd(m: &[Vec<f64>]) -> Option<f64> {
    let n = m.len();
    let flat: Vec<f64> = m.iter().flatten().copied().collect();
    cholesky(&flat, n, 0.0).map(|l| (0..n).map(|i| 2.0 * l[i * n + i].ln()).sum())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nf_model::rng::Rng;

    #[test]
    fn vectors_whitened_four_side_by_side_are_whitened_one_at_a_time() {
        let mut rng = Rng::new(9);
        let t: Vec<f64> = (0..30).map(|i| 1.4 * i as f64 + rng.uniform(0.0, 0.3)).collect();
        let model = NoiseModel {
            bias_instability_dph: 0.01,
            rrw_dph_rth: 0.03,
            ..NoiseModel::white(0.01, 1.0)
        };
        let dense = Cov::new(&window_covariance(&model, &t, &vec![1.0; t.len()]), t.len()).unwrap();
        let windows = Cov::of_windows(&model, &t, &vec![1.0; t.len()]).unwrap();
        for cov in [dense, windows] {
            for count in [1, 5, 6, 7, 8] {
                let vs: Vec<Vec<f64>> = (0..count).map(|_| t.iter().map(|_| rng.gauss()).collect()).collect();
                let one: Vec<Vec<f64>> = vs.iter().map(|v| cov.whiten(v)).collect();
                assert_eq!(cov.whiten_each(&vs), one, "{count} whitened");
                let one: Vec<Vec<f64>> = vs.iter().map(|v| cov.adjoint(v)).collect();
                assert_eq!(cov.adjoint_each(&vs), one, "{count} adjoined");
            }
        }
    }

    #[test]
    fn equals_ordinary_least_squares_on_white_noise() {
        let mut rng = Rng::new(4);
        let n = 40;
        let t: Vec<f64> = (0..n).map(|i| 3.0 * i as f64).collect();
        let cols = vec![vec![1.0; n], t.iter().map(|v| (v / 20.0).cos()).collect()];
        let y: Vec<f64> = (0..n).map(|i| 1.0 + 2.0 * cols[1][i] + 0.1 * rng.gauss()).collect();
        let model = NoiseModel::white(0.1, 2.0);
        let cov = Cov::new(&window_covariance(&model, &t, &vec![2.0; n]), n).unwrap();
        let g = fit(&cols, &y, &cov).unwrap();
        let o = linfit::fit(&cols, &y).unwrap();
        for k in 0..2 {
            assert!((g.coef[k] - o.coef[k]).abs() < 1e-12);
            // Known white variance 0.01: the GLS covariance is the OLS unit covariance times it.
            assert!((g.cov[k][k] / (o.cov_unit[k][k] * 0.01) - 1.0).abs() < 1e-9);
        }
        assert!((g.chi2 - o.rss / 0.01).abs() < 1e-6 * g.chi2);
    }

    #[test]
    fn overlapping_windows_fall_back_to_the_dense_factor_only_when_small() {
        let model = NoiseModel {
            bias_instability_dph: 0.01,
            ..NoiseModel::white(0.01, 2.0)
        };
        let over = |n: usize| Cov::of_windows(&model, &(0..n).map(|i| i as f64).collect::<Vec<_>>(), &vec![2.0; n]);
        assert!(matches!(over(50).map(|c| c.factor), Some(Factor::Dense { .. })));
        assert!(over(DENSE_LIMIT + 1).is_none());
    }

    #[test]
    fn the_constant_added_for_flicker_changes_no_contrast() {
        // Two different shifts must give the same slope, its variance and the REML likelihood.
        let model = NoiseModel {
            bias_instability_dph: 0.02,
            rrw_dph_rth: 0.01,
            ..NoiseModel::white(0.005, 2.0)
        };
        let n = 30;
        let t: Vec<f64> = (0..n).map(|i| 5.0 * i as f64).collect();
        let sigma = window_covariance(&model, &t, &vec![2.0; n]);
        let cols = vec![vec![1.0; n], t.iter().map(|v| (v / 40.0).sin()).collect()];
        let y: Vec<f64> = t.iter().map(|v| 0.3 + (v / 17.0).cos() * 0.01).collect();
        let a = fit(&cols, &y, &Cov::new(&sigma, n).unwrap()).unwrap();
        let shifted: Vec<f64> = sigma.iter().map(|v| v + 1.0).collect();
        let b = fit(&cols, &y, &Cov::new(&shifted, n).unwrap()).unwrap();
        assert!((a.coef[1] - b.coef[1]).abs() < 1e-9 * a.coef[1].abs().max(1e-6));
        assert!((a.cov[1][1] / b.cov[1][1] - 1.0).abs() < 1e-6);
        assert!((a.reml_loglik - b.reml_loglik).abs() < 1e-6);
    }

    #[test]
    fn colour_inverts_the_whitening_and_draws_the_covariance() {
        let model = NoiseModel {
            bias_instability_dph: 0.02,
            rrw_dph_rth: 0.05,
            gm_sigma_dph: 0.01,
            gm_tau_s: 20.0,
            ..NoiseModel::white(0.01, 2.0)
        };
        let n = 24;
        let t: Vec<f64> = (0..n).map(|i| 2.5 * i as f64 + 0.1 * (i % 3) as f64).collect();
        let sigma = window_covariance(&model, &t, &vec![2.0; n]);
        let dense = Cov::new(&sigma, n).unwrap();
        let windows = Cov::of_windows(&model, &t, &vec![2.0; n]).unwrap();
        assert!(matches!(windows.factor, Factor::Windows(_)));
        let mut rng = Rng::new(8);
        for cov in [&dense, &windows] {
            let z: Vec<f64> = (0..n).map(|_| rng.gauss()).collect();
            let back = cov.whiten(&cov.colour(&z));
            assert!(z.iter().zip(&back).all(|(a, b)| (a - b).abs() < 1e-9));
            // Contrasts of the draws have the closed form's variance (a first and a last
            // difference; the free constant drops out of both).
            let (draws, pairs) = (4000, [(0, 1), (0, n - 1), (5, 11)]);
            for (i, j) in pairs {
                let want = sigma[i * n + i] + sigma[j * n + j] - 2.0 * sigma[i * n + j];
                let got = (0..draws)
                    .map(|_| {
                        let v = cov.colour(&(0..n).map(|_| rng.gauss()).collect::<Vec<_>>());
                        (v[i] - v[j]).powi(2)
                    })
                    .sum::<f64>()
                    / draws as f64;
                assert!((got / want - 1.0).abs() < 0.07, "({i}, {j}): {got} vs {want}");
            }
        }
    }

    #[test]
    fn a_dense_factor_whitens_and_colours_blocks_column_by_column() {
        let n = 12;
        let t: Vec<f64> = (0..n).map(|i| 3.0 * i as f64).collect();
        let sigma = window_covariance(&NoiseModel::white(0.01, 2.0), &t, &vec![2.0; n]);
        let dense = Cov::new(&sigma, n).unwrap();
        let mut rng = Rng::new(3);
        let block: Vec<[f64; 2]> = (0..n).map(|_| [rng.gauss(), rng.gauss()]).collect();
        let (white, coloured) = (dense.whiten_block(&block), dense.colour_block(&block));
        for b in 0..2 {
            let column: Vec<f64> = block.iter().map(|row| row[b]).collect();
            assert_eq!(
                white.iter().map(|row| row[b]).collect::<Vec<_>>(),
                dense.whiten(&column)
            );
            assert_eq!(
                coloured.iter().map(|row| row[b]).collect::<Vec<_>>(),
                dense.colour(&column)
            );
        }
    }
}
