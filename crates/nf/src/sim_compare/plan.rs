//! The recording's run plan in an instrument file's terms: its positions, when its angles lie
//! on an equal grid, the order it visited them in (a named order, or a list), and its sample
//! rate, and the settling time that makes the file's run take the recording's time.

use crate::instrument_file::InstrumentFile;
use crate::recording::Recording;
use crate::schedule::{Schedule, Timing};
use nf_model::order::{MAX_VISITS, Order};

/// Angles closer than this (deg) are one position.
const SAME_DEG: f64 = 0.01;

/// Positions over the turn and the order as an instrument file writes it; `None` when the
/// angles are not on an equal grid from 0.
pub fn infer(rec: &Recording) -> Option<(u16, String)> {
    let mut rows: Vec<_> = rec.rows.iter().collect();
    rows.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    let mut angles: Vec<f64> = rows.iter().map(|r| r.encoder_deg.rem_euclid(360.0)).collect();
    angles.sort_by(f64::total_cmp);
    let mut distinct = angles.windows(2).filter(|w| w[1] - w[0] > SAME_DEG).count() + 1;
    // The last and the first are one position across 0.
    if angles.len() > 1 && angles[0] + 360.0 - angles[angles.len() - 1] <= SAME_DEG {
        distinct -= 1;
    }
    let n = u16::try_from(distinct).ok().filter(|n| (4..=720).contains(n))?;
    let step = 360.0 / n as f64;
    let visits: Vec<u16> = rows
        .iter()
        .map(|r| {
            let k = r.encoder_deg / step;
            ((k - k.round()).abs() * step <= SAME_DEG.max(0.05 * step)).then(|| (k.round() as u32 % n as u32) as u16)
        })
        .collect::<Option<_>>()?;
    let named = Order::NAMED
        .iter()
        .find(|o| o.visits(n) as usize == visits.len() && o.positions(n).eq(visits.iter().copied()));
    match named {
        Some(o) => Some((n, o.name().to_string())),
        None if visits.len() <= MAX_VISITS => {
            let list: Vec<String> = visits.iter().map(u16::to_string).collect();
            Some((n, list.join(",")))
        }
        None => None,
    }
}

/// The sample rate the recording's metadata gives, where an instrument file can have it.
pub fn sample_rate_hz(rec: &Recording) -> Option<u32> {
    rec.meta
        .get("sample_rate_hz")
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|r| r.fract() == 0.0 && (1.0..=100_000.0).contains(r))
        .map(|r| r as u32)
}

/// Mean time from one dwell to the next, s.
fn mean_spacing(times: &[f64]) -> Option<f64> {
    let (lo, hi) = times.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
        (lo.min(*t), hi.max(*t))
    });
    (times.len() > 1).then(|| (hi - lo) / (times.len() - 1) as f64)
}

/// How the fixed file keeps the recording's pace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pace {
    pub settle_s: f64,
    /// The motor sped up by this ([`crate::instrument_file::Motor::sped_up`]).
    pub motor_factor: f64,
    /// Mean time from one dwell to the next in the recording, and in the file's run as it
    /// was, s.
    pub recorded_s: f64,
    pub planned_s: f64,
}

/// The largest speed-up of the motor a fix writes.
const FASTEST: f64 = 100.0;

/// The settling time (s) and the motor's speed with which `file`'s run, its positions,
/// order and dwell, spaces its dwells as `rec` does on average: the settling time where one
/// of 0 s or more does it, else the file's with the motor sped up. A run's time is what the
/// gyro's drift and wander act over: a fixed file with the recording's effects but another
/// pace does not reproduce them.
pub fn pace(rec: &Recording, file: &InstrumentFile) -> Option<Pace> {
    let order = file.order().ok()?;
    let n = usize::from(file.run.positions);
    let planned = |settle_s: f64, factor: f64| {
        let timing = Timing {
            motor: file.motor.sped_up(factor).config(),
            settle_s,
            dwell_s: file.run.dwell_s,
            ..Timing::default()
        };
        // The levelling leaves the shaft at half a turn.
        mean_spacing(&Schedule::new(&order, n, n / 2, &timing).t_mid_s)
    };
    let times: Vec<f64> = rec.rows.iter().map(|r| r.t_s).collect();
    let recorded_s = mean_spacing(&times)?;
    let planned_s = planned(file.run.settle_s, 1.0)?;
    let settle_s = file.run.settle_s + recorded_s - planned_s;
    let pace = |settle_s: f64, motor_factor: f64| Pace {
        settle_s: settle_s.clamp(0.0, 60.0),
        motor_factor,
        recorded_s,
        planned_s,
    };
    if settle_s >= 0.0 {
        return Some(pace(settle_s, 1.0));
    }
    // The spacing falls as the motor speeds up: bisect its factor on the log scale.
    let (mut lo, mut hi) = (1.0f64, FASTEST);
    if planned(file.run.settle_s, hi)? > recorded_s {
        let settle_s = file.run.settle_s + recorded_s - planned(file.run.settle_s, hi)?;
        return Some(pace(settle_s, hi));
    }
    for _ in 0..40 {
        let mid = (lo * hi).sqrt();
        if planned(file.run.settle_s, mid)? > recorded_s {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(pace(file.run.settle_s, hi))
}
