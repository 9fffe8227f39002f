//! Bad inputs to `nf` and to the main run: each gets a clear error naming what and where, exit
//! code 2, no panic and no NaN printed as a result; a closed standard output ends a command
//! quietly.

use nf_model::noise::NoiseModel;
use nf_twin::StaticLog;
use std::process::{Command, Stdio};

fn nf(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_nf")).args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into(),
        String::from_utf8_lossy(&o.stderr).into(),
    )
}

fn tmp(name: &str) -> String {
    let d = std::env::temp_dir().join(format!("nf-bad-input-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name).to_string_lossy().into_owned()
}

/// A twin recording of `n` positions written to `name`.
fn recording(name: &str, n: &str) -> String {
    let path = tmp(name);
    let (code, _, err) = nf(&["simulate", "--n", n, "--dwell", "0.5", "-o", &path]);
    assert_eq!(code, 0, "{err}");
    path
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
