//! `nf diagnose`: the physics a recording has that the model left out, and the evaluation suite.

use super::noise_args::{NoiseArgs, STATIC_LOG_HINT, colour_text};
use super::spinner::spinning;
use super::suite_keep::Keeper;
use super::{Fail, angle5, diagnose_sim, read_recording, write_out};
use crate::diagnose::{Diagnosis, Kind, Options, Point, diagnose};
use crate::diagnose_eval::{self, EvalOptions};
use crate::instrument_file::InstrumentFile;
use crate::noise_calib;
use crate::noise_est::THINNED;
use crate::noise_fit::NoiseChoice;
use crate::plot::{self, Panel, Series, Style};
use crate::range::above;
use crate::recording::Recording;
use crate::report::Page;
use crate::sim_compare;
use std::io::Write;
use std::path::Path;

mod json;

#[derive(clap::Args)]
pub struct DiagnoseArgs {
    /// The recording (not needed with --evaluate).
    recording: Option<String>,
    /// Family-wise false-alarm rate of each selection step.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.05, value_parser = above(0.0, 0.5))]
    alpha: f64,
    /// Bootstrap replicates that calibrate the final sigma and the baseline's under a noise
    /// model estimated from the recording, up to 2000 positions (0: none; each costs one more
    /// noise estimate).
    #[arg(long, allow_hyphen_values = true, default_value_t = noise_calib::REPLICATES, value_parser = clap::value_parser!(u16).range(0..=1000))]
    replicates: u16,
    #[arg(long)]
    json: bool,
    /// Plot the residuals before and after (*.svg or *.png).
    #[arg(long, value_parser = super::plot_file)]
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
    /// The gyro's noise model; without one it is estimated from the recording.
    #[command(flatten)]
    noise: NoiseArgs,
    /// The instrument file the recording was meant to match (docs/instrument-file.md): it is
    /// replayed under the recording's plan and compared, and the physics it lacks is named.
    #[arg(long, conflicts_with = "evaluate")]
    sim: Option<String>,
    /// Write the instrument file of --sim with what the recording showed put in.
    #[arg(long, requires = "sim")]
    fix: Option<String>,
    /// Replays of the simulation per comparison.
    #[arg(long, allow_hyphen_values = true, default_value_t = 20, value_parser = clap::value_parser!(u32).range(3..=1000))]
    replays: u32,
    /// Write each suite recording the diagnosis missed (a false alarm, a final worse than the
    /// baseline or beyond 3 sigma) into this directory, its truth in the metadata.
    #[arg(long, requires = "evaluate")]
    keep: Option<String>,
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
    super::folders_exist(&[&a.plot, &a.report, &a.fix])?;
    let rec = read_recording(path)?;
    let file = match &a.sim {
        Some(p) => Some(InstrumentFile::read(p).map_err(|e| Fail(e, 2))?),
        None => None,
    };
    let opt = Options {
        alpha: a.alpha,
        noise: if a.noise.any() {
            NoiseChoice::Given(a.noise.given()?, a.noise.describe())
        } else {
            NoiseChoice::Estimate
        },
        replicates: usize::from(a.replicates),
    };
    // Too few positions, or a shaft that did not turn, is bad input, like a malformed line.
    rec.require_turning()
        .and_then(|_| rec.require_positions(crate::diagnose::MIN_POSITIONS, "diagnosing"))
        .map_err(|e| Fail(format!("{path}: {e}"), 2))?;
    let n = rec.rows.len();
    let replicated = opt.noise == NoiseChoice::Estimate && a.replicates > 0 && n <= THINNED;
    let message = if replicated {
        format!(
            "diagnosing {n} positions and up to {} bootstrap replicates (--replicates 0 skips them)",
            a.replicates
        )
    } else {
        format!("diagnosing {n} positions")
    };
    let d = spinning(message, || diagnose(&rec, &opt));
    let d = d.map_err(|e| Fail(format!("{path}: {e}"), 2))?;
    let sim = match &file {
        Some(f) => {
            let so = sim_compare::Options {
                replays: a.replays as usize,
                alpha: a.alpha,
                diagnose: opt.clone(),
            };
            let s = sim_compare::against(&rec, &d, f, &so).map_err(|e| Fail(format!("{path}: {e}"), 2))?;
            for w in &s.warnings {
                super::note!("nf: warning: {w}");
            }
            Some(s)
        }
        None => None,
    };
    if let (Some(out), Some(s)) = (&a.fix, &sim) {
        let head = [format!(
            "nf diagnose --fix: {} with what {path} showed",
            a.sim.as_deref().unwrap_or_default()
        )];
        let notes: Vec<String> = head.into_iter().chain(s.fixed.changes.iter().cloned()).collect();
        write_out(&Some(out.clone()), &s.fixed.file.write(&notes))?;
    }
    let mut panels = diagnose_panels(&d);
    if let Some(s) = &sim {
        panels.extend(diagnose_sim::panels(s));
    }
    if let Some(p) = &a.plot {
        plot::write(p, &panels)?;
    }
    let mut out = std::io::stdout().lock();
    if a.json {
        writeln!(
            out,
            "{}",
            serde_json::to_string_pretty(&json::diagnosis_json(&d, sim.as_ref())).unwrap_or_default()
        )?;
        if a.report.is_none() {
            return Ok(());
        }
    }
    // The text goes to standard output, or into the report beside the JSON.
    let mut text: Vec<u8> = Vec::new();
    write_text(&mut text, &d)?;
    if let Some(s) = &sim {
        diagnose_sim::text(&mut text, s)?;
    }
    if let Some(report) = &a.report {
        let names: Vec<&str> = d.findings.iter().map(|f| f.effect.name()).collect();
        let result = match &d.unresolved {
            Some(why) => format!("Earth rate not resolved: {why}"),
            None => format!(
                "final psi {} deg +- {:.2}\"",
                angle5(d.final_.azimuth_deg),
                d.final_.sigma_arcsec
            ),
        };
        let mut headline = format!(
            "{result}; findings: {}",
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            }
        );
        if let Some(s) = &sim {
            let change: Vec<&str> = s
                .physics
                .iter()
                .filter(|p| p.verdict.needs_change())
                .map(|p| p.kind.name())
                .collect();
            headline += &format!(
                "; against the simulation: {}; {} quantities apart before the fix, {} after",
                if change.is_empty() {
                    "nothing it lacks".to_string()
                } else {
                    format!("to change {}", change.join(", "))
                },
                s.before.mismatches(),
                s.fixed.after.mismatches()
            );
        }
        let page = Page {
            title: &format!("nf diagnose: {path}"),
            headline: &headline,
            text: &String::from_utf8_lossy(&text),
            svgs: &[plot::render_svg(&panels)],
            notes: &d.notes,
        };
        page.write(report)?;
    }
    if !a.json {
        out.write_all(&text)?;
    }
    Ok(())
}

/// Residuals before and after, against the angle and against time, with the fitted effects.
fn diagnose_panels(d: &Diagnosis) -> Vec<Panel> {
    let pick = |x: fn(&Point) -> f64, y: fn(&Point) -> f64| -> Vec<(f64, f64)> {
        let mut v: Vec<(f64, f64)> = d.points.iter().map(|p| (x(p), y(p))).collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    let struck: Vec<&Point> = d.points.iter().filter(|p| p.struck).collect();
    let panel = |title: &str, x_label: &str, x: fn(&Point) -> f64| Panel {
        title: title.into(),
        x_label: x_label.into(),
        y_label: "residual (deg/h)".into(),
        series: [
            Series {
                name: "before: Eq. 7 by least squares".into(),
                points: pick(x, |p| p.before),
                style: Style::Points,
            },
            Series {
                name: "after: less the findings".into(),
                points: pick(x, |p| p.after),
                style: Style::Points,
            },
            Series {
                name: "the findings as fitted".into(),
                points: unbroken_in_time(&d.points, x),
                style: Style::Line,
            },
        ]
        .into_iter()
        // Over the dwells' `after` dots, which show round them as rings.
        .chain((!struck.is_empty()).then(|| Series {
            name: "after, read as struck by a shock (weighed down)".into(),
            points: struck.iter().map(|p| (x(p), p.after)).collect(),
            style: Style::Points,
        }))
        .collect(),
        log_x: false,
        log_y: false,
    };
    let not_resolved = match d.unresolved {
        Some(_) => " (the Earth rate is NOT RESOLVED, no azimuth)",
        None => "",
    };
    vec![
        panel(
            &format!("residuals against the encoder angle{not_resolved}"),
            "encoder angle gamma (deg)",
            |p| p.gamma_deg,
        ),
        panel("residuals against time", "time (s)", |p| p.t_s),
    ]
}

/// The findings as fitted, by `x`, the line broken (by a point that cannot be drawn) between
/// positions not visited one after the other: an effect of time drawn against the angle
/// would otherwise jump across the plot where the visits do (the first position of a sweep,
/// read at 359.998 deg, joined to the last).
fn unbroken_in_time(points: &[Point], x: fn(&Point) -> f64) -> Vec<(f64, f64)> {
    let mut by_time: Vec<usize> = (0..points.len()).collect();
    by_time.sort_by(|&a, &b| points[a].t_s.total_cmp(&points[b].t_s));
    let mut rank = vec![0; points.len()];
    for (r, &i) in by_time.iter().enumerate() {
        rank[i] = r;
    }
    let mut by_x: Vec<usize> = (0..points.len()).collect();
    by_x.sort_by(|&a, &b| x(&points[a]).total_cmp(&x(&points[b])));
    let mut line = Vec::with_capacity(2 * by_x.len());
    for (k, &i) in by_x.iter().enumerate() {
        if k > 0 && rank[i].abs_diff(rank[by_x[k - 1]]) != 1 {
            line.push((f64::NAN, f64::NAN));
        }
        line.push((x(&points[i]), points[i].fitted));
    }
    line
}

fn write_text(out: &mut impl Write, d: &Diagnosis) -> std::io::Result<()> {
    let b = d.baseline;
    writeln!(out, "noise model: {}", d.noise_source)?;
    let m = &d.noise_model;
    writeln!(out, "     N {:.3e} deg/sqrt(h), {}", m.arw_deg_rth, colour_text(m))?;
    if d.noise_estimated {
        writeln!(out, "     {STATIC_LOG_HINT}")?;
    }
    let (c, r) = (&d.cautious_model, &d.drift_model);
    if d.noise_estimated {
        writeln!(
            out,
            "     encoder harmonics and the slow amplitude and 2 psi harmonic judged under the most coloured plausible model: {}",
            colour_text(c)
        )?;
        writeln!(
            out,
            "     drift, jump and temperature judged under the model estimated with a drift: {}",
            colour_text(r)
        )?;
    } else {
        writeln!(out, "     every effect judged under the given model")?;
    }
    if d.noise_with_effects != d.noise_model {
        let how = match d.through_shocks {
            true => "beside the shocks, with the final model's columns",
            false => "with the named effects in the design",
        };
        writeln!(
            out,
            "     {how} (the noise terms below are its): N {:.3e} deg/sqrt(h), {}",
            d.noise_with_effects.arw_deg_rth,
            colour_text(&d.noise_with_effects)
        )?;
    }
    if let Some(from) = &d.final_sigma_from {
        writeln!(out, "     the final sigma {from}")?;
    }
    if d.wander_tested {
        writeln!(
            out,
            "     drift, jump, temperature, encoder harmonics and the 2 psi harmonic also with the noise re-estimated with and without each (named only when both tests agree)"
        )?;
    }
    writeln!(
        out,
        "baseline (Eq. 7, level ideal instrument): psi {} deg +- {:.2}\"",
        angle5(b.azimuth_deg),
        b.sigma_arcsec
    )?;
    if d.findings.iter().all(|f| f.effect.is_noise()) {
        let agrees = match d.undecided.as_slice() {
            [] => "the recording agrees with the model".to_string(),
            held => format!(
                "{}: found by {} but not named, as the run's own wander explains the recording as well (notes)",
                held.iter().map(|u| u.effect.name()).collect::<Vec<_>>().join(", "),
                if held.len() == 1 {
                    "its own test"
                } else {
                    "their own tests"
                }
            ),
        };
        let noise = if d.findings.is_empty() {
            ""
        } else {
            "; below, the gyro's noise as measured (not effects)"
        };
        writeln!(
            out,
            "no effect is significant (family-wise false-alarm rate {} per step): {agrees}{noise}",
            d.alpha
        )?;
    }
    for (i, f) in d.findings.iter().enumerate() {
        writeln!(
            out,
            "{}. {} (p = {:.2e}): {}",
            i + 1,
            f.effect.name(),
            f.p_value,
            f.location
        )?;
        for p in &f.parameters {
            match p.sigma {
                Some(s) => writeln!(out, "     {} = {:.6} +- {:.6}", p.name, p.value, s)?,
                None => writeln!(out, "     {} = {:.6}", p.name, p.value)?,
            }
        }
        // Structure left unexplained changes no fit: a "with it" would read as a model's.
        if !f.effect.is_noise() && f.effect != Kind::Unexplained {
            writeln!(
                out,
                "     with it: psi {} deg +- {:.2}\" ({:+.2}\" from the baseline)",
                angle5(f.after.azimuth_deg),
                f.after.sigma_arcsec,
                nf_model::angle::wrap_180(f.after.azimuth_deg - b.azimuth_deg) * 3600.0
            )?;
        }
    }
    let (s, fz) = (d.selected, d.final_);
    writeln!(
        out,
        "selected model: psi {} deg +- {:.2}\"",
        angle5(s.azimuth_deg),
        s.sigma_arcsec
    )?;
    match &d.unresolved {
        Some(why) => writeln!(
            out,
            "final: NOT RESOLVED: {why}; no azimuth can be given (the fit's numbers, not an azimuth: psi {} deg +- {:.2}\")",
            angle5(fz.azimuth_deg),
            fz.sigma_arcsec
        )?,
        None => writeln!(
            out,
            "final: psi {} deg +- {:.2}\" (the models met, averaged by their weights and {})",
            angle5(fz.azimuth_deg),
            fz.sigma_arcsec,
            match (d.through_shocks, d.residual_dof) {
                (true, _) => "fitted through the shocks".to_string(),
                (false, Some(dof)) => format!(
                    "each white at its residual level, its sigma widened by Student's t ({dof} dof at the most likely) so that 95 % of errors lie within 1.96 sigma"
                ),
                (false, None) => {
                    "refitted under every noise model the recording allows: the sigma holds the wander one run cannot rule out".to_string()
                }
            }
        )?,
    }
    for n in &d.notes {
        writeln!(out, "note: {n}")?;
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
    let opt = Options {
        alpha: a.alpha,
        replicates: usize::from(a.replicates),
        ..Options::default()
    };
    let diag = |rec: &Recording| diagnose(rec, &opt).ok().map(|d| diagnose_eval::outcome_of(&d));
    let mut keeper = match &a.keep {
        Some(dir) => Some(Keeper::new(Path::new(dir)).map_err(|e| Fail(e, 2))?),
        None => None,
    };
    let ev = diagnose_eval::evaluate(&opts, &diag, &mut |s| {
        bar.inc(1);
        if let Some(k) = keeper.as_mut() {
            k.see(s);
        }
    });
    bar.finish_and_clear();
    if let Some(k) = keeper {
        if let Some(e) = k.failed {
            return Err(Fail(e, 1));
        }
        eprintln!(
            "kept {} missed recordings in {}",
            k.kept,
            a.keep.as_deref().unwrap_or_default()
        );
    }
    let mut out = std::io::stdout().lock();
    if a.json {
        let j = diagnose_eval::json(&ev, a.alpha);
        writeln!(out, "{}", serde_json::to_string_pretty(&j).unwrap_or_default())?;
    } else {
        write!(out, "{}", diagnose_eval::text(&ev, a.alpha))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn visits(gammas: &[f64]) -> Vec<Point> {
        gammas
            .iter()
            .enumerate()
            .map(|(i, &g)| Point {
                t_s: 2.5 * i as f64,
                gamma_deg: g,
                before: 0.0,
                after: 0.0,
                fitted: i as f64,
                struck: false,
            })
            .collect()
    }

    fn breaks(line: &[(f64, f64)]) -> usize {
        line.iter().filter(|p| p.0.is_nan()).count()
    }

    #[test]
    fn an_effect_of_time_against_the_angle_breaks_where_the_visits_jump() {
        // A sweep whose first position reads 359.998 deg: one break, before it.
        let sweep = visits(&[359.998, 90.0, 180.0, 270.0]);
        let line = unbroken_in_time(&sweep, |p| p.gamma_deg);
        assert_eq!(breaks(&line), 1);
        assert_eq!(line.last(), Some(&(359.998, 0.0)));
        // Opposite pairs: of the neighbours in angle only 180 and 90 deg were visited one
        // after the other.
        let pairs = visits(&[0.0, 180.0, 90.0, 270.0]);
        assert_eq!(breaks(&unbroken_in_time(&pairs, |p| p.gamma_deg)), 2);
        // Against time, never.
        assert_eq!(breaks(&unbroken_in_time(&pairs, |p| p.t_s)), 0);
    }
}
