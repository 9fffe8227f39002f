//! Deserializers that refuse a value outside its range where it is read, so that the TOML
//! error points at the value.

use serde::de::{Deserialize, Deserializer, Error};

macro_rules! real {
    ($(#[$doc:meta])* $name:ident, $lo:expr, $hi:expr, $unit:literal) => {
        $(#[$doc])*
        pub fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
            let v = f64::deserialize(d)?;
            // NaN is in no range.
            if ($lo..=$hi).contains(&v) {
                Ok(v)
            } else {
                Err(D::Error::custom(format!(
                    "{v} is outside [{}, {}] {}",
                    $lo, $hi, $unit
                )))
            }
        }
    };
}

macro_rules! whole {
    ($name:ident, $t:ty, $lo:expr, $hi:expr) => {
        pub fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<$t, D::Error> {
            let v = i64::deserialize(d)?;
            if ($lo..=$hi).contains(&v) {
                Ok(v as $t)
            } else {
                Err(D::Error::custom(format!("{v} is outside [{}, {}]", $lo, $hi)))
            }
        }
    };
}

real!(
    latitude,
    -crate::range::MAX_LATITUDE_DEG,
    crate::range::MAX_LATITUDE_DEG,
    "deg"
);
real!(angle, -360.0, 360.0, "deg");
real!(turn, 0.0, 360.0, "deg");
real!(small_angle, -10.0, 10.0, "deg");
real!(tilt, 0.0, 10.0, "deg");
real!(rate, -50.0, 50.0, "deg/h");
real!(scale, 0.1, 10.0, "");
real!(nonlinearity, -0.1, 0.1, "per deg/h");
real!(noise_term, 0.0, 1e3, "(IEEE Std 952 units)");
real!(drift, -1.0, 1.0, "deg/h per s");
real!(drift2, -0.01, 0.01, "deg/h per s^2");
real!(time, 0.0, 1e7, "s");
real!(celsius, -60.0, 125.0, "C");
real!(temp_ramp, -1.0, 1.0, "C per s");
real!(temp_swing, 0.0, 100.0, "C");
real!(period, 1.0, 1e7, "s");
real!(temp_coef, -10.0, 10.0, "deg/h per C");
real!(tau, 1e-4, 600.0, "s");
real!(per_hour, 0.0, 1e6, "per hour");
real!(arcsec, 0.0, 3600.0, "arcsec");
real!(incl_noise, 0.0, 1.0, "deg");
real!(speed, 1.0, 1e6, "steps/s");
real!(accel, 1.0, 1e8, "steps/s^2");
real!(dwell, 0.01, 600.0, "s");
real!(settle, 0.0, 60.0, "s");
real!(target, 0.0, 36_000.0, "arcsec");
whole!(encoder_bits, u8, 8, 32);
whole!(harmonic, u8, 1, 16);
whole!(steps_per_rev, u32, 4, 10_000_000);
whole!(pulse_us, u32, 1, 10_000);
whole!(positions, u16, 4, 720);
whole!(sample_rate, u32, 1, 100_000);

/// An optional target: absent, or within its range.
pub fn target_opt<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    target(d).map(Some)
}
