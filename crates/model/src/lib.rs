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
pub mod order;
pub mod paper;
pub mod rng;
pub mod running;
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

/// `x > 0`, false for NaN.
#[inline]
pub(crate) fn positive<F: Float>(x: F) -> bool {
    x.partial_cmp(&F::zero()) == Some(core::cmp::Ordering::Greater)
}
