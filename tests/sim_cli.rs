//! Instrument files through the `nf` binary: `simulate --config` and `--save-config`, and
//! `diagnose --sim --fix` closing the loop on a recording with a drift the file lacks.

mod common;
use common::{nf, tmp};

#[test]
fn a_saved_instrument_file_simulates_the_same_recording_as_its_flags() {
    let (inst, a, b) = (tmp("inst.toml"), tmp("a.csv"), tmp("b.csv"));
    let flags = [
        "--n",
        "24",
        "--dwell",
        "0.5",
        "--drift",
        "1e-4",
        "--encoder-error",
        "20",
        "--shocks-per-hour",
        "600",
        "--shock-size",
        "0.05",
        "--seed",
        "4",
    ];
    let mut args = vec!["simulate", "--save-config", &inst, "-o", &a];
    args.extend(flags);
    let (code, _, err) = nf(&args);
    assert_eq!(code, 0, "{err}");
    assert!(
        std::fs::read_to_string(&inst)
            .unwrap()
            .contains("[shocks]\nper_hour = 600.0\nsize_dph = 0.05\nduration_s = 1.0\n")
    );
    let (code, _, err) = nf(&["simulate", "--config", &inst, "-o", &b]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read_to_string(&a).unwrap(),
        std::fs::read_to_string(&b).unwrap()
    );
    let (code, _, err) = nf(&["simulate", "--shock-duration", "0"]);
    assert_eq!(code, 2);
    assert!(err.contains("--shock-duration"), "{err}");
    let (code, _, err) = nf(&["simulate", "--shocks-per-hour", "1e6"]);
    assert_eq!(code, 2);
    assert!(err.contains("under way at once"), "{err}");
    let (code, _, err) = nf(&["simulate", "--config", &inst, "--lat", "10"]);
    assert_eq!(code, 2);
    assert!(err.contains("cannot be used with '--lat"), "{err}");
    let (code, _, err) = nf(&["simulate", "--config", &inst, "--bias-instability", "0.01"]);
    assert_eq!(code, 2);
    assert!(err.contains("--config holds the noise model"), "{err}");
    let bad = tmp("bad.toml");
    std::fs::write(&bad, "format = \"northfinder-instrument/1\"\n[run]\npositions = 2\n").unwrap();
    let (code, _, err) = nf(&["simulate", "--config", &bad]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.toml:3:") && err.contains("outside [4, 720]"), "{err}");
    let (code, _, err) = nf(&["diagnose", &a, "--sim", &bad]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.toml:3:"), "{err}");
    let (code, _, _) = nf(&["diagnose", &a, "--fix", &tmp("x.toml")]);
    assert_eq!(code, 2);
}

/// A gyro the converter cannot hold: a quantisation step beyond its range, or white noise
/// whose 6 sd reach it, is refused before the run (bad input); shocks that saturate it strike
/// at random and fail the run as the firmware would. Each message names the term and the
/// largest value of it that fits, and the largest fits indeed.
#[test]
fn a_saturated_gyro_adc_is_explained_by_the_term_that_saturates_it() {
    let (out, cfg) = (tmp("sat.csv"), tmp("sat.toml"));
    // Written by this test's later step on an earlier run: gone, so it cannot pass the check.
    let _ = std::fs::remove_file(&out);
    let _ = std::fs::remove_file(&cfg);
    let largest = |err: &str, term: &str| {
        err.split(term)
            .nth(1)
            .and_then(|t| t.split(' ').next())
            .unwrap_or_else(|| panic!("no largest value after '{term}' in: {err}"))
            .to_string()
    };
    let (code, _, err) = nf(&[
        "simulate",
        "--n",
        "12",
        "--quantization",
        "0.5",
        "-o",
        &out,
        "--save-config",
        &cfg,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot be read by the ADC"), "{err}");
    assert!(!std::path::Path::new(&out).exists(), "a recording was written");
    assert!(!std::path::Path::new(&cfg).exists(), "an instrument file was written");
    assert!(!err.contains("white noise of at most"), "{err}");
    let q = largest(&err, "a quantisation Q of at most ");
    let (code, _, err) = nf(&["simulate", "--n", "12", "--quantization", &q, "-o", &out]);
    assert_eq!(code, 0, "Q = {q}: {err}");
    // 95 deg/h of white noise in one sample at 1 kHz against +-50 deg/h.
    let sat = tmp("sat-noise.csv");
    let _ = std::fs::remove_file(&sat);
    let (code, _, err) = nf(&["simulate", "--n", "12", "--arw", "0.05", "-o", &sat]);
    assert!(code == 2 && err.contains("cannot be read by the ADC"), "{code} {err}");
    assert!(!std::path::Path::new(&sat).exists(), "a recording was written");
    let n = largest(&err, "Gaussian white noise of at most ");
    let (code, _, err) = nf(&["simulate", "--n", "12", "--arw", &n, "-o", &sat]);
    assert_eq!(code, 0, "N = {n}: {err}");
    // Bursts of 300 deg/h, one under way at any time: the run stops at the first, and says why.
    let inst = tmp("shaken.toml");
    let (code, _, err) = nf(&["simulate", "--n", "12", "--save-config", &inst, "-o", &out]);
    assert_eq!(code, 0, "{err}");
    let shaken =
        std::fs::read_to_string(&inst).unwrap() + "\n[shocks]\nper_hour = 3600.0\nsize_dph = 300.0\nduration_s = 1.0\n";
    std::fs::write(&inst, shaken).unwrap();
    let (code, _, err) = nf(&["simulate", "--config", &inst, "-o", &out]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("ADC sat at full scale")
            && err.contains("positions written")
            && err.contains("shocks of sd at most"),
        "{err}"
    );
}

#[test]
fn diagnose_against_a_simulation_names_what_it_lacks_and_the_fix_reproduces_the_recording() {
    let (base, drift, rec, fixed) = (tmp("base.toml"), tmp("drift.toml"), tmp("rec.csv"), tmp("fixed.toml"));
    let (code, _, err) = nf(&["simulate", "--save-config", &base, "--seed", "8", "-o", &tmp("x.csv")]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&base).unwrap();
    std::fs::write(
        &drift,
        text.replace("linear_dph_per_s = 0.0", "linear_dph_per_s = 0.0002"),
    )
    .unwrap();
    let (code, _, err) = nf(&["simulate", "--config", &drift, "-o", &rec]);
    assert_eq!(code, 0, "{err}");
    // A fix that could not be written is refused before the work, not after it.
    let nowhere = format!("{}/no-such-folder/fixed.toml", tmp(""));
    let (code, out, err) = nf(&["diagnose", &rec, "--sim", &base, "--fix", &nowhere]);
    assert!(
        code == 2 && out.is_empty() && err.contains("does not exist"),
        "{code} {err}"
    );
    let (svg, html) = (tmp("sim.svg"), tmp("sim.html"));
    let (code, out, err) = nf(&[
        "diagnose", &rec, "--sim", &base, "--fix", &fixed, "--json", "--plot", &svg, "--report", &html,
    ]);
    assert_eq!(code, 0, "{err}");
    // The report's headline gives the simulation's verdict too.
    let page = std::fs::read_to_string(&html).unwrap();
    let headline = page.split("<p id=\"headline\">").nth(1).unwrap_or_default();
    let headline = headline.split("</p>").next().unwrap_or_default();
    assert!(
        headline.contains("against the simulation: to change") && headline.contains("bias_drift"),
        "{headline}"
    );
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let s = &j["simulation"];
    let physics = s["physics"].as_array().unwrap();
    assert!(
        physics
            .iter()
            .any(|p| p["effect"] == "bias_drift" && p["verdict"] == "Missing"),
        "{physics:?}"
    );
    assert!(s["before"]["mismatches"].as_u64().unwrap() >= 1);
    assert!(s["after"]["mismatches"].as_u64().unwrap() <= 1, "{}", s["after"]);
    // A drift departs most at the ends of the run.
    assert!(
        s["positions_before"]["beyond"].as_u64().unwrap() >= 1,
        "{}",
        s["positions_before"]
    );
    assert!(
        s["positions_after"]["beyond"].as_u64().unwrap() <= 1,
        "{}",
        s["positions_after"]
    );
    assert!(
        std::fs::read_to_string(&svg)
            .unwrap()
            .contains("Allan deviation in time order of the residuals beyond harmonics 1-4")
    );
    let fixed_text = std::fs::read_to_string(&fixed).unwrap();
    assert!(fixed_text.starts_with("# north-finder instrument") && fixed_text.contains("bias_drift"));
    // The fixed file simulates, and the recording lacks nothing against it.
    let (code, _, err) = nf(&["simulate", "--config", &fixed, "-o", &tmp("y.csv")]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = nf(&["diagnose", &rec, "--sim", &fixed]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("missing from the simulation"), "{out}");
}

/// A site azimuth the file has wrong: nothing is missing, the azimuth differs, and the fix
/// sets it to the recording's, which then agrees by construction; the text says both.
#[test]
fn a_quantity_the_fix_sets_to_the_recording_is_said_to_agree_by_construction() {
    let (base, moved, rec) = (tmp("site.toml"), tmp("moved.toml"), tmp("site.csv"));
    let (code, _, err) = nf(&["simulate", "--save-config", &base, "--seed", "8", "-o", &tmp("z.csv")]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&base).unwrap();
    let at = text.find("azimuth_deg = ").unwrap();
    let line_end = at + text[at..].find('\n').unwrap();
    std::fs::write(
        &moved,
        format!("{}azimuth_deg = 66.0{}", &text[..at], &text[line_end..]),
    )
    .unwrap();
    let (code, _, err) = nf(&["simulate", "--config", &moved, "-o", &rec]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = nf(&["diagnose", &rec, "--sim", &base, "--fix", &tmp("site_fixed.toml")]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("azimuth_deg set to the recording's by the fix"), "{out}");
    assert!(
        out.contains("; 1 quantity below still differs beyond the bound"),
        "{out}"
    );
}
