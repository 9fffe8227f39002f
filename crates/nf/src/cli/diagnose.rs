//! `nf diagnose`: the physics a recording has that the model left out, and the evaluation suite.

use super::{Fail, read_recording};
use crate::diagnose::diagnose;
use crate::diagnose_eval::{self, EvalOptions, NOISE_TERMS, Outcome};
use crate::plot::{self, Panel, Series, Style};
use crate::range::above;
use crate::recording::Recording;
use crate::report::Page;
use serde_json::{Value, json};
use std::io::Write;

#[derive(clap::Args)]
pub struct DiagnoseArgs {
    /// The recording (not needed with --evaluate).
    recording: Option<String>,
    /// Family-wise false-alarm rate of each selection step.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.05, value_parser = above(0.0, 0.5))]
    alpha: f64,
    #[arg(long)]
    json: bool,
    /// Plot the residuals before and after (*.svg or *.png).
    #[arg(long)]
    plot: Option<String>,
    /// Write a self-contained HTML report: the findings, the output, the residual plots.
    #[arg(long)]
    report: Option<String>,
    /// Run the suite of twin recordings with concealed effects and print the rates.
    #[arg(long)]
    evaluate: bool,
    /// Recordings per effect row of the suite.
    #[arg(long, allow_hyphen_values = true, default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    seeds: u32,
    /// Clean recordings per clean row of the suite (each noise kind, visiting order, high latitudes).
    #[arg(long, allow_hyphen_values = true, default_value_t = 200, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    clean: u32,
    /// Run one category of the suite only.
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(diagnose_eval::category_names()))]
    category: Option<String>,
}

pub fn cmd_diagnose(a: DiagnoseArgs) -> Result<(), Fail> {
    if a.evaluate {
        return diagnose_evaluate(&a);
    }
    let path = a
        .recording
        .as_deref()
        .ok_or_else(|| Fail("give a recording, or --evaluate".into(), 2))?;
    let rec = read_recording(path)?;
    let d = diagnose(&rec, a.alpha).map_err(|e| Fail(format!("{path}: {e}"), 1))?;
    let panel = |title: &str, pts: &[(f64, f64)]| Panel {
        title: title.into(),
        x_label: "encoder angle gamma (deg)".into(),
        y_label: "residual (deg/h)".into(),
        series: vec![Series {
            name: "residual".into(),
            points: pts.to_vec(),
            style: Style::Points,
        }],
        log_x: false,
        log_y: false,
    };
    let panels = [
        panel("residuals of Eq. 7 (before)", &d.residuals_before),
        panel("residuals with the findings modelled (after)", &d.residuals_after),
    ];
    if let Some(p) = &a.plot {
        plot::write(p, &panels)?;
    }
    let mut out = std::io::stdout().lock();
    if a.json {
        let f: Vec<Value> = d
            .findings
            .iter()
            .map(|f| {
                let params: serde_json::Map<String, Value> =
                    f.parameters.iter().map(|p| (p.name.clone(), json!({"value": p.value, "sigma": p.sigma}))).collect();
                json!({"effect": f.effect, "parameters": params, "p_value": f.p_value, "where": f.location,
                       "rss_after": f.rss_after, "azimuth_deg_after": f.azimuth_deg_after, "sigma_arcsec_after": f.sigma_arcsec_after})
            })
            .collect();
        let j = json!({
            "alpha": d.alpha,
            "baseline": {"azimuth_deg": d.baseline.azimuth_deg, "rss": d.baseline.rss, "sigma_arcsec": d.baseline.sigma_arcsec},
            "findings": f,
            "final": {"azimuth_deg": d.final_.azimuth_deg, "rss": d.final_.rss, "sigma_arcsec": d.final_.sigma_arcsec},
            "notes": d.notes,
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&j).unwrap_or_default())?;
        if a.report.is_none() {
            return Ok(());
        }
    }
    // The text goes to standard output, or into the report beside the JSON.
    let json = a.json;
    let stdout = out;
    let mut out: Vec<u8> = Vec::new();
    let b = d.baseline;
    writeln!(
        out,
        "baseline (Eq. 7, level ideal instrument): psi {:.5} deg +- {:.2}\", RSS {:.4e} (deg/h)^2",
        b.azimuth_deg, b.sigma_arcsec, b.rss
    )?;
    if d.findings.is_empty() {
        writeln!(
            out,
            "no effect is significant (family-wise false-alarm rate {} per step): the recording agrees with the model",
            d.alpha
        )?;
    }
    for (i, f) in d.findings.iter().enumerate() {
        writeln!(
            out,
            "{}. {} (p = {:.2e}), in {}",
            i + 1,
            f.effect,
            f.p_value,
            f.location
        )?;
        for p in &f.parameters {
            match p.sigma {
                Some(s) => writeln!(out, "     {} = {:.6} +- {:.6}", p.name, p.value, s)?,
                None => writeln!(out, "     {} = {:.6}", p.name, p.value)?,
            }
        }
        writeln!(
            out,
            "     with it: RSS {:.4e} (deg/h)^2, psi {:.5} deg +- {:.2}\" ({:+.2}\" from the baseline)",
            f.rss_after,
            f.azimuth_deg_after,
            f.sigma_arcsec_after,
            nf_model::angle::wrap_180(f.azimuth_deg_after - b.azimuth_deg) * 3600.0
        )?;
    }
    let fz = d.final_;
    writeln!(
        out,
        "final: psi {:.5} deg +- {:.2}\", RSS {:.4e} (deg/h)^2",
        fz.azimuth_deg, fz.sigma_arcsec, fz.rss
    )?;
    for n in &d.notes {
        writeln!(out, "note: {n}")?;
    }
    if let Some(report) = &a.report {
        let names: Vec<&str> = d.findings.iter().map(|f| f.effect).collect();
        let headline = format!(
            "final psi {:.5} deg +- {:.2}\"; findings: {}",
            fz.azimuth_deg,
            fz.sigma_arcsec,
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            }
        );
        let page = Page {
            title: &format!("nf diagnose: {path}"),
            headline: &headline,
            text: &String::from_utf8_lossy(&out),
            svgs: &[plot::render_svg(&panels)],
            notes: &d.notes,
        };
        page.write(report)?;
    }
    if !json {
        let mut stdout = stdout;
        stdout.write_all(&out)?;
    }
    Ok(())
}

fn diagnose_evaluate(a: &DiagnoseArgs) -> Result<(), Fail> {
    let opts = EvalOptions {
        seeds: a.seeds,
        clean: a.clean,
        category: a.category.clone(),
    };
    let bar = indicatif::ProgressBar::new(diagnose_eval::planned_runs(&opts));
    let ev = diagnose_eval::evaluate(&opts, &|rec| outcome(rec, a.alpha), &mut || bar.inc(1));
    bar.finish_and_clear();
    let mut out = std::io::stdout().lock();
    if a.json {
        let j = diagnose_eval::json(&ev, a.alpha);
        writeln!(out, "{}", serde_json::to_string_pretty(&j).unwrap_or_default())?;
    } else {
        write!(out, "{}", diagnose_eval::text(&ev, a.alpha))?;
    }
    Ok(())
}

/// Today's diagnosis as the suite sees it: its noise findings apart from its effects.
fn outcome(rec: &Recording, alpha: f64) -> Option<Outcome> {
    let d = diagnose(rec, alpha).ok()?;
    let (noise_terms, effects) = d
        .findings
        .iter()
        .map(|f| f.effect)
        .partition(|e| NOISE_TERMS.contains(e));
    Some(Outcome {
        effects,
        noise_terms,
        baseline_deg: d.baseline.azimuth_deg,
        baseline_sigma_arcsec: d.baseline.sigma_arcsec,
        final_deg: d.final_.azimuth_deg,
        final_sigma_arcsec: d.final_.sigma_arcsec,
    })
}
