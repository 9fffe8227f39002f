//! `nf log`: a firmware defmt log back into a recording.

use super::{Fail, note, write_out};
use crate::logparse;
use crate::recording::{IndexGap, Recording, Row, index_gaps};
use nf_model::order::Order;
use std::io::Read;

#[derive(clap::Args)]
pub struct LogArgs {
    /// The log file ('-' for standard input).
    log: String,
    /// Output file (default: standard output).
    #[arg(long, short)]
    out: Option<String>,
    /// Write the recording even when positions are missing from the log (a lost `rec` line);
    /// without it that is an error.
    #[arg(long)]
    allow_gaps: bool,
    /// The run to take from a log that holds several (from 1, in the log's order); without it
    /// such a log is listed.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    run: Option<u32>,
}

/// One line per run: where it starts, its positions and its metadata.
fn list(runs: &[logparse::Log]) -> String {
    runs.iter()
        .enumerate()
        .map(|(i, r)| {
            let at = r.rec.first().map_or(0, |l| l.0);
            let meta: Vec<String> = ["started", "positions", "latitude_deg", "order"]
                .iter()
                .filter_map(|k| Some(format!("{k} {}", r.meta(k)?)))
                .collect();
            format!(
                "  run {}: from log line {at}, {} position lines{}{}",
                i + 1,
                r.positions(),
                if meta.is_empty() { "" } else { "; " },
                meta.join(", ")
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn describe(g: &IndexGap) -> String {
    let which = if g.first == g.last {
        format!("index {}", g.first)
    } else {
        format!("indices {} to {}", g.first, g.last)
    };
    match g.after_line {
        Some(a) => format!("{which} (between log lines {a} and {})", g.before_line),
        None => format!("{which} (before log line {})", g.before_line),
    }
}

pub fn cmd_log(a: LogArgs) -> Result<(), Fail> {
    super::folders_exist(&[&a.out])?;
    let mut bytes = Vec::new();
    if a.log == "-" {
        std::io::stdin()
            .read_to_end(&mut bytes)
            .map_err(|e| Fail(format!("cannot read standard input: {e}"), 2))?;
    } else {
        bytes = std::fs::read(&a.log).map_err(|e| Fail(format!("cannot read {}: {e}", a.log), 2))?;
    }
    let mut runs = logparse::extract(&bytes).runs();
    let count = runs.len();
    // A run followed by another in the log whose end it lacks was cut (a reset, a new START).
    let (log, cut) = match a.run {
        Some(k) if k as usize <= count => (runs.swap_remove(k as usize - 1), (k as usize) < count),
        Some(k) => {
            return Err(Fail(
                format!(
                    "{}: --run {k}, but the log holds {count} run(s):\n{}",
                    a.log,
                    list(&runs)
                ),
                2,
            ));
        }
        None if count > 1 => {
            return Err(Fail(
                format!(
                    "{}: the log holds {count} runs; pick one with --run N:\n{}",
                    a.log,
                    list(&runs)
                ),
                2,
            ));
        }
        None => (runs.swap_remove(0), false),
    };
    for w in &log.warnings {
        note!("nf: warning: {}", w.at(&a.log));
    }
    if let Some(e) = log
        .ends
        .iter()
        .find(|e| e.kept == Some(0))
        .filter(|_| log.rec.is_empty())
    {
        return Err(Fail(
            format!("{}:{}: the run recorded nothing: {}", a.log, e.line, e.text),
            2,
        ));
    }
    if log.rec.is_empty() {
        return Err(Fail(
            format!("{}: no 'rec' lines: is this the firmware's defmt log?", a.log),
            2,
        ));
    }
    // Check it as any reader would, with the log's line numbers; a log cut short still gives
    // the positions it holds.
    let rec = Recording::parse(&log.on_log_lines()).map_err(|e| Fail(e.at(&a.log), 2))?;
    for w in &rec.warnings {
        note!("nf: warning: {}", w.at(&a.log));
    }
    // The reader's warnings above name each gap; without --allow-gaps they are an error.
    let gaps = index_gaps(&rec.rows);
    if !gaps.is_empty() && !a.allow_gaps {
        let list: Vec<String> = gaps.iter().map(describe).collect();
        return Err(Fail(
            format!(
                "{}: positions missing from the log (a lost 'rec' line?): {}; --allow-gaps writes the recording without them",
                a.log,
                list.join(", ")
            ),
            2,
        ));
    }
    ends_as_logged(&a.log, &log, &rec.rows, (a.allow_gaps, cut))?;
    let lines: Vec<usize> = rec.rows.iter().map(|r| r.line).collect();
    write_out(&a.out, &log.written(&lines))?;
    note!("{} positions recovered from {}", rec.rows.len(), a.log);
    Ok(())
}

/// The positions against the count the run's end gives (`result: ..., n 72`): lines lost at
/// the end of a run leave no gap in the indices, and a line beyond the count is not the
/// firmware's. A run that stopped early, or whose end the log does not hold, is said so.
fn ends_as_logged(path: &str, log: &logparse::Log, rows: &[Row], (allow_gaps, cut): (bool, bool)) -> Result<(), Fail> {
    for e in log.ends.iter().filter(|e| e.early()) {
        note!("nf: note: {path}:{}: the run stopped early: {}", e.line, e.text);
    }
    let Some((kept, end)) = log.kept() else {
        let why = match cut {
            true => "the next run in the log begins before this one's end (a reset or a new START cut it)",
            false => "the log ends before the run does",
        };
        note!("nf: note: {path}: {why} (no 'result:' or 'run ended:' line): the positions it holds are written");
        return beyond_the_order(path, log, rows);
    };
    if let Some(r) = rows.iter().find(|r| r.index as usize >= kept) {
        return Err(Fail(
            format!(
                "{path}:{}: index {} is beyond the {kept} positions the firmware recorded ({path}:{}: {})",
                r.line, r.index, end.line, end.text
            ),
            2,
        ));
    }
    let next = rows.iter().map(|r| r.index as usize + 1).max().unwrap_or(0);
    if next < kept {
        let which = if next + 1 == kept {
            format!("index {next}")
        } else {
            format!("indices {next} to {}", kept - 1)
        };
        let what = format!(
            "{path}:{}: the firmware recorded {kept} positions, the log lacks {which} (lost 'rec' lines?)",
            end.line
        );
        if !allow_gaps {
            return Err(Fail(
                format!("{what}; --allow-gaps writes the recording without them"),
                2,
            ));
        }
        note!("nf: warning: {what}");
    }
    Ok(())
}

/// Without the run's end, the visits its metadata make (`positions` and a named `order`) bound
/// the indices: a line beyond them is not the firmware's.
fn beyond_the_order(path: &str, log: &logparse::Log, rows: &[Row]) -> Result<(), Fail> {
    let n: Option<u16> = log.meta("positions").and_then(|n| n.parse().ok());
    let order = log.meta("order").and_then(|o| Order::parse(o).ok());
    let (n, o) = match (n, order) {
        (Some(n), Some(o)) if !matches!(o, Order::List(_)) => (n, o),
        _ => return Ok(()),
    };
    let visits = o.visits(n) as usize;
    match rows.iter().find(|r| r.index as usize >= visits) {
        Some(r) => Err(Fail(
            format!(
                "{path}:{}: index {} is beyond the {visits} visits of the run's {n} positions in {} order",
                r.line,
                r.index,
                o.name()
            ),
            2,
        )),
        None => Ok(()),
    }
}
