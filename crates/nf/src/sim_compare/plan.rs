//! The recording's run plan in an instrument file's terms: its positions, when its angles lie
//! on an equal grid, the order it visited them in (a named order, or a list), and its sample
//! rate.

use crate::recording::Recording;
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
