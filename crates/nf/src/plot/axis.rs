//! A plot axis as a plotters coordinate: the range fitted to the finite data (a log axis in
//! decades), round ticks, and tick labels. Any data gives a finite range of non-zero width, a
//! bounded number of ticks and pixel positions near the plot, so that nothing downstream can
//! loop, overflow or panic.

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use std::ops::Range;

/// One axis: `lo < hi` in axis units (decades on a log axis), both finite.
#[derive(Debug, Clone)]
pub struct Axis {
    log: bool,
    lo: f64,
    hi: f64,
}

impl Axis {
    /// The range of the values this axis can show (finite, and positive on a log axis),
    /// widened where it is empty or a single value, then padded by `pad` of its width on
    /// each side.
    pub fn fit(values: impl IntoIterator<Item = f64>, log: bool, pad: f64) -> Axis {
        let at = |v: f64| if log { v.log10() } else { v };
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for t in values.into_iter().map(at).filter(|t| t.is_finite()) {
            (lo, hi) = (lo.min(t), hi.max(t));
        }
        if lo > hi {
            (lo, hi) = (0.0, 1.0);
        }
        // Halves, so that the width of [-f64::MAX, f64::MAX] is finite.
        let (mid, half) = (lo / 2.0 + hi / 2.0, hi / 2.0 - lo / 2.0);
        if half <= (mid.abs() * 1e-12).max(1e-290) {
            let w = if mid.abs() < 1e-200 { 1.0 } else { mid.abs() * 0.1 };
            (lo, hi) = (mid - w, mid + w);
        }
        let p = (hi / 2.0 - lo / 2.0) * 2.0 * pad;
        let (mut lo, mut hi) = ((lo - p).max(-f64::MAX), (hi + p).min(f64::MAX));
        if log {
            // Beyond f64's decades there is nothing to show.
            (lo, hi) = (lo.max(-400.0), hi.min(400.0));
        }
        Axis { log, lo, hi }
    }

    /// The axis with its top raised so that the values it showed take the lower `1 - share`
    /// of it (on a log axis, in decades).
    pub fn with_room_above(&self, share: f64) -> Axis {
        let share = share.clamp(0.0, 0.9);
        let width = self.hi / 2.0 - self.lo / 2.0;
        let hi = self.lo + (2.0 * width / (1.0 - share)).min(f64::MAX);
        let hi = if self.log { hi.min(400.0) } else { hi.min(f64::MAX) };
        Axis {
            hi: if hi.is_finite() && hi > self.hi { hi } else { self.hi },
            ..self.clone()
        }
    }

    /// Whether `v` has a place on this axis (finite; positive on a log axis).
    pub fn shows(&self, v: f64) -> bool {
        self.at(v).is_finite()
    }

    fn at(&self, v: f64) -> f64 {
        if self.log { v.log10() } else { v }
    }

    /// The range in data units where the ticks are linear: always on a linear axis, and on a
    /// log axis too short for three of its own ticks (a fraction of a decade).
    fn linear(&self) -> Option<(f64, f64)> {
        if !self.log {
            return Some((self.lo, self.hi));
        }
        if log_ticks(self.lo, self.hi).len() >= 3 {
            return None;
        }
        Some((10f64.powf(self.lo), 10f64.powf(self.hi)))
    }

    /// The tick positions, in data units.
    pub fn ticks(&self) -> Vec<f64> {
        match self.linear() {
            Some((a, b)) => ticks(a, b).into_iter().filter(|&t| self.shows(t)).collect(),
            None => log_ticks(self.lo, self.hi),
        }
    }

    /// A tick's label, with as many digits as the tick step needs.
    pub fn label(&self, t: f64) -> String {
        match self.linear() {
            Some((a, b)) => fmt_tick(t, step(a, b)),
            None => fmt_tick(t, t),
        }
    }
}

impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let f = (self.at(*v) / 2.0 - self.lo / 2.0) / (self.hi / 2.0 - self.lo / 2.0);
        // Points off the axis stay within a plot's width of it: pixel arithmetic downstream
        // cannot overflow.
        let f = if f.is_nan() { 0.0 } else { f.clamp(-1.0, 2.0) };
        limit.0 + (f64::from(limit.1 - limit.0) * f).round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        // Grid lines at the labelled ticks only: none of plotters' light lines between them.
        if hint.weight().allow_light_points() {
            return Vec::new();
        }
        self.ticks()
    }

    fn range(&self) -> Range<f64> {
        if self.log {
            10f64.powf(self.lo)..10f64.powf(self.hi)
        } else {
            self.lo..self.hi
        }
    }
}

impl ValueFormatter<f64> for Axis {
    fn format_ext(&self, v: &f64) -> String {
        self.label(*v)
    }
}

/// A round step (1, 2 or 5 times a power of ten) giving about five ticks over `[lo, hi]`.
fn step(lo: f64, hi: f64) -> f64 {
    // Halves, so that the width of [-f64::MAX, f64::MAX] is finite.
    let raw = ((hi / 2.0 - lo / 2.0) / 2.5).abs().max(1e-300);
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag)
}

/// Round tick positions covering `[lo, hi]`.
pub(super) fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let step = step(lo, hi);
    let mut t = (lo / step).ceil() * step;
    let mut out = Vec::new();
    while t.is_finite() && t - step * 1e-9 <= hi && out.len() < 20 {
        out.push(if t.abs() < step * 1e-9 { 0.0 } else { t });
        // Where the step is below the spacing of floats at `t` (values all equal, or a few
        // ulps apart, at a large magnitude), adding it leaves `t` where it is.
        let next = t + step;
        if next <= t {
            break;
        }
        t = next;
    }
    out
}

/// Ticks of a log axis whose range is `[lo, hi]` in decades: 1, 2, 3 and 5 per decade
/// within a decade, 1, 2 and 5 when it spans few decades, decades only otherwise, and every k-th decade past a dozen of them.
pub(super) fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let (lo, hi) = (lo.max(-400.0), hi.min(400.0));
    let mults: &[f64] = match hi - lo {
        d if d <= 1.0 => &[1.0, 2.0, 3.0, 5.0],
        d if d <= 2.5 => &[1.0, 2.0, 5.0],
        _ => &[1.0],
    };
    let every = ((hi - lo) / 10.0).ceil().max(1.0) as i32;
    let mut out = Vec::new();
    for d in (lo.floor() as i32)..=(hi.ceil() as i32) {
        if d.rem_euclid(every) != 0 {
            continue;
        }
        for m in mults {
            let t = m * 10f64.powi(d);
            if (lo - 1e-9..=hi + 1e-9).contains(&t.log10()) {
                out.push(t);
            }
        }
    }
    out
}

/// `t` with the digits a tick step of `step` needs: plain between 1e-3 and 1e6, else with an
/// exponent.
pub(super) fn fmt_tick(t: f64, step: f64) -> String {
    let digits = |x: f64| x.abs().log10().floor();
    if t.abs() < step.abs() * 1e-6 {
        return "0".into();
    }
    if t.abs() < 1e-3 || t.abs() >= 1e6 {
        let d = (digits(t) - digits(step)).clamp(0.0, 12.0) as usize;
        let s = format!("{t:.d$e}");
        // 2.50e3 -> 2.5e3
        return match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        };
    }
    let d = (-digits(step)).clamp(0.0, 12.0) as usize;
    format!("{t:.d$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_axes_tick_at_decades() {
        assert_eq!(log_ticks(-0.2, 1.1), vec![1.0, 2.0, 5.0, 10.0]);
        assert_eq!(log_ticks(-3.0, 2.0), vec![1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0]);
        // All of f64's decades: a tick every 70 or so, not 630.
        let all = log_ticks(-324.0, 308.0);
        assert!((8..=12).contains(&all.len()), "{all:?}");
    }

    #[test]
    fn a_log_axis_shorter_than_a_decade_has_linear_ticks_where_its_own_are_too_few() {
        let x = Axis::fit([2.5, 19.99], true, 0.0);
        assert_eq!(x.ticks(), vec![3.0, 5.0, 10.0]);
        let x = Axis::fit([2.5, 4.9], true, 0.0);
        assert_eq!(x.ticks(), vec![2.5, 3.0, 3.5, 4.0, 4.5]);
        let y = Axis::fit([0.0013, 0.0041], true, 0.05);
        let labels: Vec<String> = y.ticks().iter().map(|&t| y.label(t)).collect();
        assert_eq!(labels, ["0.002", "0.003", "0.004"]);
        let wide = Axis::fit([0.3, 20.0], true, 0.0);
        assert_eq!(wide.ticks(), vec![0.5, 1.0, 2.0, 5.0, 10.0, 20.0]);
    }

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(ticks(0.0, 10.0), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        let t = ticks(-0.013, 0.021);
        assert!(t.first().unwrap() >= &-0.013 && t.last().unwrap() <= &0.021 && t.len() >= 3);
        let t = ticks(-f64::MAX, f64::MAX);
        assert!((2..=20).contains(&t.len()) && t.iter().all(|t| t.is_finite()), "{t:?}");
    }

    #[test]
    fn labels_have_the_digits_the_step_needs() {
        assert_eq!(fmt_tick(1e-4, 1e-4), "1e-4");
        assert_eq!(fmt_tick(2.0, 0.5), "2.0");
        assert_eq!(fmt_tick(300.0, 100.0), "300");
        assert_eq!(fmt_tick(-0.0000000001, 0.005), "0");
        assert_eq!(fmt_tick(2000.0002, 0.0001), "2000.0002");
        assert_eq!(fmt_tick(2.5e7, 5e6), "2.5e7");
        assert_eq!(fmt_tick(1.0000002e6, 1e-1), "1.0000002e6");
    }

    #[test]
    fn degenerate_data_gives_a_finite_range_of_nonzero_width() {
        let cases: [&[f64]; 8] = [
            &[],
            &[f64::NAN, f64::INFINITY],
            &[2000.0, 2000.0],
            &[2000.0, f64::from_bits(2000f64.to_bits() + 1)],
            &[-f64::MAX, f64::MAX],
            &[1e300],
            &[0.0, 5e-324],
            &[-1.0, 0.0],
        ];
        for log in [false, true] {
            for c in cases {
                let a = Axis::fit(c.iter().copied(), log, 0.05);
                assert!(a.lo.is_finite() && a.hi.is_finite() && a.lo < a.hi, "{c:?} {a:?}");
                assert!(a.hi / 2.0 - a.lo / 2.0 > 0.0, "{c:?} {a:?}");
                let t = a.ticks();
                assert!(t.len() <= 20, "{c:?} {t:?}");
                for v in c.iter().chain(&t) {
                    let p = a.map(v, (0, 600));
                    assert!((-600..=1200).contains(&p), "{c:?} {v} {p}");
                }
            }
        }
    }
}
