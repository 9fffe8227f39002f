//! The one tilt path of `nf fit` and `nf diagnose`: the vertical Earth rate a tilted shaft adds
//! to each position, from the inclinometer. The exact model of the tilt circle, fitted to the
//! readings there are (both columns, or either alone: over a turn one axis draws the whole
//! circle), iterated with the fitted azimuth and scale to convergence; first order per position
//! from `tilt_x_deg` on request. Positions without a reading are bridged by the circle.
//! Readings that turn round the circle the mirror way (`crate::tilt_sense`) are said to, and
//! the circle is drawn from X alone.

use crate::analysis::{TiltMethod, exact_tilt_correction};
use crate::linfit;
use crate::recording::Recording;
use crate::stats::f_sf;
use crate::tilt_sense::{self, AxisReading};
use nf_model::angle::wrap_180;
use nf_model::fit::{AzimuthFit, FitConfig, Obs, vertical_earth_rate_dph};
use nf_model::level::ShaftTilt;
use nf_model::uncertainty::{amplitude_dph, amplitude_is_earth_rate};

/// Tilt (deg) above which a requested first-order correction is warned against.
const FIRST_ORDER_MAX_DEG: f64 = 1.0;
/// A tilt left uncorrected is warned of where the circle stands out of the readings' scatter
/// at this p (the circle test's).
const LEFT_IN_P: f64 = 1e-3;
/// Iterations of the exact correction before it counts as not converging.
const MAX_ITERATIONS: u32 = 50;
/// Convergence: the azimuth moves less than this between iterations, deg.
const PSI_TOL_DEG: f64 = 1e-9;
/// A point whose azimuth step is below this (0.004"), when the iterations never met
/// `PSI_TOL_DEG`, is taken: far below any sigma, and an answer beats none.
const NEAR_ENOUGH_DEG: f64 = 1e-6;

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
    /// Why some readings were not used, when they were not.
    pub warning: Option<String>,
    /// The azimuth's standard deviation that the circle's own uncertainty carries (exact
    /// method; deg). First order corrects each dwell mean by its own reading, whose noise is
    /// then in the rates and in their residuals.
    pub sigma_psi_deg: f64,
    /// How the fit's errors carry through the correction's dependence on the fit.
    pub sensitivity: Sensitivity,
    /// Whether the tilt stands out of the readings' scatter, when there is a circle.
    pub circle_test: Option<CircleTest>,
}

/// The tilt against none: the F test of the circle's first harmonic `(a, b)`, which both axes
/// draw (one tilt, two parameters), against constant readings; and the tilt's sigma.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircleTest {
    pub p: f64,
    pub sigma_tilt_deg: f64,
}

/// How a change of the fitted azimuth and amplitude (deg, deg/h) carries into the result of
/// the exact correction, which depends on them: `(I - F')^-1`, `F'` the slope of "correct
/// with them, then fit" (identity without that dependence).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensitivity(pub [[f64; 2]; 2]);

impl Sensitivity {
    pub const NONE: Sensitivity = Sensitivity([[1.0, 0.0], [0.0, 1.0]]);

    /// The sigmas (deg, deg/h) of the azimuth and amplitude of a fit of the corrected rates
    /// (taken as uncorrelated, as over a turn of even steps), carried through the exact
    /// correction: at a large tilt near the pole the vertical Earth rate the tilt adds scales
    /// with the fitted amplitude (the gyro's scale factor) as much as the horizontal one, and
    /// the azimuth is then known far less well than the fit of the corrected rates says.
    pub fn carried(self, sigma_psi_deg: f64, sigma_amplitude_dph: f64) -> (f64, f64) {
        let m = self.0;
        (
            (m[0][0] * sigma_psi_deg).hypot(m[0][1] * sigma_amplitude_dph),
            (m[1][0] * sigma_psi_deg).hypot(m[1][1] * sigma_amplitude_dph),
        )
    }
}

/// What a tilt the readings show (the circle against none, `test`, at [`LEFT_IN_P`]) does
/// when it is left uncorrected: the azimuth moves by up to `eta tan(lat)`, which no sigma
/// holds.
fn left_in(s: &ShaftTilt<f64>, test: CircleTest, lat_deg: f64) -> Option<String> {
    (test.p < LEFT_IN_P).then(|| {
        format!(
            "the inclinometer shows the shaft tilted {:.4} deg towards {:.1} deg, left uncorrected: it moves the azimuth by up to eta tan(lat) = {:.1}\", which the sigma does not hold (--tilt auto corrects it)",
            s.tilt_deg,
            s.tilt_dir_deg,
            s.tilt_deg * 3600.0 * lat_deg.to_radians().tan().abs()
        )
    })
}

/// The exact correction for one tilt circle, solved.
struct Solution {
    corrections: Vec<f64>,
    iterations: u32,
    psi_deg: f64,
    sensitivity: Sensitivity,
    /// Whether the gyro's scale was taken as 1 ([`unit_scale`]), not fitted.
    scale_one: bool,
}

/// The tilt circle as fitted: its coefficients and the covariance of its first harmonic.
struct Circle {
    shaft: ShaftTilt<f64>,
    cx: f64,
    cy: f64,
    a: f64,
    b: f64,
    /// Covariance of `a` and `b`, from the readings' scatter about the circle.
    cov: [[f64; 2]; 2],
    /// Degrees of freedom of that scatter.
    dof: usize,
}

/// The radius (sin of the tilt, 0.0002") below which a circle, or its sigma, is the rounding
/// of identical readings: an outside audit's level shaft read in 0.01 deg steps gave a radius
/// of 8.7e-19 and a Wald test of rounding against rounding, a tilt named at p 2.4e-7.
const EXACT_CIRCLE: f64 = 1e-9;

impl Circle {
    fn test(&self) -> CircleTest {
        let [[caa, cab], [_, cbb]] = self.cov;
        let det = caa * cbb - cab * cab;
        let r = self.a.hypot(self.b);
        // Scatter below the radius a circle is read from is rounding: no scatter.
        let scatter = det > 0.0 && caa.max(cbb).sqrt() >= EXACT_CIRCLE;
        let p = if self.dof == 0 {
            1.0
        } else if scatter {
            // Wald's quadratic form of (a, b) over 2: an F of 2 and the scatter's dof.
            let w = (self.a * self.a * cbb - 2.0 * self.a * self.b * cab + self.b * self.b * caa) / det;
            f_sf(0.5 * w, 2.0, self.dof as f64)
        } else if r > EXACT_CIRCLE {
            // Readings on the circle exactly.
            0.0
        } else {
            1.0
        };
        // tilt = asin(r): its sigma along (a, b), by the delta method.
        let (ua, ub) = if r > 0.0 { (self.a / r, self.b / r) } else { (1.0, 0.0) };
        let var_r = ua * ua * caa + 2.0 * ua * ub * cab + ub * ub * cbb;
        CircleTest {
            p,
            sigma_tilt_deg: (var_r.max(0.0).sqrt() / (1.0 - r * r).max(1e-12).sqrt()).to_degrees(),
        }
    }

    /// The tilt with the first harmonic moved by `(da, db)`.
    fn moved(&self, da: f64, db: f64) -> ShaftTilt<f64> {
        ShaftTilt::from_circle(self.cx, self.cy, self.a + da, self.b + db, self.shaft.rms_deg)
    }
}

/// What the tilt circle is drawn from when X and Y turn round it the mirror way.
const WRONG_WAY: &str = "the inclinometer's X and Y turn round the tilt circle the wrong way for the format's axes (Y 90 deg counter-clockwise from X, the encoder angle growing counter-clockwise): Y read with the opposite sign, X and Y swapped, or an encoder counting the other way; the tilt is taken from X alone";

/// The method a recording allows: exact with readings of either axis on three positions or
/// more, else none.
pub fn auto_method(rec: &Recording) -> TiltMethod {
    if readings(rec).len() >= 3 {
        TiltMethod::Exact
    } else {
        TiltMethod::None
    }
}

fn readings(rec: &Recording) -> Vec<AxisReading> {
    let at = |r: &crate::recording::Row, v: Option<f64>, y: bool| {
        v.map(|deg: f64| AxisReading {
            gamma_deg: r.encoder_deg,
            sin_elev: deg.to_radians().sin(),
            y,
        })
    };
    rec.rows
        .iter()
        .flat_map(|r| [at(r, r.tilt_x_deg, false), at(r, r.tilt_y_deg, true)])
        .flatten()
        .collect()
}

/// The tilt circle from the readings there are, by the model of `nf_model::level::fit_tilt`:
/// `sin x = cx + a cos(gamma) + b sin(gamma)`, `sin y = cy - a sin(gamma) + b cos(gamma)`, a
/// mounting offset for each axis read (NaN for an axis never read).
fn circle(rec: &Recording) -> Result<(Circle, Option<String>), String> {
    let mut r = readings(rec);
    let mut warning = None;
    if tilt_sense::turns_the_wrong_way(&r) {
        r.retain(|r| !r.y);
        warning = Some(WRONG_WAY.to_string());
    }
    if r.len() < 3 {
        return Err(format!(
            "the exact tilt correction needs inclinometer readings (tilt_x_deg, tilt_y_deg or both) on three positions or more, the recording has {}",
            r.len()
        ));
    }
    let (has_x, has_y) = (r.iter().any(|r| !r.y), r.iter().any(|r| r.y));
    let cols = tilt_sense::circle_cols(&r, false);
    let sines: Vec<f64> = r.iter().map(|r| r.sin_elev).collect();
    let ls = linfit::fit(&cols, &sines).ok_or_else(|| {
        format!(
            "the inclinometer's {} readings do not determine the tilt circle",
            r.len()
        )
    })?;
    let k = cols.len();
    let (a, b) = (ls.coef[k - 2], ls.coef[k - 1]);
    let offsets = |i: Option<usize>| i.map_or(f64::NAN, |i| ls.coef[i]);
    // Readings that fit the circle exactly leave no scatter to measure it by.
    let s2 = if ls.dof > 0 { ls.s2() } else { 0.0 };
    let rms_deg = s2.sqrt().asin().to_degrees();
    let (cx, cy) = (
        offsets(has_x.then_some(0)),
        offsets(has_y.then_some(usize::from(has_x))),
    );
    let cov = [
        [s2 * ls.cov_unit[k - 2][k - 2], s2 * ls.cov_unit[k - 2][k - 1]],
        [s2 * ls.cov_unit[k - 1][k - 2], s2 * ls.cov_unit[k - 1][k - 1]],
    ];
    let circle = Circle {
        shaft: ShaftTilt::from_circle(cx, cy, a, b, rms_deg),
        cx,
        cy,
        a,
        b,
        cov,
        dof: ls.dof,
    };
    Ok((circle, warning))
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
        warning: None,
        sigma_psi_deg: 0.0,
        sensitivity: Sensitivity::NONE,
        circle_test: None,
    };
    // Measured where not used, so the output can say what a tilt the correction left.
    let measured = || circle(rec).ok().map(|c| c.0);
    match method {
        TiltMethod::None => {
            let c = measured();
            let circle_test = c.as_ref().map(Circle::test);
            Ok(Tilt {
                shaft: c.as_ref().map(|c| c.shaft),
                circle_test,
                warning: c.zip(circle_test).and_then(|(c, t)| left_in(&c.shaft, t, lat)),
                ..none
            })
        }
        TiltMethod::FirstOrder => {
            let (x, bridged) = bridged_x(rec)?;
            let c = measured();
            Ok(Tilt {
                corrections: x.iter().map(|&x| vertical_earth_rate_dph(lat, x)).collect(),
                bridged,
                shaft: c.as_ref().map(|c| c.shaft),
                circle_test: c.as_ref().map(Circle::test),
                warning: c.filter(|c| c.shaft.tilt_deg > FIRST_ORDER_MAX_DEG).map(|c| {
                    format!(
                        "the shaft is tilted {:.2} deg; first order leaves an error of the order of the tilt squared, tens of sigma at a few degrees: --tilt exact",
                        c.shaft.tilt_deg
                    )
                }),
                ..none
            })
        }
        TiltMethod::Exact => {
            let (c, warning) = circle(rec)?;
            let read =
                |r: &crate::recording::Row| r.tilt_x_deg.is_some() || (warning.is_none() && r.tilt_y_deg.is_some());
            let bridged = rec.rows.iter().filter(|r| !read(r)).count();
            let s = solve(lat, &gammas, &c.shaft, &mut fit, true, false)?;
            let sigma_psi_deg = circle_sigma_deg(lat, &gammas, &c, &mut fit, &s);
            let ratio = vertical_ratio(lat, c.shaft.tilt_deg);
            let scale_one = s.scale_one.then(|| {
                format!(
                    "the exact tilt correction with the gyro's scale fitted beside the azimuth did not converge (at a tilt of {:.2} deg and latitude {lat} deg the vertical Earth rate the tilt adds is {ratio:.2} times the horizontal one, and both scale with the gyro's scale factor): the scale is taken as 1, and a scale off by 0.1 % moves this azimuth by {:.0}\", which the sigma does not hold",
                    c.shaft.tilt_deg,
                    1e-3 * ratio * 180.0 / std::f64::consts::PI * 3600.0
                )
            });
            let warning = match (warning, scale_one) {
                (Some(w), Some(o)) => Some(format!("{w}; {o}")),
                (w, o) => w.or(o),
            };
            Ok(Tilt {
                corrections: s.corrections,
                shaft: Some(c.shaft),
                bridged,
                iterations: s.iterations,
                warning,
                sigma_psi_deg,
                sensitivity: s.sensitivity,
                circle_test: Some(c.test()),
                ..none
            })
        }
    }
}

/// The exact correction for the tilt `t`, with the azimuth and amplitude it leaves, and its
/// sensitivity where `carry` asks for it (two more fits); the gyro's scale taken as 1 where
/// `unit`, or where its fit beside the azimuth does not converge.
fn solve(
    lat: f64,
    gammas: &[f64],
    t: &ShaftTilt<f64>,
    fit: &mut impl FnMut(&[f64]) -> Result<(f64, f64), String>,
    carry: bool,
    unit: bool,
) -> Result<Solution, String> {
    // Start from first order (the circle's X at each position), then solve the exact model
    // with the fitted azimuth and scale.
    let corr: Vec<f64> = gammas
        .iter()
        .map(|&g| vertical_earth_rate_dph(lat, circle_x_deg(t, g)))
        .collect();
    let (mut psi, mut amp) = fit(&corr)?;
    let start_psi = psi;
    if unit {
        return unit_scale(lat, gammas, t, fit, carry, start_psi);
    }
    // No Earth rate to scale the exact correction by (constant rates, a dead gyro): where
    // Newton then fails, the fit says it is not resolved, and first order is as good as any.
    let no_earth_rate = !amplitude_is_earth_rate(amp, 0.0, amplitude_dph(lat));
    let first_order = (corr, psi, amp);
    // The azimuth and the amplitude are a fixed point of "correct with them, then fit". At
    // high latitude and large tilt the map moves nearly as fast as its arguments (its slope is
    // about eta tan(lat)), and plain iteration stalls: Newton on
    // G(psi, amp) = fit(correct(psi, amp)) - (psi, amp), its Jacobian by differences.
    let mut eval = |psi: f64, amp: f64| gap(lat, gammas, t, fit, psi, amp);
    // The closest point met, for when rounding keeps the step from the tolerance.
    let mut closest: Option<(f64, Vec<f64>, f64, f64)> = None;
    let mut converged = None;
    for k in 1..=MAX_ITERATIONS {
        let (g, c) = match eval(psi, amp) {
            Err(_) if no_earth_rate => break,
            r => r?,
        };
        if g[0].abs() < PSI_TOL_DEG && g[1].abs() < 1e-12 * amp.abs().max(1e-6) {
            converged = Some((k, c, psi, amp, g));
            break;
        }
        if closest.as_ref().is_none_or(|(d, ..)| g[0].abs() < *d) {
            closest = Some((g[0].abs(), c, psi, amp));
        }
        let j = match jacobian(&mut eval, psi, amp, g) {
            Err(_) if no_earth_rate => break,
            r => r?,
        };
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
    let found = match (converged, closest) {
        (Some(found), _) => Some(found),
        (None, Some((d, corrections, psi, amp))) if d < NEAR_ENOUGH_DEG => {
            let (g, _) = eval(psi, amp)?;
            Some((MAX_ITERATIONS, corrections, psi, amp, g))
        }
        _ if no_earth_rate => {
            let (corrections, psi_deg, _) = first_order;
            return Ok(Solution {
                corrections,
                iterations: MAX_ITERATIONS,
                psi_deg,
                sensitivity: Sensitivity::NONE,
                scale_one: false,
            });
        }
        _ => None,
    };
    let Some((iterations, corrections, psi, amp, g)) = found else {
        return unit_scale(lat, gammas, t, fit, carry, start_psi);
    };
    let sensitivity = if carry {
        carried(jacobian(&mut eval, psi, amp, g)?)
    } else {
        Sensitivity::NONE
    };
    Ok(Solution {
        corrections,
        iterations,
        psi_deg: psi + g[0],
        sensitivity,
        scale_one: false,
    })
}

/// `G(psi, amp) = fit(correct(psi, amp)) - (psi, amp)`, the exact correction's fixed-point
/// gap, and the correction.
fn gap(
    lat: f64,
    gammas: &[f64],
    t: &ShaftTilt<f64>,
    fit: &mut impl FnMut(&[f64]) -> Result<(f64, f64), String>,
    psi: f64,
    amp: f64,
) -> Result<([f64; 2], Vec<f64>), String> {
    let corr = exact_tilt_correction(lat, psi, amp, t, gammas);
    let (p, a) = fit(&corr)?;
    Ok(([wrap_180(p - psi), a - amp], corr))
}

/// The exact correction with the gyro's scale taken as 1 (the correction's amplitude the
/// latitude's `WE cos(lat)`), the azimuth alone iterated from `psi`: near the pole at a large
/// tilt the vertical Earth rate the tilt adds outweighs the horizontal one, both scale with
/// the gyro's scale factor, and the fit of the scale beside the azimuth may not converge.
fn unit_scale(
    lat: f64,
    gammas: &[f64],
    t: &ShaftTilt<f64>,
    fit: &mut impl FnMut(&[f64]) -> Result<(f64, f64), String>,
    carry: bool,
    mut psi: f64,
) -> Result<Solution, String> {
    let amp = amplitude_dph(lat);
    let mut eval = |psi: f64| gap(lat, gammas, t, fit, psi, amp).map(|(g, corr)| (g[0], corr));
    const STEP_DEG: f64 = 1e-6;
    for k in 1..=MAX_ITERATIONS {
        let (g, corrections) = eval(psi)?;
        let slope = (eval(psi + STEP_DEG)?.0 - g) / STEP_DEG;
        if g.abs() < PSI_TOL_DEG {
            // G = F - 1: a fit's azimuth error is carried as 1 / (1 - F') = -1 / G'.
            let m = if carry { -1.0 / slope } else { 1.0 };
            return Ok(Solution {
                corrections,
                iterations: k,
                psi_deg: psi + g,
                sensitivity: Sensitivity([[m, 0.0], [0.0, 1.0]]),
                scale_one: true,
            });
        }
        let step = if slope.is_finite() && slope.abs() > 1e-12 {
            -g / slope
        } else {
            g
        };
        psi += step.clamp(-30.0, 30.0);
    }
    Err(format!(
        "the exact tilt correction did not converge in {MAX_ITERATIONS} iterations, with the gyro's scale fitted or taken as 1: at a tilt of {:.2} deg and latitude {lat} deg the vertical Earth rate the tilt adds is {:.2} times the horizontal one",
        t.tilt_deg,
        vertical_ratio(lat, t.tilt_deg)
    ))
}

/// The vertical Earth rate a tilt `eta` adds to the first harmonic over the horizontal one,
/// `sin(eta) tan|lat|`: also the radians a relative scale error moves the azimuth by, per unit.
fn vertical_ratio(lat: f64, tilt_deg: f64) -> f64 {
    tilt_deg.to_radians().sin() * lat.to_radians().tan().abs()
}

/// The Jacobian of `G` at `(psi, amp)`, where it is `g`, by differences.
fn jacobian(
    eval: &mut impl FnMut(f64, f64) -> Result<([f64; 2], Vec<f64>), String>,
    psi: f64,
    amp: f64,
    g: [f64; 2],
) -> Result<[[f64; 2]; 2], String> {
    let (hp, ha) = (1e-6, 1e-6 * amp.abs().max(1e-3));
    let (gp, _) = eval(psi + hp, amp)?;
    let (ga, _) = eval(psi, amp + ha)?;
    Ok([
        [(gp[0] - g[0]) / hp, (ga[0] - g[0]) / ha],
        [(gp[1] - g[1]) / hp, (ga[1] - g[1]) / ha],
    ])
}

/// `(I - F')^-1 = -G'^-1` from G's Jacobian `j` (`G = F - I`); infinite where G' is singular:
/// the data then do not fix the azimuth.
fn carried(j: [[f64; 2]; 2]) -> Sensitivity {
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    if !det.is_finite() || det == 0.0 {
        return Sensitivity([[f64::INFINITY; 2]; 2]);
    }
    Sensitivity([[-j[1][1] / det, j[0][1] / det], [j[1][0] / det, -j[0][0] / det]])
}

/// The azimuth's standard deviation (deg) from the circle's own uncertainty: the correction
/// solved again with the circle's first harmonic moved by one standard deviation of each
/// coefficient, the two slopes propagated through their covariance. A quiet gyro's azimuth
/// can know less than the inclinometer: about `tan(lat)` times the circle's sigma.
fn circle_sigma_deg(
    lat: f64,
    gammas: &[f64],
    c: &Circle,
    fit: &mut impl FnMut(&[f64]) -> Result<(f64, f64), String>,
    at: &Solution,
) -> f64 {
    let psi = at.psi_deg;
    let h = [c.cov[0][0].sqrt(), c.cov[1][1].sqrt()];
    let mut slope = [0.0; 2];
    for k in 0..2 {
        if h[k].is_nan() || h[k] <= 0.0 {
            continue;
        }
        let moved = c.moved(if k == 0 { h[k] } else { 0.0 }, if k == 1 { h[k] } else { 0.0 });
        match solve(lat, gammas, &moved, fit, false, at.scale_one) {
            Ok(s) => slope[k] = wrap_180(s.psi_deg - psi) / h[k],
            // To first order either coefficient turns the azimuth by tan(lat) radians.
            Err(_) => return lat.to_radians().tan().abs() * (0.5 * (c.cov[0][0] + c.cov[1][1])).sqrt().to_degrees(),
        }
    }
    let var =
        slope[0] * slope[0] * c.cov[0][0] + 2.0 * slope[0] * slope[1] * c.cov[0][1] + slope[1] * slope[1] * c.cov[1][1];
    var.max(0.0).sqrt()
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
    if obs.is_empty() {
        return Err(
            "the first-order tilt correction reads tilt_x_deg, which the recording does not have; the exact one (--tilt exact, or auto) reads tilt_y_deg alone"
                .into(),
        );
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sensitivity_inverts_one_less_the_slope() {
        // No dependence of the fit on its own result: G' = -I, the sensitivity is I.
        assert_eq!(carried([[-1.0, 0.0], [0.0, -1.0]]), Sensitivity::NONE);
        // F' = G' + I; (I - F') times the sensitivity is I.
        let j = [[-0.3, 0.2], [-1.7, -0.05]];
        let m = carried(j).0;
        for (r, c) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let p: f64 = (0..2).map(|k| m[r][k] * -j[k][c]).sum();
            assert!((p - f64::from(u8::from(r == c))).abs() < 1e-12, "{r}{c}: {p}");
        }
        // The amplitude's slope near 1 (a tilt of eta with eta tan(lat) = 0.99): the azimuth's
        // sigma grows with the amplitude's share.
        let near = carried([[-1.0, 0.5], [0.0, -0.01]]);
        let (psi, amp) = near.carried(1.0, 1.0);
        assert!(
            (psi - 50.0f64.hypot(1.0)).abs() < 1e-9 && (amp - 100.0).abs() < 1e-9,
            "{psi} {amp}"
        );
        assert!(carried([[0.0, 0.0], [0.0, 0.0]]).0[0][0].is_infinite());
    }

    /// A sweep of 36 positions whose inclinometer reads a tilt of `tilt_deg` toward 40 deg,
    /// mounting offsets, and noise of 0.001 deg on both axes.
    fn readings_of(tilt_deg: f64, rng: &mut nf_model::rng::Rng) -> Recording {
        let mut text = String::from("# format = northfinder-recording/1\n# latitude_deg = 45\n");
        text.push_str("index,t_s,encoder_deg,rate_dph,tilt_x_deg,tilt_y_deg\n");
        for k in 0..36 {
            let g = k as f64 * 10.0;
            // The axis at gamma dips by the tilt's component along it (tilt direction 40 deg).
            let x = 0.02 - tilt_deg * (g - 40.0).to_radians().cos() + 0.001 * rng.gauss();
            let y = -0.01 + tilt_deg * (g - 40.0).to_radians().sin() + 0.001 * rng.gauss();
            text.push_str(&format!("{k},{},{g},{},{x},{y}\n", 2 * k, 10.0 * g.to_radians().cos()));
        }
        Recording::parse(&text).unwrap()
    }

    #[test]
    fn identical_readings_are_no_tilt_and_readings_on_a_circle_exactly_are_one() {
        let on = |tilt_deg: f64| {
            let mut text = String::from("# format = northfinder-recording/1\n# latitude_deg = 45\n");
            text.push_str("index,t_s,encoder_deg,rate_dph,tilt_x_deg,tilt_y_deg\n");
            for k in 0..36 {
                let g = k as f64 * 10.0;
                let x = -0.007176 - tilt_deg * (g - 40.0).to_radians().cos();
                let y = 0.007176 + tilt_deg * (g - 40.0).to_radians().sin();
                text.push_str(&format!("{k},{},{g},1,{x},{y}\n", 2 * k));
            }
            circle(&Recording::parse(&text).unwrap()).unwrap().0.test().p
        };
        // A level shaft read in steps: every reading the same (an outside audit: p 2.4e-7).
        assert_eq!(on(0.0), 1.0);
        assert_eq!(on(0.001), 0.0);
    }

    #[test]
    fn the_tilt_test_agrees_with_the_tilt_and_its_sigma() {
        // Without a tilt, (a, b) is a 2-d normal: its size over its sigma is Rayleigh, so the
        // p-value is close to exp(-z^2 / 2), and below 0.05 in one run of 20.
        let mut rng = nf_model::rng::Rng::new(3);
        let runs = 400;
        let mut below = 0;
        for _ in 0..runs {
            let (c, _) = circle(&readings_of(0.0, &mut rng)).unwrap();
            let t = c.test();
            let z = c.shaft.tilt_deg / t.sigma_tilt_deg;
            assert!((t.p - (-0.5 * z * z).exp()).abs() < 0.02, "p {} z {z}", t.p);
            below += usize::from(t.p < 0.05);
        }
        assert!((10..=30).contains(&below), "{below} of {runs}");
        // A reading's noise of tilt stands out of 72 readings; its sigma holds.
        let (c, _) = circle(&readings_of(0.001, &mut rng)).unwrap();
        let t = c.test();
        assert!(t.p < 1e-3, "{t:?}");
        assert!(
            (c.shaft.tilt_deg - 0.001).abs() < 3.0 * t.sigma_tilt_deg,
            "{} {t:?}",
            c.shaft.tilt_deg
        );
        assert!((t.sigma_tilt_deg / (0.001 / 36f64.sqrt()) - 1.0).abs() < 0.3, "{t:?}");
    }
}
