//! The paper's equations exactly as published, to reproduce its numbers.
//!
//! They are not the project's physics: [`crate::exact`] and [`crate::uncertainty`] are. What
//! each one gets wrong is said beside it and pinned by tests.

use crate::angle::sincos_deg;
use crate::{ARCSEC_PER_DEG, EARTH_RATE_DPH, Float, c};

fn rad<F: Float>(deg: F) -> F {
    deg.to_radians()
}

/// Eq. 7: the ideal gyro output at encoder angle `gamma`.
pub fn eq7_rate<F: Float>(lat_deg: F, psi_deg: F, gamma_deg: F, bias_dph: F) -> F {
    c::<F>(EARTH_RATE_DPH) * sincos_deg(lat_deg).1 * sincos_deg(gamma_deg + psi_deg).1 + bias_dph
}

/// Eq. 10: with a gyro misalignment `eps` only. Agrees with the exact model.
pub fn eq10_rate<F: Float>(lat_deg: F, psi_deg: F, gamma_deg: F, eps_deg: F, bias_dph: F) -> F {
    let (sl, cl) = sincos_deg(lat_deg);
    let (se, ce) = sincos_deg(eps_deg);
    c::<F>(EARTH_RATE_DPH) * (cl * sincos_deg(gamma_deg + psi_deg).1 * ce + sl * se) + bias_dph
}

/// Eq. 18: `cos(alpha_i)` for shaft misalignment `eta` and gyro misalignment `eps`.
pub fn eq18_cos_alpha<F: Float>(gamma_deg: F, eta_deg: F, eps_deg: F) -> F {
    let (sg, cg) = sincos_deg(gamma_deg);
    let (sh, ch) = sincos_deg(eta_deg);
    let (se, ce) = sincos_deg(eps_deg);
    sg * sg * ce + cg * (sh * se + ch * ce * cg)
}

/// Eq. 19 as published, with `sin(alpha) = +sqrt(1 - cos^2(alpha))`.
///
/// The positive root drops the sign of the gyro axis elevation: the exact elevation is Eq. 17's
/// `z_i = cos(eta) sin(eps) - sin(eta) cos(eps) cos(gamma)`, whose first harmonic shifts the
/// azimuth. Eq. 19 turns it into a rectified `|cos(gamma)|` (even harmonics only): residuals
/// and no azimuth shift, where the physics has an azimuth shift and no residual.
pub fn eq19_rate<F: Float>(lat_deg: F, psi_deg: F, gamma_deg: F, eta_deg: F, eps_deg: F, bias_dph: F) -> F {
    let (sl, cl) = sincos_deg(lat_deg);
    let ca = eq18_cos_alpha(gamma_deg, eta_deg, eps_deg).min(F::one());
    let sa = (F::one() - ca * ca).max(F::zero()).sqrt();
    c::<F>(EARTH_RATE_DPH) * (cl * sincos_deg(gamma_deg + psi_deg).1 * ca + sl * sa) + bias_dph
}

/// Eq. 24: azimuth uncertainty (arcsec) from the gyro uncertainty `sigma_w` (deg/h) over `n`
/// equal steps. Exact for white noise on equal steps (checked against the fit's covariance).
pub fn eq24_arcsec<F: Float>(n: u32, sigma_w_dph: F, lat_deg: F) -> F {
    let amp = c::<F>(EARTH_RATE_DPH) * sincos_deg(lat_deg).1;
    (c::<F>(2.0) / c(n as f64)).sqrt() * sigma_w_dph / amp * c(180.0 * ARCSEC_PER_DEG / core::f64::consts::PI)
}

/// Eq. 26: the paper's encoder term, `sigma_psi = sigma_gamma`, in arcsec.
///
/// That holds for an error common to all positions (a zero offset, which is the azimuth
/// reference itself); for independent errors at each position the fit averages them to
/// `sigma_gamma sqrt(3 / (2 n))` ([`crate::uncertainty::encoder_arcsec`]).
pub fn eq26_arcsec<F: Float>(sigma_gamma_deg: F) -> F {
    sigma_gamma_deg * c(ARCSEC_PER_DEG)
}

/// Eq. 30 as printed: the azimuth uncertainty (arcsec) from an uncertainty `sigma_eta` of the
/// shaft misalignment `eta`, with gyro misalignment `eps`.
///
/// It does not depend on the direction of the tilt and gives 0.7" for `sigma_eta = eta =
/// 0.003 deg`, `eps = 0.01 deg`, `n = 180`, `psi = 45 deg`, `lat = 43.8 deg`; the exact model
/// gives up to `sigma_eta tan(lat)` = 10.4" ([`crate::uncertainty::tilt_arcsec`]). Its `a6` is
/// a difference of nearly equal terms: evaluate it in `f64`.
pub fn eq30_arcsec<F: Float>(n: u32, lat_deg: F, psi_deg: F, eta_deg: F, eps_deg: F, sigma_eta_deg: F) -> F {
    let (sp, cp) = (rad(lat_deg).sin(), rad(lat_deg).cos());
    let (ss, cs) = (rad(psi_deg).sin(), rad(psi_deg).cos());
    let (sh, ch) = (rad(eta_deg).sin(), rad(eta_deg).cos());
    let (se, ce) = (rad(eps_deg).sin(), rad(eps_deg).cos());
    let k = |x: f64| c::<F>(x);
    let p2 = |x: F| x * x;
    let p4 = |x: F| x * x * x * x;
    let a1 = p2(ch) * p2(se) * (k(0.125) + k(0.25) * p2(cs));
    let a2 = p2(sh) * p2(ce) * (k(0.0625) + k(0.25) * p2(cs));
    let a3 = p2(sh) * p2(ch) * (k(0.375) * p4(se) + k(0.2734) * p4(ce));
    let a4 = p2(sh) * ch * (k(0.0782) * p4(ce) - k(0.125) * p2(se) * p2(ce));
    let a5 = k(0.0625) * p2(ce) * p2(ch) * p2(se) + k(0.0234) * p4(ce) * p2(sh) + k(0.3125) * p2(se) * p2(ce);
    let a6 =
        F::one() - (k(0.375) * p2(ce) + k(0.25) * p2(ce) * ch + k(0.5) * p2(sh) * p2(se) + k(0.375) * p2(ch) * p2(ce));
    let b1 = p2(sh) * p2(se) * (k(0.125) + k(0.25) * p2(ss)) + p2(ch) * p2(ce) * (k(0.0625) + k(0.25) * p2(ss));
    let b2 = k(0.25) * p2(cs) * p2(ce) + k(0.0625) * p2(ce) + k(0.125) * p2(ce) * ch;
    let nn = k(n as f64);
    let num = nn * p2(cp) * (a1 + a2) + p2(sp) * ((a3 + a4 + a5) / a6);
    let den = nn * p2(cp) * (b1 + b2);
    rad(sigma_eta_deg) * (num / den).sqrt() * k(180.0 * ARCSEC_PER_DEG / core::f64::consts::PI)
}

/// Eq. 31: the total of independent terms.
pub fn eq31<F: Float>(gyro: F, encoder: F, shaft: F) -> F {
    (gyro * gyro + encoder * encoder + shaft * shaft).sqrt()
}

/// Eq. 32: shaft misalignment (deg) from the inclinometer at two positions 180 deg apart.
pub fn eq32_tilt_deg<F: Float>(x1: F, y1: F, x2: F, y2: F) -> F {
    let two = c::<F>(2.0);
    let tx = rad((x2 - x1) / two).tan();
    let ty = rad((y2 - y1) / two).tan();
    (tx * tx + ty * ty).sqrt().atan().to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::Instrument;

    #[test]
    fn eq24_reference_values() {
        // The reference values, from the paper's Fig. 6 setting.
        for (n, want) in [(72, 15.83), (90, 14.16), (120, 12.26), (180, 10.01)] {
            let got = eq24_arcsec(n, 0.005f64, 43.8);
            assert!((got - want).abs() < 0.006, "n = {n}: {got}");
        }
    }

    #[test]
    fn eq19_reduces_to_eq10_and_eq7() {
        for i in 0..72 {
            let g = i as f64 * 5.0;
            let e19 = eq19_rate(43.8, 65.5, g, 0.0, 0.05, 0.2);
            let e10 = eq10_rate(43.8, 65.5, g, 0.05, 0.2);
            // Eq. 19 recovers sin(eps) from 1 - cos^2: a cancellation that costs digits.
            assert!((e19 - e10).abs() < 1e-10, "{g}");
            let e7 = eq7_rate(43.8, 65.5, g, 0.2);
            // At eps = 0, sqrt(1 - cos^2) of a rounded 1 is 1e-8: Eq. 19 is that coarse there.
            assert!((eq19_rate(43.8, 65.5, g, 0.0, 0.0, 0.2) - e7).abs() < 1e-6);
            assert!((eq10_rate(43.8, 65.5, g, 0.0, 0.2) - e7).abs() < 1e-12);
        }
    }

    #[test]
    fn eq10_agrees_with_the_exact_model() {
        let m = Instrument {
            gyro_elev_deg: 0.05,
            bias_dph: 0.2,
            ..Instrument::level(43.8, 65.5)
        };
        for i in 0..72 {
            let g = i as f64 * 5.0;
            assert!((m.rate_dph(g) - eq10_rate(43.8, 65.5, g, 0.05, 0.2)).abs() < 1e-12);
        }
    }

    #[test]
    fn eq19_parts_from_the_exact_model_by_the_rectified_vertical_rate() {
        // Paper geometry: the platform is lowest at gamma = 0 (tau = 0).
        let (lat, eta) = (43.8f64, 1.0f64);
        let m = Instrument {
            tilt_deg: eta,
            ..Instrument::level(lat, 65.5)
        };
        let mut worst = 0.0f64;
        for i in 0..360 {
            let g = i as f64;
            worst = worst.max((eq19_rate(lat, 65.5, g, eta, 0.0, 0.0) - m.rate_dph(g)).abs());
        }
        // Twice the vertical-rate amplitude: 2 WE sin(lat) sin(eta) = 0.363 deg/h.
        let want = 2.0 * EARTH_RATE_DPH * lat.to_radians().sin() * eta.to_radians().sin();
        assert!((worst - want).abs() < 2e-3, "{worst} vs {want}");
    }

    #[test]
    fn eq30_gives_the_papers_0_7_arcsec() {
        let v = eq30_arcsec(180, 43.8f64, 45.0, 0.003, 0.01, 0.003);
        assert!((v - 0.683).abs() < 0.01, "{v}");
    }

    #[test]
    fn eq32_and_eq31() {
        assert!((eq32_tilt_deg(-0.3f64, 0.1, 0.3, -0.1) - 0.1f64.hypot(0.3)).abs() < 1e-5);
        assert_eq!(eq31(3.0f64, 4.0, 12.0), 13.0);
    }
}
