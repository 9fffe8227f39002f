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
    // q mod 4, also for negative q; in floats, which hold every whole q exactly (no f32 to
    // i64 routine on the MCU).
    let four = c::<F>(4.0);
    let k = (q - four * (q / four).floor()).to_u8().unwrap_or(0);
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
///
/// The remainder is taken by `floor`, not `%`: on the Cortex-M4F the float remainder is 4 KiB
/// of soft-`f64` code. It is the remainder `%` gives, but for the rounding of `r + 360` for a
/// small negative `r` (as with `%`), wherever `q * 360` is exact: `|deg|` below `2^53` in `f64`
/// and `2^24` in `f32`. Beyond that, where one unit in the last place is a degree or more, the
/// result is some angle in `[0, 360)`. NaN and infinities give NaN.
pub fn wrap_360<F: Float>(deg: F) -> F {
    let full = c::<F>(360.0);
    let zero = F::zero();
    if deg >= zero && deg < full {
        return deg;
    }
    // `deg / 360` may round to the next integer: `r` is then within a turn of `[0, 360)`, and
    // exact (Sterbenz) but for `q = -1`.
    let q = (deg / full).floor();
    let mut r = deg - q * full;
    if r < zero {
        // `-1e-20 + 360` rounds to 360.
        r = r + full;
    } else if r >= full {
        r = r - full;
    }
    if r.is_nan() || (r >= zero && r < full) { r } else { zero }
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

    /// The same angle (`-0.0`, which `%` gives for `-720`, is `0.0`).
    fn same<F: Float + core::fmt::LowerExp>(a: F, b: F, d: F) {
        assert!(
            a == b || (a.is_nan() && b.is_nan()),
            "{d:e}: {a:e} by floor, {b:e} by remainder"
        );
    }

    /// What `wrap_360` was, with the float remainder.
    fn by_rem<F: Float>(deg: F) -> F {
        let full = c::<F>(360.0);
        let r = deg % full;
        let r = if r < F::zero() { r + full } else { r };
        if r >= full { F::zero() } else { r }
    }

    #[test]
    fn wrapping_by_floor_is_the_remainder() {
        let mut rng = crate::rng::Rng::new(7);
        let near = |k: f64, ulps: i64| {
            let x = k * 360.0;
            f64::from_bits((x.to_bits() as i64 + ulps) as u64)
        };
        for k in -2000..2000 {
            for ulps in -3..=3 {
                for d in [near(k as f64, ulps), near(k as f64 * 1e9, ulps)] {
                    same(wrap_360(d), by_rem(d), d);
                    let f = d as f32;
                    if f.abs() < 1.6e7 {
                        same(wrap_360(f), by_rem(f), f);
                    }
                }
            }
        }
        for _ in 0..200_000 {
            let scale = 10f64.powi((rng.unit() * 30.0) as i32 - 12);
            let d = (rng.unit() - 0.5) * scale;
            same(wrap_360(d), by_rem(d), d);
            let f = d as f32;
            if f.abs() < 1.6e7 {
                same(wrap_360(f), by_rem(f), f);
            }
        }
    }

    #[test]
    fn wrapping() {
        assert_eq!(wrap_360(-10.0f64), 350.0);
        assert_eq!(wrap_360(360.0f64), 0.0);
        assert_eq!(wrap_360(725.0f64), 5.0);
        assert_eq!(wrap_360(-1e-20f64), 0.0);
        assert_eq!(wrap_360(-1e-20f32), 0.0);
        assert_eq!(wrap_360(-360.0f64), 0.0);
        assert_eq!(wrap_360(720.0f32), 0.0);
        assert!(wrap_360(f64::NAN).is_nan() && wrap_360(f64::INFINITY).is_nan());
        assert!(wrap_360(f32::NEG_INFINITY).is_nan());
        for huge in [1e300f64, -1e300, 2f64.powi(60) + 7.0, f64::MAX, -f64::MAX] {
            let r = wrap_360(huge);
            assert!((0.0..360.0).contains(&r), "{huge}: {r}");
        }
        for huge in [1e30f32, -3e9, f32::MAX] {
            let r = wrap_360(huge);
            assert!((0.0..360.0).contains(&r), "{huge}: {r}");
        }
        assert_eq!(wrap_180(190.0f64), -170.0);
        assert_eq!(wrap_180(-180.0f64), -180.0);
        assert_eq!(surveying_azimuth_deg(65.5f64), 294.5);
    }
}
