//! The suite's results as a text table and as JSON.

use super::{Evaluation, Tally};
use crate::diagnose::Kind;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::fmt::Write;

const LEGEND: &str = "\
named first: recordings with a concealed effect whose first named effect is one of them
recall: concealed effects named (both of a pair); false alarms: clean recordings with any effect named
rms: azimuth error against the twin's truth, arcsec, of the baseline and of the final azimuth
worse: final error larger than the baseline's by 3 baseline sigma; beyond: final error over 3 reported sigma
";

fn percent(rate: Option<f64>) -> String {
    rate.map_or("-".into(), |r| format!("{:.0}%", 100.0 * r))
}

fn arcsec(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.1}\""))
}

fn line(out: &mut String, label: &str, t: &Tally) {
    let _ = writeln!(
        out,
        "  {label:<42} {:>5} {:>6} {:>6} {:>6} {:>9} {:>9} {:>6} {:>6}",
        t.runs,
        percent(t.named_first_rate()),
        percent(t.recall()),
        percent(t.false_alarm_rate()),
        arcsec(t.rms_baseline()),
        arcsec(t.rms_final()),
        t.worse_than_baseline,
        t.beyond_3_sigma
    );
}

/// A line of how often each name was given, if any was.
fn counts(out: &mut String, what: &str, named: &BTreeMap<Kind, u32>) {
    if !named.is_empty() {
        let list: Vec<String> = named.iter().map(|(n, k)| format!("{n} x{k}")).collect();
        let _ = writeln!(out, "  {what}: {}", list.join(", "));
    }
}

/// The table: a group per category, a line per row and one for the category's total.
pub fn text(ev: &Evaluation, alpha: f64) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "  {:<42} {:>5} {:>6} {:>6} {:>6} {:>9} {:>9} {:>6} {:>6}",
        "row", "runs", "named", "recall", "false", "rms", "rms", "worse", "beyond"
    );
    let _ = writeln!(
        out,
        "  {:<42} {:>5} {:>6} {:>6} {:>6} {:>9} {:>9} {:>6} {:>6}",
        "", "", "first", "", "alarms", "baseline", "final", "3 sd", "3 sd"
    );
    for c in &ev.categories {
        let _ = write!(out, "{}: {}", c.name, c.about);
        if c.total.refused > 0 {
            let _ = write!(out, " ({} recordings refused)", c.total.refused);
        }
        out.push('\n');
        for r in &c.rows {
            line(&mut out, &r.label, &r.tally);
        }
        line(&mut out, "all", &c.total);
        counts(&mut out, "named on clean recordings", &c.total.false_named);
        counts(&mut out, "noise terms named", &c.total.noise_named);
    }
    let _ = write!(out, "alpha {alpha} per selection step\n{LEGEND}");
    out
}

fn counts_json(named: &BTreeMap<Kind, u32>) -> Value {
    named
        .iter()
        .map(|(n, k)| (n.name().to_string(), json!(k)))
        .collect::<serde_json::Map<_, _>>()
        .into()
}

fn tally_json(t: &Tally) -> Value {
    json!({
        "runs": t.runs,
        "refused": t.refused,
        "named_first_rate": t.named_first_rate(),
        "set_recall": t.recall(),
        "false_alarm_rate": t.false_alarm_rate(),
        "rms_error_baseline_arcsec": t.rms_baseline(),
        "rms_error_final_arcsec": t.rms_final(),
        "worse_than_baseline_3sigma": t.worse_than_baseline,
        "beyond_3_reported_sigma": t.beyond_3_sigma,
        "noise_terms_named": counts_json(&t.noise_named),
        "named_on_clean": counts_json(&t.false_named),
    })
}

/// The same as JSON: rates that do not apply (no clean recordings in a row, say) are null.
pub fn json(ev: &Evaluation, alpha: f64) -> Value {
    let categories: Vec<Value> = ev
        .categories
        .iter()
        .map(|c| {
            let rows: Vec<Value> = c
                .rows
                .iter()
                .map(|r| json!({"row": r.label, "results": tally_json(&r.tally)}))
                .collect();
            json!({"name": c.name, "about": c.about, "total": tally_json(&c.total), "rows": rows})
        })
        .collect();
    json!({"alpha": alpha, "categories": categories})
}
