//! The recording's thermometer as an instrument file's temperature: a ramp, and a heater's
//! swing where the readings show one, fitted by least squares with the swing's period
//! searched.

use crate::linfit;
use crate::stats::f_sf;
use nf_model::angle::atan2_deg;
use std::f64::consts::TAU;

/// The readings' temperature as `start + ramp t + amplitude sin(2 pi t / period + phase)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TempFit {
    pub start_c: f64,
    pub ramp_c_per_s: f64,
    /// `None` when the readings show no swing beyond the ramp.
    pub swing: Option<Swing>,
    /// RMS of the readings about the fit, C.
    pub rms_c: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Swing {
    pub amplitude_c: f64,
    pub period_s: f64,
    pub phase_deg: f64,
}

/// A swing is kept when the F test of its three parameters against the ramp alone has a
/// p-value under this (the period is searched, so the test is taken strictly).
const SWING_P: f64 = 1e-4;

/// Periods searched per factor of 2, between two reading spacings and twice the span.
const PER_OCTAVE: usize = 12;

/// Fits the readings `(t s, C)`; `None` with fewer than two distinct times.
pub fn fit(temp: &[(f64, f64)]) -> Option<TempFit> {
    let ramp = fit_at(temp, None)?;
    let mut t: Vec<f64> = temp.iter().map(|p| p.0).collect();
    t.sort_by(f64::total_cmp);
    let span = t.last()? - t.first()?;
    let mut gaps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).filter(|d| *d > 0.0).collect();
    gaps.sort_by(f64::total_cmp);
    let n = temp.len();
    // Three more parameters, and degrees of freedom left to judge them by.
    if n < 8 || gaps.is_empty() {
        return Some(ramp.0);
    }
    let (lo, hi) = (2.0 * gaps[gaps.len() / 2], 2.0 * span);
    let steps = (PER_OCTAVE as f64 * (hi / lo).log2()).ceil().max(1.0) as usize;
    let period = |k: f64| lo * (hi / lo).powf(k / steps as f64);
    let rss = |k: f64| fit_at(temp, Some(period(k))).map_or(f64::MAX, |f| f.1);
    let best = (0..=steps)
        .map(|k| (k, rss(k as f64)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?
        .0 as f64;
    // Golden-section search between the grid's neighbours of the best.
    let (mut a, mut b) = ((best - 1.0).max(0.0), (best + 1.0).min(steps as f64));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..40 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if rss(c) < rss(d) {
            b = d;
        } else {
            a = c;
        }
    }
    let (swing, rss_swing) = fit_at(temp, Some(period((a + b) / 2.0)))?;
    let dof = (n - 4) as f64;
    let f = (ramp.1 - rss_swing) / 3.0 / (rss_swing / dof);
    // Readings written to a resolution (a thousandth of a degree) leave a rounding error that
    // a ramp sampled at even spacings turns into a periodic pattern: a swing smaller than that
    // resolution is the rounding's, not the heater's.
    let above_resolution = swing.swing.is_some_and(|s| s.amplitude_c > resolution(temp));
    let kept = (rss_swing <= 0.0 || f_sf(f, 3.0, dof) < SWING_P) && above_resolution;
    Some(if kept { swing } else { ramp.0 })
}

/// The smallest step between two distinct readings: their resolution where they were written
/// to one, else finer than any swing.
fn resolution(temp: &[(f64, f64)]) -> f64 {
    let mut v: Vec<f64> = temp.iter().map(|p| p.1).collect();
    v.sort_by(f64::total_cmp);
    v.windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 1e-12)
        .fold(f64::INFINITY, f64::min)
        .min(f64::MAX)
}

/// The least-squares fit with the swing at `period` (none: the ramp alone), and its residual
/// sum of squares.
fn fit_at(temp: &[(f64, f64)], period: Option<f64>) -> Option<(TempFit, f64)> {
    let t: Vec<f64> = temp.iter().map(|p| p.0).collect();
    let mut cols = vec![vec![1.0; t.len()], t.clone()];
    if let Some(p) = period {
        cols.push(t.iter().map(|t| (TAU * t / p).sin()).collect());
        cols.push(t.iter().map(|t| (TAU * t / p).cos()).collect());
    }
    let y: Vec<f64> = temp.iter().map(|p| p.1).collect();
    let ls = linfit::fit(&cols, &y)?;
    let swing = period.map(|period_s| Swing {
        amplitude_c: ls.coef[2].hypot(ls.coef[3]),
        period_s,
        // s sin(w t) + c cos(w t) = a sin(w t + phase).
        phase_deg: atan2_deg(ls.coef[3], ls.coef[2]),
    });
    let fit = TempFit {
        start_c: ls.coef[0],
        ramp_c_per_s: ls.coef[1],
        swing,
        rms_c: (ls.rss / t.len() as f64).sqrt(),
    };
    Some((fit, ls.rss))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nf_model::rng::Rng;

    fn readings(swing: Option<Swing>, seed: u64) -> Vec<(f64, f64)> {
        let mut rng = Rng::new(seed);
        (0..72)
            .map(|i| {
                let t = 12.0 + 2.6 * i as f64;
                let s = swing.map_or(0.0, |s| {
                    s.amplitude_c * (TAU * t / s.period_s + s.phase_deg.to_radians()).sin()
                });
                (t, 40.0 + 0.004 * t + s + 0.01 * rng.gauss())
            })
            .collect()
    }

    #[test]
    fn a_heater_swing_is_found_with_its_period_and_phase() {
        for (seed, (amplitude_c, period_s, phase_deg)) in [(2.0, 50.0, 0.0), (0.3, 130.0, -120.0), (1.0, 170.0, 75.0)]
            .into_iter()
            .enumerate()
        {
            let truth = Swing {
                amplitude_c,
                period_s,
                phase_deg,
            };
            let f = fit(&readings(Some(truth), seed as u64)).unwrap();
            let s = f.swing.unwrap_or_else(|| panic!("{truth:?}: no swing in {f:?}"));
            assert!((s.amplitude_c / amplitude_c - 1.0).abs() < 0.05, "{s:?} for {truth:?}");
            assert!((s.period_s / period_s - 1.0).abs() < 0.02, "{s:?} for {truth:?}");
            let dphase = (s.phase_deg - phase_deg + 540.0).rem_euclid(360.0) - 180.0;
            assert!(dphase.abs() < 5.0, "{s:?} for {truth:?}");
            assert!((f.ramp_c_per_s - 0.004).abs() < 5e-4, "{f:?}");
            assert!(f.rms_c < 0.015, "{f:?}");
        }
    }

    #[test]
    fn a_swing_longer_than_the_run_still_follows_the_readings() {
        // 0.6 of a cycle: the ramp and the swing trade off, the curve does not.
        let truth = Swing {
            amplitude_c: 1.0,
            period_s: 300.0,
            phase_deg: 75.0,
        };
        let f = fit(&readings(Some(truth), 7)).unwrap();
        assert!(f.swing.is_some() && f.rms_c < 0.015, "{f:?}");
    }

    #[test]
    fn a_ramp_written_to_a_thousandth_gets_no_swing_from_its_rounding() {
        // 0.02 C/s read every 2.496 s and written to 0.001 C (a twin recording's): the
        // rounding error is a sawtooth of 12.5 readings, which the swing's search found.
        let temp: Vec<(f64, f64)> = (0..72)
            .map(|i| {
                let t = 5.383 + 2.496 * i as f64;
                (t, ((40.1033 + 0.02 * t) * 1000.0).round() / 1000.0)
            })
            .collect();
        let f = fit(&temp).unwrap();
        assert!(f.swing.is_none(), "{f:?}");
    }

    #[test]
    fn a_ramp_alone_gets_no_swing() {
        let found = (0..20)
            .filter(|&seed| fit(&readings(None, seed)).unwrap().swing.is_some())
            .count();
        assert!(found <= 1, "a swing in {found} of 20 ramps");
        let f = fit(&readings(None, 1)).unwrap();
        assert!(
            (f.start_c - 40.0).abs() < 0.01 && (f.ramp_c_per_s - 0.004).abs() < 1e-4,
            "{f:?}"
        );
    }

    #[test]
    fn too_few_readings_give_a_ramp_or_nothing() {
        assert_eq!(fit(&[(1.0, 20.0)]), None);
        let f = fit(&[(1.0, 20.0), (3.0, 21.0), (5.0, 22.0)]).unwrap();
        assert!(f.swing.is_none() && (f.ramp_c_per_s - 0.5).abs() < 1e-12, "{f:?}");
    }
}
