//! Overlapping Allan variance of a rate series, as allantools' `oadev` computes it: from the
//! cumulative sum, at octave-spaced averaging factors m = 1, 2, 4, ...; the second differences
//! of contiguous segments are pooled, none spans a gap. The confidence interval is chi-square
//! with the estimate's equivalent degrees of freedom (`allan_model`).

use crate::stats::chi2_quantile;

/// The longest averaging factor leaves this many non-overlapping clusters in the longest
/// segment: beyond it the estimate has a couple of degrees of freedom at most.
pub const MIN_CLUSTERS: usize = 8;

/// Fewest averaging times a fit is tried on.
pub const MIN_POINTS: usize = 4;

/// Probability inside the reported intervals: one sigma of a normal.
pub const CI_LEVEL: f64 = 0.682_689_492_137_086;

/// The Allan variance at one averaging time.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Averaging factor: `tau_s` is `m` sample steps.
    pub m: usize,
    pub tau_s: f64,
    /// (deg/h)^2.
    pub avar: f64,
    /// Second differences averaged, over all segments.
    pub terms: usize,
    /// Non-overlapping clusters of `m` samples, over all segments.
    pub clusters: usize,
}

/// Averaging factors 1, 2, 4, ... that leave `MIN_CLUSTERS` clusters in `longest` samples.
pub fn octaves(longest: usize) -> Vec<usize> {
    std::iter::successors(Some(1usize), |m| m.checked_mul(2))
        .take_while(|m| longest / m >= MIN_CLUSTERS)
        .collect()
}

/// Overlapping Allan variance at each factor in `ms` of segments sampled every `step_s`.
pub fn oavar(segments: &[&[f64]], step_s: f64, ms: &[usize]) -> Vec<Point> {
    // The cumulative sum ("phase") of each segment less its mean: the variance is blind to a
    // constant, and a large bias would cost digits in the second differences.
    let phases: Vec<Vec<f64>> = segments
        .iter()
        .map(|s| {
            let mean = s.iter().sum::<f64>() / s.len().max(1) as f64;
            std::iter::once(0.0)
                .chain(s.iter().scan(0.0, |acc, v| {
                    *acc += v - mean;
                    Some(*acc)
                }))
                .collect()
        })
        .collect();
    ms.iter()
        .map(|&m| {
            let (mut sum, mut terms, mut clusters) = (0.0, 0, 0);
            for x in &phases {
                let n = x.len() - 1;
                clusters += n / m;
                if n + 1 > 2 * m {
                    let k = n + 1 - 2 * m;
                    terms += k;
                    sum += (0..k).map(|i| second_difference(x, i, m).powi(2)).sum::<f64>();
                }
            }
            Point {
                m,
                tau_s: m as f64 * step_s,
                avar: if terms > 0 {
                    sum / (2.0 * terms as f64)
                } else {
                    f64::NAN
                },
                terms,
                clusters,
            }
        })
        .collect()
}

/// From prefix sums `s` (a phase): the mean of the `m` values from `j + m` less the mean of
/// the `m` before.
pub fn second_difference(s: &[f64], j: usize, m: usize) -> f64 {
    (s[j + 2 * m] - 2.0 * s[j + m] + s[j]) / m as f64
}

/// The `CI_LEVEL` interval of the Allan deviation given its variance estimate and the
/// estimate's equivalent degrees of freedom: `edf avar / sigma^2` is chi-square with `edf`.
pub fn adev_interval(avar: f64, edf: f64) -> (f64, f64) {
    let tail = (1.0 - CI_LEVEL) / 2.0;
    let lo = edf * avar / chi2_quantile(1.0 - tail, edf);
    let hi = edf * avar / chi2_quantile(tail, edf);
    (lo.sqrt(), hi.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octaves_stop_at_the_minimum_cluster_count() {
        assert_eq!(octaves(64), vec![1, 2, 4, 8]);
        assert_eq!(octaves(63), vec![1, 2, 4]);
        assert!(octaves(7).is_empty());
    }

    #[test]
    fn second_differences_never_span_a_gap() {
        // A step between segments would be a huge Allan variance if it were bridged.
        let a = [1.0, 2.0, 1.0, 2.0];
        let b = [101.0, 102.0, 101.0, 102.0];
        let p = oavar(&[&a, &b], 0.5, &[1]);
        assert_eq!((p[0].terms, p[0].clusters, p[0].tau_s), (6, 8, 0.5));
        assert!((p[0].avar - 0.5).abs() < 1e-12, "{}", p[0].avar);
    }

    #[test]
    fn interval_brackets_the_estimate_and_narrows_with_edf() {
        let (lo, hi) = adev_interval(4.0, 10.0);
        assert!(lo < 2.0 && hi > 2.0);
        let (lo2, hi2) = adev_interval(4.0, 1000.0);
        assert!(hi2 - lo2 < (hi - lo) / 5.0);
        // Large edf: about +- 1 / sqrt(2 edf) relative.
        assert!(((hi2 - lo2) / 2.0 / 2.0 - 1.0 / 2000f64.sqrt()).abs() < 1e-3);
    }
}
