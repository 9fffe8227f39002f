//! The JSON of `nf fit --json`.
//!
//! The fields of each struct are in alphabetical order, the order the keys have always had.

use super::super::json::BudgetJson;
use crate::analysis::Analysis;
use crate::noise_fit::NoiseSource;
use nf_model::angle::surveying_azimuth_deg;
use serde::Serialize;

/// The fit of a recording: the azimuth under the gyro's noise model (generalised least
/// squares), the white-noise fit beside it, and the budgets.
#[derive(Serialize)]
pub(super) struct FitJson {
    /// Fitted amplitude of the Earth-rate harmonic, deg/h.
    amplitude_dph: f64,
    /// Amplitude the latitude predicts, deg/h.
    amplitude_predicted_dph: f64,
    /// Why the amplitude, resolved, disagrees with the latitude's (a scale factor or a
    /// latitude far off); null when it agrees.
    amplitude_warning: Option<String>,
    /// Azimuth psi of Eq. 7 (generalised least squares), deg; null when the Earth rate is
    /// not resolved.
    azimuth_deg: Option<f64>,
    /// The paper's budget (Eq. 31).
    budget_eq31_paper: BudgetJson,
    /// The exact model's budget.
    budget_exact: BudgetJson,
    /// Degrees of freedom of the white-noise fit.
    dof: u32,
    /// Linear drift, deg/h per s (0 when not fitted).
    drift_dph_per_s: f64,
    /// Quadratic drift, deg/h per s^2 (0 when not fitted).
    drift_dph_per_s2: f64,
    /// Whether the Earth rate is resolved; without it no azimuth can be given.
    earth_rate_resolved: bool,
    /// Dwell means far off the fit of the others (a glitch or a fill value), held out of it.
    far_off: Vec<FarOff>,
    /// Latitude of the recording, deg.
    latitude_deg: f64,
    /// How the azimuth was fitted.
    method: &'static str,
    /// Positions fitted.
    n: u32,
    /// The gyro noise model the fit used.
    noise_model: NoiseModelJson,
    /// Why the Earth rate is not resolved; null when it is.
    not_resolved_because: Option<String>,
    /// The fit's phase psi, deg, given whether or not the Earth rate is resolved (then it is
    /// no azimuth).
    psi_fitted_deg: f64,
    /// Gyro bias (the fit's offset), deg/h.
    offset_dph: f64,
    /// The white-noise least-squares fit.
    ols: Ols,
    /// Residual sum of squares of the white-noise fit, (deg/h)^2.
    rss: f64,
    /// Fitted over predicted amplitude (dimensionless).
    scale_factor: f64,
    /// Shaft tilt from the inclinometer's tilt circle, deg; null without one.
    shaft_tilt_deg: Option<f64>,
    /// Direction the platform is lowest towards, deg; null without a tilt circle.
    shaft_tilt_dir_deg: Option<f64>,
    /// 1-sigma uncertainty of the amplitude, deg/h.
    sigma_amplitude_dph: f64,
    /// 1-sigma uncertainty of the azimuth, arcsec: the gyro's, and the tilt circle's.
    sigma_arcsec: f64,
    /// The tilt circle's share of `sigma_arcsec` (its readings' scatter propagated through the
    /// exact correction), arcsec; 0 without one.
    sigma_inclinometer_arcsec: f64,
    /// RMS of the residuals, deg/h.
    sigma_gyro_dph: f64,
    /// The surveying azimuth (clockwise from true north) of the gamma = 0 direction, deg;
    /// null when the Earth rate is not resolved.
    surveying_azimuth_deg: Option<f64>,
    /// Positions without an inclinometer reading, corrected from the tilt circle.
    tilt_bridged_positions: usize,
    /// The tilt correction applied: none, first-order or exact.
    tilt_correction: &'static str,
    /// Why some inclinometer readings were not used; null when all were.
    tilt_warning: Option<String>,
}

/// The gyro noise model, given or estimated, and how well it fits.
#[derive(Serialize)]
struct NoiseModelJson {
    /// Angle random walk N, deg/sqrt(h).
    arw_deg_rth: f64,
    /// Bias instability B, deg/h.
    bias_instability_dph: f64,
    /// Chi-square of the generalised least-squares fit (dimensionless).
    chi2: f64,
    /// Its degrees of freedom.
    chi2_dof: usize,
    /// Where the dwell came from.
    dwell_from: &'static str,
    /// The shortest and longest dwell, s, where the rows' samples make them differ (each
    /// dwell mean weighed by its own); null where every dwell is `dwell_s`.
    dwell_range_s: Option<(f64, f64)>,
    /// Dwell per position (the typical one where they differ), s.
    dwell_s: f64,
    /// Gauss-Markov bias standard deviation, deg/h.
    gm_sigma_dph: f64,
    /// Gauss-Markov correlation time, s.
    gm_tau_s: f64,
    /// Quantisation Q, arcsec.
    quantization_arcsec: f64,
    /// Rate random walk K, deg/h/sqrt(h).
    rrw_dph_rth: f64,
    /// Where the dwell means are heavy-tailed: the shocks each dwell was weighed through
    /// (null otherwise).
    shocks: Option<ShocksJson>,
    /// The factor a parametric bootstrap scaled the azimuth's sigma by (an estimated model
    /// only; null when given, when no replicate could be drawn, or when one or two residuals
    /// alone measured the noise and the sigma is read off Student's t).
    sigma_calibration: Option<f64>,
    /// How many times the gyro's share of `sigma_arcsec` exceeds GLS under this model alone:
    /// the spread of the noise models the recording allows, and the calibration (1 when the
    /// model was given; Student's t 95 % half-width over 1.96 when one or two residuals alone
    /// measured the noise).
    sigma_widening: f64,
    /// Where the model came from: the flags, a file, or estimated from the recording.
    source: String,
}

#[derive(Serialize)]
struct ShocksJson {
    /// The share of dwells a shock struck.
    share: f64,
    /// Standard deviation of a shock's shift of a dwell mean, deg/h.
    shift_dph: f64,
    /// Lines of the dwells more likely struck than not.
    struck_lines: Vec<usize>,
}

/// The white-noise least-squares fit.
#[derive(Serialize)]
struct FarOff {
    index: u32,
    line: usize,
    rate_dph: f64,
    /// The residual in robust sigmas of the white fit's residuals.
    robust_sigmas: f64,
    /// Left out of the fit; false when more than a tenth lie this far off (the data) or the
    /// rest would leave no degree of freedom.
    held_out: bool,
}

#[derive(Serialize)]
struct Ols {
    /// Azimuth psi, deg.
    azimuth_deg: f64,
    /// What this fit is.
    note: &'static str,
    /// 1-sigma uncertainty of the azimuth from the residuals, arcsec.
    sigma_arcsec: f64,
}

pub(super) fn fit_json(an: &Analysis) -> FitJson {
    let f = &an.fit;
    let g = &an.gls;
    let m = &g.model;
    let (d1, d2) = f.drift();
    let unresolved = g.unresolved(an.amplitude_predicted_dph);
    FitJson {
        amplitude_dph: g.amplitude_dph,
        amplitude_predicted_dph: an.amplitude_predicted_dph,
        amplitude_warning: an.amplitude_warning(),
        // + 0.0: a -0.0 azimuth reads as a sign error.
        azimuth_deg: unresolved.is_none().then_some(g.psi_deg + 0.0),
        budget_eq31_paper: (&an.budget_paper).into(),
        budget_exact: (&an.budget_exact).into(),
        dof: f.dof,
        drift_dph_per_s: d1,
        drift_dph_per_s2: d2,
        earth_rate_resolved: unresolved.is_none(),
        far_off: an
            .wild
            .iter()
            .map(|w| FarOff {
                index: w.index,
                line: w.line,
                rate_dph: w.rate_dph,
                robust_sigmas: w.sigmas,
                held_out: w.held_out,
            })
            .collect(),
        latitude_deg: an.latitude_deg,
        method: "generalised least squares under the gyro noise model",
        n: f.n,
        noise_model: NoiseModelJson {
            arw_deg_rth: m.arw_deg_rth,
            bias_instability_dph: m.bias_instability_dph,
            chi2: g.chi2,
            chi2_dof: g.dof,
            dwell_from: g.dwell_from,
            dwell_range_s: g.dwell_range_s,
            dwell_s: g.dwell_s,
            gm_sigma_dph: m.gm_sigma_dph,
            gm_tau_s: m.gm_tau_s,
            quantization_arcsec: m.quantization_arcsec,
            rrw_dph_rth: m.rrw_dph_rth,
            shocks: g.shocks.as_ref().map(|s| ShocksJson {
                share: s.share,
                shift_dph: s.shift_dph,
                struck_lines: s.struck.clone(),
            }),
            sigma_calibration: match &g.source {
                NoiseSource::Estimated { calibration, .. } => calibration.map(|c| c.psi),
                NoiseSource::Residuals { .. } | NoiseSource::Given { .. } => None,
            },
            sigma_widening: g.widening,
            source: g.source.describe(),
        },
        psi_fitted_deg: g.psi_deg + 0.0,
        offset_dph: f.offset_dph,
        ols: Ols {
            azimuth_deg: f.psi_deg,
            note: "white-noise least squares, sigma from the residuals",
            sigma_arcsec: f.sigma_psi_deg * 3600.0,
        },
        rss: f.rss,
        scale_factor: g.amplitude_dph / an.amplitude_predicted_dph,
        shaft_tilt_deg: an.shaft.map(|s| s.tilt_deg),
        shaft_tilt_dir_deg: an.shaft.map(|s| s.tilt_dir_deg),
        sigma_amplitude_dph: g.sigma_amplitude_dph,
        sigma_arcsec: g.sigma_psi_deg * 3600.0,
        sigma_inclinometer_arcsec: an.sigma_inclinometer_deg * 3600.0,
        sigma_gyro_dph: an.sigma_gyro_dph,
        surveying_azimuth_deg: unresolved.is_none().then_some(surveying_azimuth_deg(g.psi_deg) + 0.0),
        tilt_bridged_positions: an.tilt_bridged,
        tilt_warning: an.tilt_warning.clone(),
        tilt_correction: an.method.name(),
        not_resolved_because: unresolved,
    }
}
