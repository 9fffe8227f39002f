//! Short gaps in a static log bridged for the Allan variance. A gap splits the log, and the
//! averaging times end where the longest piece holds too few clusters: seven samples lost at
//! random from two hours cut them from 819 s to 205 s, and 2 % lost left a few seconds, where
//! a rate random walk fitted 18 times its size. A handful of lost samples (or spikes left
//! out) is filled with the mean of the samples around it: that changes the variance at the
//! shortest averaging times by about the share of samples filled, and leaves the long ones
//! whole.

use std::ops::Range;

/// Lost samples a gap may have and still be bridged.
pub const MAX_LOST: usize = 10;

/// Samples on each side whose mean fills a gap.
const AROUND: usize = 10;

/// The series with its short gaps filled, as one or more contiguous segments.
#[derive(Debug, Clone, PartialEq)]
pub struct Bridged {
    pub rates: Vec<f64>,
    pub segments: Vec<Range<usize>>,
    /// Gaps bridged, and the samples filled in them.
    pub gaps: usize,
    pub filled: usize,
}

/// `segments` of `rates` (sampled at times `t_s`, every `step_s` but where samples are lost
/// or left out) joined across each gap of at most [`MAX_LOST`] missing samples.
pub fn bridge(rates: &[f64], t_s: &[f64], segments: &[Range<usize>], step_s: f64) -> Bridged {
    let mut out = Bridged {
        rates: Vec::with_capacity(rates.len()),
        segments: Vec::new(),
        gaps: 0,
        filled: 0,
    };
    let mut start = 0;
    let mut last: Option<&Range<usize>> = None;
    for r in segments.iter().filter(|r| !r.is_empty()) {
        if let Some(prev) = last {
            let lost = ((t_s[r.start] - t_s[prev.end - 1]) / step_s).round() - 1.0;
            if (0.0..=MAX_LOST as f64).contains(&lost) {
                let before = &rates[prev.end.saturating_sub(AROUND).max(prev.start)..prev.end];
                let after = &rates[r.start..(r.start + AROUND).min(r.end)];
                let fill =
                    (before.iter().sum::<f64>() + after.iter().sum::<f64>()) / (before.len() + after.len()) as f64;
                out.rates.extend(std::iter::repeat_n(fill, lost as usize));
                out.gaps += 1;
                out.filled += lost as usize;
            } else {
                out.segments.push(start..out.rates.len());
                start = out.rates.len();
            }
        }
        out.rates.extend_from_slice(&rates[r.clone()]);
        last = Some(r);
    }
    if out.rates.len() > start {
        out.segments.push(start..out.rates.len());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lost_sample_costs_one_sample_and_a_long_gap_stays_a_gap() {
        // 0..5 at 1 s, sample 5 lost, 6..10; then 30 s lost, 41..44.
        let t: Vec<f64> = (0..5).chain(6..10).chain(41..44).map(f64::from).collect();
        let rates: Vec<f64> = t.iter().map(|v| v * 2.0).collect();
        let b = bridge(&rates, &t, &[0..5, 5..9, 9..12], 1.0);
        assert_eq!(b.segments, vec![0..10, 10..13]);
        assert_eq!((b.gaps, b.filled), (1, 1));
        // The mean of the nine samples around it.
        assert_eq!(
            b.rates[5],
            (0..5).chain(6..10).map(|v| 2.0 * v as f64).sum::<f64>() / 9.0
        );
        assert_eq!(&b.rates[10..], &[82.0, 84.0, 86.0]);
    }

    #[test]
    fn a_spike_left_out_is_filled_and_the_pieces_join() {
        // Sample 3 was a spike: its time is there, its value left out of the segments.
        let t: Vec<f64> = (0..8).map(f64::from).collect();
        let rates = [1.0, 1.0, 1.0, 1e6, 3.0, 3.0, 3.0, 3.0];
        let b = bridge(&rates, &t, &[0..3, 4..8], 1.0);
        assert_eq!(b.segments, vec![0..8]);
        assert_eq!(b.rates[3], 15.0 / 7.0);
        assert_eq!((b.gaps, b.filled), (1, 1));
        // Ten lost are bridged, eleven are not.
        let t: Vec<f64> = (0..4).chain(14..18).map(f64::from).collect();
        assert_eq!(bridge(&[0.0; 8], &t, &[0..4, 4..8], 1.0).segments, vec![0..18]);
        let t: Vec<f64> = (0..4).chain(15..19).map(f64::from).collect();
        assert_eq!(bridge(&[0.0; 8], &t, &[0..4, 4..8], 1.0).segments, vec![0..4, 4..8]);
    }
}
