//! Spikes in a static log: samples far off their neighbours or off the whole log, beyond
//! what any gyro noise gives (a fill value, a bit error, a logger's glitch). One -9999 fill
//! value in a 4 h log at 10 Hz made the Allan fit's N 69 times too large without a word; a
//! single sample of 50 deg/h against 0.38 deg/h of sample noise moved N by 5.5 % (29 of
//! its sigmas).

use crate::stats::robust_sigma;
use std::ops::Range;

/// Robust sigmas off beyond which a sample is a spike: Gaussian noise never comes near, a
/// Student-t of 3 dof 1.5 times in a million samples (at 50, 12 times).
pub const SIGMAS: f64 = 100.0;

/// Neighbours on each side whose median a sample is held against: a spike of up to this many
/// samples in a row is still found; a longer run of fill values is found off the whole log.
const HALF: usize = 4;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spike {
    pub index: usize,
    /// How far off, in robust sigmas of the scale it was judged by.
    pub sigmas: f64,
}

/// The spikes of `rates` within `segments` (contiguous runs): off the median of their
/// neighbours by `SIGMAS` sample-noise sigmas (from the differences of neighbours, which the
/// slow wander does not reach), or off the log's median by `SIGMAS` robust sigmas of all the
/// rates (wander included). Where most neighbours are equal (a coarse quantisation), the
/// sample noise is at least one quantisation step.
pub fn find(rates: &[f64], segments: &[Range<usize>]) -> Vec<Spike> {
    let diffs = || {
        segments
            .iter()
            .flat_map(|r| rates[r.clone()].windows(2).map(|w| w[1] - w[0]))
    };
    let step = diffs().map(f64::abs).filter(|d| *d > 0.0).fold(f64::INFINITY, f64::min);
    let local = (robust_sigma(diffs()) / 2f64.sqrt()).max(if step.is_finite() { step } else { 0.0 });
    let mut all: Vec<f64> = rates.to_vec();
    all.sort_by(f64::total_cmp);
    let middle = all.get(all.len() / 2).copied().unwrap_or(0.0);
    let global = robust_sigma(rates.iter().map(|r| r - middle));
    if local <= 0.0 || !local.is_finite() {
        return Vec::new();
    }
    let mut spikes = Vec::new();
    for r in segments {
        for i in r.clone() {
            let lo = i.saturating_sub(HALF).max(r.start);
            let hi = (i + HALF + 1).min(r.end);
            let mut near: Vec<f64> = (lo..hi).filter(|&k| k != i).map(|k| rates[k]).collect();
            let off_local = if near.is_empty() {
                0.0
            } else {
                near.sort_by(f64::total_cmp);
                (rates[i] - near[near.len() / 2]).abs() / local
            };
            let off_global = if global > 0.0 {
                (rates[i] - middle).abs() / global
            } else {
                0.0
            };
            let sigmas = off_local.max(off_global);
            if sigmas > SIGMAS {
                spikes.push(Spike { index: i, sigmas });
            }
        }
    }
    spikes
}

/// `segments` with the spikes left out: each split where one lies.
pub fn split(segments: &[Range<usize>], spikes: &[Spike]) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut at = spikes.iter().map(|s| s.index).peekable();
    for r in segments {
        let mut start = r.start;
        while let Some(&i) = at.peek() {
            if i >= r.end {
                break;
            }
            at.next();
            if i > start {
                out.push(start..i);
            }
            start = i + 1;
        }
        if start < r.end {
            out.push(start..r.end);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nf_model::rng::Rng;

    /// One segment of `n` samples.
    fn whole(n: usize) -> Vec<Range<usize>> {
        std::iter::once(0..n).collect()
    }

    fn student3(rng: &mut Rng) -> f64 {
        let chi2: f64 = (0..3).map(|_| rng.gauss().powi(2)).sum();
        rng.gauss() / (chi2 / 3.0).sqrt()
    }

    #[test]
    fn a_fill_value_a_glitch_and_a_run_of_fills_are_spikes_and_wandering_noise_is_not() {
        let mut rng = Rng::new(4);
        let mut walk = 0.0;
        let mut rates: Vec<f64> = (0..200_000)
            .map(|_| {
                walk += 0.01 * rng.gauss();
                walk + 0.4 * rng.gauss()
            })
            .collect();
        let whole = whole(rates.len());
        assert!(find(&rates, &whole).is_empty());
        rates[70_000] = -9999.0;
        rates[120_000] += 50.0;
        for r in &mut rates[150_000..150_020] {
            *r = -9999.0;
        }
        let found: Vec<usize> = find(&rates, &whole).iter().map(|s| s.index).collect();
        let mut expected = vec![70_000, 120_000];
        expected.extend(150_000..150_020);
        assert_eq!(found, expected);
    }

    #[test]
    fn heavy_tailed_and_quantised_noise_keep_their_samples() {
        let mut rng = Rng::new(5);
        let heavy: Vec<f64> = (0..200_000).map(|_| student3(&mut rng)).collect();
        assert!(find(&heavy, &whole(heavy.len())).len() <= 2);
        // Counts of 0.5 deg/h, mostly the same: a step is no spike, 120 are.
        let mut quantised: Vec<f64> = (0..10_000).map(|_| (0.2 * rng.gauss() / 0.5).round() * 0.5).collect();
        assert!(find(&quantised, &whole(10_000)).is_empty());
        quantised[500] = 60.0;
        assert_eq!(find(&quantised, &whole(10_000))[0].index, 500);
    }

    #[test]
    fn spikes_split_their_segments() {
        let at = |index: usize| Spike { index, sigmas: 100.0 };
        let segments = [0..10, 10..20];
        assert_eq!(
            split(&segments, &[at(0), at(5), at(6), at(19)]),
            vec![1..5, 7..10, 10..19]
        );
        assert_eq!(split(&segments, &[]), segments.to_vec());
    }
}
