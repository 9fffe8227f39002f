//! What a noise model predicts for the overlapping Allan variance of a sampled rate series: its
//! expected value at each averaging factor (the fit's basis functions) and the covariance of
//! the estimates at two factors, whose diagonal gives the equivalent degrees of freedom. This
//! follows Greenhall's approach: the covariance of means of squared second differences, exact
//! for Gaussian noise, from the covariance of the window means under the model
//! (`NoiseModel::coloured_cov`), so it suits any mixture of terms.

use crate::allan::Point;
use nf_model::noise::NoiseModel;

/// Lags of the second differences summed beyond their overlap, in units of the longer
/// factor: the flicker tail beyond is below 1e-4 of the sum, the other terms end at the overlap
/// or decay exponentially.
const LAG_SPAN: i64 = 16;
/// Lag grid points per shorter factor at long averaging times, where the covariance is smooth
/// in the lag between kinks that fall on the grid.
const LAG_STEPS: i64 = 32;
/// Most lag grid points for a pair of factors far apart, where the short difference's
/// structure is no longer resolved: their correlation is then small (white, flicker) or
/// smooth in the lag (random walk).
const MAX_GRID: i64 = 4096;

/// How the values were taken: each a mean over `window_s`, one every `step_s`. A static log
/// has window = step; a recording's dwell means have dead time between them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampling {
    pub step_s: f64,
    pub window_s: f64,
}

impl Sampling {
    pub fn contiguous(step_s: f64) -> Sampling {
        Sampling {
            step_s,
            window_s: step_s,
        }
    }

    pub fn is_contiguous(&self) -> bool {
        (self.window_s - self.step_s).abs() <= 1e-9 * self.step_s
    }

    /// Expected overlapping Allan variance at factor `m`, (deg/h)^2.
    pub fn expected_avar(&self, model: &NoiseModel, m: usize) -> f64 {
        if self.is_contiguous() {
            model.allan_var(m as f64 * self.step_s)
        } else {
            let (c, _) = self.diff_cov(model, m, m, 0);
            c / 2.0
        }
    }

    /// Expected Allan variance at `tau_s`, taken to whole steps where there is dead time.
    pub fn expected_at(&self, model: &NoiseModel, tau_s: f64) -> f64 {
        if self.is_contiguous() {
            model.allan_var(tau_s)
        } else {
            self.expected_avar(model, (tau_s / self.step_s).round().max(1.0) as usize)
        }
    }

    /// Generalised covariance of the mean of `ma` values from value 0 and the mean of `mb`
    /// values from value `delta`, as (smooth part, a contiguous series' quantisation). The
    /// quantisation is white noise of the integrated angle (variance Q^2), so it enters only
    /// where window ends coincide.
    fn window_cov(&self, model: &NoiseModel, ma: i64, mb: i64, delta: i64) -> (f64, f64) {
        if !self.is_contiguous() {
            return (means_of_means(ma, mb, delta, |q| self.value_cov(model, q)), 0.0);
        }
        let step = self.step_s;
        let (fa, fb) = (ma as f64, mb as f64);
        let (ta, tb) = (fa * step, fb * step);
        let centres = (delta as f64 + (fb - fa) / 2.0) * step;
        let overlap = ((ma.min(delta + mb) - delta.max(0)).max(0)) as f64 * step;
        let w = model.white_dph_rts();
        let smooth = model.coloured_cov(centres, ta, tb) + w * w * overlap / (ta * tb);
        let same = |x: i64, y: i64| f64::from(u8::from(x == y));
        let ends = same(ma, delta + mb) - same(ma, delta) - same(0, delta + mb) + same(0, delta);
        (smooth, model.quantization_arcsec.powi(2) * ends / (ta * tb))
    }

    /// Covariance of two values `q` steps apart (means over the window, with dead time).
    fn value_cov(&self, model: &NoiseModel, q: i64) -> f64 {
        model.mean_cov(q as f64 * self.step_s, self.window_s, self.window_s, q == 0)
    }

    /// Covariance of the second differences `ybar(i + ma) - ybar(i)` at `ma` and at `mb` with
    /// `j - i = lag`, as (smooth, quantisation) parts.
    fn diff_cov(&self, model: &NoiseModel, ma: usize, mb: usize, lag: i64) -> (f64, f64) {
        let (ma, mb) = (ma as i64, mb as i64);
        second_differences(ma, mb, lag, |d| self.window_cov(model, ma, mb, d))
    }

    /// Covariance of the Allan variance estimates at factors `ma` and `mb`, pooled over
    /// independent segments of `lens` values.
    pub fn avar_cov(&self, model: &NoiseModel, ma: usize, mb: usize, lens: &[usize]) -> f64 {
        self.pooled_cov(&self.lag_grid(model, ma, mb), lens)
    }

    /// The covariances of the second differences at `ma` and `mb` over the lags that matter,
    /// under `model`: linear in its terms' variances.
    pub fn lag_grid(&self, model: &NoiseModel, ma: usize, mb: usize) -> LagGrid {
        self.lag_grids(model, &[(ma, mb)]).remove(0)
    }

    /// [`Sampling::lag_grid`] of each pair of factors.
    pub fn lag_grids(&self, model: &NoiseModel, pairs: &[(usize, usize)]) -> Vec<LagGrid> {
        let spans: Vec<GridSpan> = pairs
            .iter()
            .map(|&(ma, mb)| GridSpan::of(ma as i64, mb as i64))
            .collect();
        // With dead time every window is a sum over values: their covariances by lag are
        // computed once for every lag the grids reach, not once per window (20 000 dwell
        // means took half a minute).
        let table = (!self.is_contiguous() && !spans.is_empty()).then(|| {
            let first = spans.iter().map(|g| g.lo - 2 * g.ma + 1).min().unwrap_or(0);
            let end = spans.iter().map(|g| g.hi + 2 * g.mb).max().unwrap_or(0);
            let values: Vec<f64> = (first..end).map(|q| self.value_cov(model, q)).collect();
            (first, values)
        });
        spans
            .into_iter()
            .map(|g| {
                let (ia, ib) = (g.ma, g.mb);
                let diff_cov = |l: i64| match &table {
                    Some((first, values)) => second_differences(ia, ib, l, |d| {
                        (means_of_means(ia, ib, d, |q| values[(q - first) as usize]), 0.0)
                    }),
                    None => self.diff_cov(model, ia as usize, ib as usize, l),
                };
                let smooth = (g.lo..=g.hi)
                    .step_by(g.stride as usize)
                    .map(|l| diff_cov(l).0)
                    .collect();
                // Quantisation: only at lags where ends of the two differences coincide.
                let mut lags: Vec<i64> = [0, ia, 2 * ia]
                    .iter()
                    .flat_map(|ea| [0, ib, 2 * ib].map(|eb| ea - eb))
                    .collect();
                lags.sort_unstable();
                lags.dedup();
                let spikes = lags.into_iter().map(|l| (l, diff_cov(l))).collect();
                LagGrid {
                    ma: ia,
                    mb: ib,
                    lo: g.lo,
                    hi: g.hi,
                    stride: g.stride,
                    smooth,
                    spikes,
                }
            })
            .collect()
    }

    /// The pooled covariance of the Allan variance estimates from their lag grid.
    pub fn pooled_cov(&self, g: &LagGrid, lens: &[usize]) -> f64 {
        let terms = |m: i64| -> Vec<i64> { lens.iter().map(|&n| (n as i64 + 1 - 2 * m).max(0)).collect() };
        let (ta, tb) = (terms(g.ma), terms(g.mb));
        let (sum_a, sum_b) = (ta.iter().sum::<i64>() as f64, tb.iter().sum::<i64>() as f64);
        if sum_a == 0.0 || sum_b == 0.0 {
            return f64::NAN;
        }
        let grid: Vec<(i64, f64)> = (g.lo..=g.hi)
            .step_by(g.stride as usize)
            .zip(g.smooth.iter().copied())
            .collect();
        let spikes: Vec<(i64, f64)> = g
            .spikes
            .iter()
            .filter(|(_, (_, q))| *q != 0.0)
            .map(|&(l, (s, q))| (l, 2.0 * s * q + q * q))
            .collect();
        let mut total = 0.0;
        for (&na, &nb) in ta.iter().zip(&tb) {
            // Pairs (i, j) of second differences with j - i = l.
            let pairs = |l: i64| (na.min(nb - l) - (-l).max(0)).max(0) as f64;
            let (first, last) = ((1 - na).max(g.lo), (nb - 1).min(g.hi));
            if first > last {
                continue;
            }
            let inside: Vec<(i64, f64)> = grid
                .iter()
                .filter(|(l, _)| (first..=last).contains(l))
                .map(|&(l, v)| (l, pairs(l) * v * v))
                .collect();
            let smooth = match (inside.first(), inside.last()) {
                (Some(a), Some(b)) => {
                    let ends = (a.1 + b.1) / 2.0;
                    g.stride as f64 * (inside.iter().map(|x| x.1).sum::<f64>() - ends) + ends
                }
                _ => 0.0,
            };
            let spike: f64 = spikes.iter().map(|&(l, v)| pairs(l) * v).sum();
            // Cov of two sums of squared Gaussian differences: 2 sum_ij c(i, j)^2.
            total += 2.0 * (smooth + spike);
        }
        total / (4.0 * sum_a * sum_b)
    }

    /// Equivalent degrees of freedom of the pooled estimate at factor `m`:
    /// `2 E[avar]^2 / Var[avar]`.
    pub fn edf(&self, model: &NoiseModel, m: usize, lens: &[usize]) -> f64 {
        let e = self.expected_avar(model, m);
        2.0 * e * e / self.avar_cov(model, m, m, lens)
    }
}

/// The lags a pair of factors' grid covers, and its stride.
struct GridSpan {
    ma: i64,
    mb: i64,
    lo: i64,
    hi: i64,
    stride: i64,
}

impl GridSpan {
    fn of(ma: i64, mb: i64) -> GridSpan {
        let reach = LAG_SPAN * ma.max(mb);
        let span = 2 * (ma + mb) + 2 * reach;
        let stride = (ma.min(mb) / LAG_STEPS).max(span / MAX_GRID).max(1) as u64;
        let stride = stride.next_power_of_two() as i64;
        GridSpan {
            ma,
            mb,
            lo: (-2 * mb - reach) / stride * stride,
            hi: (2 * ma + reach) / stride * stride,
            stride,
        }
    }
}

/// Covariance of the means of `ma` values from 0 and of `mb` values from `delta`, from the
/// covariance `one(q)` of two values `q` apart: each pair of values by its lag, counted.
fn means_of_means(ma: i64, mb: i64, delta: i64, one: impl Fn(i64) -> f64) -> f64 {
    let pairs = |d: i64| (ma.min(mb - d) - (-d).max(0)).max(0) as f64;
    let sum: f64 = (1 - ma..mb).map(|d| pairs(d) * one(delta + d)).sum();
    sum / (ma as f64 * mb as f64)
}

/// Covariance of the second differences at `ma` and `mb`, `lag` apart, from the covariance
/// `k(delta)` of their windows (the window at `mb` starting `delta` after the one at `ma`).
fn second_differences(ma: i64, mb: i64, lag: i64, k: impl Fn(i64) -> (f64, f64)) -> (f64, f64) {
    let (a, b, c, d) = (k(lag + mb - ma), k(lag - ma), k(lag + mb), k(lag));
    (a.0 - b.0 - c.0 + d.0, a.1 - b.1 - c.1 + d.1)
}

/// The covariances of two second differences (at factors `ma`, `mb`) at each lag of a grid
/// and at the lags where their ends meet, as (smooth, quantisation) parts. Linear in a noise
/// model's variances, so a model's grid is the sum of its terms' unit grids, scaled.
#[derive(Debug, Clone, PartialEq)]
pub struct LagGrid {
    ma: i64,
    mb: i64,
    lo: i64,
    hi: i64,
    stride: i64,
    smooth: Vec<f64>,
    spikes: Vec<(i64, (f64, f64))>,
}

impl LagGrid {
    /// `self + c other`, for grids of the same two factors.
    pub fn add_scaled(&mut self, other: &LagGrid, c: f64) {
        for (a, b) in self.smooth.iter_mut().zip(&other.smooth) {
            *a += c * b;
        }
        for ((_, a), (_, b)) in self.spikes.iter_mut().zip(&other.spikes) {
            a.0 += c * b.0;
            a.1 += c * b.1;
        }
    }

    /// The same lags with every covariance zero.
    pub fn zero(&self) -> LagGrid {
        LagGrid {
            smooth: vec![0.0; self.smooth.len()],
            spikes: self.spikes.iter().map(|&(l, _)| (l, (0.0, 0.0))).collect(),
            ..self.clone()
        }
    }
}

/// Where the curve bottoms out (tau s, adev deg/h): the measured point with the lowest
/// deviation, and the fitted model's minimum between the first and last averaging times.
pub fn floor(points: &[Point], model: &NoiseModel, sampling: Sampling) -> ((f64, f64), (f64, f64)) {
    let measured = points
        .iter()
        .map(|p| (p.tau_s, p.avar.sqrt()))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((f64::NAN, f64::NAN));
    let fitted = curve_taus(points, sampling, 256)
        .into_iter()
        .map(|t| (t, sampling.expected_at(model, t).max(0.0).sqrt()))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((f64::NAN, f64::NAN));
    (measured, fitted)
}

/// About `count` log-spaced averaging times over the points' range, at whole sample steps
/// where the sampling has dead time.
pub fn curve_taus(points: &[Point], sampling: Sampling, count: usize) -> Vec<f64> {
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return Vec::new();
    };
    let ratio = last.tau_s / first.tau_s;
    let mut taus: Vec<f64> = (0..count)
        .map(|i| first.tau_s * ratio.powf(i as f64 / (count - 1).max(1) as f64))
        .map(|t| {
            if sampling.is_contiguous() {
                t
            } else {
                (t / sampling.step_s).round().max(1.0) * sampling.step_s
            }
        })
        .collect();
    taus.dedup();
    taus
}

#[cfg(test)]
mod tests {
    use super::*;

    fn white() -> NoiseModel {
        NoiseModel {
            arw_deg_rth: 0.01,
            ..NoiseModel::WHITE_NONE
        }
    }

    #[test]
    fn contiguous_expectation_is_the_models_allan_variance() {
        let m = NoiseModel {
            arw_deg_rth: 0.003,
            bias_instability_dph: 0.02,
            rrw_dph_rth: 0.1,
            gm_sigma_dph: 0.01,
            gm_tau_s: 30.0,
            quantization_arcsec: 0.5,
            ..NoiseModel::WHITE_NONE
        };
        let s = Sampling::contiguous(0.1);
        for k in [1usize, 8, 256] {
            let (smooth, quant) = s.diff_cov(&m, k, k, 0);
            let via_cov = (smooth + quant) / 2.0;
            assert!((via_cov / s.expected_avar(&m, k) - 1.0).abs() < 1e-9, "{k}");
        }
    }

    #[test]
    fn dead_time_leaves_white_noise_at_the_window_length() {
        // Means of 2 s every 3 s: white noise averages over the 2 s it sees, not 3 s.
        let s = Sampling {
            step_s: 3.0,
            window_s: 2.0,
        };
        let w = white().white_dph_rts();
        for k in [1usize, 4] {
            let want = w * w / (2.0 * k as f64);
            assert!((s.expected_avar(&white(), k) / want - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn white_edf_matches_the_classic_formula() {
        // Howe, Allan and Barnes' white-FM edf for the overlapping estimator (NIST SP 1065
        // Table 9 form), N values: [3(N-1)/(2m) - 2(N-2)/N] 4m^2/(4m^2 + 5).
        let s = Sampling::contiguous(1.0);
        let n = 4096usize;
        for m in [1usize, 4, 64, 512] {
            let (nf, mf) = (n as f64 + 1.0, m as f64);
            let hab = (3.0 * (nf - 1.0) / (2.0 * mf) - 2.0 * (nf - 2.0) / nf) * 4.0 * mf * mf / (4.0 * mf * mf + 5.0);
            let edf = s.edf(&white(), m, &[n]);
            assert!((edf / hab - 1.0).abs() < 0.03, "m {m}: {edf} vs {hab}");
        }
        // Two independent halves: about the edf of the whole.
        let halves = s.edf(&white(), 4, &[2048, 2048]);
        assert!((halves / s.edf(&white(), 4, &[4096]) - 1.0).abs() < 0.01);
    }

    #[test]
    fn power_law_edf_matches_greenhall() {
        // allantools 2024.6 edf_greenhall(alpha, d=2, m, N=4097, overlapping=True) for white,
        // flicker and random-walk FM and white PM (quantisation); n = 4096 rates.
        let s = Sampling::contiguous(1.0);
        let unit = |f: fn(&mut NoiseModel)| {
            let mut m = NoiseModel::WHITE_NONE;
            f(&mut m);
            m
        };
        let models = [
            unit(|m| m.arw_deg_rth = 0.01),
            unit(|m| m.bias_instability_dph = 0.01),
            unit(|m| m.rrw_dph_rth = 0.01),
            unit(|m| m.quantization_arcsec = 0.01),
        ];
        let greenhall = [
            (
                64,
                [
                    93.77953351219203,
                    73.30858212055797,
                    57.79292637190099,
                    2058.268896583262,
                ],
            ),
            (
                512,
                [
                    9.821087301983495,
                    7.602024714048248,
                    5.89764370968433,
                    1728.5097672337529,
                ],
            ),
        ];
        for (m, want) in greenhall {
            for (model, want) in models.iter().zip(want) {
                let edf = s.edf(model, m, &[4096]);
                assert!((edf / want - 1.0).abs() < 0.01, "m {m} {model:?}: {edf} vs {want}");
            }
        }
    }
}
