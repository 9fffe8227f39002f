//! The gyro's noise as physics (`shared/noise-model.md`, IEEE Std 952 units): angle random
//! walk, bias instability (flicker), rate random walk, a Gauss-Markov bias, quantisation and
//! optionally heavy-tailed sample noise.
//!
//! Every second-order statement comes from one kernel: the covariance of two window means of
//! the rate is a second difference of `F`, where `F'' = k` is the term's (generalised)
//! autocovariance. Flicker and random walk are not stationary, so their `k` is defined only up
//! to a constant; a constant adds the same amount to every covariance, which a fit with a
//! constant term (the bias `C`) absorbs exactly. Covariances here are therefore "generalised":
//! right for every contrast of window means (differences, fits with a constant, Allan
//! variances), not for one mean on its own.

use crate::Float;
use core::f64::consts::{LN_2, PI};

/// Seconds per hour: IEEE units are per hour, the project's times are in seconds.
const S_PER_H: f64 = 3600.0;

/// The noise terms of a rate gyro. Zero switches a term off.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NoiseModel {
    /// Angle random walk N, deg/sqrt(h): white rate noise.
    pub arw_deg_rth: f64,
    /// Bias instability B, deg/h: flicker (1/f) bias with the Allan floor 0.664 B (two-sided
    /// PSD `B^2 / (2 pi f)`, IEEE Std 952).
    pub bias_instability_dph: f64,
    /// Rate random walk K, deg/h/sqrt(h).
    pub rrw_dph_rth: f64,
    /// First-order Gauss-Markov bias: standard deviation (deg/h) and correlation time (s).
    pub gm_sigma_dph: f64,
    pub gm_tau_s: f64,
    /// Quantisation Q of the integrated output, arcsec (a step `Q sqrt(12)`).
    pub quantization_arcsec: f64,
    /// Student-t degrees of freedom of the sample noise (same variance); 0 for Gaussian.
    pub student_t_dof: f64,
}

/// Why a noise model is not usable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NoiseError {
    /// A parameter is negative, NaN or infinite; names the parameter.
    Invalid(&'static str),
    /// A Gauss-Markov term needs a positive correlation time.
    GmWithoutTau,
    /// Student-t noise needs more than 2 degrees of freedom for a finite variance.
    DofTooSmall,
}

impl core::fmt::Display for NoiseError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            NoiseError::Invalid(p) => write!(f, "{p} must be a finite number >= 0"),
            NoiseError::GmWithoutTau => write!(f, "a Gauss-Markov sigma needs gm_tau_s > 0"),
            NoiseError::DofTooSmall => write!(f, "student_t_dof must be 0 (Gaussian) or more than 2"),
        }
    }
}

impl Default for NoiseModel {
    fn default() -> Self {
        Self::WHITE_NONE
    }
}

impl NoiseModel {
    /// No noise at all.
    pub const WHITE_NONE: NoiseModel = NoiseModel {
        arw_deg_rth: 0.0,
        bias_instability_dph: 0.0,
        rrw_dph_rth: 0.0,
        gm_sigma_dph: 0.0,
        gm_tau_s: 0.0,
        quantization_arcsec: 0.0,
        student_t_dof: 0.0,
    };

    /// White noise only, given as the standard deviation of a mean over `dwell_s`.
    pub fn white(sigma_dph: f64, dwell_s: f64) -> Self {
        NoiseModel {
            arw_deg_rth: arw_from_mean_sd(sigma_dph, dwell_s),
            ..Self::WHITE_NONE
        }
    }

    pub fn validate(&self) -> Result<(), NoiseError> {
        check_terms(
            &[
                ("arw_deg_rth", self.arw_deg_rth),
                ("bias_instability_dph", self.bias_instability_dph),
                ("rrw_dph_rth", self.rrw_dph_rth),
                ("gm_sigma_dph", self.gm_sigma_dph),
                ("gm_tau_s", self.gm_tau_s),
                ("quantization_arcsec", self.quantization_arcsec),
                ("student_t_dof", self.student_t_dof),
            ],
            self.gm_sigma_dph,
            self.gm_tau_s,
        )?;
        if self.student_t_dof != 0.0 && self.student_t_dof <= 2.0 {
            return Err(NoiseError::DofTooSmall);
        }
        Ok(())
    }

    /// Whether any term correlates the rate over time (everything but white and quantisation).
    pub fn is_coloured(&self) -> bool {
        self.bias_instability_dph > 0.0 || self.rrw_dph_rth > 0.0 || self.gm_sigma_dph > 0.0
    }

    /// White noise density, deg/h * sqrt(s): a mean over `T` s has sd `white_dph_rts / sqrt(T)`.
    pub fn white_dph_rts(&self) -> f64 {
        self.arw_deg_rth * S_PER_H.sqrt()
    }

    /// Rate random walk, deg/h per sqrt(s).
    pub fn rrw_dph_rts(&self) -> f64 {
        self.rrw_dph_rth / S_PER_H.sqrt()
    }

    /// Flicker level `h` of the PSD `h / f` in the convention where white noise has PSD `N^2`.
    pub fn flicker_h(&self) -> f64 {
        self.bias_instability_dph * self.bias_instability_dph / (2.0 * PI)
    }

    /// Standard deviation (deg/h) of the white part of a mean over `t_s` seconds.
    pub fn white_mean_sd_dph(&self, t_s: f64) -> f64 {
        self.white_dph_rts() / t_s.sqrt()
    }

    /// Whether the Gauss-Markov term is short beside a mean over `t_s` s (a tenth of it or
    /// less: a sensor's filter, as `nf allan` fits it), so that such means do not share it.
    pub fn gm_within(&self, t_s: f64) -> bool {
        self.gm_sigma_dph > 0.0 && 10.0 * self.gm_tau_s <= t_s
    }

    /// Standard deviation (deg/h) of a mean over `t_s` s that it shares with no other such
    /// mean: the white part, and the Gauss-Markov term where it is short beside `t_s`
    /// ([`Self::gm_within`]), the exact variance of its mean.
    pub fn own_mean_sd_dph(&self, t_s: f64) -> f64 {
        let white = self.white_mean_sd_dph(t_s);
        if !self.gm_within(t_s) {
            return white;
        }
        let gm = NoiseModel {
            gm_sigma_dph: self.gm_sigma_dph,
            gm_tau_s: self.gm_tau_s,
            ..Self::WHITE_NONE
        };
        (white * white + gm.coloured_cov(0.0, t_s, t_s)).sqrt()
    }

    /// Second antiderivative of the coloured terms' autocovariance (deg/h)^2 s^2.
    fn kernel(&self, x: f64) -> f64 {
        let x = x.abs();
        let mut f = 0.0;
        if self.gm_sigma_dph > 0.0 {
            let (s, tau) = (self.gm_sigma_dph, self.gm_tau_s);
            f += s * s * tau * tau * (Float::exp(-x / tau) + x / tau);
        }
        let k = self.rrw_dph_rts();
        f -= k * k * x * x * x / 12.0;
        if x > 0.0 {
            f -= self.flicker_h() * x * x * Float::ln(x);
        }
        f
    }

    /// Generalised covariance (deg/h)^2 of the coloured terms' means over two windows of
    /// lengths `t1_s`, `t2_s` whose centres are `dt_s` apart (see the module note).
    pub fn coloured_cov(&self, dt_s: f64, t1_s: f64, t2_s: f64) -> f64 {
        let (s, d) = ((t1_s + t2_s) / 2.0, (t1_s - t2_s) / 2.0);
        let f = |x: f64| self.kernel(x);
        (f(dt_s + s) + f(dt_s - s) - f(dt_s + d) - f(dt_s - d)) / (t1_s * t2_s)
    }

    /// Variance (deg/h)^2 that one window mean of length `t_s` has on its own, beyond the
    /// coloured part: white noise and quantisation (independent between separate windows).
    pub fn independent_var(&self, t_s: f64) -> f64 {
        let w = self.white_dph_rts();
        let q = self.quantization_arcsec;
        w * w / t_s + 2.0 * q * q / (t_s * t_s)
    }

    /// Generalised covariance of two separate (non-overlapping) window means; `same` when
    /// they are one window.
    pub fn mean_cov(&self, dt_s: f64, t1_s: f64, t2_s: f64, same: bool) -> f64 {
        let own = if same { self.independent_var(t1_s) } else { 0.0 };
        own + self.coloured_cov(dt_s, t1_s, t2_s)
    }

    /// Allan variance (deg/h)^2 at averaging time `tau_s`, every term included.
    pub fn allan_var(&self, tau_s: f64) -> f64 {
        let w = self.white_dph_rts();
        let q = self.quantization_arcsec;
        // Adjacent windows share an end point of the quantised angle: 3 Q^2 / tau^2.
        let coloured = (4.0 * self.kernel(tau_s) - 3.0 * self.kernel(0.0) - self.kernel(2.0 * tau_s)) / (tau_s * tau_s);
        w * w / tau_s + 3.0 * q * q / (tau_s * tau_s) + coloured
    }

    pub fn allan_dev(&self, tau_s: f64) -> f64 {
        self.allan_var(tau_s).max(0.0).sqrt()
    }
}

/// The rules every noise model keeps, in either float: each term finite and not negative, a
/// Gauss-Markov sigma with a correlation time.
pub(crate) fn check_terms<F: Float>(terms: &[(&'static str, F)], gm_sigma: F, gm_tau: F) -> Result<(), NoiseError> {
    if let Some((name, _)) = terms.iter().find(|(_, v)| !(v.is_finite() && *v >= F::zero())) {
        return Err(NoiseError::Invalid(name));
    }
    if gm_sigma > F::zero() && gm_tau <= F::zero() {
        return Err(NoiseError::GmWithoutTau);
    }
    Ok(())
}

/// ARW N (deg/sqrt(h)) that gives a mean over `dwell_s` the standard deviation `sigma_dph`.
pub fn arw_from_mean_sd(sigma_dph: f64, dwell_s: f64) -> f64 {
    sigma_dph * (dwell_s / S_PER_H).sqrt()
}

/// The Allan deviation floor of pure flicker, as a multiple of B: `sqrt(2 ln 2 / pi)`.
pub fn flicker_floor_factor() -> f64 {
    (2.0 * LN_2 / PI).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs()
    }

    #[test]
    fn allan_slopes_match_the_ieee_table() {
        let n = NoiseModel {
            arw_deg_rth: 0.01,
            ..NoiseModel::WHITE_NONE
        };
        // N / sqrt(tau), tau in hours.
        for tau in [1.0, 36.0, 3600.0] {
            assert!(close(n.allan_dev(tau), 0.01 / (tau / 3600.0).sqrt(), 1e-12));
        }
        let b = NoiseModel {
            bias_instability_dph: 0.05,
            ..NoiseModel::WHITE_NONE
        };
        for tau in [0.1, 10.0, 1e4] {
            assert!(close(b.allan_dev(tau), 0.664 * 0.05, 1e-3), "{}", b.allan_dev(tau));
        }
        let k = NoiseModel {
            rrw_dph_rth: 0.2,
            ..NoiseModel::WHITE_NONE
        };
        for tau in [1.0, 100.0, 1e5] {
            assert!(close(k.allan_dev(tau), 0.2 * (tau / 3600.0 / 3.0).sqrt(), 1e-6));
        }
        let q = NoiseModel {
            quantization_arcsec: 2.0,
            ..NoiseModel::WHITE_NONE
        };
        assert!(close(q.allan_dev(0.5), 3f64.sqrt() * 2.0 / 0.5, 1e-12));
    }

    #[test]
    fn a_short_gauss_markov_term_is_part_of_a_means_own_noise() {
        // An ADIS16405 as `nf allan` fits it: N 1.272e-4 deg/sqrt(h), a 0.01 s filter tail
        // of 0.0444 deg/h. A 1 s mean: white 0.00763 deg/h, with the tail 0.0099.
        let m = NoiseModel {
            arw_deg_rth: 1.272e-4,
            gm_sigma_dph: 0.04441,
            gm_tau_s: 0.01,
            ..NoiseModel::WHITE_NONE
        };
        let (s, r) = (m.gm_sigma_dph, 1.0 / m.gm_tau_s);
        let textbook = 2.0 * s * s * (r - 1.0 + (-r).exp()) / (r * r);
        let white = m.white_mean_sd_dph(1.0);
        assert!(close(m.own_mean_sd_dph(1.0), (white * white + textbook).sqrt(), 1e-9));
        assert!(
            close(m.own_mean_sd_dph(1.0), 0.00988, 2e-3),
            "{}",
            m.own_mean_sd_dph(1.0)
        );
        // A term as long as a tenth of the mean or longer is shared: not the mean's own.
        let long = NoiseModel { gm_tau_s: 0.2, ..m };
        assert_eq!(long.own_mean_sd_dph(1.0), white);
        assert_eq!(
            NoiseModel::white(0.005, 2.0).own_mean_sd_dph(2.0),
            NoiseModel::white(0.005, 2.0).white_mean_sd_dph(2.0)
        );
    }

    #[test]
    fn gauss_markov_allan_variance_is_the_textbook_form() {
        let (s, tc) = (0.02, 50.0);
        let m = NoiseModel {
            gm_sigma_dph: s,
            gm_tau_s: tc,
            ..NoiseModel::WHITE_NONE
        };
        for tau in [0.5, 10.0, 50.0, 400.0, 1e4] {
            let r = tau / tc;
            let want = s * s / (r * r) * (2.0 * r - 3.0 + 4.0 * (-r).exp() - (-2.0 * r).exp());
            assert!(close(m.allan_var(tau), want, 1e-6), "{tau}");
        }
        // Peak near tau = 1.89 tc at 0.62 sigma.
        let peak = (1..400).map(|i| m.allan_dev(i as f64)).fold(0.0, f64::max);
        assert!(close(peak, 0.6178 * s, 2e-3), "{peak}");
    }

    #[test]
    fn stationary_covariance_of_separate_windows() {
        // Gauss-Markov: cov of two T-means D apart is sigma^2 (tau/T)^2 2 (cosh(T/tau) - 1) e^(-D/tau).
        let m = NoiseModel {
            gm_sigma_dph: 0.1,
            gm_tau_s: 7.0,
            ..NoiseModel::WHITE_NONE
        };
        let (t, d) = (2.0, 9.0);
        let want = 0.01 * (7.0f64 / t).powi(2) * 2.0 * ((t / 7.0).cosh() - 1.0) * (-d / 7.0f64).exp();
        assert!(close(m.coloured_cov(d, t, t), want, 1e-9));
        // White: N^2 / T on the diagonal, nothing between separate windows.
        let w = NoiseModel::white(0.005, 2.0);
        assert!(close(w.mean_cov(0.0, 2.0, 2.0, true), 0.005f64.powi(2), 1e-12));
        assert_eq!(w.mean_cov(3.0, 2.0, 2.0, false), 0.0);
    }

    #[test]
    fn random_walk_and_flicker_differences() {
        // Random walk: the difference of two T-means D apart has variance K^2 (D - T/3) for D >= T.
        let m = NoiseModel {
            rrw_dph_rth: 0.3,
            ..NoiseModel::WHITE_NONE
        };
        let (t, d) = (2.0, 10.0);
        let var_diff = 2.0 * m.coloured_cov(0.0, t, t) - 2.0 * m.coloured_cov(d, t, t);
        let k2 = m.rrw_dph_rts().powi(2);
        assert!(close(var_diff, k2 * (d - t / 3.0), 1e-9), "{var_diff}");
        // Flicker: Allan variance (adjacent windows) is 2 ln2 B^2 / pi at every tau.
        let f = NoiseModel {
            bias_instability_dph: 0.01,
            ..NoiseModel::WHITE_NONE
        };
        for t in [0.25, 2.0, 300.0] {
            let adj = f.coloured_cov(0.0, t, t) - f.coloured_cov(t, t, t);
            assert!(close(adj, 2.0 * LN_2 / PI * 1e-4, 1e-9), "{t}");
        }
    }

    #[test]
    fn validation_names_the_parameter() {
        let bad = NoiseModel {
            rrw_dph_rth: f64::NAN,
            ..NoiseModel::WHITE_NONE
        };
        assert_eq!(bad.validate(), Err(NoiseError::Invalid("rrw_dph_rth")));
        let gm = NoiseModel {
            gm_sigma_dph: 0.1,
            ..NoiseModel::WHITE_NONE
        };
        assert_eq!(gm.validate(), Err(NoiseError::GmWithoutTau));
        let t = NoiseModel {
            student_t_dof: 2.0,
            ..NoiseModel::WHITE_NONE
        };
        assert_eq!(t.validate(), Err(NoiseError::DofTooSmall));
        assert_eq!(NoiseModel::white(0.005, 2.0).validate(), Ok(()));
    }
}
