//! Physics of a stepped-rotation gyro north finder, shared by the firmware and the host.
//!
//! Conventions (`shared/recording-format.md`): angles in degrees, rates in deg/h, time in s.
//! The azimuth `psi` is the one of the paper's Eq. 7: on a level ideal instrument the rate at
//! encoder angle `gamma` is `WE * cos(lat) * cos(gamma + psi)`. The encoder angle grows
//! counter-clockwise seen from above, so the surveying azimuth (clockwise from true north) of
//! the `gamma = 0` direction is `-psi` (see [`angle::surveying_azimuth_deg`]).
//!
//! Everything is generic over [`num_traits::Float`] so that the firmware runs it in `f32` and
//! the host in `f64`.
#![no_std]

pub mod angle;
pub mod dwell;
pub mod exact;
pub mod fit;
pub mod level;
pub mod noise;
pub mod noise_terms;
pub mod order;
pub mod paper;
pub mod rng;
pub mod running;
pub mod text;
pub mod tilt_bias;
pub mod uncertainty;

pub use num_traits::Float;

#[cfg(test)]
extern crate std;

/// Earth rotation rate in deg/h, as the paper and the recording format use it.
pub const EARTH_RATE_DPH: f64 = 15.041;

/// Arc seconds per degree.
pub const ARCSEC_PER_DEG: f64 = 3600.0;

/// Converts an `f64` constant into the working float type.
#[inline]
pub(crate) fn c<F: Float>(x: f64) -> F {
    F::from(x).unwrap_or_else(F::nan)
}

/// `x.sqrt()`. An `f32` on an Arm core with a hardware FPU (the `eabihf` targets: the
/// firmware's Cortex-M4F) takes the FPU's VSQRT instruction (14 cycles); elsewhere, and for
/// `f64`, `num_traits` (in `no_std`, `libm`, whose `sqrtf` is a software routine).
#[inline]
pub fn sqrt<F: Float>(x: F) -> F {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    if is_f32::<F>()
        && let Some(v) = x.to_f32()
    {
        return F::from(vsqrt(v)).unwrap_or_else(F::nan);
    }
    x.sqrt()
}

/// VSQRT through core registers: Rust's `sreg` operands need the `vfp2` target feature, which
/// is unstable (and unset for `thumbv7em-none-eabihf`, whose FPU LLVM knows as `vfp4d16sp`);
/// `s0` is saved and restored around it.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[inline(never)]
fn vsqrt(x: f32) -> f32 {
    let y: u32;
    // Safety: reads and writes only `s0`, which it restores, and the stack below `sp`.
    unsafe {
        core::arch::asm!(
            "vpush {{s0}}",
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {y}, s0",
            "vpop {{s0}}",
            x = in(reg) x.to_bits(),
            y = lateout(reg) y,
            options(pure, nomem, preserves_flags),
        );
    }
    f32::from_bits(y)
}

/// Whether `F` is `f32`, the firmware's float (the only 4-byte [`Float`]).
#[inline]
pub(crate) fn is_f32<F>() -> bool {
    core::mem::size_of::<F>() == 4
}

/// `x.asin()`; for `f32` as `atan(x / sqrt(1 - x^2))`, since `libm`'s `asinf` takes its square
/// root in `f64` (soft on the M4F). NaN beyond `[-1, 1]` either way.
#[inline]
pub(crate) fn asin<F: Float>(x: F) -> F {
    if is_f32::<F>() {
        let one = F::one();
        (x / sqrt((one - x) * (one + x))).atan()
    } else {
        x.asin()
    }
}

/// `x > 0`, false for NaN.
#[inline]
pub(crate) fn positive<F: Float>(x: F) -> bool {
    x.partial_cmp(&F::zero()) == Some(core::cmp::Ordering::Greater)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn asin_of_f32_stays_in_single_precision_and_range() {
        let mut worst = 0.0f64;
        for i in -10_000..=10_000 {
            let x = i as f32 / 10_000.0;
            let got = asin(x) as f64;
            let want = (x as f64).asin();
            worst = worst.max((got - want).abs());
        }
        // A few units of f32's last place at pi/2.
        assert!(worst < 4e-7, "worst {worst}");
        assert_eq!(asin(1.0f32), core::f32::consts::FRAC_PI_2);
        assert_eq!(asin(-1.0f32), -core::f32::consts::FRAC_PI_2);
        assert_eq!(asin(0.0f32), 0.0);
        assert!(asin(1.0001f32).is_nan() && asin(-2.0f32).is_nan() && asin(f32::NAN).is_nan());
        // Small tilts, as the levelling sees them: to a relative 1e-7.
        for x in [1e-3f32, 2.5e-5, -7e-4, 1e-7] {
            assert!(((asin(x) as f64) / (x as f64).asin() - 1.0).abs() < 2e-7, "{x}");
        }
        assert_eq!(asin(0.5f64), 0.5f64.asin());
    }

    #[test]
    fn sqrt_is_the_square_root() {
        for x in [0.0f32, 1.0, 2.0, 1e-30, 3.4e38, 0.25] {
            assert_eq!(sqrt(x), x.sqrt(), "{x}");
        }
        assert!(sqrt(-1.0f32).is_nan() && sqrt(f32::NAN).is_nan());
        assert_eq!(sqrt(f32::INFINITY), f32::INFINITY);
        assert_eq!(sqrt(2.0f64), 2.0f64.sqrt());
    }
}
