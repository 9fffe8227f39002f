//! A recording's profile against the profiles of replays of the simulation: each quantity
//! judged against the replays' spread (a prediction interval, Student-t on the replays'
//! degrees of freedom), Bonferroni over the quantities.

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
            let m = v.iter().sum::<f64>() / v.len() as f64;
            let sd = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt();
            // A noise-free simulation has no spread: then only digits separate them.
            let scale = sd.max(1e-9 * r.abs().max(m.abs())).max(q.resolution());
            let z = (r - m) / (scale * (1.0 + 1.0 / v.len() as f64).sqrt());
            Some((q, r, m, sd, z, t_sf2(z, (v.len() - 1) as f64)))
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
