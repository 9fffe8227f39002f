//! The model's fit and the run sequencer on the emulated MCU (QEMU `mps2-an386`, a Cortex-M4F)
//! against the same on the host: `qemu/` is built for thumbv7em and run under
//! `qemu-system-arm`; its `fit` and `run` lines must agree with the host's to 0.1 arcsec, and
//! the fit of n = 180 must stay within its instruction budget.
//! QEMU is required where `NF_REQUIRE_QEMU` is set (`.ci/run` installs it); elsewhere the test
//! says why it did nothing and passes.

use nf_model::fit::{AzimuthFit, FitConfig, Obs};
use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

#[path = "../qemu/src/fake.rs"]
mod fake;
#[path = "../qemu/src/synthetic.rs"]
mod synthetic;

/// Agreement asked for between the MCU and the host, arcsec.
const TOLERANCE_ARCSEC: f64 = 0.1;
/// The budget for the n = 180 fit on the Cortex-M4F.
const FIT_BUDGET_INSTRUCTIONS: f64 = 300_000.0;

fn qemu_found() -> bool {
    Command::new("qemu-system-arm")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Builds and runs the QEMU binary (its own workspace, target and runner: `qemu/.cargo`), with
/// its build under this test's scratch directory; returns its standard output.
fn run_on_qemu() -> String {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args(["run", "--release", "--quiet"])
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("qemu"))
        .env("CARGO_TARGET_DIR", Path::new(env!("CARGO_TARGET_TMPDIR")).join("qemu"))
        .output()
        .expect("cargo runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "the QEMU binary failed ({}):\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// The `key=value` fields of the line that starts with `name`.
fn fields<'a>(stdout: &'a str, name: &str) -> HashMap<&'a str, &'a str> {
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix(name)?.strip_prefix(' '))
        .unwrap_or_else(|| panic!("no `{name}` line in:\n{stdout}"));
    line.split_whitespace().filter_map(|kv| kv.split_once('=')).collect()
}

fn number(f: &HashMap<&str, &str>, key: &str) -> f64 {
    let v = f.get(key).unwrap_or_else(|| panic!("no {key} in {f:?}"));
    v.parse().unwrap_or_else(|e| panic!("{key}={v}: {e}"))
}

/// `a - b` in arcsec, across the 0/360 deg wrap.
fn diff_arcsec(a_deg: f64, b_deg: f64) -> f64 {
    ((a_deg - b_deg + 180.0).rem_euclid(360.0) - 180.0) * 3600.0
}

#[test]
fn fit_and_run_on_the_emulated_mcu_match_the_host() {
    if !qemu_found() {
        assert!(
            std::env::var_os("NF_REQUIRE_QEMU").is_none(),
            "NF_REQUIRE_QEMU is set and qemu-system-arm was not found"
        );
        eprintln!("qemu-system-arm not found: the emulated-MCU test did nothing (NF_REQUIRE_QEMU=1 makes it fail)");
        return;
    }
    let stdout = run_on_qemu();
    print!("{stdout}");

    // The MCU fits in f32; the host fits the same f32 numbers in f64.
    let fit = fields(&stdout, "fit");
    let obs: Vec<Obs<f64>> = synthetic::observations::<f32>()
        .iter()
        .map(|o| Obs {
            gamma_deg: o.gamma_deg as f64,
            t_s: o.t_s as f64,
            rate_dph: o.rate_dph as f64,
            tilt_x_deg: None,
            weight: 1.0,
        })
        .collect();
    let host = AzimuthFit::fit_all(FitConfig::default(), &obs).unwrap();
    assert_eq!(number(&fit, "n"), synthetic::N as f64);
    let d_psi = diff_arcsec(number(&fit, "psi_deg"), host.psi_deg);
    let d_sigma = number(&fit, "sigma_arcsec") - host.sigma_psi_deg * 3600.0;
    println!("fit: QEMU f32 - host f64: psi {d_psi:+.4} arcsec, sigma {d_sigma:+.4} arcsec");
    assert!(d_psi.abs() <= TOLERANCE_ARCSEC && d_sigma.abs() <= TOLERANCE_ARCSEC);
    let instructions = number(&fit, "instructions");
    println!("fit of n = {}: {instructions} instructions", synthetic::N);
    assert!(
        instructions > 0.0 && instructions < FIT_BUDGET_INSTRUCTIONS,
        "{instructions} instructions, budget {FIT_BUDGET_INSTRUCTIONS}"
    );

    // The same run, on the same fake instrument, on the host.
    let run = fields(&stdout, "run");
    let (report, lines) = fake::run();
    report.result.unwrap();
    let az = report.azimuth.unwrap();
    let d_psi = diff_arcsec(number(&run, "psi_deg"), az.psi_deg as f64);
    let d_sigma = number(&run, "sigma_arcsec") - az.sigma_arcsec.unwrap() as f64;
    println!("run: QEMU - host: psi {d_psi:+.4} arcsec, sigma {d_sigma:+.4} arcsec");
    assert!(d_psi.abs() <= TOLERANCE_ARCSEC && d_sigma.abs() <= TOLERANCE_ARCSEC);
    // The running azimuth under the noise model (the f32 square-root information filter).
    let noise = report.under_noise.unwrap();
    let d_psi = diff_arcsec(number(&run, "noise_psi_deg"), noise.psi_deg as f64);
    let d_sigma = number(&run, "noise_sigma_arcsec") - noise.sigma_psi_deg as f64 * 3600.0;
    println!("run under the noise model: QEMU - host: psi {d_psi:+.4} arcsec, sigma {d_sigma:+.4} arcsec");
    assert!(d_psi.abs() <= TOLERANCE_ARCSEC && d_sigma.abs() <= TOLERANCE_ARCSEC);
    assert_eq!(number(&run, "positions"), report.positions as f64);
    assert_eq!(number(&run, "lines"), lines as f64);
}
