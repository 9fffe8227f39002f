//! What the per-position first-order tilt correction leaves on a tilted shaft, and its
//! removal. Each dwell's inclinometer X reading is the gyro axis's elevation, so the vertical
//! Earth rate it removes is exact; but the axis's horizontal part is also turned and shortened
//! by the tilt, in the second harmonic of the encoder angle, and the first-harmonic fit takes
//! a share of it: an azimuth error of order `eta^2 / 4` that varies with `2 psi` (63" at 2
//! deg, 0.43 deg at 10). The firmware fits first order as it goes; at the end it removes that
//! error with the exact model ([`crate::exact`]) and the levelling's tilt.

use crate::angle::{sincos_deg, wrap_180};
use crate::exact::Instrument;
use crate::fit::{AzimuthFit, FitConfig, FitError, Obs};
use crate::{EARTH_RATE_DPH, c};
use num_traits::Float;

/// The azimuth a first-order fit at `gammas` gives on a noise-free instrument at `lat` whose
/// azimuth is `psi_deg` and whose shaft is tilted by `tilt_deg` towards `tilt_dir_deg`.
fn first_order_psi<F: Float>(
    lat: F,
    psi_deg: F,
    (tilt_deg, tilt_dir_deg): (F, F),
    gammas: impl Iterator<Item = F>,
) -> Result<F, FitError> {
    let inst = Instrument {
        tilt_deg,
        tilt_dir_deg,
        ..Instrument::level(lat, psi_deg)
    };
    // The first-order correction removes the vertical Earth rate of the axis's elevation,
    // which the inclinometer's X axis reads: the axis's up component (no `asin`, whose `libm`
    // form brings soft `f64` to the MCU).
    let vertical = c::<F>(EARTH_RATE_DPH) * sincos_deg(lat).0;
    let mut fit = AzimuthFit::new(FitConfig::default())?;
    for g in gammas {
        let up = inst.axis_level(g)[2];
        fit.add(&Obs::new(g, inst.rate_dph(g) - vertical * up))?;
    }
    Ok(fit.solve()?.psi_deg)
}

/// The error a first-order fit at `gammas` makes at the azimuth `psi_fit_deg` it gave, deg:
/// the true azimuth is `psi_fit_deg` less it. The error changes with the azimuth at about
/// `eta^2 / 2` of it (0.015 at 10 deg), so each step of the fixed point gains that factor:
/// four leave under a milli-arcsecond at 10 deg.
pub fn first_order_error_deg<F: Float>(
    lat: F,
    psi_fit_deg: F,
    tilt: (F, F),
    gammas: impl Iterator<Item = F> + Clone,
) -> Result<F, FitError> {
    let mut error = F::zero();
    for _ in 0..4 {
        let psi = psi_fit_deg - error;
        error = wrap_180(first_order_psi(lat, psi, tilt, gammas.clone())? - psi);
    }
    Ok(error)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn the_error_left_is_of_order_the_tilt_squared_and_removed() {
        let mut rng = Rng::new(3);
        let gammas = || (0..72).map(|k| k as f64 * 5.0);
        let mut largest = 0.0f64;
        for _ in 0..200 {
            let lat = rng.uniform(-80.0, 80.0);
            let psi = rng.uniform(0.0, 360.0);
            let tilt = (rng.uniform(0.0, 10.0), rng.uniform(0.0, 360.0));
            let fitted = first_order_psi(lat, psi, tilt, gammas()).unwrap();
            let error = first_order_error_deg(lat, fitted, tilt, gammas()).unwrap();
            // Against the exact model's truth, to a micro-arcsecond at 10 deg of tilt.
            // Against the exact model's truth: under a milli-arcsecond at 10 deg of tilt.
            let left = wrap_180(fitted - error - psi).abs() * 3600.0;
            assert!(left < 1e-3, "{lat} {psi} {tilt:?}: {left}\"");
            let eta = tilt.0.to_radians();
            // Of order eta^2 / 4, not more.
            assert!(wrap_180(fitted - psi).abs().to_radians() <= 0.3 * eta * eta + 1e-12);
            largest = largest.max(wrap_180(fitted - psi).abs() / (eta * eta / 4.0).to_degrees());
        }
        assert!(largest > 0.9, "the error reached {largest} of eta^2 / 4");
    }

    #[test]
    fn in_f32_as_the_firmware_has_it() {
        let gammas = || (0..36).map(|k| k as f32 * 10.0);
        let (lat, psi, tilt) = (43.8f32, 65.5378f32, (2.0f32, 30.0f32));
        let fitted = first_order_psi(lat, psi, tilt, gammas()).unwrap();
        let error = first_order_error_deg(lat, fitted, tilt, gammas()).unwrap();
        assert!(wrap_180(fitted - psi).abs() * 3600.0 > 10.0, "{fitted} {psi}");
        assert!(
            wrap_180(fitted - error - psi).abs() * 3600.0 < 0.05,
            "{}",
            (fitted - error - psi) * 3600.0
        );
    }
}
