//! The `--sim` part of `nf diagnose`: the simulation's missing physics, the mismatch before
//! and after the fix, as text, JSON and plots.

use crate::plot::{Panel, Series, Style};
use crate::sim_compare::{Comparison, Quantity, Residuals, SimReport, Verdict, Where};
use serde::Serialize;
use std::io::Write;

/// The `simulation` object of `nf diagnose --sim --json`: the physics the simulation lacks and
/// the mismatch before and after the fix. The fields of each struct are in alphabetical order,
/// the order the keys have always had.
#[derive(Serialize)]
pub struct SimJson<'a> {
    /// The comparison with the fixed instrument file.
    after: ComparisonJson,
    /// The comparison with the instrument file as given.
    before: ComparisonJson,
    /// What the fix changed in the instrument file.
    changes: &'a [String],
    /// Dwell of the recording's plan, s.
    dwell_s: f64,
    /// Whether the physics was judged under the instrument file's noise model, else under the
    /// recording's own estimate.
    judged_under_file_noise: bool,
    /// Each effect: in the recording, in the simulation, and the verdict.
    physics: Vec<PhysicsJson<'a>>,
    /// Where the recording departs from the fixed file's replays.
    positions_after: WhereJson,
    /// Where it departs from the replays of the file as given.
    positions_before: WhereJson,
    /// What to know before reading the comparison (a file made for another latitude).
    warnings: &'a [String],
}

/// Where the recording departs from the replays, position by position.
#[derive(Serialize)]
struct WhereJson {
    /// Positions beyond the Bonferroni bound.
    beyond: usize,
    /// The largest departures, largest first.
    largest: Vec<DepartureJson>,
}

/// One position's Eq. 7 residual against the replays'.
#[derive(Serialize)]
struct DepartureJson {
    /// Recording less the replays' mean, deg/h.
    difference_dph: f64,
    /// Encoder angle, deg.
    gamma_deg: f64,
    /// Visit number.
    index: u32,
    /// Beyond the Bonferroni bound.
    significant: bool,
    /// Time of the dwell's middle, s.
    t_s: f64,
    /// The difference in units of the prediction sd (dimensionless).
    z: f64,
}

fn where_json(w: &Where) -> WhereJson {
    WhereJson {
        beyond: w.beyond,
        largest: w
            .largest
            .iter()
            .map(|d| DepartureJson {
                difference_dph: d.difference_dph,
                gamma_deg: d.gamma_deg,
                index: d.index,
                significant: d.significant,
                t_s: d.t_s,
                z: d.z,
            })
            .collect(),
    }
}

fn where_text(out: &mut impl Write, label: &str, w: &Where) -> std::io::Result<()> {
    let list: Vec<String> = w
        .largest
        .iter()
        .map(|d| {
            format!(
                "index {} (gamma {:.3} deg, t {:.1} s) z {:+.1}{}",
                d.index,
                d.gamma_deg,
                d.t_s,
                d.z,
                if d.significant { "*" } else { "" }
            )
        })
        .collect();
    writeln!(
        out,
        "  positions {label}: {} beyond the bound; largest: {}",
        w.beyond,
        list.join("; ")
    )
}

/// One effect, in the recording and in the simulation.
#[derive(Serialize)]
struct PhysicsJson<'a> {
    /// The effect's name.
    effect: &'static str,
    /// The parameter compared; its unit is the one its name ends with.
    parameter: &'a str,
    /// The parameter's value in the recording; null where the recording does not name it.
    recording: Option<f64>,
    /// Its standard error in the recording; null where the fit gives none.
    sigma: Option<f64>,
    /// The parameter's value in the simulation.
    simulated: f64,
    /// Missing, Different, Modelled, OnlyInSimulation or Equivalent.
    verdict: String,
}

/// The recording against replays of the simulation.
#[derive(Serialize)]
struct ComparisonJson {
    /// Quantities beyond the Bonferroni bound.
    mismatches: usize,
    /// Each quantity compared.
    quantities: Vec<QuantityJson>,
    /// Replays of the simulation.
    replays: usize,
}

/// One quantity, in the quantity's own unit (the one its name ends with).
#[derive(Serialize)]
struct QuantityJson {
    /// Beyond the Bonferroni bound at the false-alarm rate.
    mismatch: bool,
    /// p-value of z (Student-t on the replays' degrees of freedom).
    p: f64,
    /// The quantity's name.
    quantity: String,
    /// Its value in the recording.
    recording: f64,
    /// Its mean over the replays.
    simulated: f64,
    /// Its spread over the replays.
    simulated_sd: f64,
    /// (recording - simulated) in units of the prediction sd (dimensionless).
    z: f64,
}

fn comparison_json(c: &Comparison) -> ComparisonJson {
    ComparisonJson {
        mismatches: c.mismatches(),
        quantities: c
            .lines
            .iter()
            .map(|l| QuantityJson {
                mismatch: l.mismatch,
                p: l.p,
                quantity: l.quantity.to_string(),
                recording: l.recording,
                simulated: l.simulated,
                simulated_sd: l.simulated_sd,
                z: l.z,
            })
            .collect(),
        replays: c.replays,
    }
}

pub fn json(s: &SimReport) -> SimJson<'_> {
    SimJson {
        after: comparison_json(&s.fixed.after),
        before: comparison_json(&s.before),
        changes: &s.fixed.changes,
        dwell_s: s.dwell_s,
        judged_under_file_noise: s.under_file_noise,
        physics: s
            .physics
            .iter()
            .map(|p| PhysicsJson {
                effect: p.kind.name(),
                parameter: &p.parameter.name,
                recording: (p.verdict != Verdict::OnlyInSimulation).then_some(p.parameter.value),
                sigma: p.parameter.sigma,
                simulated: p.simulated,
                verdict: format!("{:?}", p.verdict),
            })
            .collect(),
        positions_after: where_json(&s.fixed.places),
        positions_before: where_json(&s.places),
        warnings: &s.warnings,
    }
}

pub fn text(out: &mut impl Write, s: &SimReport) -> std::io::Result<()> {
    writeln!(
        out,
        "\nagainst the simulation (replayed under the recording's plan, dwell {:.3} s):",
        s.dwell_s
    )?;
    for w in &s.warnings {
        writeln!(out, "  warning: {w}")?;
    }
    if s.under_file_noise {
        writeln!(
            out,
            "  judged under the instrument file's noise model: what departs from the simulation as it is, its noise included (the recording's noise matches it, or what is found under it, put in, leaves fewer quantities departing; the diagnosis above is under the recording's own noise estimate)"
        )?;
    }
    let lacking: Vec<_> = s.physics.iter().filter(|p| p.verdict.needs_change()).collect();
    if lacking.is_empty() {
        let still = match s.before.mismatches() {
            0 => String::new(),
            1 => "; 1 quantity below still differs beyond the bound".into(),
            k => format!("; {k} quantities below still differ beyond the bound"),
        };
        writeln!(
            out,
            "  the simulation has every effect and noise term the recording's diagnosis names{still}"
        )?;
        if !still.is_empty() {
            writeln!(
                out,
                "  (a value the file has wrong, as the site's azimuth, physics the catalogue does not name, or wander one run cannot show)"
            )?;
        }
    }
    for p in &s.physics {
        let sigma = p.parameter.sigma.map_or(String::new(), |v| format!(" +- {v:.4e}"));
        let recording = match p.verdict {
            Verdict::OnlyInSimulation => "not named in the recording".to_string(),
            _ => format!("{:.4e}{sigma} in the recording", p.parameter.value),
        };
        writeln!(
            out,
            "  {}: {} ({} = {:.4e} in the simulation, {recording})",
            p.kind.name(),
            p.verdict,
            p.parameter.name,
            p.simulated
        )?;
    }
    writeln!(
        out,
        "  mismatch (z against {} replays; * beyond the Bonferroni bound at the false-alarm rate):",
        s.before.replays
    )?;
    writeln!(
        out,
        "    {:<26} {:>13} {:>13} {:>8} {:>13} {:>8}",
        "quantity", "recording", "simulation", "z", "after fix", "z"
    )?;
    for l in &s.before.lines {
        let after = s.fixed.after.line(l.quantity);
        let star = |m: bool| if m { "*" } else { " " };
        writeln!(
            out,
            "    {:<26} {:>13.5e} {:>13.5e} {:>7.1}{} {:>13} {:>8}",
            l.quantity.to_string(),
            l.recording,
            l.simulated,
            l.z,
            star(l.mismatch),
            after.map_or("-".into(), |a| format!("{:.5e}", a.simulated)),
            after.map_or("-".into(), |a| format!("{:.1}{}", a.z, star(a.mismatch))),
        )?;
    }
    let set: Vec<String> = s.fixed.set.iter().map(|q| q.to_string()).collect();
    let by_construction = if set.is_empty() {
        String::new()
    } else {
        format!(
            " ({} set to the recording's by the fix: those agree by construction)",
            set.join(", ")
        )
    };
    writeln!(
        out,
        "  mismatches: {} before, {} after the fix{by_construction}",
        s.before.mismatches(),
        s.fixed.after.mismatches()
    )?;
    where_text(out, "departing (Eq. 7 residual against the replays')", &s.places)?;
    where_text(out, "departing after the fix", &s.fixed.places)?;
    for c in &s.fixed.changes {
        writeln!(out, "  fix: {c}")?;
    }
    Ok(())
}

fn sorted(r: &Residuals) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = r.gamma_deg.iter().copied().zip(r.resid_dph.iter().copied()).collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v
}

/// Allan deviations of the residuals from a comparison: the recording's or the replays'.
fn allan(c: &Comparison, recording: bool) -> Vec<(f64, f64)> {
    c.lines
        .iter()
        .filter_map(|l| match l.quantity {
            Quantity::Allan(m) => Some((m as f64, if recording { l.recording } else { l.simulated })),
            _ => None,
        })
        .collect()
}

/// The replays' spread of those Allan deviations: a bar of one sd either side of their
/// mean at each averaging, shifted along x by `shift` so that two sets stand apart (its low
/// end kept above a tenth of the mean, for the log axis).
fn allan_spread(c: &Comparison, shift: f64) -> Vec<(f64, f64)> {
    c.lines
        .iter()
        .filter_map(|l| match l.quantity {
            Quantity::Allan(m) => Some((m as f64 * shift, l.simulated, l.simulated_sd)),
            _ => None,
        })
        .flat_map(|(x, mean, sd)| [(x, (mean - sd).max(mean / 10.0)), (x, mean + sd)])
        .collect()
}

pub fn panels(s: &SimReport) -> Vec<Panel> {
    let series = |name: &str, points, style| Series {
        name: name.into(),
        points,
        style,
    };
    vec![
        Panel {
            title: "Eq. 7 residuals: recording and simulation".into(),
            x_label: "encoder angle gamma (deg)".into(),
            y_label: "residual (deg/h)".into(),
            series: vec![
                series("recording", sorted(&s.recording), Style::Points),
                series("simulation", sorted(&s.simulation), Style::Points),
                series("simulation after the fix", sorted(&s.fixed.residuals), Style::Points),
            ],
            log_x: false,
            log_y: false,
        },
        Panel {
            title: "Allan deviation in time order of the residuals beyond harmonics 1-4".into(),
            x_label: "positions averaged".into(),
            y_label: "Allan deviation (deg/h)".into(),
            // The recording as points: after the fix the simulation's line should lie on it.
            series: vec![
                series("recording", allan(&s.before, true), Style::Points),
                series("simulation: replays' mean and sd", allan(&s.before, false), Style::Line),
                series("", allan_spread(&s.before, 0.97), Style::Spread),
                series("after the fix", allan(&s.fixed.after, false), Style::Line),
                series("", allan_spread(&s.fixed.after, 1.03), Style::Spread),
            ],
            log_x: true,
            log_y: true,
        },
    ]
}
