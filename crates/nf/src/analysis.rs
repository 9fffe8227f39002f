//! The fit of a recording: the azimuth with the tilt correction the recording allows, its
//! uncertainty from the residuals and from the budgets, the residuals themselves.

use crate::noise_calib;
use crate::noise_fit::{self, NoiseChoice, NoiseFit};
use crate::recording::Recording;
use crate::tilt;
use nf_model::EARTH_RATE_DPH;
use nf_model::exact::Instrument;
use nf_model::fit::{AzimuthFit, Drift, FitConfig, FitError, FitResult, Obs};
use nf_model::level::ShaftTilt;
use nf_model::uncertainty::{Budget, Sigmas, amplitude_dph};

/// How the vertical Earth rate of a tilted shaft is removed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TiltMethod {
    /// None: the recording has no inclinometer columns, or the user said so.
    None,
    /// Per position, `WE sin(lat) sin(tilt_x)`: first order in the tilt.
    FirstOrder,
    /// The exact model of the tilt fitted to all X and Y readings (the tilt circle), iterated
    /// with the fitted azimuth and scale: also right to second order, for tilts of a degree.
    Exact,
}

impl TiltMethod {
    pub fn name(&self) -> &'static str {
        match self {
            TiltMethod::None => "none",
            TiltMethod::FirstOrder => "first-order",
            TiltMethod::Exact => "exact",
        }
    }
}

#[derive(Debug, Clone)]
pub struct Options {
    /// `None`: the best the recording allows.
    pub tilt: Option<TiltMethod>,
    pub drift: Drift,
    pub harmonics: u8,
    /// Encoder uncertainty and shaft-tilt uncertainty for the budgets.
    pub sigma_encoder_deg: f64,
    pub sigma_tilt_deg: f64,
    /// Gyro misalignment for Eq. 30.
    pub gyro_elev_deg: f64,
    /// The noise model of the GLS fit.
    pub noise: NoiseChoice,
    /// Bootstrap replicates that calibrate an estimated noise model's sigma (0: none).
    pub replicates: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tilt: None,
            drift: Drift::None,
            harmonics: 1,
            sigma_encoder_deg: 0.001,
            sigma_tilt_deg: 0.003,
            gyro_elev_deg: 0.01,
            noise: NoiseChoice::Estimate,
            replicates: noise_calib::REPLICATES.into(),
        }
    }
}

#[derive(Debug, Clone)]
pub struct Analysis {
    pub latitude_deg: f64,
    pub fit: FitResult<f64>,
    pub method: TiltMethod,
    /// Per-position correction removed from the rates (deg/h).
    pub corrections: Vec<f64>,
    pub shaft: Option<ShaftTilt<f64>>,
    /// Positions without an inclinometer reading, corrected from the tilt circle.
    pub tilt_bridged: usize,
    /// `(gamma, t, rate, fitted, residual)` per position.
    pub points: Vec<[f64; 5]>,
    pub amplitude_predicted_dph: f64,
    pub budget_paper: Budget<f64>,
    pub budget_exact: Budget<f64>,
    /// Gyro noise per position estimated from the residuals.
    pub sigma_gyro_dph: f64,
    /// The azimuth under the gyro's noise model (generalised least squares): the result.
    pub gls: NoiseFit,
    /// Dwell means far off the rest, which the fit weighs like any other.
    pub wild: Vec<Wild>,
}

/// A dwell mean [`WILD_SIGMAS`] robust sigmas or more off the white fit: a glitch or a fill
/// value, which moves a least-squares azimuth; `nf diagnose` tests it as an outlier.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wild {
    pub line: usize,
    pub index: u32,
    pub rate_dph: f64,
    /// Its residual in robust sigmas (1.4826 times the median absolute residual).
    pub sigmas: f64,
}

/// Far enough that no Gaussian dwell of a run of a million gets there (p 1e-15 each).
pub const WILD_SIGMAS: f64 = 8.0;

fn wild(rec: &Recording, points: &[[f64; 5]]) -> Vec<Wild> {
    let mut abs: Vec<f64> = points.iter().map(|p| p[4].abs()).collect();
    abs.sort_by(f64::total_cmp);
    let sigma = 1.4826 * abs[abs.len() / 2];
    rec.rows
        .iter()
        .zip(points)
        .filter(|(_, p)| sigma > 0.0 && p[4].abs() >= WILD_SIGMAS * sigma)
        .map(|(r, p)| Wild {
            line: r.line,
            index: r.index,
            rate_dph: r.rate_dph,
            sigmas: p[4].abs() / sigma,
        })
        .collect()
}

fn plain(cfg: FitConfig<f64>, rec: &Recording, corr: &[f64]) -> Result<FitResult<f64>, FitError> {
    let obs: Vec<Obs<f64>> = rec
        .rows
        .iter()
        .zip(corr)
        .map(|(r, c)| Obs {
            t_s: r.t_s,
            ..Obs::new(r.encoder_deg, r.rate_dph - c)
        })
        .collect();
    AzimuthFit::fit_all(cfg, &obs)
}

/// Fits a recording.
pub fn analyse(rec: &Recording, opt: &Options) -> Result<Analysis, String> {
    rec.require_turning()?;
    let lat = rec.latitude_deg;
    let method = opt.tilt.unwrap_or_else(|| tilt::auto_method(rec));
    let cfg = FitConfig {
        drift: opt.drift,
        harmonics: opt.harmonics,
        ..FitConfig::default()
    };
    let fail = |e: FitError| match e {
        FitError::NonFinite { index } | FitError::BadWeight { index } | FitError::MissingTilt { index } => {
            format!("line {}: {e}", rec.rows[index as usize].line)
        }
        e => format!("the fit failed: {e}"),
    };
    let tilt = tilt::correct(rec, method, |corr| {
        plain(cfg, rec, corr)
            .map(|f| (f.psi_deg, f.amplitude_dph))
            .map_err(fail)
    })?;
    let fit = plain(cfg, rec, &tilt.corrections).map_err(fail)?;
    let (corrections, shaft, bridged) = (tilt.corrections, tilt.shaft, tilt.bridged);
    let points: Vec<[f64; 5]> = rec
        .rows
        .iter()
        .zip(&corrections)
        .map(|(r, c)| {
            let f = fit.predict(r.encoder_deg, r.t_s, None) + c;
            [r.encoder_deg, r.t_s, r.rate_dph, f, r.rate_dph - f]
        })
        .collect();
    let wild = wild(rec, &points);
    let y: Vec<f64> = rec.rows.iter().zip(&corrections).map(|(r, c)| r.rate_dph - c).collect();
    let gls = noise_fit::fit(rec, &y, &cfg, &opt.noise, opt.replicates)?;
    let n = fit.n;
    let sigma_gyro_dph = fit.s2.sqrt();
    // With the tilt measured, what is left of it is the inclinometer's uncertainty.
    let sigma_tilt = match (method, shaft) {
        (TiltMethod::Exact, Some(s)) => s.rms_deg * (2.0 / n as f64).sqrt(),
        (TiltMethod::FirstOrder, _) => tilt_x_scatter(rec) * (2.0 / n as f64).sqrt(),
        _ => opt.sigma_tilt_deg,
    };
    let sig = Sigmas {
        gyro_dph: sigma_gyro_dph,
        encoder_deg: opt.sigma_encoder_deg,
        tilt_deg: sigma_tilt,
    };
    let paper_sig = Sigmas {
        tilt_deg: opt.sigma_tilt_deg,
        ..sig
    };
    Ok(Analysis {
        latitude_deg: lat,
        amplitude_predicted_dph: EARTH_RATE_DPH * lat.to_radians().cos(),
        budget_paper: Budget::paper(n, &paper_sig, lat, fit.psi_deg, opt.gyro_elev_deg),
        budget_exact: Budget::closed_form(n, &sig, lat),
        fit,
        method,
        corrections,
        shaft,
        tilt_bridged: bridged,
        points,
        sigma_gyro_dph,
        gls,
        wild,
    })
}

/// Scatter (deg) of the inclinometer X readings about their tilt circle `C + A cos + B sin`.
fn tilt_x_scatter(rec: &Recording) -> f64 {
    let obs: Vec<Obs<f64>> = rec
        .rows
        .iter()
        .filter_map(|r| Some(Obs::new(r.encoder_deg, r.tilt_x_deg?)))
        .collect();
    match AzimuthFit::fit_all(FitConfig::default(), &obs) {
        Ok(f) if f.s2.is_finite() => f.s2.sqrt(),
        // A level shaft has no circle to fit: the readings' own spread is the scatter.
        _ => {
            let m = obs.iter().map(|o| o.rate_dph).sum::<f64>() / obs.len() as f64;
            (obs.iter().map(|o| (o.rate_dph - m).powi(2)).sum::<f64>() / (obs.len().max(2) - 1) as f64).sqrt()
        }
    }
}

/// The rate a shaft tilt adds at each `gamma` in the exact model (the tilted instrument's rate
/// minus the level one's), for the fitted azimuth and first-harmonic amplitude.
pub fn exact_tilt_correction(
    lat: f64,
    psi_deg: f64,
    amplitude: f64,
    tilt: &ShaftTilt<f64>,
    gammas: &[f64],
) -> Vec<f64> {
    let tilted = Instrument {
        latitude_deg: lat,
        psi_deg,
        tilt_deg: tilt.tilt_deg,
        tilt_dir_deg: tilt.tilt_dir_deg,
        gyro_elev_deg: 0.0,
        scale: amplitude / amplitude_dph(lat),
        bias_dph: 0.0,
    };
    let level = Instrument {
        tilt_deg: 0.0,
        ..tilted
    };
    gammas.iter().map(|&g| tilted.rate_dph(g) - level.rate_dph(g)).collect()
}
