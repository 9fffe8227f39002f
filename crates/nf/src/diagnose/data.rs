//! The recording as columns, in time order: the order the noise acts in.

use crate::recording::Recording;

/// The smallest change of the encoder angle between dwells that is a move, deg: well above an
/// encoder's noise, well below any step of a run.
const MOVE_DEG: f64 = 0.01;

pub struct Data {
    /// The recording with its rows sorted by time.
    pub rec: Recording,
    pub gamma: Vec<f64>,
    pub t: Vec<f64>,
    pub rate: Vec<f64>,
    /// The temperature of each dwell, those without a reading bridged ([`temperatures`]).
    pub temp: Option<Vec<f64>>,
    /// Dwells whose temperature was bridged.
    pub temp_bridged: usize,
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
        let (temp, temp_bridged) = temperatures(&t, &rec.rows.iter().map(|r| r.temp_c).collect::<Vec<_>>());
        Data {
            gamma: rec.rows.iter().map(|r| r.encoder_deg).collect(),
            rate: rec.rows.iter().map(|r| r.rate_dph).collect(),
            temp,
            temp_bridged,
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

    /// Whether `col` wanders as slowly as the bias does, about one cycle over the run or less
    /// in time (its sign changes at most twice): the harmonic that is the amplitude in a
    /// sweep, or the second one in opposite pairs. The noise estimate cannot see the noise at
    /// such a column's pace, as its design holds the column, so its test needs the cautious
    /// model.
    pub fn slow_in_time(&self, col: &[f64]) -> bool {
        let big = col.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let (mut sign, mut changes) = (0.0, 0);
        // Values near zero do not count, so that rounding does not make a change.
        for v in col.iter().filter(|v| v.abs() > 0.2 * big) {
            if sign != 0.0 && v.signum() != sign {
                changes += 1;
            }
            sign = v.signum();
        }
        changes <= 2
    }

    /// Whether the shaft moved before each dwell: its angle differs from the dwell before's
    /// (the first dwell follows the move to the start).
    pub fn moved(&self) -> Vec<bool> {
        (0..self.n())
            .map(|i| i == 0 || nf_model::angle::wrap_180(self.gamma[i] - self.gamma[i - 1]).abs() > MOVE_DEG)
            .collect()
    }

    /// A column that is 1 at row `i` and 0 elsewhere.
    pub fn indicator(&self, i: usize) -> Vec<f64> {
        (0..self.n()).map(|k| if k == i { 1.0 } else { 0.0 }).collect()
    }
}

/// The temperature at times `t` (sorted) from the readings there are: a dwell without one
/// takes the line between its neighbours in time that have one (the nearest at either end),
/// as a temperature moves slowly; with how many were bridged. `None` where fewer than half
/// the dwells have a reading: three blank cells in 36 switched the thermal test off (an
/// outside audit: a clear thermal drift then named as an encoder error and a walk).
fn temperatures(t: &[f64], read: &[Option<f64>]) -> (Option<Vec<f64>>, usize) {
    let known: Vec<usize> = (0..read.len()).filter(|&i| read[i].is_some()).collect();
    if known.is_empty() || 2 * known.len() < read.len() {
        return (None, 0);
    }
    let at = |i: usize| read[i].unwrap_or_default();
    let bridged = (0..read.len())
        .map(|i| {
            read[i].unwrap_or_else(|| {
                let after = known.partition_point(|&k| k < i);
                match (after.checked_sub(1).map(|b| known[b]), known.get(after).copied()) {
                    (Some(b), Some(a)) => at(b) + (at(a) - at(b)) * (t[i] - t[b]) / (t[a] - t[b]),
                    (b, a) => at(b.or(a).unwrap_or(i)),
                }
            })
        })
        .collect();
    (Some(bridged), read.len() - known.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_temperature_is_bridged_from_its_neighbours_in_time() {
        let t = [0.0, 1.0, 2.0, 3.0, 5.0];
        let read = [None, Some(20.0), None, Some(22.0), Some(23.0)];
        assert_eq!(temperatures(&t, &read), (Some(vec![20.0, 20.0, 21.0, 22.0, 23.0]), 2));
        let read = [Some(20.0), None, Some(22.0), Some(23.0), None];
        assert_eq!(temperatures(&t, &read), (Some(vec![20.0, 21.0, 22.0, 23.0, 23.0]), 2));
        assert_eq!(temperatures(&t, &[Some(1.0); 5]), (Some(vec![1.0; 5]), 0));
        // Fewer than half read: no temperature.
        assert_eq!(temperatures(&t[..3], &[None, Some(20.0), None]), (None, 0));
        assert_eq!(temperatures(&t[..2], &[None, None]), (None, 0));
    }

    /// Data of `n` positions visited at `gammas`, 1.35 s apart.
    fn data(gammas: &[f64]) -> Data {
        let mut text =
            String::from("# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n");
        for (i, g) in gammas.iter().enumerate() {
            text += &format!("{i},{},{g},1.0\n", 1.35 * i as f64);
        }
        Data::new(&Recording::parse(&text).unwrap())
    }

    #[test]
    fn the_harmonics_slow_in_time_depend_on_the_order() {
        let n = 48;
        let step = 360.0 / n as f64;
        let sweep: Vec<f64> = (0..n).map(|k| 7.0 + step * k as f64).collect();
        let pairs: Vec<f64> = (0..n / 2)
            .flat_map(|k| [7.0 + step * k as f64, 187.0 + step * k as f64])
            .collect();
        let slow = |d: &Data, k: u32| d.harmonic(k).iter().map(|c| d.slow_in_time(c)).collect::<Vec<_>>();
        let (sweep, pairs) = (data(&sweep), data(&pairs));
        assert_eq!(slow(&sweep, 1), [true, true]);
        assert_eq!(slow(&sweep, 2), [false, false]);
        assert_eq!(slow(&pairs, 1), [false, false]);
        assert_eq!(slow(&pairs, 2), [true, true]);
        // The bias wander itself; a cycle whose crossing rounding makes flicker in sign.
        assert!(sweep.slow_in_time(&sweep.tau));
        let mut cycle = sweep.harmonic(1)[0].clone();
        let at = cycle.iter().position(|v| v.abs() < 0.1).unwrap();
        cycle[at..at + 3].copy_from_slice(&[1e-17, -1e-17, 1e-17]);
        assert!(sweep.slow_in_time(&cycle));
    }
}
