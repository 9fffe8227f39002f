//! Properties over random instruments (proptest): what must hold for every input.

use nf_model::angle::wrap_180;
use nf_model::exact::Instrument;
use nf_model::fit::{AzimuthFit, FitConfig, Obs};
use nf_model::level::{TiltReading, fit_tilt};
use proptest::prelude::*;

fn instrument() -> impl Strategy<Value = Instrument<f64>> {
    (
        -80.0..80.0f64,
        0.0..360.0f64,
        0.0..2.0f64,
        0.0..360.0f64,
        -0.5..0.5f64,
        0.95..1.05f64,
        -20.0..20.0f64,
    )
        .prop_map(|(lat, psi, tilt, dir, elev, scale, bias)| Instrument {
            latitude_deg: lat,
            psi_deg: psi,
            tilt_deg: tilt,
            tilt_dir_deg: dir,
            gyro_elev_deg: elev,
            scale,
            bias_dph: bias,
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// With the tilt correction (inclinometer X on the gyro axis, any mounting offset), the fit
    /// recovers psi on any instrument, to the second-order terms of the tilt.
    #[test]
    fn tilt_corrected_fit_recovers_psi(inst in instrument(), n in 8usize..200, start in 0.0..360.0f64, ox in -0.3..0.3f64) {
        let obs: Vec<Obs<f64>> = (0..n).map(|i| {
            let g = (start + i as f64 * 360.0 / n as f64).rem_euclid(360.0);
            let (x, _) = inst.inclinometer_deg(g, ox + inst.gyro_elev_deg, 0.0);
            Obs { tilt_x_deg: Some(x), ..Obs::new(g, inst.rate_dph(g)) }
        }).collect();
        let cfg = FitConfig { tilt_correction_lat_deg: Some(inst.latitude_deg), ..FitConfig::default() };
        let r = AzimuthFit::fit_all(cfg, &obs).unwrap();
        // Second order: eta^2 of the heading, and eta times the scale error that the unit-scale
        // correction leaves of the vertical rate.
        let eta = inst.tilt_deg.to_radians();
        let scale_err = (inst.scale - 1.0).abs() / inst.scale;
        let tol_deg = (eta * eta + eta * scale_err * inst.latitude_deg.to_radians().tan().abs()).to_degrees() * 1.01 + 1e-9;
        prop_assert!(wrap_180(r.psi_deg - inst.psi_deg).abs() <= tol_deg, "{} vs {}", r.psi_deg, inst.psi_deg);
    }

    /// Without it, a tilt shifts psi by at most eta tan(lat) (and second order), never more.
    #[test]
    fn uncorrected_tilt_shift_is_bounded_by_eta_tan_lat(inst in instrument()) {
        let obs: Vec<Obs<f64>> = (0..72).map(|i| Obs::new(i as f64 * 5.0, inst.rate_dph(i as f64 * 5.0))).collect();
        let r = AzimuthFit::fit_all(FitConfig::default(), &obs).unwrap();
        let eta = inst.tilt_deg.to_radians();
        let bound = (eta * inst.latitude_deg.to_radians().tan().abs() + eta * eta).to_degrees() * 1.01 + 1e-9;
        prop_assert!(wrap_180(r.psi_deg - inst.psi_deg).abs() <= bound);
    }

    /// The tilt circle fit recovers any tilt from readings at any spread of angles.
    #[test]
    fn tilt_circle_round_trip(inst in instrument(), ox in -0.5..0.5f64, n in 2usize..40, start in 0.0..360.0f64) {
        let readings: Vec<TiltReading<f64>> = (0..n).map(|i| {
            let g = start + i as f64 * 360.0 / n as f64;
            let (x, y) = inst.inclinometer_deg(g, ox, ox);
            TiltReading { gamma_deg: g, x_deg: x, y_deg: y }
        }).collect();
        let t = fit_tilt(&readings).unwrap();
        prop_assert!((t.tilt_deg - inst.tilt_deg).abs() < 1e-6);
        prop_assert!((t.offset_x_deg - ox).abs() < 1e-6);
        if inst.tilt_deg > 1e-3 {
            prop_assert!(wrap_180(t.tilt_dir_deg - inst.tilt_dir_deg).abs() < 1e-3);
        }
    }
}
