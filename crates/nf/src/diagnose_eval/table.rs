//! The suite's results as a text table and as JSON.

use super::{Evaluation, Tally};
use crate::diagnose::Kind;
use serde::Serialize;
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

/// The suite's results as JSON: rates that do not apply (no clean recordings in a row, say) are
/// null. The fields of each struct are in alphabetical order, the order the keys have always had.
#[derive(Serialize)]
pub struct EvaluationJson<'a> {
    /// Family-wise false-alarm rate of each selection step.
    alpha: f64,
    /// One entry per category of the suite.
    categories: Vec<CategoryJson<'a>>,
}

/// A category of the suite: its rows and their total.
#[derive(Serialize)]
struct CategoryJson<'a> {
    /// What the category tests.
    about: &'static str,
    /// The category's name.
    name: &'static str,
    /// One entry per row.
    rows: Vec<RowJson<'a>>,
    /// The rows together.
    total: TallyJson,
}

/// A row of a category.
#[derive(Serialize)]
struct RowJson<'a> {
    /// The row's counts and rates.
    results: TallyJson,
    /// The row's label.
    row: &'a str,
}

/// Counts and rates over the recordings of a row or a category; rates are fractions (0 to 1).
#[derive(Serialize)]
struct TallyJson {
    /// Final azimuths off by more than 3 of their own reported sigma.
    beyond_3_reported_sigma: u32,
    /// Share of the clean recordings with an effect named; null without clean recordings.
    false_alarm_rate: Option<f64>,
    /// Share of the recordings with an effect whose first named effect is concealed in them;
    /// null without such recordings.
    named_first_rate: Option<f64>,
    /// How often each effect was named on a clean recording, by name.
    named_on_clean: BTreeMap<&'static str, u32>,
    /// How often each noise term was named, by name.
    noise_terms_named: BTreeMap<&'static str, u32>,
    /// Recordings the diagnosis gave no outcome for (not in `runs`).
    refused: u32,
    /// RMS azimuth error of the baseline against the twin's truth, arcsec; null without runs.
    rms_error_baseline_arcsec: Option<f64>,
    /// RMS azimuth error of the final azimuth against the twin's truth, arcsec; null without
    /// runs.
    rms_error_final_arcsec: Option<f64>,
    /// RMS of the final azimuth's error over its reported sigma (1 where the sigmas hold);
    /// null without runs.
    rms_z_final: Option<f64>,
    /// Recordings diagnosed.
    runs: u32,
    /// Share of the concealed effects that were named; null without concealed effects.
    set_recall: Option<f64>,
    /// Final azimuths worse than the baseline's by more than 3 baseline sigma.
    worse_than_baseline_3sigma: u32,
}

fn counts_json(named: &BTreeMap<Kind, u32>) -> BTreeMap<&'static str, u32> {
    named.iter().map(|(n, &k)| (n.name(), k)).collect()
}

fn tally_json(t: &Tally) -> TallyJson {
    TallyJson {
        beyond_3_reported_sigma: t.beyond_3_sigma,
        false_alarm_rate: t.false_alarm_rate(),
        named_first_rate: t.named_first_rate(),
        named_on_clean: counts_json(&t.false_named),
        noise_terms_named: counts_json(&t.noise_named),
        refused: t.refused,
        rms_error_baseline_arcsec: t.rms_baseline(),
        rms_error_final_arcsec: t.rms_final(),
        rms_z_final: t.rms_z_final(),
        runs: t.runs,
        set_recall: t.recall(),
        worse_than_baseline_3sigma: t.worse_than_baseline,
    }
}

/// The suite's results as JSON.
pub fn json(ev: &Evaluation, alpha: f64) -> EvaluationJson<'_> {
    let categories = ev
        .categories
        .iter()
        .map(|c| CategoryJson {
            about: c.about,
            name: c.name,
            rows: c
                .rows
                .iter()
                .map(|r| RowJson {
                    results: tally_json(&r.tally),
                    row: &r.label,
                })
                .collect(),
            total: tally_json(&c.total),
        })
        .collect();
    EvaluationJson { alpha, categories }
}
