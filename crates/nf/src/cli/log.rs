//! `nf log`: a firmware defmt log back into a recording.

use super::{Fail, note, write_out};
use crate::logparse;
use crate::recording::Recording;

#[derive(clap::Args)]
pub struct LogArgs {
    /// The log file ('-' for standard input).
    log: String,
    /// Output file (default: standard output).
    #[arg(long, short)]
    out: Option<String>,
}

pub fn cmd_log(a: LogArgs) -> Result<(), Fail> {
    let text = if a.log == "-" {
        std::io::read_to_string(std::io::stdin()).map_err(|e| Fail(format!("cannot read standard input: {e}"), 2))?
    } else {
        std::fs::read_to_string(&a.log).map_err(|e| Fail(format!("cannot read {}: {e}", a.log), 2))?
    };
    let lines = logparse::extract(&text);
    if lines.is_empty() {
        return Err(Fail(
            format!("{}: no 'rec' lines: is this the firmware's defmt log?", a.log),
            1,
        ));
    }
    let out: String = lines.iter().map(|l| format!("{l}\n")).collect();
    // Check it as any reader would; a log cut short still gives the positions it holds.
    let rec =
        Recording::parse(&out).map_err(|e| Fail(format!("{} (recording extracted from the log): {e}", a.log), 1))?;
    write_out(&a.out, &out)?;
    note!("{} positions recovered from {}", rec.rows.len(), a.log);
    Ok(())
}
