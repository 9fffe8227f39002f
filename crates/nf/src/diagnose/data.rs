//! The recording as columns, in time order: the order the noise acts in.

use crate::recording::Recording;

pub struct Data {
    /// The recording with its rows sorted by time.
    pub rec: Recording,
    pub gamma: Vec<f64>,
    pub t: Vec<f64>,
    pub rate: Vec<f64>,
    pub temp: Option<Vec<f64>>,
    pub quarters: Option<Vec<[f64; 4]>>,
    /// Time scaled to [-1, 1] over the run, and the half span it was scaled by, s.
    pub tau: Vec<f64>,
    pub half_span_s: f64,
}

impl Data {
    pub fn new(rec: &Recording) -> Data {
        let mut rec = rec.clone();
        rec.rows.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
        let t: Vec<f64> = rec.rows.iter().map(|r| r.t_s).collect();
        let (lo, hi) = (t[0], t[t.len() - 1]);
        let half_span_s = ((hi - lo) / 2.0).max(1e-9);
        Data {
            gamma: rec.rows.iter().map(|r| r.encoder_deg).collect(),
            rate: rec.rows.iter().map(|r| r.rate_dph).collect(),
            temp: rec.rows.iter().map(|r| r.temp_c).collect(),
            quarters: rec.rows.iter().map(|r| r.quarters_dph).collect(),
            tau: t.iter().map(|v| (v - (lo + hi) / 2.0) / half_span_s).collect(),
            half_span_s,
            t,
            rec,
        }
    }

    pub fn n(&self) -> usize {
        self.gamma.len()
    }

    /// `1, cos gamma, sin gamma`: Eq. 7.
    pub fn base_cols(&self) -> Vec<Vec<f64>> {
        vec![
            vec![1.0; self.n()],
            self.gamma.iter().map(|g| g.to_radians().cos()).collect(),
            self.gamma.iter().map(|g| g.to_radians().sin()).collect(),
        ]
    }

    /// `cos k gamma, sin k gamma`.
    pub fn harmonic(&self, k: u32) -> [Vec<f64>; 2] {
        let arg = |g: &f64| (k as f64 * g).to_radians();
        [
            self.gamma.iter().map(|g| arg(g).cos()).collect(),
            self.gamma.iter().map(|g| arg(g).sin()).collect(),
        ]
    }

    /// A column that is 1 at row `i` and 0 elsewhere.
    pub fn indicator(&self, i: usize) -> Vec<f64> {
        (0..self.n()).map(|k| if k == i { 1.0 } else { 0.0 }).collect()
    }
}
