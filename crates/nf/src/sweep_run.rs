//! A sequential run for the unit tests of the noise likelihoods: its design (constant, cos,
//! sin), dwell means of `3 + 10 cos(gamma)` deg/h with a bias that walks and drifts, and the
//! quarter means, each with white noise of 0.02 deg/h.

use crate::quarter_contrasts::Quarters;
use nf_model::rng::Rng;

/// The run's shape: `n` dwells of 1 s whose centres are `spacing_s` apart from `t0_s`.
pub struct Sweep {
    pub n: usize,
    pub t0_s: f64,
    pub spacing_s: f64,
    /// Step of the bias's random walk from one dwell to the next, sd, deg/h.
    pub walk_dph: f64,
    pub drift_dph_per_s: f64,
}

pub struct SweepRun {
    pub t: Vec<f64>,
    pub cols: Vec<Vec<f64>>,
    pub y: Vec<f64>,
    pub quarters: Vec<Quarters>,
    /// Each dwell's length (1 s).
    pub dwells: Vec<f64>,
}

impl Sweep {
    pub fn run(&self, seed: u64) -> SweepRun {
        let n = self.n;
        let mut rng = Rng::new(seed);
        let t: Vec<f64> = (0..n).map(|i| self.t0_s + self.spacing_s * i as f64).collect();
        let g: Vec<f64> = (0..n).map(|i| (i as f64 * 360.0 / n as f64).to_radians()).collect();
        let cols = vec![
            vec![1.0; n],
            g.iter().map(|g| g.cos()).collect(),
            g.iter().map(|g| g.sin()).collect(),
        ];
        let mut bias = 0.0;
        let quarters: Vec<Quarters> = (0..n)
            .map(|i| {
                bias += self.walk_dph * rng.gauss();
                let rate = 3.0 + 10.0 * cols[1][i] + bias + self.drift_dph_per_s * t[i];
                Quarters {
                    dph: core::array::from_fn(|_| rate + 0.02 * rng.gauss()),
                    dwell_s: 1.0,
                }
            })
            .collect();
        let y = quarters.iter().map(|q| q.dph.iter().sum::<f64>() / 4.0).collect();
        SweepRun {
            t,
            cols,
            y,
            quarters,
            dwells: vec![1.0; n],
        }
    }
}
