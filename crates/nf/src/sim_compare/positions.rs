//! Where the recording departs from the simulation: each position's Eq. 7 residual against
//! the replays' residuals at that position (a prediction interval over the replays,
//! Bonferroni over the positions).

use super::Residuals;
use super::compare::predict;
use crate::recording::Recording;

/// Positions listed, the largest departures first.
const SHOWN: usize = 5;

#[derive(Debug, Clone, PartialEq)]
pub struct Departure {
    pub index: u32,
    pub gamma_deg: f64,
    pub t_s: f64,
    /// Recording less the replays' mean, deg/h.
    pub difference_dph: f64,
    pub z: f64,
    /// Beyond the Bonferroni bound.
    pub significant: bool,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Where {
    /// The largest departures, at most `SHOWN`.
    pub largest: Vec<Departure>,
    /// Positions beyond the bound.
    pub beyond: usize,
}

pub fn departures(rec: &Recording, mine: &Residuals, sims: &[Residuals], alpha: f64) -> Where {
    let n = mine.resid_dph.len();
    if sims.len() < 3 || sims.iter().any(|s| s.resid_dph.len() != n) {
        return Where::default();
    }
    let mut all: Vec<Departure> = (0..n)
        .map(|i| {
            let v: Vec<f64> = sims.iter().map(|s| s.resid_dph[i]).collect();
            let at = predict(&v, mine.resid_dph[i], |_| 1e-12);
            let r = &rec.rows[i];
            Departure {
                index: r.index,
                gamma_deg: r.encoder_deg,
                t_s: r.t_s,
                difference_dph: mine.resid_dph[i] - at.mean,
                z: at.z,
                significant: at.p < alpha / n as f64,
            }
        })
        .collect();
    let beyond = all.iter().filter(|d| d.significant).count();
    all.sort_by(|a, b| b.z.abs().total_cmp(&a.z.abs()));
    all.truncate(SHOWN);
    Where { largest: all, beyond }
}
