//! The main run's log read back by `nf log`, and the positions checked against what the run's
//! last line says it recorded: lines lost at the end of a run, a line the run never wrote, a
//! run stopped early, a log cut before the run's end.

use std::process::Command;

mod common;
use common::{nf, tmp};

/// The main run with `args`: its exit code, its log (standard error) and its recording.
fn main_run(name: &str, args: &[&str]) -> (i32, String, Option<String>) {
    let out = tmp(name);
    let _ = std::fs::remove_file(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_north-finder"))
        .args(args)
        .args(["--out", &out])
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        std::fs::read_to_string(&out).ok(),
    )
}

fn write(name: &str, text: &str) -> String {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The log without the `rec` line of position `index` (its data line starts `index,`).
fn without(log: &str, index: usize) -> String {
    let tag = format!(" rec {index},");
    log.lines()
        .filter(|l| !l.contains(&tag))
        .map(|l| format!("{l}\n"))
        .collect()
}

#[test]
fn the_main_run_s_log_gives_back_its_recording() {
    let (code, log, rec) = main_run("logged.csv", &["--positions", "12", "--dwell-ms", "200"]);
    assert_eq!(code, 0, "{log}");
    let path = write("main.log", &log);
    let back = tmp("main-back.csv");
    let (code, _, err) = nf(&["log", &path, "-o", &back]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(std::fs::read_to_string(&back).ok(), rec);
    assert!(!err.contains("note"), "{err}");
}

#[test]
fn lines_lost_at_the_end_of_a_run_are_missed_and_a_line_beyond_it_refused() {
    let (code, log, _) = main_run("ends.csv", &["--positions", "12", "--dwell-ms", "200"]);
    assert_eq!(code, 0, "{log}");
    // The last two positions' lines lost: no gap in the indices, but the result says 12.
    let lost = write("lost-end.log", &without(&without(&log, 11), 10));
    let (code, _, err) = nf(&["log", &lost]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("the firmware recorded 12 positions, the log lacks indices 10 to 11")
            && err.contains("--allow-gaps"),
        "{err}"
    );
    let (code, out, err) = nf(&["log", &lost, "--allow-gaps"]);
    assert!(
        code == 0 && err.contains("warning") && err.contains("10 positions recovered"),
        "{err}"
    );
    assert_eq!(out.lines().filter(|l| l.starts_with("9,")).count(), 1);
    // A position line after the last the run recorded: not the firmware's.
    let last = log.lines().find(|l| l.contains(" rec 11,")).unwrap();
    let (head, data) = last.split_once(" rec ").unwrap();
    let mut cells: Vec<String> = data.split(',').map(str::to_string).collect();
    cells[0] = "12".into();
    cells[1] = format!("{:.3}", cells[1].parse::<f64>().unwrap() + 1.0);
    let invented = log.replace(last, &format!("{last}\n{head} rec {}", cells.join(",")));
    let invented = write("invented.log", &invented);
    let (code, _, err) = nf(&["log", &invented]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("index 12 is beyond the 12 positions the firmware recorded"),
        "{err}"
    );
    // Cut before the run's end: the positions there are, said so.
    let cut: String = log
        .lines()
        .take_while(|l| !l.contains("result:"))
        .map(|l| format!("{l}\n"))
        .collect();
    let cut = write("cut.log", &cut);
    let (code, _, err) = nf(&["log", &cut]);
    assert!(code == 0 && err.contains("the log ends before the run does"), "{err}");
}

#[test]
fn a_run_stopped_at_its_target_is_said_to_have_stopped_early() {
    let (code, log, rec) = main_run(
        "early.csv",
        &["--positions", "72", "--dwell-ms", "1000", "--target-arcsec", "60"],
    );
    assert_eq!(code, 0, "{log}");
    let rows = rec
        .unwrap()
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
        .count();
    assert!(rows < 72, "{rows}");
    let path = write("early.log", &log);
    let (code, _, err) = nf(&["log", &path]);
    assert!(
        code == 0
            && err.contains("the run stopped early: target 60")
            && err.contains(&format!("{rows} positions recovered")),
        "{err}"
    );
}

#[test]
fn a_run_that_recorded_nothing_is_said_so() {
    // Refused at levelling: no recording line, the run's end says why.
    let (code, log, rec) = main_run("refused.csv", &["--positions", "12", "--tilt", "1"]);
    assert!(code == 1 && rec.is_none(), "{log}");
    let path = write("refused.log", &log);
    let (code, _, err) = nf(&["log", &path]);
    assert!(
        code == 2 && err.contains("the run recorded nothing: run ended:") && err.contains("0 positions kept"),
        "{err}"
    );
}

#[test]
fn a_log_cut_before_its_end_bounds_the_indices_by_the_order_and_says_what_cut_it() {
    let (code, log, _) = main_run("cut.csv", &["--positions", "12", "--dwell-ms", "200"]);
    assert_eq!(code, 0, "{log}");
    let head: String = log
        .lines()
        .take_while(|l| !l.contains("result:"))
        .map(|l| format!("{l}\n"))
        .collect();
    // A line the 12 positions of a sequential run never make, without the run's end.
    let last = head.lines().find(|l| l.contains(" rec 11,")).unwrap();
    let (before, cells) = last.split_once(" rec 11,").unwrap();
    let (t, rest) = cells.split_once(',').unwrap();
    let t: f64 = t.parse().unwrap();
    let extra = format!("{before} rec 12,{:.3},{rest}", t + 3.0);
    let (code, _, err) = nf(&["log", &write("beyond.log", &format!("{head}{extra}\n"))]);
    assert!(
        code == 2 && err.contains("index 12 is beyond the 12 visits of the run's 12 positions in sequential order"),
        "{err}"
    );
    // Cut by the next run: said so, not "the log ends".
    let (code, _, err) = nf(&["log", &write("cut-by-next.log", &format!("{head}{log}")), "--run", "1"]);
    assert!(
        code == 0 && err.contains("the next run in the log begins before this one's end"),
        "{err}"
    );
}

#[test]
fn a_refused_run_before_a_whole_one_is_not_read_as_its_end() {
    let (_, refused, _) = main_run("refused-first.csv", &["--positions", "12", "--tilt", "1"]);
    let (code, log, _) = main_run("whole.csv", &["--positions", "12", "--dwell-ms", "200"]);
    assert_eq!(code, 0, "{log}");
    let (code, _, err) = nf(&["log", &write("refused-then-whole.log", &format!("{refused}{log}"))]);
    assert!(
        code == 0 && !err.contains("stopped early") && err.contains("12 positions recovered"),
        "{err}"
    );
}
