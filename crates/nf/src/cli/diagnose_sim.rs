//! The `--sim` part of `nf diagnose`: the simulation's missing physics, the mismatch before
//! and after the fix, as text, JSON and plots.

use crate::plot::{Panel, Series, Style};
use crate::sim_compare::{Comparison, Quantity, Residuals, SimReport, Verdict, Where};
use serde_json::{Value, json};
use std::io::Write;

fn comparison_json(c: &Comparison) -> Value {
    json!({
        "replays": c.replays,
        "mismatches": c.mismatches(),
        "quantities": c.lines.iter().map(|l| json!({
            "quantity": l.quantity.to_string(), "recording": l.recording, "simulated": l.simulated,
            "simulated_sd": l.simulated_sd, "z": l.z, "p": l.p, "mismatch": l.mismatch,
        })).collect::<Vec<_>>(),
    })
}

fn where_json(w: &Where) -> Value {
    json!({
        "beyond": w.beyond,
        "largest": w.largest.iter().map(|d| json!({
            "index": d.index, "gamma_deg": d.gamma_deg, "t_s": d.t_s,
            "difference_dph": d.difference_dph, "z": d.z, "significant": d.significant,
        })).collect::<Vec<_>>(),
    })
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

pub fn json(s: &SimReport) -> Value {
    json!({
        "dwell_s": s.dwell_s,
        "physics": s.physics.iter().map(|p| json!({
            "effect": p.kind.name(), "verdict": format!("{:?}", p.verdict),
            "parameter": p.parameter.name, "recording": p.parameter.value, "sigma": p.parameter.sigma,
            "simulated": p.simulated,
        })).collect::<Vec<_>>(),
        "before": comparison_json(&s.before),
        "after": comparison_json(&s.fixed.after),
        "positions_before": where_json(&s.places),
        "positions_after": where_json(&s.fixed.places),
        "changes": s.fixed.changes,
    })
}

pub fn text(out: &mut impl Write, s: &SimReport) -> std::io::Result<()> {
    writeln!(
        out,
        "\nagainst the simulation (replayed under the recording's plan, dwell {:.3} s):",
        s.dwell_s
    )?;
    let lacking: Vec<_> = s.physics.iter().filter(|p| p.verdict != Verdict::Modelled).collect();
    if lacking.is_empty() {
        writeln!(out, "  the simulation has every effect the recording shows")?;
    }
    for p in &s.physics {
        let sigma = p.parameter.sigma.map_or(String::new(), |v| format!(" +- {v:.4e}"));
        writeln!(
            out,
            "  {}: {} ({} = {:.4e}{sigma} in the recording, {:.4e} in the simulation)",
            p.kind.name(),
            p.verdict,
            p.parameter.name,
            p.parameter.value,
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
    writeln!(
        out,
        "  mismatches: {} before, {} after the fix",
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
            title: "Allan deviation of the residuals in time order".into(),
            x_label: "positions averaged".into(),
            y_label: "Allan deviation (deg/h)".into(),
            series: vec![
                series("recording", allan(&s.before, true), Style::Line),
                series("simulation (mean of replays)", allan(&s.before, false), Style::Line),
                series("after the fix", allan(&s.fixed.after, false), Style::Line),
            ],
            log_x: true,
            log_y: true,
        },
    ]
}
