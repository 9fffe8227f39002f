//! What a noise model predicts for the overlapping Allan variance of a sampled rate series: its
//! expected value at each averaging factor (the fit's basis functions) and how uncertain the
//! estimate is, as equivalent degrees of freedom. The edf follows Greenhall's approach: the
//! variance of a mean of squared second differences, exact for Gaussian noise, from their
//! covariance under the model (`NoiseModel::coloured_cov`), so it suits any mixture of terms.

use nf_model::noise::NoiseModel;

/// Lags of the second differences summed, in units of m: the flicker tail beyond is below
/// 1e-4 of the sum, the other terms end at 2 m or decay exponentially.
const LAG_SPAN: usize = 16;
/// Lag grid points per m at long averaging times, where the covariance is smooth in the lag.
const LAG_STEPS: usize = 32;

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
            self.group_cov(model, m, 0) - self.group_cov(model, m, m as i64)
        }
    }

    /// Generalised covariance of the means of `m` consecutive values whose first values are
    /// `lag` apart; without a contiguous series' quantisation (`quant_diff_cov`).
    fn group_cov(&self, model: &NoiseModel, m: usize, lag: i64) -> f64 {
        let (mf, step) = (m as f64, self.step_s);
        if self.is_contiguous() {
            // m consecutive values are one window of m steps.
            let t = mf * step;
            let overlap = (t - lag.abs() as f64 * step).max(0.0);
            let w = model.white_dph_rts();
            return model.coloured_cov(lag as f64 * step, t, t) + w * w * overlap / (t * t);
        }
        let win = self.window_s;
        let one = |q: i64| model.mean_cov(q as f64 * step, win, win, q == 0);
        let m = m as i64;
        (1 - m..m).map(|d| (mf - d.abs() as f64) * one(lag + d)).sum::<f64>() / (mf * mf)
    }

    /// Covariance of the second differences `ybar(k + m) - ybar(k)` at `lag`, without a
    /// contiguous series' quantisation.
    fn diff_cov(&self, model: &NoiseModel, m: usize, lag: i64) -> f64 {
        let mi = m as i64;
        2.0 * self.group_cov(model, m, lag) - self.group_cov(model, m, lag + mi) - self.group_cov(model, m, lag - mi)
    }

    /// Quantisation of a contiguous series is white noise of the integrated angle (variance
    /// Q^2): its second differences correlate at lags 0, m and 2m only.
    fn quant_diff_cov(&self, model: &NoiseModel, m: usize, lag: i64) -> f64 {
        if !self.is_contiguous() {
            return 0.0;
        }
        let t = m as f64 * self.step_s;
        let q2 = (model.quantization_arcsec / t).powi(2);
        match lag.unsigned_abs() as usize {
            0 => 6.0 * q2,
            l if l == m => -4.0 * q2,
            l if l == 2 * m => q2,
            _ => 0.0,
        }
    }

    /// Equivalent degrees of freedom of the pooled estimate at factor `m` over segments of
    /// `lens` values: `2 E[avar]^2 / Var[avar]`, segments taken as independent.
    pub fn edf(&self, model: &NoiseModel, m: usize, lens: &[usize]) -> f64 {
        let terms: Vec<usize> = lens
            .iter()
            .filter(|&&n| n + 1 > 2 * m)
            .map(|&n| n + 1 - 2 * m)
            .collect();
        let longest = terms.iter().copied().max().unwrap_or(0);
        if longest == 0 {
            return f64::NAN;
        }
        let c = |l: usize| {
            let l = l as i64;
            (self.diff_cov(model, m, l), self.quant_diff_cov(model, m, l))
        };
        let (s0, q0) = c(0);
        let c0 = s0 + q0;
        // The smooth part on a lag grid (trapezoid rule, with the kinks at m and 2m on grid
        // points), quantisation's lags m and 2m exactly.
        let stride = (m / LAG_STEPS).max(1);
        let reach = |n: usize| (n - 1).min(LAG_SPAN * m) / stride * stride;
        let grid: Vec<(usize, f64)> = (0..=reach(longest)).step_by(stride).map(|l| (l, c(l).0)).collect();
        let spikes: Vec<(usize, f64)> = [m, 2 * m]
            .into_iter()
            .map(|l| (l, c(l)))
            .filter(|(_, (_, q))| *q != 0.0)
            .map(|(l, (s, q))| (l, 2.0 * s * q + q * q))
            .collect();
        let var_sum: f64 = terms
            .iter()
            .map(|&n| {
                let nf = n as f64;
                let last = reach(n);
                let g = |l: usize, v: f64| (nf - l as f64) * v * v;
                let inner: f64 = grid.iter().take_while(|(l, _)| *l <= last).map(|&(l, v)| g(l, v)).sum();
                let (g0, gl) = (g(0, s0), g(last, grid[last / stride].1));
                let ends = (g0 + gl) / 2.0;
                // sum over lags 1..=last of (n - l) c(l)^2
                let smooth = stride as f64 * (inner - ends) + ends - g0;
                let spike: f64 = spikes
                    .iter()
                    .filter(|(l, _)| *l < n)
                    .map(|&(l, v)| (nf - l as f64) * v)
                    .sum();
                // Var of a sum of n squared Gaussian differences: 2 sum_ij c(i - j)^2.
                2.0 * (nf * c0 * c0 + 2.0 * (smooth + spike))
            })
            .sum();
        let total = terms.iter().sum::<usize>() as f64;
        2.0 * c0 * c0 * total * total / var_sum
    }
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
            let via_cov = s.group_cov(&m, k, 0) - s.group_cov(&m, k, k as i64) + s.quant_diff_cov(&m, k, 0) / 2.0;
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
