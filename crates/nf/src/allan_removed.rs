//! What removing a fit from a series costs its Allan variance. A recording's dwell means are
//! read after its bias and Earth-rate harmonic are fitted out (least squares on the columns
//! `X`): the residuals are `P x`, `P = I - X (X'X)^-1 X'`, and the harmonic, one cycle per
//! run, takes the slowest noise with it (a walk's Allan variance at the longest averaging time
//! of 72 dwells by a fifth). Each second difference `a` of cluster means is a contrast, as is
//! `P a` (the columns hold a constant), so under the model's generalised covariance `G` of the
//! means `E (a' P x)^2 = a'Ga - 2 a'G X M X'a + a'X M X'G X M X'a`, `M = (X'X)^-1`: the first
//! term is the Allan variance without the fit, the rest what the fit took.

use crate::allan::second_difference;
use crate::allan_model::Sampling;
use crate::linfit;
use crate::toeplitz;
use nf_model::noise::NoiseModel;

/// The columns fitted out of one contiguous series, in its time order.
#[derive(Debug, Clone, PartialEq)]
pub struct Removed {
    cols: Vec<Vec<f64>>,
    /// Their prefix sums, for every second difference of cluster means.
    sums: Vec<Vec<f64>>,
    /// The columns' transforms, for `G X` with each model's `G`.
    spectra: toeplitz::Vectors,
    /// `(X'X)^-1`.
    inv: Vec<Vec<f64>>,
}

impl Removed {
    /// `None` when the columns are dependent or do not span the series' length.
    pub fn new(cols: Vec<Vec<f64>>) -> Option<Removed> {
        let n = cols.first()?.len();
        if cols.iter().any(|c| c.len() != n) {
            return None;
        }
        let inv = linfit::fit(&cols, &vec![0.0; n])?.cov_unit;
        let spectra = toeplitz::Vectors::of(&cols);
        let sums = cols.iter().map(|c| prefix(c)).collect();
        Some(Removed {
            cols,
            sums,
            spectra,
            inv,
        })
    }

    /// The values in the series.
    pub fn values(&self) -> usize {
        self.cols[0].len()
    }

    /// The expected Allan variance the fit takes from `model`'s noise at each factor in `ms`.
    pub fn loss(&self, model: &NoiseModel, sampling: Sampling, ms: &[usize]) -> Vec<f64> {
        let n = self.values();
        let w = sampling.window_s;
        let g: Vec<f64> = (0..n)
            .map(|k| model.mean_cov(k as f64 * sampling.step_s, w, w, k == 0))
            .collect();
        // G X, G Toeplitz in the lag.
        let gx = self.spectra.times(&g);
        let xgx: Vec<Vec<f64>> = self
            .cols
            .iter()
            .map(|a| gx.iter().map(|b| dot(a, b)).collect())
            .collect();
        let mid = product(&product(&self.inv, &xgx), &self.inv);
        let (sx, sgx) = (&self.sums, gx.iter().map(|c| prefix(c)).collect::<Vec<_>>());
        ms.iter()
            .map(|&m| {
                let starts = (n + 1).saturating_sub(2 * m);
                if starts == 0 {
                    return 0.0;
                }
                // Sums over the differences of v u' and u u', then weighed by M and M X'GX M.
                let k = sx.len();
                let (mut vu, mut uu) = (vec![vec![0.0; k]; k], vec![vec![0.0; k]; k]);
                let (mut u, mut v) = (vec![0.0; k], vec![0.0; k]);
                for j in 0..starts {
                    for c in 0..k {
                        u[c] = second_difference(&sx[c], j, m);
                        v[c] = second_difference(&sgx[c], j, m);
                    }
                    for p in 0..k {
                        for q in 0..k {
                            vu[p][q] += v[p] * u[q];
                            uu[p][q] += u[p] * u[q];
                        }
                    }
                }
                let weigh = |a: &[Vec<f64>], s: &[Vec<f64>]| -> f64 { a.iter().zip(s).map(|(x, y)| dot(x, y)).sum() };
                (2.0 * weigh(&self.inv, &vu) - weigh(&mid, &uu)) / (2.0 * starts as f64)
            })
            .collect()
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn product(a: &[Vec<f64>], b: &[Vec<f64>]) -> Vec<Vec<f64>> {
    a.iter()
        .map(|row| {
            (0..b[0].len())
                .map(|j| row.iter().zip(b).map(|(x, r)| x * r[j]).sum())
                .collect()
        })
        .collect()
}

fn prefix(v: &[f64]) -> Vec<f64> {
    let mut s = vec![0.0; v.len() + 1];
    for (i, x) in v.iter().enumerate() {
        s[i + 1] = s[i] + x;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The expected Allan variance of the residuals, by brute force: `P G P` built whole.
    fn brute(cols: &[Vec<f64>], model: &NoiseModel, s: Sampling, m: usize) -> f64 {
        let n = cols[0].len();
        let inv = linfit::fit(cols, &vec![0.0; n]).unwrap().cov_unit;
        let p: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let h: f64 = (0..cols.len())
                            .flat_map(|a| (0..cols.len()).map(move |b| (a, b)))
                            .map(|(a, b)| cols[a][i] * inv[a][b] * cols[b][j])
                            .sum();
                        f64::from(u8::from(i == j)) - h
                    })
                    .collect()
            })
            .collect();
        let g = |i: usize, j: usize| model.mean_cov(i.abs_diff(j) as f64 * s.step_s, s.window_s, s.window_s, i == j);
        let starts = n + 1 - 2 * m;
        let mut total = 0.0;
        for j in 0..starts {
            let a: Vec<f64> = (0..n)
                .map(|i| match i {
                    i if (j..j + m).contains(&i) => -1.0 / m as f64,
                    i if (j + m..j + 2 * m).contains(&i) => 1.0 / m as f64,
                    _ => 0.0,
                })
                .collect();
            let pa: Vec<f64> = p.iter().map(|row| dot(row, &a)).collect();
            total += (0..n)
                .map(|i| (0..n).map(|k| pa[i] * g(i, k) * pa[k]).sum::<f64>())
                .sum::<f64>();
        }
        total / (2.0 * starts as f64)
    }

    #[test]
    fn the_loss_is_what_the_residuals_lose_by_brute_force() {
        let n = 40;
        let cols: Vec<Vec<f64>> = vec![
            vec![1.0; n],
            (0..n).map(|i| (i as f64 * 0.157).cos()).collect(),
            (0..n).map(|i| (i as f64 * 0.157).sin()).collect(),
        ];
        let s = Sampling {
            step_s: 3.0,
            window_s: 2.0,
        };
        let walk = NoiseModel {
            arw_deg_rth: 0.003,
            bias_instability_dph: 0.01,
            rrw_dph_rth: 0.05,
            ..NoiseModel::WHITE_NONE
        };
        let removed = Removed::new(cols.clone()).unwrap();
        let ms = [1, 2, 4, 8];
        for (m, lost) in ms.iter().zip(removed.loss(&walk, s, &ms)) {
            let left = brute(&cols, &walk, s, *m);
            let whole = s.expected_avar(&walk, *m);
            assert!(
                ((whole - lost) / left - 1.0).abs() < 1e-9,
                "m {m}: {whole} - {lost} against {left}"
            );
            assert!(lost > 0.0 && lost < whole, "m {m}: {lost} of {whole}");
        }
    }

    #[test]
    fn dependent_or_ragged_columns_are_refused() {
        assert!(Removed::new(vec![vec![1.0; 5], vec![2.0; 5]]).is_none());
        assert!(Removed::new(vec![vec![1.0; 5], vec![1.0; 4]]).is_none());
        assert!(Removed::new(Vec::new()).is_none());
    }
}
