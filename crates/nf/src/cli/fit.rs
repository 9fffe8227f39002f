//! `nf fit`: azimuth, amplitude, bias, residuals and uncertainty of a recording.

use super::noise_args::NoiseArgs;
use super::spinner::spinning;
use super::{Fail, read_recording};
use crate::analysis::{Analysis, Options, TiltMethod, analyse};
use crate::noise_calib;
use crate::noise_fit::NoiseChoice;
use crate::plot;
use crate::plot::{Panel, Series, Style};
use crate::range::real;
use crate::recording::Recording;
use crate::report::Page;
use clap::ValueEnum;
use nf_model::fit::Drift;
use std::io::Write;

mod json;
mod text;

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
    super::folders_exist(&[&a.plot, &a.report])?;
    let rec = read_recording(&a.recording)?;
    let opt = options(&a)?;
    check_positions(&a, &rec, &opt).map_err(|e| Fail(format!("{}: {e}", a.recording), 2))?;
    let n = rec.rows.len();
    let message = match a.replicates {
        0 => format!("fitting {n} positions"),
        r => format!("fitting {n} positions and {r} bootstrap replicates (--replicates 0 skips them)"),
    };
    // What the recording cannot give (no inclinometer for --tilt exact, too few distinct
    // angles) is bad input.
    let an = spinning(message, || analyse(&rec, &opt)).map_err(|e| Fail(format!("{}: {e}", a.recording), 2))?;
    if let Some(p) = &a.plot {
        plot::write(p, &fit_panels(&an))?;
    }
    // The text goes to standard output, or into the report beside the JSON.
    let mut out: Vec<u8> = Vec::new();
    text::write(&mut out, &a.recording, n, &an, opt.drift)?;
    if let Some(path) = &a.report {
        write_report(path, &a.recording, &an, &out)?;
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

/// The fit's options from the command line.
fn options(a: &FitArgs) -> Result<Options, Fail> {
    Ok(Options {
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
            NoiseChoice::Given(a.noise.given()?, a.noise.describe())
        } else {
            NoiseChoice::Estimate
        },
        replicates: usize::from(a.replicates),
        ..Options::default()
    })
}

/// Too few positions, or a shaft that did not turn, is bad input, like a malformed line.
/// The noise needs a residual degree of freedom unless it is given or the dwells' insides
/// (quarter means, samples' spread) show it.
fn check_positions(a: &FitArgs, rec: &Recording, opt: &Options) -> Result<(), String> {
    let within = a.noise.any()
        || rec.rows.iter().any(|r| r.quarters_dph.is_some())
        || !crate::sample_spread::of_rows(rec.rows.iter().map(|r| (r, 1.0)), || 0).is_empty(); // any dwell: only whether one exists
    rec.require_turning()?;
    let terms = opt.fit_config().terms().unwrap_or(3);
    if within {
        rec.require_positions(terms, "this fit (one for each unknown)")
    } else {
        rec.require_positions(
            terms + 1,
            "this fit without quarter means, samples' spread or a given noise model (its unknowns and one degree of freedom for the noise)",
        )
    }
}

/// The HTML report: the headline, the text output and the plots.
fn write_report(path: &str, recording: &str, an: &Analysis, text: &[u8]) -> Result<(), Fail> {
    let g = &an.gls;
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
        title: &format!("nf fit: {recording}"),
        headline: &headline,
        text: &String::from_utf8_lossy(text),
        svgs: &[plot::render_svg(&fit_panels(an))],
        notes: &[],
    };
    page.write(path)?;
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
    // The curve is the fit at the run's start: each dwell is drawn as the curve plus its
    // residual, so the tilt and drift the fit removed are removed from what is drawn too.
    let at_start = |g: f64| an.fit.predict(g, an.fit.t0_s, None);
    let curve: Vec<(f64, f64)> = (0..=360).map(|g| (g as f64, at_start(g as f64))).collect();
    let cfg = &an.fit.cfg;
    let removed: Vec<&str> = [
        (an.corrections.iter().any(|c| *c != 0.0), "tilt"),
        (cfg.drift != Drift::None, "drift"),
    ]
    .iter()
    .filter_map(|(on, what)| on.then_some(*what))
    .collect();
    let measured = match removed.as_slice() {
        [] => "measured".to_string(),
        r => format!("measured, fitted {} removed", r.join(" and ")),
    };
    let model = match cfg.harmonics {
        1 => "A cos + B sin + C".to_string(),
        2 => "A cos + B sin + C + harmonic 2".to_string(),
        h => format!("A cos + B sin + C + harmonics 2..{h}"),
    };
    let mut panels = vec![Panel {
        title: match an.gls.unresolved(an.amplitude_predicted_dph) {
            Some(_) => format!("gyro output: the Earth rate is NOT RESOLVED, no azimuth{not_drawn}"),
            None => format!(
                "gyro output; least-squares psi {:.4} deg, the result (noise model) {:.4} deg{not_drawn}",
                an.fit.psi_deg, an.gls.psi_deg
            ),
        },
        x_label: "encoder angle gamma (deg)".into(),
        y_label: "rate (deg/h)".into(),
        series: vec![
            Series {
                name: measured,
                points: drawn().map(|p| (p[0], at_start(p[0]) + p[4])).collect(),
                style: Style::Points,
            },
            Series {
                name: format!("least-squares fit {model}"),
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
            // The zero line over the whole turn keeps this panel's angle axis the one above.
            series: vec![
                Series {
                    name: "residual".into(),
                    points: drawn().map(|p| (p[0], p[4])).collect(),
                    style: Style::Points,
                },
                Series {
                    name: "zero".into(),
                    points: vec![(0.0, 0.0), (360.0, 0.0)],
                    style: Style::Line,
                },
            ],
            log_x: false,
            log_y: false,
        });
    }
    panels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plot_draws_each_dwell_off_the_curve_by_its_residual_with_the_tilt_and_drift_removed() {
        // 36 positions, a shaft tilted 1 deg towards 40 deg (what the inclinometer reads), a
        // drift, and a little noise: the raw rates are far off the level curve.
        let mut rng = nf_model::rng::Rng::new(5);
        let mut text = String::from("# format = northfinder-recording/1\n# latitude_deg = 60\n");
        text.push_str("index,t_s,encoder_deg,rate_dph,tilt_x_deg,tilt_y_deg\n");
        for k in 0..36 {
            let g = k as f64 * 10.0;
            let (x, y) = (-(g - 40f64).to_radians().cos(), (g - 40f64).to_radians().sin());
            let t = 3.0 * k as f64;
            let rate = 7.5 * (g + 30.0).to_radians().cos() + 0.3 + 0.002 * t + 0.003 * rng.gauss();
            text.push_str(&format!("{k},{t},{g},{rate},{x},{y}\n"));
        }
        let rec = Recording::parse(&text).unwrap();
        let opt = Options {
            drift: Drift::Linear,
            replicates: 0,
            ..Options::default()
        };
        let an = analyse(&rec, &opt).unwrap();
        let panels = fit_panels(&an);
        let (measured, curve) = (&panels[0].series[0].points, &panels[0].series[1].points);
        let residuals = &panels[1].series[0].points;
        assert!(panels[0].series[0].name.contains("tilt and drift removed"));
        for ((g, m), (g2, r)) in measured.iter().zip(residuals) {
            let on_curve = curve[*g as usize];
            assert_eq!((on_curve.0, *g2), (*g, *g));
            assert!((m - on_curve.1 - r).abs() < 1e-9, "gamma {g}: {m} {} {r}", on_curve.1);
            assert!(r.abs() < 0.02, "gamma {g}: residual {r}");
        }
    }
}
