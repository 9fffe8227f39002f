//! The one tilt path of `nf fit` and `nf diagnose`: the vertical Earth rate a tilted shaft adds
//! to each position, from the inclinometer. With both columns, the exact model of the tilt
//! circle, iterated with the fitted azimuth and scale to convergence; with `tilt_x_deg` alone,
//! first order per position. Positions without a reading are bridged by the circle fitted to
//! the readings there are.

use crate::analysis::{TiltMethod, exact_tilt_correction};
use crate::recording::Recording;
use nf_model::angle::wrap_180;
use nf_model::fit::{AzimuthFit, FitConfig, Obs, vertical_earth_rate_dph};
use nf_model::level::{ShaftTilt, TiltReading, fit_tilt};

/// Iterations of the exact correction before it counts as not converging.
const MAX_ITERATIONS: u32 = 50;
/// Convergence: the azimuth moves less than this between iterations, deg.
const PSI_TOL_DEG: f64 = 1e-9;

/// The correction of each position, and how it was made.
#[derive(Debug, Clone)]
pub struct Tilt {
    pub method: TiltMethod,
    /// Rate to subtract from each position's mean, deg/h.
    pub corrections: Vec<f64>,
    /// The tilt circle (exact method).
    pub shaft: Option<ShaftTilt<f64>>,
    /// Positions whose reading was missing and taken from the circle.
    pub bridged: usize,
    /// Iterations of the exact correction.
    pub iterations: u32,
}

/// The method a recording allows: exact with both columns on three positions or more, first
/// order with `tilt_x_deg` alone, else none.
pub fn auto_method(rec: &Recording) -> TiltMethod {
    let xy = rec
        .rows
        .iter()
        .filter(|r| r.tilt_x_deg.is_some() && r.tilt_y_deg.is_some())
        .count();
    let x = rec.rows.iter().filter(|r| r.tilt_x_deg.is_some()).count();
    if xy >= 3 {
        TiltMethod::Exact
    } else if x >= 3 {
        TiltMethod::FirstOrder
    } else {
        TiltMethod::None
    }
}

/// The corrections by `method`. `fit` gives the azimuth (deg) and amplitude (deg/h) of the
/// rates less a set of corrections, as the caller fits them.
pub fn correct(
    rec: &Recording,
    method: TiltMethod,
    mut fit: impl FnMut(&[f64]) -> Result<(f64, f64), String>,
) -> Result<Tilt, String> {
    let lat = rec.latitude_deg;
    let n = rec.rows.len();
    let gammas: Vec<f64> = rec.rows.iter().map(|r| r.encoder_deg).collect();
    let none = Tilt {
        method,
        corrections: vec![0.0; n],
        shaft: None,
        bridged: 0,
        iterations: 0,
    };
    match method {
        TiltMethod::None => Ok(none),
        TiltMethod::FirstOrder => {
            let (x, bridged) = bridged_x(rec)?;
            Ok(Tilt {
                corrections: x.iter().map(|&x| vertical_earth_rate_dph(lat, x)).collect(),
                bridged,
                ..none
            })
        }
        TiltMethod::Exact => {
            let readings: Vec<TiltReading<f64>> = rec
                .rows
                .iter()
                .filter_map(|r| {
                    Some(TiltReading {
                        gamma_deg: r.encoder_deg,
                        x_deg: r.tilt_x_deg?,
                        y_deg: r.tilt_y_deg?,
                    })
                })
                .collect();
            if readings.len() < 3 {
                return Err(format!(
                    "the exact tilt correction needs tilt_x_deg and tilt_y_deg on three positions or more, the recording has {}",
                    readings.len()
                ));
            }
            let t = fit_tilt(&readings).map_err(|e| format!("the tilt circle fit failed: {e}"))?;
            // Start from first order (the circle's X at each position), then solve the exact
            // model with the fitted azimuth and scale.
            let corr: Vec<f64> = gammas
                .iter()
                .map(|&g| vertical_earth_rate_dph(lat, circle_x_deg(&t, g)))
                .collect();
            let (mut psi, mut amp) = fit(&corr)?;
            // The azimuth and the amplitude are a fixed point of "correct with them, then fit".
            // At high latitude and large tilt the map moves nearly as fast as its arguments (its
            // slope is about eta tan(lat)), and plain iteration stalls: Newton on
            // G(psi, amp) = fit(correct(psi, amp)) - (psi, amp), its Jacobian by differences.
            let mut eval = |psi: f64, amp: f64| -> Result<([f64; 2], Vec<f64>), String> {
                let corr = exact_tilt_correction(lat, psi, amp, &t, &gammas);
                let (p, a) = fit(&corr)?;
                Ok(([wrap_180(p - psi), a - amp], corr))
            };
            for k in 1..=MAX_ITERATIONS {
                let (g, c) = eval(psi, amp)?;
                if g[0].abs() < PSI_TOL_DEG && g[1].abs() < 1e-12 * amp.abs().max(1e-6) {
                    return Ok(Tilt {
                        corrections: c,
                        shaft: Some(t),
                        bridged: n - readings.len(),
                        iterations: k,
                        ..none
                    });
                }
                let (hp, ha) = (1e-6, 1e-6 * amp.abs().max(1e-3));
                let (gp, _) = eval(psi + hp, amp)?;
                let (ga, _) = eval(psi, amp + ha)?;
                let j = [
                    [(gp[0] - g[0]) / hp, (ga[0] - g[0]) / ha],
                    [(gp[1] - g[1]) / hp, (ga[1] - g[1]) / ha],
                ];
                let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
                let (dp, da) = if det.is_finite() && det.abs() > 1e-300 {
                    (
                        (-g[0] * j[1][1] + g[1] * j[0][1]) / det,
                        (-g[1] * j[0][0] + g[0] * j[1][0]) / det,
                    )
                } else {
                    (g[0], g[1])
                };
                psi += dp.clamp(-30.0, 30.0);
                amp = (amp + da).max(1e-9);
            }
            Err(format!(
                "the exact tilt correction did not converge in {MAX_ITERATIONS} iterations"
            ))
        }
    }
}

/// The X axis's elevation on the tilt circle at `gamma`, without its mounting offset: what
/// tilts the gyro axis (`sin x = -sin(eta) cos(gamma - tau)`).
fn circle_x_deg(t: &ShaftTilt<f64>, gamma_deg: f64) -> f64 {
    let s = -t.tilt_deg.to_radians().sin() * (gamma_deg - t.tilt_dir_deg).to_radians().cos();
    s.clamp(-1.0, 1.0).asin().to_degrees()
}

/// Every position's X reading, those missing from the circle fitted to the others.
fn bridged_x(rec: &Recording) -> Result<(Vec<f64>, usize), String> {
    let obs: Vec<Obs<f64>> = rec
        .rows
        .iter()
        .filter_map(|r| Some(Obs::new(r.encoder_deg, r.tilt_x_deg?)))
        .collect();
    let missing = rec.rows.len() - obs.len();
    if missing == 0 {
        return Ok((rec.rows.iter().filter_map(|r| r.tilt_x_deg).collect(), 0));
    }
    let circle = AzimuthFit::fit_all(FitConfig::default(), &obs)
        .map_err(|e| format!("{missing} positions lack tilt_x_deg and the others do not give its circle: {e}"))?;
    let x = rec
        .rows
        .iter()
        .map(|r| {
            r.tilt_x_deg
                .unwrap_or_else(|| circle.predict(r.encoder_deg, r.t_s, None))
        })
        .collect();
    Ok((x, missing))
}
