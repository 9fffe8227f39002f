//! Angles in degrees, with the range reduction that keeps `f32` accurate to well under 0.1".

use crate::{Float, c};

/// `(sin, cos)` of an angle in degrees.
///
/// The angle is reduced to `[-45, 45]` degrees around a multiple of 90 before it is converted
/// to radians: `f32` then keeps about 1e-7 rad of absolute accuracy anywhere on the circle,
/// where a plain `to_radians()` of 359 deg would lose 0.1".
pub fn sincos_deg<F: Float>(deg: F) -> (F, F) {
    let ninety = c::<F>(90.0);
    let q = (deg / ninety).round();
    let r = (deg - q * ninety).to_radians();
    let (s, co) = sincos_quarter(r);
    // q mod 4, also for negative q.
    let k = q.to_i64().unwrap_or(0).rem_euclid(4);
    match k {
        0 => (s, co),
        1 => (co, -s),
        2 => (-s, -co),
        _ => (-co, s),
    }
}

/// `(sin, cos)` of `r` radians, `|r| <= pi/4`, by their Taylor series to `r^19` and `r^18`
/// (what is left is under 1e-19 there), nested so that every step is `1 - t r^2 / k`.
///
/// Not `libm`: its `f32` functions compute in `f64`, which the Cortex-M4F does in software.
/// On the emulated M4F (`qemu/`) a call of `sincos_deg` took 2 400 instructions with `libm`
/// and takes 270 with this.
fn sincos_quarter<F: Float>(r: F) -> (F, F) {
    let r2 = r * r;
    let (mut s, mut co) = (F::one(), F::one());
    for k in (1..=9).rev() {
        s = F::one() - s * r2 / c((2 * k * (2 * k + 1)) as f64);
        co = F::one() - co * r2 / c(((2 * k - 1) * 2 * k) as f64);
    }
    (r * s, co)
}

/// `atan2(y, x)` in degrees, in `[0, 360)`.
///
/// The arc tangent is taken of a ratio at most 1 (at most 45 deg, where `f32` resolves 0.01")
/// and the quadrant is added last, so the result carries one rounding at the 360 deg scale
/// instead of three.
pub fn atan2_deg<F: Float>(y: F, x: F) -> F {
    let (ax, ay) = (x.abs(), y.abs());
    let a = if ay <= ax {
        if ax == F::zero() {
            F::zero()
        } else {
            (ay / ax).atan().to_degrees()
        }
    } else {
        c::<F>(90.0) - (ax / ay).atan().to_degrees()
    };
    let r = match (x < F::zero(), y < F::zero()) {
        (false, false) => a,
        (true, false) => c::<F>(180.0) - a,
        (true, true) => c::<F>(180.0) + a,
        (false, true) => c::<F>(360.0) - a,
    };
    wrap_360(r)
}

/// Wraps an angle into `[0, 360)`.
pub fn wrap_360<F: Float>(deg: F) -> F {
    let full = c::<F>(360.0);
    let r = deg % full;
    let r = if r < F::zero() { r + full } else { r };
    // `-1e-20 + 360` rounds to 360.
    if r >= full { F::zero() } else { r }
}

/// Wraps an angle into `[-180, 180)`.
pub fn wrap_180<F: Float>(deg: F) -> F {
    let half = c::<F>(180.0);
    wrap_360(deg + half) - half
}

/// The surveying azimuth (clockwise from true north) of the encoder's `gamma = 0` direction,
/// for the paper's azimuth `psi`.
///
/// The encoder angle grows counter-clockwise seen from above, so the gyro axis at `gamma`
/// points at surveying azimuth `-psi - gamma`, and `rate = WE cos(lat) cos(gamma + psi)`.
pub fn surveying_azimuth_deg<F: Float>(psi_deg: F) -> F {
    wrap_360(-psi_deg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sincos_matches_f64_everywhere_in_f32() {
        let mut worst = 0.0f64;
        for i in 0..=36_000 {
            let d = i as f64 * 0.01 - 0.005;
            let (s, co) = sincos_deg(d as f32);
            let dr = (d as f32) as f64;
            let (s64, c64) = dr.to_radians().sin_cos();
            worst = worst.max((s as f64 - s64).abs()).max((co as f64 - c64).abs());
        }
        // 1e-7 rad is 0.02": the reduction must keep f32 there.
        assert!(worst < 1.2e-7, "worst {worst}");
        let (s, co) = 359.0f32.to_radians().sin_cos();
        let naive =
            ((s as f64) - 359.0f64.to_radians().sin()).abs() + ((co as f64) - 359.0f64.to_radians().cos()).abs();
        assert!(naive > worst, "the reduction must beat the naive form");
    }

    #[test]
    fn quadrants_and_negative_angles() {
        for (d, s, co) in [
            (0.0, 0.0, 1.0),
            (90.0, 1.0, 0.0),
            (180.0, 0.0, -1.0),
            (270.0, -1.0, 0.0),
            (-90.0, -1.0, 0.0),
            (450.0, 1.0, 0.0),
        ] {
            let (a, b) = sincos_deg::<f64>(d);
            assert!((a - s).abs() < 1e-15 && (b - co).abs() < 1e-15, "{d}");
        }
    }

    #[test]
    fn atan2_deg_in_all_quadrants() {
        for i in 0..3600 {
            let d = i as f64 * 0.1 + 0.05;
            let (s, co) = d.to_radians().sin_cos();
            assert!((atan2_deg(s * 3.0, co * 3.0) - d).abs() < 1e-10, "{d}");
            let d32 = atan2_deg(s as f32, co as f32) as f64;
            assert!(wrap_180(d32 - d).abs() * 3600.0 < 0.07, "{d}: {d32}");
        }
        assert_eq!(atan2_deg(0.0f64, 0.0), 0.0);
        assert_eq!(atan2_deg(-1.0f64, 0.0), 270.0);
    }

    #[test]
    fn wrapping() {
        assert_eq!(wrap_360(-10.0f64), 350.0);
        assert_eq!(wrap_360(360.0f64), 0.0);
        assert_eq!(wrap_360(725.0f64), 5.0);
        assert_eq!(wrap_360(-1e-20f64), 0.0);
        assert_eq!(wrap_180(190.0f64), -170.0);
        assert_eq!(wrap_180(-180.0f64), -180.0);
        assert_eq!(surveying_azimuth_deg(65.5f64), 294.5);
    }
}
