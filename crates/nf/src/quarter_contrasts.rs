//! The short-time noise inside each dwell: the three Helmert contrasts of its four quarter
//! means, orthogonal to the dwell mean, whose scatter over the dwells enters every noise
//! likelihood beside the dwell means.

use crate::recording::Row;
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

/// One dwell's four quarter means, deg/h, and its length, s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quarters {
    pub dph: [f64; 4],
    pub dwell_s: f64,
}

/// The quarter means of `rows` that have them, each with its dwell's length.
pub fn of_rows<'a>(rows: impl Iterator<Item = (&'a Row, f64)>) -> Vec<Quarters> {
    rows.filter_map(|(r, dwell_s)| r.quarters_dph.map(|dph| Quarters { dph, dwell_s }))
        .collect()
}

/// The quarter contrasts of a recording's dwells, summed over the dwells of each length.
#[derive(Debug, Clone)]
pub struct QuarterContrasts {
    groups: Vec<Group>,
}

/// The dwells of one length: their contrasts share a covariance.
#[derive(Debug, Clone)]
struct Group {
    dwell_s: f64,
    /// Scatter of the contrasts, summed over the group's dwells.
    scatter: [[f64; 3]; 3],
    dwells: usize,
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
    pub fn new(quarters: &[Quarters]) -> QuarterContrasts {
        let mut groups: Vec<Group> = Vec::new();
        for q in quarters {
            let c: Vec<f64> = HELMERT.iter().map(|h| (0..4).map(|k| h[k] * q.dph[k]).sum()).collect();
            let g = match groups.iter().position(|g| g.dwell_s == q.dwell_s) {
                Some(at) => &mut groups[at],
                None => {
                    groups.push(Group {
                        dwell_s: q.dwell_s,
                        scatter: [[0.0; 3]; 3],
                        dwells: 0,
                    });
                    groups.last_mut().expect("just pushed")
                }
            };
            g.dwells += 1;
            for i in 0..3 {
                for j in 0..3 {
                    g.scatter[i][j] += c[i] * c[j];
                }
            }
        }
        QuarterContrasts { groups }
    }

    /// How many contrasts there are: three a dwell.
    pub fn count(&self) -> usize {
        3 * self.groups.iter().map(|g| g.dwells).sum::<usize>()
    }

    /// Their part of the likelihood under `m`; nothing when there are none.
    pub fn part(&self, m: &NoiseModel) -> Option<Part> {
        let mut part = Part {
            log_det: 0.0,
            quad: 0.0,
            count: 0,
        };
        for g in &self.groups {
            let (inv, log_det) = inverse3(&cov(m, g.dwell_s))?;
            part = part.plus(Part {
                log_det: g.dwells as f64 * log_det,
                quad: (0..3)
                    .flat_map(|i| (0..3).map(move |j| (i, j)))
                    .map(|(i, j)| inv[i][j] * g.scatter[j][i])
                    .sum(),
                count: 3 * g.dwells,
            });
        }
        Some(part)
    }
}

/// Covariance of the three quarter contrasts of one dwell of `dwell_s` under `m`.
fn cov(m: &NoiseModel, dwell_s: f64) -> [[f64; 3]; 3] {
    let tq = dwell_s / 4.0;
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
