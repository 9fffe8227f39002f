//! Dense least squares for the host (modified Gram-Schmidt QR): coefficients, residuals,
//! leverages and coefficient variances, for models with any number of columns.

#[derive(Debug, Clone)]
pub struct Ls {
    pub coef: Vec<f64>,
    pub resid: Vec<f64>,
    pub rss: f64,
    /// Leverage `h_ii` of each row.
    pub hat: Vec<f64>,
    /// `(X^T X)^-1`: multiply by `s2` for the covariance.
    pub cov_unit: Vec<Vec<f64>>,
    pub dof: usize,
}

impl Ls {
    pub fn s2(&self) -> f64 {
        if self.dof > 0 {
            self.rss / self.dof as f64
        } else {
            f64::NAN
        }
    }

    pub fn sigma(&self, k: usize) -> f64 {
        (self.cov_unit[k][k] * self.s2()).sqrt()
    }
}

/// Fits `y ~ cols`; `None` when the columns are (numerically) dependent or too many to leave
/// a residual degree of freedom.
pub fn fit(cols: &[Vec<f64>], y: &[f64]) -> Option<Ls> {
    solve(&slices(cols), y, 1)
}

/// [`fit`] of columns kept elsewhere, which need not be copied into one design first.
pub fn fit_slices(cols: &[&[f64]], y: &[f64]) -> Option<Ls> {
    solve(cols, y, 1)
}

/// As [`fit`], but as many rows as columns are allowed: an exact fit, for a noise known from
/// elsewhere (GLS under a given covariance).
pub fn fit_exact(cols: &[Vec<f64>], y: &[f64]) -> Option<Ls> {
    solve(&slices(cols), y, 0)
}

fn slices(cols: &[Vec<f64>]) -> Vec<&[f64]> {
    cols.iter().map(Vec::as_slice).collect()
}

fn solve(cols: &[&[f64]], y: &[f64], min_dof: usize) -> Option<Ls> {
    let (n, p) = (y.len(), cols.len());
    if p == 0 || n < p + min_dof {
        return None;
    }
    let mut q: Vec<Vec<f64>> = cols.iter().map(|c| c.to_vec()).collect();
    let mut r = vec![vec![0.0; p]; p];
    for j in 0..p {
        let norm0 = q[j].iter().map(|v| v * v).sum::<f64>().sqrt();
        let (done, rest) = q.split_at_mut(j);
        let qj = &mut rest[0];
        for (i, qi) in done.iter().enumerate() {
            let d: f64 = qi.iter().zip(qj.iter()).map(|(a, b)| a * b).sum();
            r[i][j] = d;
            for (v, a) in qj.iter_mut().zip(qi) {
                *v -= d * a;
            }
        }
        let norm = q[j].iter().map(|v| v * v).sum::<f64>().sqrt();
        // Dependent on the earlier columns (or NaN).
        if norm.is_nan() || norm <= 1e-9 * norm0.max(1e-300) {
            return None;
        }
        r[j][j] = norm;
        for v in &mut q[j] {
            *v /= norm;
        }
    }
    let qty: Vec<f64> = q.iter().map(|c| c.iter().zip(y).map(|(a, b)| a * b).sum()).collect();
    let mut coef = vec![0.0; p];
    for i in (0..p).rev() {
        let s: f64 = (i + 1..p).map(|k| r[i][k] * coef[k]).sum();
        coef[i] = (qty[i] - s) / r[i][i];
    }
    let mut rinv = vec![vec![0.0; p]; p];
    for j in 0..p {
        rinv[j][j] = 1.0 / r[j][j];
        for i in (0..j).rev() {
            let s: f64 = (i + 1..=j).map(|k| r[i][k] * rinv[k][j]).sum();
            rinv[i][j] = -s / r[i][i];
        }
    }
    let cov_unit = (0..p)
        .map(|i| (0..p).map(|j| (0..p).map(|k| rinv[i][k] * rinv[j][k]).sum()).collect())
        .collect();
    let resid: Vec<f64> = (0..n)
        .map(|i| y[i] - (0..p).map(|k| cols[k][i] * coef[k]).sum::<f64>())
        .collect();
    let hat = (0..n).map(|i| q.iter().map(|c| c[i] * c[i]).sum()).collect();
    Some(Ls {
        rss: resid.iter().map(|v| v * v).sum(),
        coef,
        resid,
        hat,
        cov_unit,
        dof: n - p,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_line_and_its_leverages() {
        let x: Vec<f64> = (0..5).map(|i| i as f64).collect();
        let y: Vec<f64> = x.iter().map(|v| 2.0 + 3.0 * v).collect();
        let l = fit(&[vec![1.0; 5], x.clone()], &y).unwrap();
        assert!((l.coef[0] - 2.0).abs() < 1e-12 && (l.coef[1] - 3.0).abs() < 1e-12 && l.rss < 1e-20);
        // Leverages of a straight line: 1/n + (x - mean)^2 / Sxx.
        assert!((l.hat[0] - (0.2 + 4.0 / 10.0)).abs() < 1e-12);
        assert!((l.hat.iter().sum::<f64>() - 2.0).abs() < 1e-12);
        assert!((l.cov_unit[1][1] - 0.1).abs() < 1e-12);
        assert!(fit(&[vec![1.0; 5], vec![2.0; 5]], &y).is_none());
    }

    #[test]
    fn an_exact_fit_passes_through_as_many_rows_as_columns() {
        let cols = [vec![1.0, 1.0], vec![0.0, 2.0]];
        let y = [3.0, 7.0];
        assert!(fit(&cols, &y).is_none());
        let l = fit_exact(&cols, &y).unwrap();
        assert!((l.coef[0] - 3.0).abs() < 1e-12 && (l.coef[1] - 2.0).abs() < 1e-12);
        assert!(l.dof == 0 && l.rss < 1e-20);
        // No residual: no variance from it.
        assert!(l.s2().is_nan());
        assert!(fit_exact(&cols, &y[..1]).is_none());
    }
}
