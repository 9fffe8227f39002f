//! The fit of a recording: the azimuth with the tilt correction the recording allows, its
//! uncertainty from the residuals and from the budgets, the residuals themselves.

use crate::amplitude_check;
use crate::far_off::{self, Wild};
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

impl Options {
    /// The white fit's configuration: the drift and harmonics asked for.
    pub fn fit_config(&self) -> FitConfig<f64> {
        FitConfig {
            drift: self.drift,
            harmonics: self.harmonics,
            ..FitConfig::default()
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
    /// Why some inclinometer readings were not used, when they were not.
    pub tilt_warning: Option<String>,
    /// The share of the azimuth's sigma (deg) that the tilt circle's uncertainty carries;
    /// `gls.sigma_psi_deg` includes it.
    pub sigma_inclinometer_deg: f64,
    /// `(gamma, t, rate, fitted, residual)` per position.
    pub points: Vec<[f64; 5]>,
    pub amplitude_predicted_dph: f64,
    pub budget_paper: Budget<f64>,
    pub budget_exact: Budget<f64>,
    /// Gyro noise per position estimated from the residuals (where none are left, the noise
    /// model's white noise of a dwell mean).
    pub sigma_gyro_dph: f64,
    /// The azimuth under the gyro's noise model (generalised least squares): the result.
    pub gls: NoiseFit,
    /// Dwell means far off the rest: glitches held out of the fit, or listed only.
    pub wild: Vec<Wild>,
}

impl Analysis {
    /// Why the amplitude, the Earth rate resolved, still disagrees with `WE cos(lat)` at the
    /// latitude given, when it does ([`amplitude_check::amplitude_off`]).
    pub fn amplitude_warning(&self) -> Option<String> {
        let g = &self.gls;
        if g.unresolved(self.amplitude_predicted_dph).is_some() {
            return None;
        }
        amplitude_check::amplitude_off(
            g.amplitude_dph,
            g.sigma_amplitude_dph,
            self.latitude_deg,
            self.method == TiltMethod::None,
        )
    }
}

/// Fits a recording.
pub fn analyse(rec: &Recording, opt: &Options) -> Result<Analysis, String> {
    rec.require_turning()?;
    let lat = rec.latitude_deg;
    let method = opt.tilt.unwrap_or_else(|| tilt::auto_method(rec));
    let cfg = opt.fit_config();
    let Plain {
        tilt,
        fit,
        points,
        wild,
        out,
    } = plain_holding_out(rec, method, cfg)?;
    let (sigma_inclinometer_deg, sensitivity) = (tilt.sigma_psi_deg, tilt.sensitivity);
    let (corrections, shaft, bridged, tilt_warning) = (tilt.corrections, tilt.shaft, tilt.bridged, tilt.warning);
    let used = Recording {
        rows: out_of(&rec.rows, &out),
        ..rec.clone()
    };
    let y: Vec<f64> = used
        .rows
        .iter()
        .zip(out_of(&corrections, &out))
        .map(|(r, c)| r.rate_dph - c)
        .collect();
    let mut gls = noise_fit::fit(&used, &y, &cfg, &opt.noise, opt.replicates)?;
    let (sigma_psi, sigma_amplitude) = sensitivity.carried(gls.sigma_psi_deg, gls.sigma_amplitude_dph);
    // The tilt circle is measured apart from the gyro: its uncertainty adds.
    gls.sigma_psi_deg = sigma_psi.hypot(sigma_inclinometer_deg);
    gls.sigma_amplitude_dph = sigma_amplitude;
    let n = fit.n;
    // With no residual left, the gyro's noise per position is the noise model's.
    let sigma_gyro_dph = match fit.dof {
        0 => gls.model.white_mean_sd_dph(gls.dwell_s),
        _ => fit.s2.sqrt(),
    };
    // With the tilt measured, what is left of it is the inclinometer's uncertainty.
    let sigma_tilt = match (method, shaft) {
        (TiltMethod::Exact, Some(s)) => s.rms_deg * (2.0 / n as f64).sqrt(),
        (TiltMethod::FirstOrder, _) => tilt_x_scatter(rec).map_or(opt.sigma_tilt_deg, |s| s * (2.0 / n as f64).sqrt()),
        // Left uncorrected, the tilt the readings show is the error.
        (TiltMethod::None, Some(s)) => s.tilt_deg.max(opt.sigma_tilt_deg),
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
        tilt_warning,
        sigma_inclinometer_deg,
        points,
        sigma_gyro_dph,
        gls,
        wild,
    })
}

/// White least squares with the tilt correction, the dwell means far off it held out.
struct Plain {
    tilt: tilt::Tilt,
    fit: FitResult<f64>,
    /// `(gamma, t, rate, fitted, residual)` of every row, held out or not.
    points: Vec<[f64; 5]>,
    wild: Vec<Wild>,
    /// The rows held out.
    out: Vec<usize>,
}

fn plain_holding_out(rec: &Recording, method: TiltMethod, cfg: FitConfig<f64>) -> Result<Plain, String> {
    // A glitch moves a least-squares azimuth and, through the fitted amplitude, the exact tilt
    // correction: dwell means far off the fit of the others are held out, and looked for
    // again without them (one large glitch hides a smaller one).
    let mut out: Vec<usize> = Vec::new();
    let mut pass = 0;
    loop {
        let kept: Vec<usize> = (0..rec.rows.len()).filter(|i| !out.contains(i)).collect();
        let tilt = tilt::correct(rec, method, |corr| {
            plain(cfg, rec, corr, &kept).map(|f| (f.psi_deg, f.amplitude_dph))
        })?;
        let fit = plain(cfg, rec, &tilt.corrections, &kept)?;
        let points: Vec<[f64; 5]> = rec
            .rows
            .iter()
            .zip(&tilt.corrections)
            .map(|(r, c)| {
                let f = fit.predict(r.encoder_deg, r.t_s, None) + c;
                [r.encoder_deg, r.t_s, r.rate_dph, f, r.rate_dph - f]
            })
            .collect();
        let residuals: Vec<f64> = points.iter().map(|p| p[4]).collect();
        // As many positions as unknowns: the fit passes through every one, and none can be
        // judged against the others.
        let mut found = Vec::new();
        if fit.dof > 0 {
            found = far_off::find(&residuals, &kept);
            found.extend(studentised_wild(cfg, rec, &tilt.corrections, &kept, &fit, &residuals));
        }
        found.sort_unstable();
        found.dedup();
        let hold = far_off::to_hold(&found, rec.rows.len(), cfg.terms().unwrap_or(usize::MAX));
        pass += 1;
        if hold == out || pass == far_off::PASSES {
            let wild = far_off::describe(rec, &residuals, &kept, &found, &out);
            return Ok(Plain {
                tilt,
                fit,
                points,
                wild,
                out,
            });
        }
        out = hold;
    }
}

/// The rows far off by their externally studentised residual ([`far_off::studentised_wild`]):
/// those left out of `fit`, the fit of the rows `kept`, against it; and the largest residual
/// of those kept against the fit of the others.
fn studentised_wild(
    cfg: FitConfig<f64>,
    rec: &Recording,
    corr: &[f64],
    kept: &[usize],
    fit: &FitResult<f64>,
    residuals: &[f64],
) -> Vec<usize> {
    let n = rec.rows.len();
    let wild = |f: &FitResult<f64>, i: usize, residual: f64| {
        let s = (f.rss / f.dof as f64).sqrt();
        let r = &rec.rows[i];
        far_off::studentised_wild(residual, s, f.prediction_variance_unit(r.encoder_deg, r.t_s), f.dof, n)
    };
    let mut fitted = vec![false; n];
    kept.iter().for_each(|&i| fitted[i] = true);
    let mut found: Vec<usize> = (0..n).filter(|&i| !fitted[i] && wild(fit, i, residuals[i])).collect();
    let largest = kept
        .iter()
        .copied()
        .max_by(|a, b| residuals[*a].abs().total_cmp(&residuals[*b].abs()));
    if let Some(c) = largest {
        let others: Vec<usize> = kept.iter().copied().filter(|&i| i != c).collect();
        // Without it the positions may not determine the fit: then it is not judged so.
        if let Ok(f) = plain(cfg, rec, corr, &others) {
            let r = &rec.rows[c];
            if wild(&f, c, r.rate_dph - corr[c] - f.predict(r.encoder_deg, r.t_s, None)) {
                found.push(c);
            }
        }
    }
    found
}

/// Least squares on the rows `kept`, less their corrections; an error names its line.
fn plain(cfg: FitConfig<f64>, rec: &Recording, corr: &[f64], kept: &[usize]) -> Result<FitResult<f64>, String> {
    let obs: Vec<Obs<f64>> = kept
        .iter()
        .map(|&i| {
            let r = &rec.rows[i];
            Obs {
                t_s: r.t_s,
                ..Obs::new(r.encoder_deg, r.rate_dph - corr[i])
            }
        })
        .collect();
    AzimuthFit::fit_all(cfg, &obs).map_err(|e| match e {
        FitError::NonFinite { index } | FitError::BadWeight { index } | FitError::MissingTilt { index } => {
            format!("line {}: {e}", rec.rows[kept[index as usize]].line)
        }
        FitError::Singular { column } => format!(
            "the positions do not determine the fit's term {}: fit fewer terms (--harmonics, --drift) or visit more angles",
            term_name(&cfg, column)
        ),
        e => format!("the fit failed: {e}"),
    })
}

/// The fit's term in column `k` of `nf_model::fit::design_row`.
fn term_name(cfg: &FitConfig<f64>, k: u8) -> String {
    let mut names = vec!["C (the bias)".to_string(), "cos(gamma)".into(), "sin(gamma)".into()];
    if cfg.drift != Drift::None {
        names.push("t (linear drift)".into());
    }
    if cfg.drift == Drift::Quadratic {
        names.push("t^2 (quadratic drift)".into());
    }
    for h in 2..=cfg.harmonics {
        names.extend([format!("cos({h} gamma)"), format!("sin({h} gamma)")]);
    }
    names.get(k as usize).cloned().unwrap_or_else(|| format!("number {k}"))
}

/// The items not at the indices `out`.
fn out_of<T: Clone>(all: &[T], out: &[usize]) -> Vec<T> {
    all.iter()
        .enumerate()
        .filter(|(i, _)| !out.contains(i))
        .map(|(_, v)| v.clone())
        .collect()
}

/// Scatter (deg) of the inclinometer X readings about their tilt circle `C + A cos + B sin`;
/// `None` where three readings leave the circle none.
fn tilt_x_scatter(rec: &Recording) -> Option<f64> {
    let obs: Vec<Obs<f64>> = rec
        .rows
        .iter()
        .filter_map(|r| Some(Obs::new(r.encoder_deg, r.tilt_x_deg?)))
        .collect();
    match AzimuthFit::fit_all(FitConfig::default(), &obs) {
        Ok(f) if f.dof == 0 => None,
        Ok(f) if f.s2.is_finite() => Some(f.s2.sqrt()),
        // A level shaft has no circle to fit: the readings' own spread is the scatter.
        _ => {
            let m = obs.iter().map(|o| o.rate_dph).sum::<f64>() / obs.len() as f64;
            Some((obs.iter().map(|o| (o.rate_dph - m).powi(2)).sum::<f64>() / (obs.len().max(2) - 1) as f64).sqrt())
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
