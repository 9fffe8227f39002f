//! A recording's profile against the profiles of replays of the simulation: each quantity
//! judged against the replays' spread (a prediction interval, Student-t on the replays'
//! degrees of freedom; a scatter's on the log scale), Bonferroni over the quantities.

use super::profile::{Profile, Quantity};
use crate::stats::t_sf2;

#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    pub quantity: Quantity,
    pub recording: f64,
    pub simulated: f64,
    /// Spread of the quantity over the replays.
    pub simulated_sd: f64,
    /// (recording - simulated) in units of the prediction sd.
    pub z: f64,
    pub p: f64,
    pub mismatch: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    pub lines: Vec<Line>,
    pub replays: usize,
}

impl Comparison {
    pub fn line(&self, q: Quantity) -> Option<&Line> {
        self.lines.iter().find(|l| l.quantity == q)
    }

    pub fn mismatches(&self) -> usize {
        self.lines.iter().filter(|l| l.mismatch).count()
    }

    /// Whether any of `qs` is a mismatch.
    pub fn any(&self, qs: impl Fn(Quantity) -> bool) -> bool {
        self.lines.iter().any(|l| l.mismatch && qs(l.quantity))
    }
}

/// `v` moved by whole turns to within half a turn of `near`.
fn unwrap_near(v: f64, near: f64) -> f64 {
    near + (v - near + 180.0).rem_euclid(360.0) - 180.0
}

/// Where a value falls among the replays' values of it.
pub struct Prediction {
    pub mean: f64,
    pub sd: f64,
    /// (value - mean) in units of the prediction sd, `sd sqrt(1 + 1/k)` for `k` replays.
    pub z: f64,
    /// Two-sided p of `z`, Student-t on `k - 1` degrees of freedom.
    pub p: f64,
}

/// `x` against `v` (at least two values), the spread floored at `floor(mean)`.
pub fn predict(v: &[f64], x: f64, floor: impl Fn(f64) -> f64) -> Prediction {
    let k = v.len() as f64;
    let mean = v.iter().sum::<f64>() / k;
    let sd = (v.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
    let z = (x - mean) / (sd.max(floor(mean)) * (1.0 + 1.0 / k).sqrt());
    Prediction {
        mean,
        sd,
        z,
        p: t_sf2(z, k - 1.0),
    }
}

/// Compares; `alpha` is the false-alarm rate over all quantities.
pub fn compare(rec: &Profile, sims: &[Profile], alpha: f64) -> Comparison {
    let s = sims.len() as f64;
    let lines: Vec<Line> = rec
        .iter()
        .filter_map(|&(q, r)| {
            let mut v: Vec<f64> = sims
                .iter()
                .filter_map(|p| p.iter().find(|x| x.0 == q).map(|x| x.1))
                .collect();
            if v.len() < 3 {
                return None;
            }
            if q.wraps() {
                v.iter_mut().for_each(|x| *x = unwrap_near(*x, r));
            }
            // A noise-free simulation has no spread: then only digits separate them.
            let at = predict(&v, r, |m| (1e-9 * r.abs().max(m.abs())).max(q.resolution()));
            let logs = (q.is_scatter() && r > 0.0 && v.iter().all(|x| *x > 0.0)).then(|| {
                let ln: Vec<f64> = v.iter().map(|x| x.ln()).collect();
                predict(&ln, r.ln(), |_| 1e-9)
            });
            let (z, p) = logs.map_or((at.z, at.p), |l| (l.z, l.p));
            Some((q, r, at.mean, at.sd, z, p))
        })
        .map(|(quantity, recording, simulated, simulated_sd, z, p)| Line {
            quantity,
            recording,
            simulated,
            simulated_sd,
            z,
            p,
            mismatch: false,
        })
        .collect();
    let q = lines.len().max(1) as f64;
    let lines = lines
        .into_iter()
        .map(|l| Line {
            mismatch: l.p < alpha / q,
            ..l
        })
        .collect();
    Comparison {
        lines,
        replays: s as usize,
    }
}
