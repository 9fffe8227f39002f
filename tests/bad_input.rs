//! Bad inputs to `nf` and to the main run: each gets a clear error naming what and where, exit
//! code 2, no panic and no NaN printed as a result; a closed standard output ends a command
//! quietly.

use nf_instrument::run::RunConfig;
use nf_model::noise::NoiseModel;
use nf_twin::{Recorder, StaticLog, TwinConfig, simulate};
use std::process::{Command, Stdio};

mod common;
use common::{nf, tmp};

/// A twin recording of `n` positions written to `name`.
fn recording(name: &str, n: &str) -> String {
    let path = tmp(name);
    let (code, _, err) = nf(&["simulate", "--n", n, "--dwell", "0.5", "-o", &path]);
    assert_eq!(code, 0, "{err}");
    path
}

/// `text` written to a file `name` of the tests' folder: its path.
fn write(name: &str, text: &str) -> String {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// `nf args` with standard output a pipe whose reader has already gone: every write fails
/// with EPIPE. Returns the exit code and standard error.
fn into_closed_pipe(args: &[&str]) -> (i32, String) {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let o = Command::new(env!("CARGO_BIN_EXE_nf"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(writer)
        .output()
        .unwrap();
    (o.status.code().unwrap_or(-1), String::from_utf8_lossy(&o.stderr).into())
}

#[test]
fn a_closed_standard_output_ends_every_subcommand_quietly() {
    let rec = recording("pipe.csv", "24");
    let log = tmp("pipe-static.csv");
    let noise = NoiseModel {
        arw_deg_rth: 0.002,
        ..NoiseModel::WHITE_NONE
    };
    let st = StaticLog {
        noise,
        rate_dph: 7.3,
        sample_rate_hz: 10.0,
        duration_s: 600.0,
        seed: 1,
    };
    st.write(&mut std::fs::File::create(&log).unwrap()).unwrap();
    let defmt = tmp("pipe.log");
    let text = std::fs::read_to_string(&rec).unwrap();
    std::fs::write(
        &defmt,
        text.lines().map(|l| format!("INFO  rec {l}\n")).collect::<String>(),
    )
    .unwrap();
    for args in [
        vec!["paper"],
        vec!["paper", "--json"],
        vec!["simulate", "--n", "8", "--dwell", "0.2"],
        vec!["plan", "--mc-runs", "0"],
        vec!["fit", &rec],
        vec!["fit", &rec, "--json"],
        vec!["diagnose", &rec],
        vec!["allan", &log],
        vec!["log", &defmt],
        vec!["--help"],
    ] {
        let (code, err) = into_closed_pipe(&args);
        assert_eq!(code, 0, "{args:?}: {err}");
        assert!(
            !err.contains("panicked") && !err.contains("Broken pipe"),
            "{args:?}: {err}"
        );
    }
}

/// `nf args` is refused with exit code 2 and a message naming `what`, without a panic.
fn refused(args: &[&str], what: &str) -> String {
    let (code, out, err) = nf(args);
    assert_eq!(code, 2, "{args:?}: {out}{err}");
    assert!(err.contains(what) && !err.contains("panicked"), "{args:?}: {err}");
    assert!(!out.contains("NaN"), "{args:?}: {out}");
    err
}

#[test]
fn every_numeric_option_has_a_checked_range() {
    let rec = recording("ranges.csv", "12");
    let r = rec.as_str();
    let cases: &[(&[&str], &str)] = &[
        (&["plan", "--gyro-noise", "nan"], "--gyro-noise"),
        (&["plan", "--tilt", "nan"], "--tilt"),
        (&["plan", "--n", "4294967295"], "--n"),
        (&["plan", "--ref-dwell", "inf"], "--ref-dwell"),
        (&["plan", "--encoder", "-1"], "--encoder"),
        (&["plan", "--lat", "90"], "--lat"),
        (&["plan", "--dwell", "0"], "--dwell"),
        (&["plan", "--settle", "nan"], "--settle"),
        (&["plan", "--max-sps", "1e300"], "--max-sps"),
        (&["plan", "--accel", "0"], "--accel"),
        (&["plan", "--steps-per-rev", "0"], "--steps-per-rev"),
        (&["plan", "--target", "-5"], "--target"),
        (&["plan", "--max-time", "inf"], "--max-time"),
        (&["plan", "--twin-runs", "4294967295"], "--twin-runs"),
        (&["plan", "--mc-runs", "99999999"], "--mc-runs"),
        (&["plan", "--arw", "nan"], "--arw"),
        (&["simulate", "--lat", "nan"], "--lat"),
        (&["simulate", "--psi", "inf"], "--psi"),
        (&["simulate", "--n", "100000"], "--n"),
        (&["simulate", "--target-arcsec", "0"], "--target-arcsec"),
        (&["simulate", "--dwell", "1e9"], "--dwell"),
        (&["simulate", "--bias", "nan"], "--bias"),
        (&["simulate", "--drift", "inf"], "--drift"),
        (&["simulate", "--tilt", "-1"], "--tilt"),
        (&["simulate", "--scale", "0"], "--scale"),
        (&["simulate", "--encoder-error", "nan"], "--encoder-error"),
        (&["simulate", "--temp", "1e6"], "--temp"),
        (&["simulate", "--incl-noise", "nan"], "--incl-noise"),
        (&["simulate", "--rrw", "-1"], "--rrw"),
        (&["simulate", "--student-t-dof", "1.5"], "--student-t-dof"),
        (&["simulate", "--gm-sigma", "0.1"], "--gm-tau"),
        (&["plan", "--gm-tau", "5"], "--gm-sigma"),
        // A model given to a fit without its white noise.
        (
            &["fit", r, "--bias-instability", "0.004"],
            "without --arw: a noise model given to the fit needs",
        ),
        (&["diagnose", r, "--rrw", "0.01"], "--rrw 0.01 without --arw"),
        (&["fit", r, "--sigma-encoder", "nan"], "--sigma-encoder"),
        (&["fit", r, "--sigma-tilt", "inf"], "--sigma-tilt"),
        (&["fit", r, "--harmonics", "9"], "--harmonics"),
        (&["fit", r, "--bias-instability", "nan"], "--bias-instability"),
        (&["diagnose", r, "--alpha", "nan"], "--alpha"),
        (&["diagnose", "--evaluate", "--seeds", "0"], "--seeds"),
        (&["diagnose", "--evaluate", "--clean", "4294967295"], "--clean"),
        (&["allan", r, "--sample-rate", "-10"], "--sample-rate"),
    ];
    for (args, option) in cases {
        let err = refused(args, option);
        assert!(
            err.contains("finite number")
                || err.contains(" is not in ")
                || err.contains("needs")
                || err.contains("0 (Gaussian)"),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn an_order_of_fewer_than_three_positions_or_four_visits_is_refused_before_the_run() {
    refused(
        &["simulate", "--n", "8", "--order", "0,4,0,4"],
        "fewer than 3 different positions listed",
    );
    refused(
        &["simulate", "--n", "8", "--order", "0,0,0"],
        "fewer than 3 different positions listed",
    );
    // Three visits: no residual, so no sigma; a named order's run has at least 4 positions.
    refused(
        &["simulate", "--n", "8", "--order", "0,4,1"],
        "fewer than 4 visits listed: the fit's 3 terms leave no residual for a sigma",
    );
    let (code, _, err) = nf(&["simulate", "--n", "8", "--order", "0,4,1,6"]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn the_main_run_checks_its_options() {
    let main_run = |args: &[&str]| {
        let out = tmp("main-run.csv");
        let o = Command::new(env!("CARGO_BIN_EXE_north-finder"))
            .args(args)
            .args(["--quiet", "--out", &out])
            .output()
            .unwrap();
        (
            o.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    for (args, option) in [
        (["--lat", "nan"], "--lat"),
        (["--lat", "95"], "--lat"),
        (["--lat", "-90"], "--lat"),
        (["--dwell-ms", "5000000"], "--dwell-ms"),
        (["--positions", "65536"], "--positions"),
        (["--psi", "inf"], "--psi"),
        (["--tilt", "nan"], "--tilt"),
        (["--target-arcsec", "-1"], "--target-arcsec"),
        (["--order", "spiral"], "--order"),
        (["--order", "0,36,0,36"], "fewer than 3 different positions listed"),
    ] {
        let (code, err) = main_run(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(option) && !err.contains("panicked"), "{args:?}: {err}");
    }
    // A closed standard output after a good run: quiet, status 0.
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let o = Command::new(env!("CARGO_BIN_EXE_north-finder"))
        .args([
            "--quiet",
            "--positions",
            "8",
            "--dwell-ms",
            "100",
            "--out",
            &tmp("piped.csv"),
        ])
        .stdout(writer)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && !err.contains("panicked"), "{err}");
}

/// A recording path that cannot be written is refused before the run (it ran its whole
/// course, then lost the result); `-` sends the recording to standard output and the summary
/// to standard error, and `nf fit -` reads it there.
#[test]
fn the_main_run_s_output_is_checked_first_and_may_be_piped() {
    let main_run = |out: &str| {
        Command::new(env!("CARGO_BIN_EXE_north-finder"))
            .args(["--quiet", "--positions", "8", "--dwell-ms", "100", "--out", out])
            .output()
            .unwrap()
    };
    let o = main_run("/nonexistent-folder/x.csv");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("the folder /nonexistent-folder does not exist") && o.stdout.is_empty(),
        "{err}"
    );
    let o = main_run("-");
    let (rec, err) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{err}");
    assert!(
        rec.starts_with("# format = northfinder-recording/1") && err.contains("recorded to standard output"),
        "{err}"
    );
    let mut fit = Command::new(env!("CARGO_BIN_EXE_nf"))
        .args(["fit", "-", "--json"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    std::io::Write::write_all(&mut fit.stdin.take().unwrap(), &o.stdout).unwrap();
    let fitted = fit.wait_with_output().unwrap();
    assert!(fitted.status.success());
    assert!(String::from_utf8_lossy(&fitted.stdout).contains("\"azimuth_deg\""));
}

#[test]
fn a_run_stopped_at_three_positions_reports_its_sigma_as_undefined() {
    let run = RunConfig {
        positions: 12,
        dwell_ms: 300,
        ..RunConfig::default()
    };
    let sigma_after = |k: usize| {
        let mut rec = Recorder {
            abort_after_records: Some(k),
            ..Default::default()
        };
        let (report, _) = simulate(&TwinConfig::default(), &run, &mut rec);
        let a = report.azimuth.unwrap();
        assert_eq!(a.n as usize, k);
        a.sigma_arcsec
    };
    // Three positions for three unknowns: no residual, so no sigma (not 0 arcsec).
    assert_eq!(sigma_after(3), None);
    assert!(sigma_after(4).is_some_and(|s| s > 0.0));
}

#[test]
fn recordings_with_a_bom_a_pole_or_repeated_rows() {
    let rec = recording("rows.csv", "12");
    let text = std::fs::read_to_string(&rec).unwrap();
    // A spreadsheet's byte-order mark.
    let bom = write("bom.csv", &format!("\u{FEFF}{text}"));
    let (code, out, err) = nf(&["fit", &bom]);
    assert!(code == 0 && out.contains("azimuth psi"), "{err}");
    // The pole: no horizontal Earth rate, no north; never "psi NaN".
    for lat in ["90", "-90", "nan", "inf"] {
        let pole = write(
            "pole.csv",
            &text.replace("latitude_deg = 43.80000", &format!("latitude_deg = {lat}")),
        );
        let err = refused(&["fit", &pole], &format!("{pole}:2: "));
        assert!(err.contains("latitude_deg"), "{err}");
        refused(&["fit", &pole, "--json"], "latitude_deg");
    }
    // An exact copy of the last line: dropped with a warning naming both lines.
    let last = text.lines().last().unwrap();
    let n = text.lines().count();
    let copy = write("copy.csv", &format!("{text}{last}\n"));
    let (code, out, err) = nf(&["fit", &copy, "--json"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains(&format!("warning: {copy}:{}: repeats line {n} exactly", n + 1)),
        "{err}"
    );
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["n"], 12);
    // The same index with other values: an error naming both lines.
    let other = write(
        "other.csv",
        &format!("{text}{}\n", last.replacen(",40.000,", ",41.000,", 1)),
    );
    let err = refused(&["fit", &other], &format!("appears on lines {n} and {}", n + 1));
    assert!(err.contains("index 11"), "{err}");
    // A run that visits each position twice: the same angles, no warning.
    let fb = tmp("fb.csv");
    let (code, _, err) = nf(&[
        "simulate",
        "--n",
        "8",
        "--order",
        "forward-back",
        "--dwell",
        "0.5",
        "-o",
        &fb,
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = nf(&["fit", &fb]);
    assert!(
        code == 0 && !err.contains("warning") && out.contains("16 positions"),
        "{err}"
    );
}

#[test]
fn files_other_programs_write_get_errors_that_name_their_line() {
    let rec = recording("other-writers.csv", "12");
    let text = std::fs::read_to_string(&rec).unwrap();
    let v2 = write(
        "v2.csv",
        &text.replace("northfinder-recording/1", "northfinder-recording/2"),
    );
    refused(
        &["fit", &v2],
        &format!("{v2}:1: format 'northfinder-recording/2' is not supported"),
    );
    // A bare `#` between metadata lines says nothing and is passed over.
    let bare = write("bare.csv", &format!("#\n{}", text.replacen('\n', "\n#\n", 1)));
    let (code, out, err) = nf(&["fit", &bare]);
    assert!(code == 0 && out.contains("12 positions"), "{err}");
    let header = text.lines().find(|l| l.starts_with("index")).unwrap();
    let tabbed = write("tabbed.csv", &text.replace(header, &header.replace(',', "\t")));
    refused(
        &["fit", &tabbed],
        "split by tabs, where the format separates columns by commas",
    );
    // A log whose rate never changes has no noise to fit: bad input, as a malformed one.
    let flat = write(
        "flat-static.csv",
        &(0..2000).fold("# format = northfinder-static/1\nt_s,rate_dph\n".to_string(), |t, i| {
            t + &format!("{},7.25\n", i as f64 * 0.01)
        }),
    );
    let err = refused(&["allan", &flat], "does not vary");
    assert!(err.starts_with(&format!("nf: {flat}")), "{err}");
    let (_, out, _) = nf(&["allan", &flat, "--json"]);
    assert!(out.is_empty(), "{out}");
}

#[test]
fn log_strips_colours_skips_invalid_utf8_and_notices_a_lost_rec_line() {
    let rec = recording("for-log.csv", "12");
    let text = std::fs::read_to_string(&rec).unwrap();
    // probe-rs with colours: a time stamp, the level in green, a location line after each.
    let mut log: Vec<Vec<u8>> =
        vec![b"\x1b[2m0.000\x1b[0m \x1b[32mINFO \x1b[0m north finder \xff\xfe firmware".to_vec()];
    for (i, l) in text.lines().enumerate() {
        log.push(format!("\x1b[2m{i}.5\x1b[0m \x1b[32mINFO \x1b[0m rec {l}").into_bytes());
        log.push("\x1b[2m└─ north_finder::firmware @ src/firmware.rs:90\x1b[0m".into());
    }
    let write = |name: &str, lines: &[Vec<u8>]| {
        let p = tmp(name);
        std::fs::write(&p, lines.join(&b'\n')).unwrap();
        p
    };
    // Log line of the recording's line k (from 0): the banner, then two lines per line.
    let log_line = |k: usize| 2 + 2 * k;
    let clean = write("clean.log", &log);
    let out = tmp("from-clean-log.csv");
    let (code, _, err) = nf(&["log", &clean, "-o", &out]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
    assert!(
        err.contains(&format!("{clean}:1: invalid UTF-8 skipped on line(s) 1")),
        "{err}"
    );
    // A bad value: the error gives the line of the log, not of the recording extracted.
    let first_row = text.lines().position(|l| l.starts_with("0,")).unwrap();
    let mut bad = log.clone();
    let mut cells: Vec<&str> = text.lines().nth(first_row + 2).unwrap().split(',').collect();
    cells[3] = "fast";
    bad[log_line(first_row + 2) - 1] = format!("INFO  rec {}", cells.join(",")).into_bytes();
    let bad = write("bad.log", &bad);
    refused(
        &["log", &bad],
        &format!("{bad}:{}: rate_dph 'fast'", log_line(first_row + 2)),
    );
    // A lost rec line (index 5): which index, between which lines of the log.
    let mut lost = log.clone();
    lost.remove(log_line(first_row + 5) - 1);
    let lost = write("lost.log", &lost);
    let err = refused(&["log", &lost], "index 5 (between log lines");
    assert!(
        err.contains(&format!(
            "lines {} and {}",
            log_line(first_row + 4),
            log_line(first_row + 6) - 1
        )),
        "{err}"
    );
    assert!(err.contains("--allow-gaps"), "{err}");
    let (code, out, err) = nf(&["log", &lost, "--allow-gaps"]);
    assert!(
        code == 0 && err.contains("warning") && err.contains("11 positions"),
        "{err}"
    );
    assert_eq!(out.lines().count(), text.lines().count() - 1);
    // Invalid UTF-8 inside a rec line: that line is dropped, and so shows as a gap.
    let mut noisy = log.clone();
    noisy[log_line(first_row + 3) - 1].insert(20, 0xff);
    let noisy = write("noisy.log", &noisy);
    let err = refused(&["log", &noisy], "index 3 (between");
    assert!(
        err.contains(&format!(
            "{noisy}:{}: a 'rec' line with 1 invalid",
            log_line(first_row + 3)
        )),
        "{err}"
    );
}

#[test]
fn the_suite_keeps_its_misses_only_where_it_can_write() {
    let file = recording("keep-is-a-file.csv", "12");
    let inside = format!("{file}/misses");
    let err = refused(
        &["diagnose", "--evaluate", "--category", "large_tilt", "--keep", &inside],
        "--keep",
    );
    assert!(err.contains("misses"), "{err}");
    refused(&["diagnose", &file, "--keep", &inside], "--keep");
}

#[test]
fn an_output_in_a_folder_that_does_not_exist_is_refused_before_any_work() {
    let r = &recording("for-outputs.csv", "8");
    let log = write("for-outputs.log", "INFO  rec # format = northfinder-recording/1\n");
    let gone = tmp("no-such-folder/x.svg");
    let gone_csv = tmp("no-such-folder/x.csv");
    let static_log = tmp("for-outputs-static.csv");
    let mut f = std::fs::File::create(&static_log).unwrap();
    nf_twin::StaticLog {
        noise: NoiseModel::white(0.005, 2.0),
        rate_dph: 1.0,
        sample_rate_hz: 10.0,
        duration_s: 3600.0,
        seed: 1,
    }
    .write(&mut f)
    .unwrap();
    let inst = tmp("for-outputs.toml");
    let (code, _, err) = nf(&[
        "simulate",
        "--n",
        "8",
        "--save-config",
        &inst,
        "-o",
        &tmp("for-outputs-2.csv"),
    ]);
    assert_eq!(code, 0, "{err}");
    let cases: [&[&str]; 9] = [
        &["fit", r, "--plot", &gone],
        &["diagnose", r, "--report", &gone],
        &["allan", &static_log, "--out", &gone_csv],
        &["log", &log, "-o", &gone_csv],
        &["paper", "--plot", &gone],
        &["plan", "--plot", &gone],
        &["simulate", "--n", "8", "-o", &gone_csv],
        &["simulate", "--n", "8", "--save-config", &gone_csv],
        &["diagnose", r, "--sim", &inst, "--fix", &gone_csv],
    ];
    for args in cases {
        let (code, out, err) = nf(args);
        assert!(code == 2 && out.is_empty(), "{args:?}: {code} {out}{err}");
        assert!(err.contains("no-such-folder does not exist"), "{args:?}: {err}");
    }
    // A file where the folder should be, and a folder where the file should be.
    let under_a_file = format!("{r}/x.svg");
    let a_folder = tmp("a-folder.svg");
    std::fs::create_dir_all(&a_folder).unwrap();
    for (path, why) in [
        (under_a_file.as_str(), "is a file, not a folder"),
        (&a_folder, "it is a folder"),
    ] {
        let (code, out, err) = nf(&["fit", r, "--plot", path]);
        assert!(
            code == 2 && out.is_empty() && err.contains(why),
            "{path}: {code} {out}{err}"
        );
    }
}

/// A noise file read from standard input as `-`, as recordings and static logs are (an outside
/// audit's `nf plan --noise -` was "cannot read -").
#[test]
fn a_noise_file_is_read_from_standard_input_as_a_dash() {
    let model = "arw_deg_rth = 0.0002\nbias_instability_dph = 0.001\nrrw_dph_rth = 0\n";
    let mut plan = Command::new(env!("CARGO_BIN_EXE_nf"))
        .args(["plan", "--noise", "-", "--mc-runs", "0", "--json"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::io::Write::write_all(&mut plan.stdin.take().unwrap(), model.as_bytes()).unwrap();
    let o = plan.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["noise_model"]["bias_instability_dph"], 0.001, "{json}");
}
