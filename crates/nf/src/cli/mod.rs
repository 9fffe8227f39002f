//! The command line: `nf simulate | fit | plan | paper | log | diagnose | allan`, one file each.

mod adc_budget;
mod allan;
mod diagnose;
mod diagnose_sim;
mod fit;
mod json;
mod log;
mod noise_args;
mod paper;
mod plan;
mod simulate;
mod spinner;
mod suite_keep;

use crate::recording::Recording;
use allan::{AllanArgs, cmd_allan};
use clap::{Parser, Subcommand};
use diagnose::{DiagnoseArgs, cmd_diagnose};
use fit::{FitArgs, cmd_fit};
use log::{LogArgs, cmd_log};
use paper::{PaperArgs, cmd_paper};
use plan::{PlanArgs, cmd_plan};
use simulate::{SimArgs, cmd_simulate};
use std::io::Write;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "nf",
    version,
    about = "North finder host tool: simulate, fit, plan, reproduce the paper, read firmware logs"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Write a recording from the digital twin (the firmware's run logic on a simulated instrument).
    Simulate(SimArgs),
    /// Fit a recording: azimuth, amplitude, bias, residuals and uncertainty.
    Fit(FitArgs),
    /// Plan a run: uncertainty budget, n and dwell for a target, time to north, Monte Carlo check.
    Plan(PlanArgs),
    /// Reproduce the paper's numbers and list where it disagrees with itself or the physics.
    Paper(PaperArgs),
    /// Turn a firmware defmt log (probe-rs or defmt-print output) into a recording.
    Log(LogArgs),
    /// Find the physics a recording has and the simulation left out; `--evaluate` runs the test suite.
    Diagnose(DiagnoseArgs),
    /// Noise of a static gyro log: overlapping Allan deviation with intervals, and the fitted IEEE terms (N, B, K).
    Allan(AllanArgs),
}

/// A line on standard error. Unlike `eprintln!` it does not panic when standard error is
/// closed: a lost message is no reason to fail.
macro_rules! note {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($t)*);
    }};
}
pub(crate) use note;

/// An angle in [0, 360) to five decimals as a reader expects it: never "-0.00000", and 0 where
/// it would round up to "360.00000".
pub(crate) fn angle5(deg: f64) -> String {
    match format!("{:.5}", deg + 0.0).as_str() {
        "360.00000" | "-0.00000" => "0.00000".into(),
        s => s.into(),
    }
}

/// A `--plot` file name: SVG or PNG by its ending, checked before any work.
fn plot_file(name: &str) -> Result<String, String> {
    let lower = name.to_ascii_lowercase();
    if lower.ends_with(".svg") || lower.ends_with(".png") {
        Ok(name.to_string())
    } else {
        Err(format!("{name}: name the plot *.svg or *.png"))
    }
}

/// A failure to report: the message and the exit code. Code 0 is not a failure: the reader of
/// standard output closed it (`nf paper | head`), so the command stops and exits quietly.
pub(crate) struct Fail(pub String, pub u8);

impl From<String> for Fail {
    fn from(s: String) -> Self {
        Fail(s, 1)
    }
}

/// Errors of writing standard output; write with `writeln!(out, ...)?` rather than `println!`,
/// which panics on a closed pipe.
impl From<std::io::Error> for Fail {
    fn from(e: std::io::Error) -> Self {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            Fail(String::new(), 0)
        } else {
            Fail(format!("cannot write to standard output: {e}"), 1)
        }
    }
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let r = match cli.cmd {
        Cmd::Simulate(a) => cmd_simulate(a),
        Cmd::Fit(a) => cmd_fit(a),
        Cmd::Plan(a) => cmd_plan(a),
        Cmd::Paper(a) => cmd_paper(a),
        Cmd::Log(a) => cmd_log(a),
        Cmd::Diagnose(a) => cmd_diagnose(a),
        Cmd::Allan(a) => cmd_allan(a),
    };
    // What is still buffered meets a closed pipe here, not in the exit's silent flush.
    let r = r.and_then(|()| Ok(std::io::stdout().flush()?));
    match r {
        Ok(()) | Err(Fail(_, 0)) => ExitCode::SUCCESS,
        Err(Fail(msg, code)) => {
            note!("nf: {msg}");
            ExitCode::from(code)
        }
    }
}

/// Reads a recording: a bad one is an error naming the line (exit code 2); what the reader
/// accepted with a warning goes to standard error.
/// A recording's warnings printed one by one, at most: a writer's systematic fault would
/// repeat one on every line.
const WARNINGS_SHOWN: usize = 10;

pub(crate) fn read_recording(path: &str) -> Result<Recording, Fail> {
    let rec = Recording::read(path).map_err(|e| Fail(e.at(path), 2))?;
    for w in rec.warnings.iter().take(WARNINGS_SHOWN) {
        note!("nf: warning: {}", w.at(path));
    }
    if let Some(more) = rec.warnings.len().checked_sub(WARNINGS_SHOWN).filter(|m| *m > 0) {
        note!("nf: warning: {path}: {more} more warnings like these");
    }
    Ok(rec)
}

/// Refuses, before any work, output paths whose folders do not exist (bad input, exit 2).
pub(crate) fn folders_exist(paths: &[&Option<String>]) -> Result<(), Fail> {
    paths.iter().filter_map(|p| p.as_deref()).try_for_each(folder_exists)
}

/// Refuses, before any work, an output path whose folder does not exist or that names a
/// folder itself.
fn folder_exists(path: &str) -> Result<(), Fail> {
    match crate::out_path::unwritable(path) {
        Some(why) => Err(Fail(format!("cannot write {path}: {why}"), 2)),
        None => Ok(()),
    }
}

pub(crate) fn write_out(out: &Option<String>, text: &str) -> Result<(), Fail> {
    match out {
        Some(p) => std::fs::write(p, text).map_err(|e| Fail(format!("cannot write {p}: {e}"), 1)),
        None => Ok(std::io::stdout().lock().write_all(text.as_bytes())?),
    }
}
