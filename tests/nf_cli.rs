//! `nf` on twin recordings: fits that recover psi over many seeds (also with 1 deg tilts), and
//! every subcommand run as a user runs it, bad inputs included.

use nf::analysis::{Options, TiltMethod, analyse};
use nf::recording::Recording;
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_model::angle::wrap_180;
use nf_twin::{Recorder, Rng, TwinConfig, simulate};

mod common;
use common::{nf, tmp};

fn twin_recording(twin: &TwinConfig, positions: u16) -> Recording {
    let run = RunConfig {
        positions,
        dwell_ms: 500,
        settle_ms: 200,
        latitude_deg: twin.instrument.latitude_deg as f32,
        tilt_policy: TiltPolicy::Warn,
        ..RunConfig::default()
    };
    let mut rec = Recorder::default();
    let (report, _) = simulate(twin, &run, &mut rec);
    assert_eq!(report.result, Ok(()));
    Recording::parse(&rec.text()).unwrap()
}

/// Largest |error| / sigma over `seeds` random instruments with tilts up to `max_tilt`.
fn worst_z(seeds: u64, max_tilt: f64, opt: &Options) -> (f64, f64) {
    let mut rng = Rng::new(99);
    let (mut worst, mut sum2) = (0.0f64, 0.0);
    for seed in 0..seeds {
        let mut twin = TwinConfig {
            seed,
            ..TwinConfig::default()
        };
        twin.instrument.latitude_deg = rng.uniform(-60.0, 60.0);
        twin.instrument.psi_deg = rng.uniform(0.0, 360.0);
        twin.instrument.tilt_deg = rng.uniform(0.0, max_tilt);
        twin.instrument.tilt_dir_deg = rng.uniform(0.0, 360.0);
        twin.instrument.scale = rng.uniform(0.995, 1.005);
        twin.start_deg = rng.uniform(0.0, 360.0);
        let rec = twin_recording(&twin, 36);
        let an = analyse(&rec, opt).unwrap();
        let z = wrap_180(an.gls.psi_deg - twin.instrument.psi_deg) / an.gls.sigma_psi_deg;
        worst = worst.max(z.abs());
        sum2 += z * z;
    }
    (worst, (sum2 / seeds as f64).sqrt())
}

#[test]
fn fit_recovers_psi_within_three_sigma_over_many_seeds() {
    let (worst, rms) = worst_z(60, 0.005, &Options::default());
    println!("level: worst |error|/sigma {worst:.2}, rms {rms:.2}");
    assert!(worst < 3.5 && (0.75..1.3).contains(&rms), "{worst} {rms}");
}

#[test]
fn a_glitch_far_off_the_rest_is_held_out_and_clean_runs_have_none() {
    let no_bootstrap = Options {
        replicates: 0,
        ..Options::default()
    };
    for seed in 0..20 {
        let twin = TwinConfig {
            seed,
            ..TwinConfig::default()
        };
        let mut rec = twin_recording(&twin, 36);
        let clean = analyse(&rec, &no_bootstrap).unwrap();
        assert!(clean.wild.is_empty(), "seed {seed}");
        rec.rows[7].rate_dph += 300.0;
        let an = analyse(&rec, &no_bootstrap).unwrap();
        assert_eq!(an.wild.len(), 1, "seed {seed}: {:?}", an.wild);
        let w = an.wild[0];
        assert_eq!((w.index, w.line, w.held_out), (7, rec.rows[7].line, true));
        // The fit is that of the other 35 dwells: as close to the clean run's as one dwell
        // less allows (its sigma grows by about 1/70).
        let moved = wrap_180(an.gls.psi_deg - clean.gls.psi_deg) / clean.gls.sigma_psi_deg;
        assert!(moved.abs() < 0.5, "seed {seed}: moved {moved} sigma");
        assert_eq!(an.fit.n, 35);
    }
}

#[test]
fn a_glitch_in_a_short_run_is_judged_against_the_fit_of_the_others() {
    // In a dozen dwells a glitch drags the fit of all so far that its residual stays some 6
    // robust sigmas of the rest, whatever its size; against the fit without it, it stands out.
    let no_bootstrap = Options {
        replicates: 0,
        ..Options::default()
    };
    for positions in [8u16, 10, 12, 14, 18] {
        for seed in 0..10 {
            let twin = TwinConfig {
                seed,
                ..TwinConfig::default()
            };
            let mut rec = twin_recording(&twin, positions);
            let clean = analyse(&rec, &no_bootstrap).unwrap();
            assert!(
                clean.wild.is_empty(),
                "{positions} positions, seed {seed}: {:?}",
                clean.wild
            );
            let at = seed as usize % positions as usize;
            rec.rows[at].rate_dph += 300.0;
            let an = analyse(&rec, &no_bootstrap).unwrap();
            let held: Vec<usize> = an.wild.iter().filter(|w| w.held_out).map(|w| w.row).collect();
            assert_eq!(held, vec![at], "{positions} positions, seed {seed}: {:?}", an.wild);
            let z = wrap_180(an.gls.psi_deg - twin.instrument.psi_deg) / an.gls.sigma_psi_deg;
            assert!(z.abs() < 4.0, "{positions} positions, seed {seed}: {z}");
        }
    }
}

#[test]
fn a_huge_glitch_moves_neither_the_tilt_correction_nor_the_azimuth_and_does_not_hide_a_smaller_one() {
    let no_bootstrap = Options {
        replicates: 0,
        ..Options::default()
    };
    let mut twin = TwinConfig {
        seed: 3,
        ..TwinConfig::default()
    };
    twin.instrument.tilt_deg = 1.0;
    twin.instrument.latitude_deg = 50.0;
    let mut rec = twin_recording(&twin, 48);
    let clean = analyse(&rec, &no_bootstrap).unwrap();
    assert_eq!(clean.method, TiltMethod::Exact);
    // A fill value drags a least-squares fit by thousands of deg/h, under which a glitch of
    // 300 deg/h is not far off; the fit without the first shows it.
    rec.rows[10].rate_dph = 1e6;
    rec.rows[30].rate_dph += 300.0;
    let an = analyse(&rec, &no_bootstrap).unwrap();
    let held: Vec<u32> = an.wild.iter().filter(|w| w.held_out).map(|w| w.index).collect();
    assert_eq!(held, vec![10, 30], "{:?}", an.wild);
    let moved = wrap_180(an.gls.psi_deg - clean.gls.psi_deg) / clean.gls.sigma_psi_deg;
    assert!(moved.abs() < 0.5, "moved {moved} sigma");
    let (s, c) = (an.shaft.unwrap(), clean.shaft.unwrap());
    assert!((s.tilt_deg - c.tilt_deg).abs() < 1e-3, "{s:?} {c:?}");
    let z = wrap_180(an.gls.psi_deg - twin.instrument.psi_deg) / an.gls.sigma_psi_deg;
    assert!(z.abs() < 3.5, "{z}");
}

#[test]
fn a_glitch_is_held_out_in_the_cli_output_json_and_plot() {
    let rec = tmp("glitch.csv");
    let (code, _, err) = nf(&["simulate", "--n", "36", "--seed", "9", "-o", &rec]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&rec).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let header = lines.iter().position(|l| l.starts_with("index")).unwrap();
    let cols: Vec<&str> = lines[header].split(',').collect();
    let rate = cols.iter().position(|c| *c == "rate_dph").unwrap();
    let mut cells: Vec<String> = lines[header + 12].split(',').map(String::from).collect();
    cells[rate] = "1e6".into();
    lines[header + 12] = cells.join(",");
    std::fs::write(&rec, lines.join("\n") + "\n").unwrap();
    let (code, out, err) = nf(&["fit", &rec, "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["n"], 35);
    assert_eq!(j["far_off"][0]["line"], header + 13);
    assert_eq!(j["far_off"][0]["held_out"], true);
    assert_eq!(j["earth_rate_resolved"], true);
    let svg = tmp("glitch.svg");
    let (code, out, _) = nf(&["fit", &rec, "--plot", &svg]);
    assert_eq!(code, 0);
    assert!(
        out.contains(&format!("far off        line {}", header + 13)) && out.contains("held out"),
        "{out}"
    );
    assert!(std::fs::read_to_string(&svg).unwrap().contains("held out, not drawn"));
}

#[test]
fn many_dwells_far_off_are_the_data_and_are_kept() {
    // A second harmonic of 500 deg/h seen on four dwells a quarter turn apart: the first
    // harmonic and the bias do not take it, and four of 36 are more than a tenth.
    let mut rec = twin_recording(&TwinConfig::default(), 36);
    for (i, d) in [(0, 500.0), (9, -500.0), (18, 500.0), (27, -500.0)] {
        rec.rows[i].rate_dph += d;
    }
    let an = analyse(
        &rec,
        &Options {
            replicates: 0,
            ..Options::default()
        },
    )
    .unwrap();
    assert_eq!(an.wild.len(), 4, "{:?}", an.wild);
    assert!(an.wild.iter().all(|w| !w.held_out));
    assert_eq!(an.fit.n, 36);
}

#[test]
fn fit_with_tilts_up_to_1_deg_and_inclinometer_columns() {
    let (worst, rms) = worst_z(60, 1.0, &Options::default());
    println!("tilt up to 1 deg, exact correction: worst |error|/sigma {worst:.2}, rms {rms:.2}");
    assert!(worst < 3.5 && (0.75..1.3).contains(&rms), "{worst} {rms}");
    // The same recordings with the tilt ignored are far off.
    let (worst_none, _) = worst_z(
        10,
        1.0,
        &Options {
            tilt: Some(TiltMethod::None),
            ..Options::default()
        },
    );
    assert!(worst_none > 10.0, "{worst_none}");
}

#[test]
fn simulate_then_fit_json() {
    let rec = tmp("sim.csv");
    let (code, _, err) = nf(&[
        "simulate", "--n", "24", "--dwell", "0.5", "--psi", "200", "--seed", "5", "-o", &rec,
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = nf(&["fit", &rec, "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["n"], 24);
    let (psi, sigma) = (j["azimuth_deg"].as_f64().unwrap(), j["sigma_arcsec"].as_f64().unwrap());
    assert!(wrap_180(psi - 200.0).abs() * 3600.0 < 4.0 * sigma, "{psi} {sigma}");
    assert!(j["rss"].as_f64().unwrap() > 0.0);
    assert_eq!(j["tilt_correction"], "exact");
    assert!(j["noise_model"]["sigma_calibration"].as_f64().unwrap() >= 1.0);
    // The widening holds the calibration; without it the sigma is GLS under the printed model
    // (the tilt left out, whose circle adds its own share).
    let level = |extra: &[&str]| {
        let (code, out, err) = nf(&[&["fit", &rec, "--json", "--tilt", "none"], extra].concat());
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let own = level(&[]);
    let (m, widening) = (
        &own["noise_model"],
        own["noise_model"]["sigma_widening"].as_f64().unwrap(),
    );
    assert!(widening >= m["sigma_calibration"].as_f64().unwrap(), "{widening}");
    let terms = ["arw_deg_rth", "bias_instability_dph", "rrw_dph_rth"].map(|k| m[k].as_f64().unwrap().to_string());
    let given = level(&["--arw", &terms[0], "--bias-instability", &terms[1], "--rrw", &terms[2]]);
    assert_eq!(given["noise_model"]["sigma_widening"], 1.0);
    let (alone, sigma_own) = (
        given["sigma_arcsec"].as_f64().unwrap(),
        own["sigma_arcsec"].as_f64().unwrap(),
    );
    assert!(
        (alone * widening / sigma_own - 1.0).abs() < 1e-6,
        "{alone} {widening} {sigma_own}"
    );
    let (code, out, err) = nf(&["fit", &rec, "--json", "--replicates", "0"]);
    assert_eq!(code, 0, "{err}");
    let raw: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(raw["noise_model"]["sigma_calibration"].is_null());
    assert!(raw["sigma_arcsec"].as_f64().unwrap() <= sigma + 1e-9);
    let (code, out, err) = nf(&["fit", &rec, "--replicates", "-3"]);
    assert!(
        code == 2 && out.is_empty() && err.contains("--replicates"),
        "{code} {err}"
    );
    assert!((j["surveying_azimuth_deg"].as_f64().unwrap() - (360.0 - psi)).abs() < 1e-9);
    let svg = tmp("fit.svg");
    let (code, out, _) = nf(&["fit", &rec, "--plot", &svg, "--drift", "linear", "--harmonics", "2"]);
    assert_eq!(code, 0);
    assert!(out.contains("surveying az.") && out.contains("Eq. 31 (paper)") && out.contains("drift"));
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    // The noise estimated from the run alone points to a static log; a given model does not.
    let static_log = "a static log of the gyro can";
    assert!(out.contains(static_log), "{out}");
    let (code, out, _) = nf(&["fit", &rec, "--arw", "1.2e-4"]);
    assert!(code == 0 && !out.contains(static_log), "{out}");
    assert!(!out.contains("with its Gauss-Markov tail"), "{out}");
    // A sensor's short filter tail is each dwell's own noise too: said beside N's level.
    let (code, out, _) = nf(&["fit", &rec, "--arw", "1.2e-4", "--gm-sigma", "0.04", "--gm-tau", "0.01"]);
    assert!(code == 0 && out.contains(" with its Gauss-Markov tail), "), "{out}");
    // diagnose says which model judged what; a given one judges every effect, and the wander
    // test still checks it against the run.
    let (code, out, _) = nf(&["diagnose", &rec, "--arw", "1.2e-4"]);
    let given = "every effect judged under the given model";
    assert!(
        code == 0 && out.contains(given) && out.contains("also with the noise re-estimated"),
        "{out}"
    );
    let (_, out, _) = nf(&["diagnose", &rec]);
    assert!(out.contains("estimated with a drift") && !out.contains(given), "{out}");
}

#[test]
fn shocked_dwells_are_named_in_the_fit_and_white_ones_are_not() {
    let (shocked, calm) = (tmp("shocked.csv"), tmp("calm.csv"));
    let (code, _, err) = nf(&[
        "simulate",
        "--shocks-per-hour",
        "146",
        "--shock-size",
        "0.0866",
        "--shock-duration",
        "2",
        "--psi",
        "48.4",
        "--seed",
        "1",
        "--tilt",
        "0",
        "-o",
        &shocked,
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = nf(&["simulate", "--psi", "48.4", "--seed", "1", "--tilt", "0", "-o", &calm]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = nf(&["fit", &shocked, "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let s = &j["noise_model"]["shocks"];
    let struck = s["struck_lines"].as_array().unwrap();
    assert!(!struck.is_empty() && s["share"].as_f64().unwrap() > 0.0, "{s}");
    // Each struck line is a dwell of the recording (metadata and header come first).
    assert!(struck.iter().all(|l| l.as_u64().unwrap() > 3), "{s}");
    let (_, text, _) = nf(&["fit", &shocked]);
    assert!(text.contains("dwells read as struck"), "{text}");
    // diagnose's final goes through the shocks too, and lands where the fit does.
    let (psi, sigma) = (j["azimuth_deg"].as_f64().unwrap(), j["sigma_arcsec"].as_f64().unwrap());
    let (code, out, err) = nf(&["diagnose", &shocked, "--json"]);
    assert_eq!(code, 0, "{err}");
    let d: serde_json::Value = serde_json::from_str(&out).unwrap();
    let through = d["notes"]
        .as_array()
        .unwrap()
        .iter()
        .any(|n| n.as_str().unwrap().contains("fitted through shocks"));
    assert!(through, "{}", d["notes"]);
    let fin = &d["final"];
    let off = wrap_180(fin["azimuth_deg"].as_f64().unwrap() - psi).abs() * 3600.0;
    assert!(off < sigma, "diagnose {fin} against the fit's {psi} +- {sigma}\"");
    let (code, out, err) = nf(&["fit", &calm, "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(j["noise_model"]["shocks"].is_null(), "{}", j["noise_model"]);
}

#[test]
fn fit_of_a_bad_recording_names_the_line() {
    let bad = tmp("bad.csv");
    std::fs::write(&bad, "# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n1,2,90,oops\n").unwrap();
    let (code, _, err) = nf(&["fit", &bad]);
    assert_eq!(code, 2);
    // As compilers name a place: FILE:LINE, as `nf allan` does too.
    assert!(err.contains(&format!("{bad}:5: rate_dph 'oops'")), "{err}");
    let (code, _, err) = nf(&["fit", "/nonexistent.csv"]);
    assert_eq!(code, 2);
    assert!(err.contains("cannot read"), "{err}");
    // Three positions at one angle (a stalled motor): nothing to fit.
    std::fs::write(&bad, "# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n1,2,0,1\n2,3,0,1\n").unwrap();
    for cmd in ["fit", "diagnose"] {
        let (code, out, err) = nf(&[cmd, &bad]);
        assert_eq!((code, out.as_str()), (2, ""), "{cmd}");
        assert!(
            err.contains("1 distinct angle(s) over 3 positions") && err.contains("did the shaft turn"),
            "{err}"
        );
    }
    // Three angles but three positions: no degree of freedom left for the noise.
    std::fs::write(&bad, "# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n1,2,90,1\n2,3,180,1\n").unwrap();
    for (cmd, least) in [("fit", "needs at least 4"), ("diagnose", "needs at least 8")] {
        let (code, out, err) = nf(&[cmd, &bad]);
        assert_eq!((code, out.as_str()), (2, ""), "{cmd}");
        assert!(err.contains("3 positions") && err.contains(least), "{err}");
    }
    std::fs::write(&bad, "# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n1,2,90,1\n2,3,180,1\n3,4,270,1\n").unwrap();
    // What the recording cannot give is bad input: exit 2, as a malformed line.
    let (code, _, err) = nf(&["fit", &bad, "--tilt", "exact"]);
    assert_eq!(code, 2);
    assert!(err.contains("needs inclinometer readings"), "{err}");
    let (code, _, err) = nf(&["fit", &bad, "--tilt", "first-order"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("reads tilt_x_deg, which the recording does not have"),
        "{err}"
    );
    for cmd in ["fit", "diagnose", "allan"] {
        let (code, _, err) = nf(&[cmd, &bad, "--plot", &tmp("x.gif")]);
        assert_eq!(code, 2, "{cmd}");
        assert!(err.contains("name the plot *.svg or *.png"), "{cmd}: {err}");
    }
    // Four angles three times: a second harmonic's sine is zero at all of them.
    let mut text =
        String::from("# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n");
    for k in 0..12 {
        text += &format!("{k},{},{},{}\n", k + 1, 90 * (k % 4), [1.0, 2.0, 1.5, 0.5][k % 4]);
    }
    std::fs::write(&bad, text).unwrap();
    let (code, _, err) = nf(&["fit", &bad, "--harmonics", "2"]);
    assert_eq!(code, 2);
    assert!(err.contains("do not determine the fit's term sin(2 gamma)"), "{err}");
}

#[test]
fn warnings_repeated_on_every_line_are_counted_past_ten() {
    let h = 15.041 * 40f64.to_radians().cos();
    let mut text = String::from(
        "# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph,q1_dph,q2_dph,q3_dph,q4_dph\n",
    );
    // Quarters written in another unit (deg/s): none averages to its rate.
    for k in 0..12 {
        let g = 30.0 * k as f64;
        let r = 2.0 + h * g.to_radians().cos() + 0.01 * (k % 3) as f64;
        let q = r / 3600.0;
        text += &format!("{k},{},{g},{r},{q},{q},{q},{q}\n", 3 * k + 1);
    }
    let file = tmp("quarters_in_deg_per_s.csv");
    std::fs::write(&file, text).unwrap();
    let (code, _, err) = nf(&["fit", &file]);
    assert_eq!(code, 0, "{err}");
    let said: Vec<&str> = err.lines().filter(|l| l.starts_with("nf: warning:")).collect();
    assert_eq!(said.len(), 11, "{err}");
    assert!(said[0].contains(":4: q1_dph..q4_dph average"), "{err}");
    assert!(said[10].ends_with("2 more warnings like these"), "{err}");
}

#[test]
fn an_azimuth_next_to_north_prints_as_zero_not_360_or_minus_zero() {
    let h = 15.041 * 40f64.to_radians().cos();
    for psi in [0.0, 359.9999999, 1e-9] {
        let mut text =
            String::from("# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n");
        for k in 0..12 {
            let g = 30.0 * k as f64;
            text += &format!("{k},{},{g},{}\n", k + 1, 2.0 + h * (g + psi).to_radians().cos());
        }
        let file = tmp("north.csv");
        std::fs::write(&file, text).unwrap();
        let (code, out, err) = nf(&["fit", &file]);
        assert_eq!(code, 0, "{err}");
        for line in out
            .lines()
            .filter(|l| l.starts_with("azimuth psi") || l.starts_with("surveying az."))
        {
            assert!(line.contains(" 0.00000 deg"), "psi {psi}: {line}");
        }
    }
}

/// A recording at latitude 40 whose dwell means are the Earth rate plus `noise(k)`, in a file
/// whose metadata says `stated_lat`.
fn written(name: &str, stated_lat: f64, noise: impl Fn(usize) -> f64) -> String {
    let h = 15.041 * 40f64.to_radians().cos();
    let mut text = format!("# format = northfinder-recording/1\n# latitude_deg = {stated_lat}\n# dwell_s = 1\n");
    text += "index,t_s,encoder_deg,rate_dph\n";
    for k in 0..36 {
        let g = 10.0 * k as f64;
        text += &format!(
            "{k},{},{g},{}\n",
            1.5 * k as f64 + 0.5,
            2.0 + h * (g + 70.0).to_radians().cos() + noise(k)
        );
    }
    let file = tmp(name);
    std::fs::write(&file, text).unwrap();
    file
}

#[test]
fn an_earth_rate_not_resolved_gives_no_azimuth_in_fit_or_diagnose() {
    // Dwell means scattered 40 deg/h (a Weyl sequence, uniform in -0.5..0.5, sd 0.29):
    // the 11.5 deg/h harmonic is lost in them.
    let hidden = written("hidden.csv", 40.0, |k| 138.0 * ((k as f64 * 0.618_034).fract() - 0.5));
    // Clean, but the metadata's latitude predicts an eighth of the amplitude.
    let wrong_lat = written("wrong_lat.csv", 84.0, |_| 0.0);
    let clean = written("clean.csv", 40.0, |k| 0.01 * ((k as f64 * 0.618_034).fract() - 0.5));
    for (file, why) in [(&hidden, "uncertainty"), (&wrong_lat, "times the Earth rate")] {
        let svg = tmp("unresolved.svg");
        let (code, out, err) = nf(&["fit", file, "--plot", &svg]);
        assert_eq!(code, 0, "{err}");
        assert!(out.contains("NOT RESOLVED") && out.contains(why), "{out}");
        assert!(!out.lines().any(|l| l.starts_with("azimuth psi")), "{out}");
        // The plot's title gives no azimuth either.
        let drawn = std::fs::read_to_string(&svg).unwrap();
        assert!(drawn.contains("NOT RESOLVED") && !drawn.contains("psi ="), "{why}");
        let (_, out, _) = nf(&["fit", file, "--json"]);
        let j: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(j["earth_rate_resolved"], false);
        assert!(
            j["azimuth_deg"].is_null() && j["surveying_azimuth_deg"].is_null(),
            "{j}"
        );
        assert!(j["psi_fitted_deg"].is_f64() && j["not_resolved_because"].as_str().unwrap().contains(why));
        let (code, out, err) = nf(&["diagnose", file]);
        assert_eq!(code, 0, "{err}");
        let last = out.lines().find(|l| l.starts_with("final:")).unwrap();
        assert!(last.starts_with("final: NOT RESOLVED") && last.contains(why), "{out}");
        let (_, out, _) = nf(&["diagnose", file, "--json"]);
        let j: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(j["earth_rate_resolved"], false);
        assert!(
            j["final"]["azimuth_deg"].is_null() && j["final"]["sigma_arcsec"].is_f64(),
            "{j}"
        );
    }
    let (_, out, _) = nf(&["fit", &clean, "--json"]);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["earth_rate_resolved"], true);
    assert!((j["azimuth_deg"].as_f64().unwrap() - 70.0).abs() < 0.01, "{j}");
    let (_, out, _) = nf(&["diagnose", &clean, "--json"]);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(j["earth_rate_resolved"] == true && j["not_resolved_because"].is_null());
    assert!((j["final"]["azimuth_deg"].as_f64().unwrap() - 70.0).abs() < 0.01, "{j}");
}

/// A recording at latitude 43.8 deg, psi 65.5 deg, over `angles`, on a shaft tilted `tilt` deg
/// towards 140 deg, with both inclinometer columns or `tilt_y_deg` alone; `noise(k)` added.
fn tilted(name: &str, angles: &[f64], tilt: f64, y_only: bool, noise: impl Fn(usize) -> f64) -> String {
    let h = 15.041 * 43.8f64.to_radians().cos();
    let columns = if y_only { "tilt_y_deg" } else { "tilt_x_deg,tilt_y_deg" };
    let mut text = format!(
        "# format = northfinder-recording/1\n# latitude_deg = 43.8\n# dwell_s = 2\nindex,t_s,encoder_deg,rate_dph,{columns}\n"
    );
    for (k, g) in angles.iter().enumerate() {
        let (x, y) = (
            -tilt * (g - 140.0f64).to_radians().cos(),
            tilt * (g - 140.0f64).to_radians().sin(),
        );
        let cells = if y_only { format!("{y}") } else { format!("{x},{y}") };
        let rate = 3.0 + h * (g + 65.5f64).to_radians().cos() + noise(k);
        text += &format!("{k},{},{g},{rate},{cells}\n", 2.5 * k as f64 + 1.0);
    }
    let file = tmp(name);
    std::fs::write(&file, text).unwrap();
    file
}

#[test]
fn a_run_that_starts_on_a_repeated_opposite_pair_fits_with_its_tilt() {
    // Visits 10, 190, 10, 190, then 10 to 360 by 10, on a shaft tilted 0.002 deg: the fit
    // once lost its precision on the first four rows and the exact tilt correction then never
    // converged (exit 1, no azimuth).
    let mut angles = vec![10.0, 190.0, 10.0, 190.0];
    angles.extend((1..=36).map(|k| 10.0 * k as f64 % 360.0));
    let file = tilted("repeated_pair.csv", &angles, 0.002, false, |k| {
        0.004 * ((k as f64 * 0.618_034).fract() - 0.5)
    });
    let (code, out, err) = nf(&["fit", &file, "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["tilt_correction"], "exact");
    let z = (j["azimuth_deg"].as_f64().unwrap() - 65.5) * 3600.0 / j["sigma_arcsec"].as_f64().unwrap();
    assert!(z.abs() < 3.0, "{z}: {j}");
}

#[test]
fn first_order_tilt_is_warned_against_at_degrees_and_needs_tilt_x() {
    let turn: Vec<f64> = (0..36).map(|k| 10.0 * k as f64).collect();
    let steep = tilted("steep.csv", &turn, 3.0, false, |_| 0.0);
    let (code, out, err) = nf(&["fit", &steep, "--tilt", "first-order"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("WARNING: the shaft is tilted 3.00 deg"), "{out}");
    let (_, out, _) = nf(&["fit", &steep]);
    assert!(!out.contains("WARNING"), "{out}");
    let gentle = tilted("gentle.csv", &turn, 0.3, false, |_| 0.0);
    let (_, out, _) = nf(&["fit", &gentle, "--tilt", "first-order"]);
    assert!(out.contains("first order") && !out.contains("WARNING"), "{out}");
    let y_only = tilted("y_only.csv", &turn, 0.3, true, |_| 0.0);
    let (code, _, err) = nf(&["fit", &y_only, "--tilt", "first-order"]);
    assert_ne!(code, 0);
    assert!(
        err.contains("reads tilt_x_deg, which the recording does not have"),
        "{err}"
    );
}

#[test]
fn paper_prints_stated_and_recomputed_tables() {
    let (code, out, _) = nf(&["paper"]);
    assert_eq!(code, 0);
    assert!(out.contains("65.5378") && out.contains("65.54658"), "{out}");
    assert!(out.contains("Table 1: the stated mean 65.5378 deg is not the mean of its rows, 65.5466 deg"));
    assert!(out.contains("15.83") && out.contains("10.01"));
    let (code, out, _) = nf(&["paper", "--json"]);
    assert_eq!(code, 0);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["tables"].as_array().unwrap().len(), 4);
    assert!(j["findings"].as_array().unwrap().len() >= 10);
}

#[test]
fn log_turns_a_defmt_log_into_the_same_recording() {
    let (twin, run) = (
        TwinConfig::default(),
        RunConfig {
            positions: 12,
            dwell_ms: 300,
            ..RunConfig::default()
        },
    );
    let mut rec = Recorder::default();
    simulate(&twin, &run, &mut rec);
    let mut log =
        String::from("0.000000 INFO  north finder firmware 0.1.0\n└─ north_finder::firmware @ src/firmware.rs:250\n");
    for (i, l) in rec.lines.iter().enumerate() {
        log += &format!(
            "{}.{:06} INFO  rec {l}\n└─ north_finder::firmware::{{impl#1}}::line @ src/firmware.rs:88\n",
            i, i
        );
        log += "WARN  inclinometer: bad line dropped\n";
    }
    let path = tmp("run.log");
    std::fs::write(&path, &log).unwrap();
    let out = tmp("from-log.csv");
    let (code, _, err) = nf(&["log", &path, "-o", &out]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), rec.text());
    // A position's line logged twice and two lines swapped: the copy dropped, the order the
    // index's, in the file written too (it kept the copy before).
    let mut lines: Vec<String> = rec.lines.iter().map(|l| format!("INFO  rec {l}\n")).collect();
    let at = lines.len() - 4;
    lines.insert(at, lines[at].clone());
    lines.swap(at + 2, at + 3);
    std::fs::write(&path, lines.concat()).unwrap();
    let (code, _, err) = nf(&["log", &path, "-o", &out]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("the copy is dropped") && err.contains("not in the order") && err.contains("after index"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), rec.text());
    // Two runs in one log: listed, and each taken whole with --run.
    let mut second = Recorder::default();
    simulate(
        &TwinConfig { seed: 9, ..twin },
        &RunConfig { positions: 8, ..run },
        &mut second,
    );
    let two = log.clone()
        + &second
            .lines
            .iter()
            .map(|l| format!("INFO  rec {l}\n"))
            .collect::<String>();
    std::fs::write(&path, &two).unwrap();
    let (code, _, err) = nf(&["log", &path]);
    assert_eq!(code, 2);
    assert!(
        err.contains("holds 2 runs") && err.contains("run 2: from log line") && err.contains("8 position lines"),
        "{err}"
    );
    let (code, _, err) = nf(&["log", &path, "--run", "2", "-o", &out]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), second.text());
    let (code, _, err) = nf(&["log", &path, "--run", "3"]);
    assert_eq!(code, 2);
    assert!(err.contains("holds 2 run(s)"), "{err}");
    std::fs::write(&path, "INFO  nothing recorded here\n").unwrap();
    let (code, _, err) = nf(&["log", &path]);
    assert_eq!(code, 2);
    assert!(err.contains("no 'rec' lines"), "{err}");
}

#[test]
fn simulate_rejects_bad_parameters_and_reports_failed_runs() {
    let (code, _, err) = nf(&["simulate", "--n", "2"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = nf(&["simulate", "--lat", "95"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = nf(&["simulate", "--bogus"]);
    assert_eq!(code, 2, "{err}");
    // A gyro far noisier than the converter's range: refused before the run, in words.
    let (code, _, err) = nf(&["simulate", "--n", "8", "--arw", "10"]);
    assert!(
        code == 2 && err.contains("this gyro cannot be read by the ADC") && err.contains("white noise of at most"),
        "{code} {err}"
    );
    let (code, out, _) = nf(&["fit", "--help"]);
    assert_eq!(code, 0);
    assert!(out.contains("--json") && out.contains("--plot"));
}

#[test]
fn simulate_warns_of_a_list_that_visits_unevenly_and_runs_it() {
    let rec = tmp("uneven.csv");
    let (code, _, err) = nf(&[
        "simulate",
        "--n",
        "6",
        "--order",
        "0,1,2,2,5",
        "--dwell",
        "0.2",
        "-o",
        &rec,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("nf: warning: the order visits 4 of the 6 positions (never position 3), each 0 to 2 times"),
        "{err}"
    );
    let rows = std::fs::read_to_string(&rec).unwrap();
    assert_eq!(
        rows.lines().filter(|l| !l.starts_with('#')).count(),
        6,
        "header and 5 dwells"
    );
    let (code, _, err) = nf(&["simulate", "--n", "4", "--order", "0,1,2,3,3,2,1,0", "--dwell", "0.2"]);
    assert!(code == 0 && !err.contains("warning"), "{err}");
}

#[test]
fn diagnose_json_schema_and_bad_inputs() {
    let mut twin = TwinConfig::default();
    twin.instrument.tilt_deg = 0.0;
    twin.bias_jump = Some(nf_twin::BiasJump {
        time_s: 40.0,
        size_dph: 0.1,
    });
    let run = RunConfig {
        positions: 36,
        dwell_ms: 1000,
        tilt_policy: TiltPolicy::Warn,
        ..RunConfig::default()
    };
    let mut rec = Recorder::default();
    simulate(&twin, &run, &mut rec);
    let path = tmp("jump.csv");
    std::fs::write(&path, rec.text()).unwrap();
    let (code, out, err) = nf(&["diagnose", &path, "--json", "--plot", &tmp("diag.svg")]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    for k in ["azimuth_deg", "rss"] {
        assert!(j["baseline"][k].is_f64() && j["final"][k].is_f64(), "{k}");
    }
    // Noise terms come first; the first effect is the jump.
    let f = j["findings"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["noise"] == false)
        .unwrap();
    assert_eq!(f["effect"], "bias_jump");
    assert!(f["parameters"]["size_dph"]["value"].is_f64());
    assert!(f["after"]["rss"].as_f64().unwrap() < j["baseline"]["rss"].as_f64().unwrap());
    assert!(f["after"]["azimuth_deg"].is_f64() && f["noise"] == false);
    assert!(j["noise_model"]["source"].as_str().unwrap().starts_with("estimated"));
    // Each model met is judged under the noise estimated with its own columns.
    let from = j["noise_model"]["final_sigma_from"].as_str().unwrap();
    assert!(from.contains("own columns"), "{from}");
    let calibration = &j["noise_model"]["sigma_calibration"];
    assert!(
        calibration.is_null() || calibration.as_f64().unwrap() >= 1.0,
        "{calibration}"
    );
    let (code, out, err) = nf(&["diagnose", &path, "--json", "--replicates", "0"]);
    assert_eq!(code, 0, "{err}");
    let uncalibrated: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(uncalibrated["noise_model"]["sigma_calibration"].is_null());
    assert_eq!(uncalibrated["final"]["azimuth_deg"], j["final"]["azimuth_deg"]);
    let (code, _, err) = nf(&["diagnose", &path, "--replicates", "-1"]);
    assert_eq!(code, 2, "{err}");
    let weights: f64 = j["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["weight"].as_f64().unwrap())
        .sum();
    assert!((weights - 1.0).abs() < 1e-9, "model weights sum to {weights}");
    let (code, out, _) = nf(&["diagnose", &path]);
    assert_eq!(code, 0);
    assert!(out.contains(". bias_jump (p = ") && out.contains("final:"), "{out}");
    let (code, _, err) = nf(&["diagnose"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = nf(&["diagnose", &path, "--alpha", "1.5"]);
    assert_eq!(code, 2, "{err}");
}
