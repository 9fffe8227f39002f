//! `nf fit`: azimuth, amplitude, bias, residuals and uncertainty of a recording.

use super::noise_args::{NoiseArgs, STATIC_LOG_HINT, colour_text};
use super::spinner::spinning;
use super::{Fail, angle5, read_recording};
use crate::analysis::{Analysis, Options, TiltMethod, analyse};
use crate::noise_calib;
use crate::noise_fit::{NoiseChoice, NoiseSource, lines_text};
use crate::plot;
use crate::plot::{Panel, Series, Style};
use crate::range::real;
use crate::report::Page;
use clap::ValueEnum;
use nf_model::angle::surveying_azimuth_deg;
use nf_model::fit::Drift;
use nf_model::noise::NoiseModel;
use std::io::Write;

/// Tilt (deg) above which a requested first-order correction is warned against.
const FIRST_ORDER_MAX_DEG: f64 = 1.0;

mod json;

#[derive(Clone, Copy, ValueEnum)]
pub enum TiltArg {
    /// The best the recording allows.
    Auto,
    None,
    FirstOrder,
    Exact,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum DriftArg {
    None,
    Linear,
    Quadratic,
}

#[derive(clap::Args)]
pub struct FitArgs {
    /// The recording (CSV, shared/recording-format.md).
    recording: String,
    /// Tilt correction.
    #[arg(long, value_enum, default_value = "auto")]
    tilt: TiltArg,
    /// Time terms in the fit.
    #[arg(long, value_enum, default_value = "none")]
    drift: DriftArg,
    /// Highest harmonic fitted (1 to 3).
    #[arg(long, allow_hyphen_values = true, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=3))]
    harmonics: u8,
    /// Encoder uncertainty for the budgets, deg.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.001, value_parser = real(0.0, 10.0))]
    sigma_encoder: f64,
    /// Shaft-tilt uncertainty for the paper's budget (and the exact one when uncorrected), deg.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.003, value_parser = real(0.0, 10.0))]
    sigma_tilt: f64,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
    /// Plot gyro output, fitted curve and residuals (*.svg or *.png).
    #[arg(long, value_parser = super::plot_file)]
    plot: Option<String>,
    /// Write a self-contained HTML report: the azimuth, the output, the plots.
    #[arg(long)]
    report: Option<String>,
    /// The gyro's noise model; without one it is estimated from the recording.
    #[command(flatten)]
    noise: NoiseArgs,
    /// Bootstrap replicates that calibrate the sigma of a noise model estimated from the
    /// recording (0: none; each costs about one more fit).
    #[arg(long, allow_hyphen_values = true, default_value_t = noise_calib::REPLICATES, value_parser = clap::value_parser!(u16).range(0..=1000))]
    replicates: u16,
}

pub fn cmd_fit(a: FitArgs) -> Result<(), Fail> {
    let rec = read_recording(&a.recording)?;
    let opt = Options {
        tilt: match a.tilt {
            TiltArg::Auto => None,
            TiltArg::None => Some(TiltMethod::None),
            TiltArg::FirstOrder => Some(TiltMethod::FirstOrder),
            TiltArg::Exact => Some(TiltMethod::Exact),
        },
        drift: match a.drift {
            DriftArg::None => Drift::None,
            DriftArg::Linear => Drift::Linear,
            DriftArg::Quadratic => Drift::Quadratic,
        },
        harmonics: a.harmonics,
        sigma_encoder_deg: a.sigma_encoder,
        sigma_tilt_deg: a.sigma_tilt,
        noise: if a.noise.any() {
            NoiseChoice::Given(a.noise.apply(NoiseModel::WHITE_NONE)?, a.noise.describe())
        } else {
            NoiseChoice::Estimate
        },
        replicates: usize::from(a.replicates),
        ..Options::default()
    };
    // Too few positions, or a shaft that did not turn, is bad input, like a malformed line.
    // The noise needs a residual degree of freedom unless it is given or the dwells' insides
    // (quarter means, samples' spread) show it.
    let within = a.noise.any()
        || rec.rows.iter().any(|r| r.quarters_dph.is_some())
        || !crate::sample_spread::of_rows(rec.rows.iter(), || 0).is_empty();
    rec.require_turning()
        .and_then(|_| {
            let terms = opt.fit_config().terms().unwrap_or(3);
            if within {
                rec.require_positions(terms, "this fit (one for each unknown)")
            } else {
                rec.require_positions(
                    terms + 1,
                    "this fit without quarter means, samples' spread or a given noise model (its unknowns and one degree of freedom for the noise)",
                )
            }
        })
        .map_err(|e| Fail(format!("{}: {e}", a.recording), 2))?;
    let n = rec.rows.len();
    let message = match a.replicates {
        0 => format!("fitting {n} positions"),
        r => format!("fitting {n} positions and {r} bootstrap replicates (--replicates 0 skips them)"),
    };
    let an = spinning(message, || analyse(&rec, &opt));
    // What the recording cannot give (no inclinometer for --tilt exact, too few
    // distinct angles) is bad input.
    let an = an.map_err(|e| Fail(format!("{}: {e}", a.recording), 2))?;
    if let Some(p) = &a.plot {
        plot::write(p, &fit_panels(&an))?;
    }
    // The text goes to standard output, or into the report beside the JSON.
    let mut out: Vec<u8> = Vec::new();
    let f = &an.fit;
    let g = &an.gls;
    writeln!(
        out,
        "recording      {} ({} positions, latitude {} deg)",
        a.recording,
        rec.rows.len(),
        an.latitude_deg
    )?;
    if let Some(why) = g.unresolved(an.amplitude_predicted_dph) {
        writeln!(
            out,
            "NOT RESOLVED   the Earth rate is not resolved: {why}; no azimuth can be given"
        )?;
        writeln!(
            out,
            "               (the fit's numbers, not an azimuth: psi {:.3} deg +- {:.3} deg)",
            g.psi_deg, g.sigma_psi_deg
        )?;
    } else {
        writeln!(
            out,
            "azimuth psi    {} deg  (Eq. 7: rate = WE cos(lat) cos(gamma + psi))",
            angle5(g.psi_deg)
        )?;
        writeln!(
            out,
            "surveying az.  {} deg  (clockwise from true north, of the gamma = 0 direction)",
            angle5(surveying_azimuth_deg(g.psi_deg))
        )?;
        writeln!(
            out,
            "sigma          {:.2} arcsec  (1 sigma, generalised least squares under the noise model{}{})",
            g.sigma_psi_deg * 3600.0,
            widened(g.widening),
            match an.sigma_inclinometer_deg * 3600.0 {
                s if s >= 0.005 => format!(", with {s:.2} arcsec from the tilt circle's uncertainty"),
                _ => String::new(),
            }
        )?;
    }
    let m = &g.model;
    writeln!(out, "noise model    {}", g.source.describe())?;
    writeln!(
        out,
        "               N {:.3e} deg/sqrt(h) (a {:.3} s dwell mean: {:.5} deg/h), {}; chi2 {:.1} on {} dof",
        m.arw_deg_rth,
        g.dwell_s,
        m.white_mean_sd_dph(g.dwell_s),
        colour_text(m),
        g.chi2,
        g.dof
    )?;
    if matches!(g.source, NoiseSource::Estimated { .. }) {
        writeln!(out, "               {STATIC_LOG_HINT}")?;
    }
    if let Some(s) = &g.shocks {
        writeln!(
            out,
            "shocks         {} of {} dwells read as struck (a share of {:.2}, a shift of sd {:.5} deg/h; lines {}): each dwell weighed by how likely a shock struck it",
            s.struck.len(),
            an.fit.n,
            s.share,
            s.shift_dph,
            lines_text(&s.struck)
        )?;
    }
    if f.dof == 0 {
        writeln!(
            out,
            "white LS       psi {:.5} deg (no sigma from the residuals: as many positions as unknowns leave none)",
            f.psi_deg
        )?;
    } else {
        writeln!(
            out,
            "white LS       psi {:.5} deg +- {:.2} arcsec (sigma from the residuals, {} dof: too small when the noise is coloured)",
            f.psi_deg,
            f.sigma_psi_deg * 3600.0,
            f.dof
        )?;
    }
    writeln!(
        out,
        "amplitude      {:.5} +- {:.5} deg/h  (latitude predicts {:.5}: scale factor {:.5})",
        g.amplitude_dph,
        g.sigma_amplitude_dph,
        an.amplitude_predicted_dph,
        g.amplitude_dph / an.amplitude_predicted_dph
    )?;
    if f.dof == 0 {
        writeln!(out, "bias (offset)  {:.5} deg/h", f.offset_dph)?;
        writeln!(out, "residuals      none: the fit passes through every position")?;
    } else {
        writeln!(
            out,
            "bias (offset)  {:.5} +- {:.5} deg/h",
            f.offset_dph, f.sigma_offset_dph
        )?;
        writeln!(
            out,
            "residuals      RSS {:.6e} (deg/h)^2, rms {:.5} deg/h",
            f.rss, an.sigma_gyro_dph
        )?;
    }
    match (an.method, an.shaft) {
        (TiltMethod::Exact, Some(s)) => writeln!(
            out,
            "tilt           corrected with the exact model, iterated to convergence: shaft tilt {:.4} deg towards {:.1} deg (the inclinometer's {} on {} positions)",
            s.tilt_deg,
            s.tilt_dir_deg,
            match (s.offset_x_deg.is_finite(), s.offset_y_deg.is_finite()) {
                (true, true) => "X and Y",
                (true, false) => "X alone",
                _ => "Y alone",
            },
            rec.rows.len() - an.tilt_bridged
        )?,
        (TiltMethod::FirstOrder, shaft) => {
            writeln!(out, "tilt           corrected per position from tilt_x (first order)")?;
            if let Some(s) = shaft.filter(|s| s.tilt_deg > FIRST_ORDER_MAX_DEG) {
                writeln!(
                    out,
                    "               WARNING: the shaft is tilted {:.2} deg; first order leaves an error of the order of the tilt squared, tens of sigma at a few degrees: --tilt exact",
                    s.tilt_deg
                )?
            }
        }
        _ => writeln!(
            out,
            "tilt           not corrected (no inclinometer columns, or --tilt none)"
        )?,
    }
    if let Some(w) = &an.tilt_warning {
        writeln!(out, "               WARNING: {w}")?;
    }
    if an.tilt_bridged > 0 {
        writeln!(
            out,
            "tilt           {} positions without an inclinometer reading: corrected from the tilt circle of the others",
            an.tilt_bridged
        )?;
    }
    for w in &an.wild {
        let what = if w.held_out {
            "off the fit of the others: held out of this fit (a glitch or a fill value; `nf diagnose` tests it as an outlier)"
        } else {
            "off the fit: kept, as more than a tenth of the dwells lie this far off, which is the data (a model the fit lacks, heavy tails), not glitches, or the rest would leave the fit no degree of freedom"
        };
        writeln!(
            out,
            "far off        line {} (index {}): rate_dph {} lies {:.0} robust sigmas {what}",
            w.line, w.index, w.rate_dph, w.sigmas
        )?;
    }
    let (d1, d2) = f.drift();
    if opt.drift != Drift::None {
        writeln!(out, "drift          {d1:.3e} deg/h/s, {d2:.3e} deg/h/s^2")?;
    }
    for (name, b) in [("Eq. 31 (paper)", &an.budget_paper), ("exact model", &an.budget_exact)] {
        writeln!(
            out,
            "{name:<14} total {:.2}\" = gyro {:.2}\" (+) encoder {:.2}\" (+) tilt {:.2}\"",
            b.total_arcsec, b.gyro_arcsec, b.encoder_arcsec, b.tilt_arcsec
        )?;
    }
    if let Some(path) = &a.report {
        let headline = match g.unresolved(an.amplitude_predicted_dph) {
            Some(why) => format!("Earth rate not resolved: {why}"),
            None => format!(
                "azimuth psi {:.5} deg +- {:.2} arcsec (1 sigma, {})",
                g.psi_deg,
                g.sigma_psi_deg * 3600.0,
                g.source.describe()
            ),
        };
        let page = Page {
            title: &format!("nf fit: {}", a.recording),
            headline: &headline,
            text: &String::from_utf8_lossy(&out),
            svgs: &[plot::render_svg(&fit_panels(&an))],
            notes: &[],
        };
        page.write(path)?;
    }
    let mut stdout = std::io::stdout().lock();
    if a.json {
        writeln!(
            stdout,
            "{}",
            serde_json::to_string_pretty(&json::fit_json(&an)).unwrap_or_default()
        )?;
    } else {
        stdout.write_all(&out)?;
    }
    Ok(())
}

fn fit_panels(an: &Analysis) -> Vec<Panel> {
    // A held-out glitch would set the axes' range and flatten every other dwell.
    let held: Vec<usize> = an.wild.iter().filter(|w| w.held_out).map(|w| w.row).collect();
    let drawn = || {
        an.points
            .iter()
            .enumerate()
            .filter(|(i, _)| !held.contains(i))
            .map(|(_, p)| p)
    };
    let not_drawn = match held.len() {
        0 => String::new(),
        k => format!(" ({k} far-off dwell(s) held out, not drawn)"),
    };
    let curve: Vec<(f64, f64)> = (0..=360)
        .map(|g| {
            let g = g as f64;
            (g, an.fit.predict(g, an.fit.t0_s, None))
        })
        .collect();
    let mut panels = vec![Panel {
        title: match an.gls.unresolved(an.amplitude_predicted_dph) {
            Some(_) => format!("gyro output: the Earth rate is NOT RESOLVED, no azimuth{not_drawn}"),
            None => format!(
                "gyro output and its least-squares fit, psi = {:.4} deg{not_drawn}",
                an.fit.psi_deg
            ),
        },
        x_label: "encoder angle gamma (deg)".into(),
        y_label: "rate (deg/h)".into(),
        series: vec![
            Series {
                name: "measured".into(),
                points: drawn().map(|p| (p[0], p[2])).collect(),
                style: Style::Points,
            },
            Series {
                name: "fitted A cos + B sin + C".into(),
                points: curve,
                style: Style::Line,
            },
        ],
        log_x: false,
        log_y: false,
    }];
    // As many positions as unknowns leave no residual: rounding's would be drawn.
    if an.fit.dof > 0 {
        panels.push(Panel {
            title: format!("residuals, RSS = {:.3e} (deg/h)^2{not_drawn}", an.fit.rss),
            x_label: "encoder angle gamma (deg)".into(),
            y_label: "residual (deg/h)".into(),
            series: vec![Series {
                name: "residual".into(),
                points: drawn().map(|p| (p[0], p[4])).collect(),
                style: Style::Points,
            }],
            log_x: false,
            log_y: false,
        });
    }
    panels
}

/// What the gyro's sigma holds beyond GLS under the printed model alone, when it is more.
fn widened(widening: f64) -> String {
    if widening < 1.005 {
        return String::new();
    }
    format!(", widened {widening:.2} times for the noise models this run cannot rule out")
}
