//! A resolved Earth rate whose amplitude still disagrees with `WE cos(lat)`: a gyro scale
//! factor far off, or a latitude that is not the recording's. The exact tilt correction
//! scales with `tan(lat)`, so a wrong latitude moves the azimuth by far more than its sigma
//! while the fit looks clean.

use nf_model::EARTH_RATE_DPH;
use nf_model::uncertainty;

/// Relative departure of the amplitude from `WE cos(lat)` that is said, when it is also beyond
/// [`SIGMAS`]: more than a gyro's scale factor is off when it is of any use here.
const RELATIVE: f64 = 0.05;
/// Sigmas of the amplitude the departure must exceed.
const SIGMAS: f64 = 5.0;

/// Why the amplitude (deg/h, with its sigma) disagrees with the Earth rate's at `latitude_deg`,
/// when it does by more than [`RELATIVE`] and [`SIGMAS`]; `tilt_left_in` when no tilt
/// correction was made (an uncorrected tilt moves the amplitude too).
pub fn amplitude_off(
    amplitude_dph: f64,
    sigma_amplitude_dph: f64,
    latitude_deg: f64,
    tilt_left_in: bool,
) -> Option<String> {
    let predicted = uncertainty::amplitude_dph(latitude_deg);
    let off = amplitude_dph - predicted;
    if off.abs() <= RELATIVE * predicted || off.abs() <= SIGMAS * sigma_amplitude_dph {
        return None;
    }
    let ratio = amplitude_dph / predicted;
    let fits = match amplitude_dph / EARTH_RATE_DPH {
        c if c <= 1.0 => format!(
            "at scale factor 1 it is the Earth rate at latitude +-{:.1} deg",
            c.acos().to_degrees()
        ),
        _ => "more than the Earth rate at any latitude".to_string(),
    };
    Some(format!(
        "the amplitude is {ratio:.4} times WE cos(lat) at latitude_deg {latitude_deg}, {:.0} sigma off: a gyro scale factor {:+.1} % off, or latitude_deg not the recording's ({fits}){}; the tilt correction assumes the latitude given",
        off.abs() / sigma_amplitude_dph,
        (ratio - 1.0) * 100.0,
        if tilt_left_in {
            ", or a shaft tilt left uncorrected"
        } else {
            ""
        }
    ))
}

#[cfg(test)]
mod tests {
    use super::amplitude_off;
    use nf_model::EARTH_RATE_DPH;
    use nf_model::uncertainty::amplitude_dph as amplitude;

    #[test]
    fn a_recording_of_latitude_60_labelled_43_8_names_60() {
        let w = amplitude_off(amplitude(60.0), 1e-4, 43.8, false).unwrap();
        assert!(w.contains("0.6928 times") && w.contains("latitude +-60.0 deg"), "{w}");
        assert!(w.contains("-30.7 % off") && !w.contains("tilt left"), "{w}");
    }

    #[test]
    fn small_or_uncertain_departures_are_not_said() {
        let a = amplitude(43.8);
        // A scale factor of 1.04: within what a gyro's may be.
        assert_eq!(amplitude_off(1.04 * a, 1e-5, 43.8, false), None);
        // 20 % off, but 4 sigma only.
        assert_eq!(amplitude_off(1.2 * a, 0.05 * a, 43.8, false), None);
        assert!(
            amplitude_off(1.2 * a, 0.039 * a, 43.8, true)
                .unwrap()
                .contains("shaft tilt left uncorrected")
        );
    }

    #[test]
    fn more_than_the_earth_rate_has_no_latitude() {
        let w = amplitude_off(1.1 * EARTH_RATE_DPH, 1e-3, 10.0, false).unwrap();
        assert!(w.contains("more than the Earth rate at any latitude"), "{w}");
    }
}
