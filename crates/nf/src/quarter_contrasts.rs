//! The short-time noise inside each dwell: the three Helmert contrasts of its four quarter
//! means, orthogonal to the dwell mean, whose scatter over the dwells enters every noise
//! likelihood beside the dwell means.

use nf_model::noise::NoiseModel;
use std::f64::consts::FRAC_1_SQRT_2;

/// Helmert contrasts of four quarters: orthonormal, orthogonal to their mean.
const HELMERT: [[f64; 4]; 3] = [
    [FRAC_1_SQRT_2, -FRAC_1_SQRT_2, 0.0, 0.0],
    [
        0.408_248_290_463_863,
        0.408_248_290_463_863,
        -0.816_496_580_927_726,
        0.0,
    ],
    [
        0.288_675_134_594_812_9,
        0.288_675_134_594_812_9,
        0.288_675_134_594_812_9,
        -0.866_025_403_784_438_6,
    ],
];

/// The quarter contrasts of a recording's dwells, summed.
#[derive(Debug, Clone)]
pub struct QuarterContrasts {
    /// Scatter of the contrasts, summed over dwells.
    scatter: [[f64; 3]; 3],
    dwells: usize,
    dwell_s: f64,
}

/// A term of `-2 ln L = count ln w + log_det + quad / w`, white level `w` scaling a unit model.
#[derive(Debug, Clone, Copy)]
pub struct Part {
    pub log_det: f64,
    pub quad: f64,
    pub count: usize,
}

impl Part {
    pub fn plus(self, o: Part) -> Part {
        Part {
            log_det: self.log_det + o.log_det,
            quad: self.quad + o.quad,
            count: self.count + o.count,
        }
    }

    /// The log-likelihood with the white level at its best, and that level.
    pub fn profiled(self) -> Option<(f64, f64)> {
        let n = self.count as f64;
        let w = self.quad / n;
        (w > 0.0).then(|| (-0.5 * (n * w.ln() + self.log_det + n), w))
    }
}

impl QuarterContrasts {
    pub fn new(quarters: &[[f64; 4]], dwell_s: f64) -> QuarterContrasts {
        let mut scatter = [[0.0; 3]; 3];
        for q in quarters {
            let c: Vec<f64> = HELMERT.iter().map(|h| (0..4).map(|k| h[k] * q[k]).sum()).collect();
            for i in 0..3 {
                for j in 0..3 {
                    scatter[i][j] += c[i] * c[j];
                }
            }
        }
        QuarterContrasts {
            scatter,
            dwells: quarters.len(),
            dwell_s,
        }
    }

    /// How many contrasts there are: three a dwell.
    pub fn count(&self) -> usize {
        3 * self.dwells
    }

    /// Their part of the likelihood under `m`; nothing when there are none.
    pub fn part(&self, m: &NoiseModel) -> Option<Part> {
        let nq = self.dwells;
        if nq == 0 {
            return Some(Part {
                log_det: 0.0,
                quad: 0.0,
                count: 0,
            });
        }
        let (inv, log_det) = inverse3(&self.cov(m))?;
        Some(Part {
            log_det: nq as f64 * log_det,
            quad: (0..3)
                .flat_map(|i| (0..3).map(move |j| (i, j)))
                .map(|(i, j)| inv[i][j] * self.scatter[j][i])
                .sum(),
            count: self.count(),
        })
    }

    /// Covariance of the three quarter contrasts of one dwell under `m`.
    fn cov(&self, m: &NoiseModel) -> [[f64; 3]; 3] {
        let tq = self.dwell_s / 4.0;
        let centre = |k: usize| (k as f64 - 1.5) * tq;
        let mut qc = [[0.0; 4]; 4];
        for (a, row) in qc.iter_mut().enumerate() {
            for (b, v) in row.iter_mut().enumerate() {
                *v = m.mean_cov(centre(b) - centre(a), tq, tq, a == b);
            }
        }
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = (0..4)
                    .flat_map(|a| (0..4).map(move |b| (a, b)))
                    .map(|(a, b)| HELMERT[i][a] * qc[a][b] * HELMERT[j][b])
                    .sum();
            }
        }
        c
    }
}

fn inverse3(m: &[[f64; 3]; 3]) -> Option<([[f64; 3]; 3], f64)> {
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if det.is_nan() || det <= 0.0 {
        return None;
    }
    // Cyclic cofactors: inv[i][j] = C[j][i] / det.
    let inv = core::array::from_fn(|i| {
        core::array::from_fn(|j| {
            let (r0, r1) = ((j + 1) % 3, (j + 2) % 3);
            let (c0, c1) = ((i + 1) % 3, (i + 2) % 3);
            (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det
        })
    });
    Some((inv, det.ln()))
}
