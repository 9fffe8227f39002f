//! `thermal_drift`: the bias follows the recorded temperature. Judged under the drift
//! design's noise model, as drift and jump are: the three are rival explanations of one
//! wander of the bias with time, and a rival judged under a more coloured model loses to the
//! others whatever the data say.
//!
//! Without a recorded temperature, a heater's cycle still moves the bias: a sinusoid in time
//! whose period is scanned (from four dwell spacings, or a thirtieth of the run, to twice
//! the run; up to 2000 positions), its best period's F test corrected for the independent
//! frequencies tried. In a sweep such a cycle leaks into
//! the first harmonic; left out, the encoder harmonics, a curved drift and a scale factor
//! took its place together and moved the azimuth 5-9 sigma (an outside audit). Periods whose
//! cycle the angle's own low harmonics hold (an integer number of turns in a sweep) are left
//! to the encoder error.

use super::data::Data;
use super::effect::{Change, Draws, Effect, Law, Proposal, State, nested_p, param};
use super::kind::Kind;
use crate::linfit;
use crate::noise_est::THINNED;

pub struct ThermalDrift {
    /// The cycles a recording without a temperature is scanned for, made once: the
    /// coarse grid's frequencies the angle's harmonics leave, with their columns.
    cycles: Vec<(f64, [Vec<f64>; 2])>,
}

impl ThermalDrift {
    pub fn new(d: &Data) -> ThermalDrift {
        ThermalDrift {
            cycles: if d.temp.is_none() { grid(d) } else { Vec::new() },
        }
    }
}

impl Effect for ThermalDrift {
    fn kind(&self) -> Kind {
        Kind::ThermalDrift
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        if s.is_named(Kind::ThermalDrift) {
            return Vec::new();
        }
        let Some(temp) = &s.data.temp else {
            return cycle(s, &self.cycles)
                .into_iter()
                .map(|p| s.wander_judged(p, Law::Drawn))
                .collect();
        };
        let mean = temp.iter().sum::<f64>() / temp.len() as f64;
        let dt: Vec<f64> = temp.iter().map(|v| v - mean).collect();
        if dt.iter().all(|v| v.abs() < 1e-6) {
            return Vec::new();
        }
        s.drift
            .nested(
                Kind::ThermalDrift,
                vec![dt],
                |l, k| vec![param("dph_per_degc", l.coef[k], Some(l.sigma(k)))],
                "follows the recorded temperature".into(),
            )
            .into_iter()
            .map(|p| s.wander_judged(p, Law::Drawn))
            .collect()
    }
}

/// A thermal drift found without a recorded temperature: the amplitude of the bias's cycle.
pub const CYCLE_AMPLITUDE: &str = "cycle_amplitude_dph";
/// Frequencies tried per independent one (a quarter of the run's resolution).
const OVERSAMPLED: f64 = 4.0;
/// The most cycles a run a heater's cycle is sought at.
const MOST_CYCLES: f64 = 30.0;
/// A cycle the angle's harmonics 1 to 3 and a constant hold to this share of its power is
/// theirs, not a cycle in time.
const HELD_BY_ANGLE: f64 = 0.995;

/// The coarse grid of cycles for [`cycle`]: from half a cycle over the run to one in four
/// dwell spacings, and to MOST_CYCLES; none past THINNED positions, where each frequency's
/// fit would cost more than the rest of the diagnosis.
fn grid(d: &Data) -> Vec<(f64, [Vec<f64>; 2])> {
    let n = d.n();
    let span = d.t[n - 1] - d.t[0];
    if !(12..=THINNED).contains(&n) || span <= 0.0 {
        return Vec::new();
    }
    let spacing = span / (n - 1) as f64;
    let angle = angle_cols(d);
    let (lo, hi) = (0.5 / span, (1.0 / (4.0 * spacing)).min(MOST_CYCLES / span));
    let step = 1.0 / (OVERSAMPLED * span);
    (0..)
        .map(|k| lo + k as f64 * step)
        .take_while(|f| *f <= hi)
        .map(|f| (f, sinusoid(d, f)))
        .filter(|(_, cols)| !held_by_angle(&angle, cols))
        .collect()
}

/// The best sinusoid in time of the `cycles`, where the recording has no temperature.
fn cycle(s: &State, cycles: &[(f64, [Vec<f64>; 2])]) -> Option<Proposal> {
    let d = s.data;
    let span = d.t[d.n() - 1] - d.t[0];
    let step = 1.0 / (OVERSAMPLED * span);
    let (_, f0) = cycles
        .iter()
        .filter_map(|(f, cols)| Some((fitted(s, cols)?.0, *f)))
        .min_by(|a, b| a.0.total_cmp(&b.0))?;
    // The grid's best refined to a tenth of its step: a cycle near a whole number of turns
    // is left to the encoder harmonics only where they hold it whole.
    let angle = angle_cols(d);
    let (p, f, big, cols) = (-5..=5)
        .map(|k| f0 + k as f64 * step / 10.0)
        .filter(|f| *f > 0.0)
        .map(|f| (f, sinusoid(d, f)))
        .filter(|(_, cols)| !held_by_angle(&angle, cols))
        .filter_map(|(f, cols)| {
            let (p, big) = fitted(s, &cols)?;
            Some((p, f, big, cols))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))?;
    let k = s.drift.model.cols.len();
    let (c, si) = (big.coef[k], big.coef[k + 1]);
    let amplitude = c.hypot(si);
    // The amplitude's sigma, as a radius of the two coefficients'.
    let sigma = ((big.sigma(k).powi(2) + big.sigma(k + 1).powi(2)) / 2.0).sqrt();
    let independent = (cycles.len() as f64 / OVERSAMPLED).max(1.0);
    Some(Proposal {
        kind: Kind::ThermalDrift,
        p: (p * independent).min(1.0),
        change: Change::Columns(cols.to_vec()),
        parameters: vec![
            param(CYCLE_AMPLITUDE, amplitude, Some(sigma)),
            param("cycle_period_s", 1.0 / f, None),
            // As `sin(2 pi t / period + phase)`, t from the first dwell.
            param("cycle_phase_deg", c.atan2(si).to_degrees(), None),
        ],
        location: format!(
            "a bias cycling in time, {amplitude:.5} deg/h over a period of {:.1} s (no temperature recorded: a heater's cycle makes it)",
            1.0 / f
        ),
        scanned: 1,
        own_p: None,
        draws: Draws::No,
    })
}

/// The F test's p-value of a cycle's columns beside the drift frame's model, and that fit.
fn fitted(s: &State, cols: &[Vec<f64>; 2]) -> Option<(f64, linfit::Ls)> {
    let white: Vec<Vec<f64>> = cols.iter().map(|c| s.drift.whitener.apply(c)).collect();
    let big = s.drift.model.fit_plus(&white)?;
    Some((nested_p(&s.drift.fit, &big, 2), big))
}

/// `cos` and `sin` of `2 pi f t` over the run's times.
fn sinusoid(d: &Data, f: f64) -> [Vec<f64>; 2] {
    let arg = |t: &f64| std::f64::consts::TAU * f * (t - d.t[0]);
    [
        d.t.iter().map(|t| arg(t).cos()).collect(),
        d.t.iter().map(|t| arg(t).sin()).collect(),
    ]
}

/// A constant and the angle's harmonics 1 to 3.
fn angle_cols(d: &Data) -> Vec<Vec<f64>> {
    let mut cols = vec![vec![1.0; d.n()]];
    for k in 1..=3 {
        cols.extend(d.harmonic(k));
    }
    cols
}

/// Whether `angle`'s columns hold [`HELD_BY_ANGLE`] of the cycle's power.
fn held_by_angle(angle: &[Vec<f64>], cycle: &[Vec<f64>; 2]) -> bool {
    let (mut left, mut total) = (0.0, 0.0);
    for c in cycle {
        let Some(ls) = linfit::fit(angle, c) else { return true };
        left += ls.resid.iter().map(|r| r * r).sum::<f64>();
        total += c.iter().map(|v| v * v).sum::<f64>();
    }
    left < (1.0 - HELD_BY_ANGLE) * total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::Recording;

    /// 48 positions 1.4 s apart at `gamma(i)`.
    fn data(gamma: impl Fn(usize) -> f64) -> Data {
        let mut text =
            String::from("# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n");
        for i in 0..48 {
            text += &format!("{i},{},{},1.0\n", 1.4 * i as f64, gamma(i));
        }
        Data::new(&Recording::parse(&text).unwrap())
    }

    #[test]
    fn a_sweep_leaves_the_cycles_of_whole_turns_to_the_angle_s_harmonics() {
        let turn_s = 48.0 * 1.4;
        let per_turn = |g: &[(f64, [Vec<f64>; 2])]| g.iter().map(|c| c.0 * turn_s).collect::<Vec<_>>();
        let sweep = per_turn(&grid(&data(|i| 7.5 * i as f64)));
        let near = |k: f64, w: f64| sweep.iter().any(|c| (c - k).abs() < w);
        assert!(!near(2.0, 0.02) && !near(3.0, 0.02), "{sweep:?}");
        assert!(near(2.5, 0.15) && near(1.5, 0.15) && near(8.0, 0.15), "{sweep:?}");
        // In opposite pairs the angle's harmonics are fast in time: every cycle is tried.
        let pairs = per_turn(&grid(&data(|i| 7.5 * (i / 2) as f64 + 180.0 * (i % 2) as f64)));
        assert!(pairs.iter().any(|c| (c - 2.0).abs() < 0.15), "{pairs:?}");
        assert!(pairs.len() > sweep.len());
    }
}
