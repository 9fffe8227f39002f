//! `nf plan` through the binary: the white budget, its Monte Carlo and its plot, every visit
//! of a forward-back run counted, and the fastest run under flicker with its balanced orders.

mod common;
use common::{nf, tmp};

#[test]
fn plan_budget_target_and_monte_carlo() {
    let (code, out, err) = nf(&["plan", "--target", "15", "--mc-runs", "300", "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let paper = j["budget_eq31_paper"]["total_arcsec"].as_f64().unwrap();
    let exact = j["budget_exact"]["total_arcsec"].as_f64().unwrap();
    assert!(
        (paper - 16.27).abs() < 0.01 && (exact - 18.93).abs() < 0.01,
        "{paper} {exact}"
    );
    assert!(j["fastest"]["n"].as_u64().unwrap() >= 4);
    // Equal thirds: the gyro allowance alone gives 15 / sqrt(3) = 8.66" by Eq. 24 at n = 72.
    let g = j["allowance_for_target"]["gyro_dph"].as_f64().unwrap();
    assert!(
        (nf_model::paper::eq24_arcsec(72, g, 43.8) - 15.0 / 3f64.sqrt()).abs() < 1e-6,
        "{g}"
    );
    let mc = &j["monte_carlo"];
    assert!((mc["sd_arcsec"].as_f64().unwrap() / mc["formula_arcsec"].as_f64().unwrap() - 1.0).abs() < 0.15);
    let (code, out, _) = nf(&["plan", "--target", "1", "--mc-runs", "0"]);
    assert_eq!(code, 0);
    assert!(out.contains("not reachable"), "{out}");
    // The target's answer comes first, the run of the defaults (n = 72) after it as that.
    let (_, out, _) = nf(&["plan", "--target", "15", "--mc-runs", "0"]);
    assert!(
        out.starts_with("target 15\": fastest run under the noise model: "),
        "{out}"
    );
    assert!(
        out.contains("\nthe run of --n, --dwell and --order: n = 72, dwell 2 s"),
        "{out}"
    );
    assert!(!out.contains("planned run"), "{out}");
    // The plan's sigma assumes the fit knows the noise model: it says so.
    assert!(
        out.contains("these sigmas are GLS's under the noise model given: fit the run with it"),
        "{out}"
    );
    let (_, out, _) = nf(&["plan", "--mc-runs", "0"]);
    assert!(out.starts_with("planned run: n = 72, dwell 2 s"), "{out}");
    // A sensor's short filter tail (an outside audit: the ADIS16405 as nf allan fits it) is
    // each position's own noise: in the white budgets, 0.00988 deg/h at 1 s, not 0.00763.
    let adis = ["--arw", "1.272e-4", "--gm-sigma", "0.04441", "--gm-tau", "0.01"];
    let (code, out, err) = nf(&[&["plan", "--mc-runs", "0", "--dwell", "1", "--json"][..], &adis].concat());
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let g = j["gyro_dph_per_position"].as_f64().unwrap();
    assert!((g - 0.00988).abs() < 2e-5, "{g}");
    let (_, out, _) = nf(&[&["plan", "--mc-runs", "0", "--dwell", "1"][..], &adis].concat());
    assert!(
        out.contains(" deg/h per position with its 0.01 s Gauss-Markov tail)"),
        "{out}"
    );
    let (code, _, err) = nf(&["plan", "--n", "2"]);
    assert_eq!(code, 2, "{err}");
    // The plot, as SVG and as PNG.
    for (name, magic) in [("plan.svg", &b"<svg"[..]), ("plan.png", &b"\x89PNG"[..])] {
        let path = tmp(name);
        let (code, _, err) = nf(&["plan", "--target", "15", "--mc-runs", "0", "--plot", &path]);
        assert_eq!(code, 0, "{err}");
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.windows(magic.len()).take(200).any(|w| w == magic), "{name}");
    }
    // The search's answer is marked beside the run asked (an outside audit: the plot showed
    // only the default n = 72 run).
    let svg = std::fs::read_to_string(tmp("plan.svg")).unwrap();
    assert!(svg.contains("fastest: "), "{svg}");
}

#[test]
fn plan_white_budgets_count_every_visit_of_a_forward_back_run() {
    let gyro = |order: &str, key: &str| {
        let args = [
            "plan",
            "--arw",
            "0.001",
            "--n",
            "72",
            "--dwell",
            "2",
            "--tilt",
            "0",
            "--encoder",
            "0",
        ];
        let (code, out, err) = nf(&[&args[..], &["--order", order, "--mc-runs", "0", "--json"]].concat());
        assert_eq!(code, 0, "{err}");
        let j: serde_json::Value = serde_json::from_str(&out).unwrap();
        j[key]["gyro_arcsec"].as_f64().unwrap()
    };
    let sequential = gyro("sequential", "budget_exact");
    for key in [
        "budget_eq31_paper",
        "budget_exact",
        "budget_numerical",
        "budget_noise_model",
    ] {
        let fb = gyro("forward-back", key);
        assert!(
            (fb * 2f64.sqrt() / sequential - 1.0).abs() < 1e-3,
            "{key}: {fb} against {sequential}"
        );
    }
}

#[test]
fn plan_under_flicker_finds_balanced_orders_and_says_when_out_of_reach() {
    // The paper's gyro with flicker, a motor that turns half a turn in 0.5 s, no tilt residue.
    let fast = [
        "--tilt",
        "0",
        "--max-sps",
        "40000",
        "--accel",
        "400000",
        "--mc-runs",
        "0",
    ];
    let args = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v = vec!["plan", "--bias-instability", "0.004", "--json"];
        v.extend_from_slice(&fast);
        v.extend_from_slice(extra);
        v
    };
    let (code, out, err) = nf(&args(&["--target", "18", "--twin-runs", "6"]));
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["fastest"]["order"], "opposite-pairs", "{out}");
    // The twin ran the fastest run; its scatter over 6 runs is known to about 30 %.
    let twin = &j["twin_check"];
    assert_eq!(
        (twin["runs"].as_u64(), twin["n"].clone()),
        (Some(6), j["fastest"]["n"].clone())
    );
    let ratio = twin["rms_error_arcsec"].as_f64().unwrap() / twin["stated_gyro_arcsec"].as_f64().unwrap();
    assert!((0.3..2.0).contains(&ratio), "{twin}");
    let t = j["fastest"]["time_s"].as_f64().unwrap();
    assert!(
        t < 250.0 && j["fastest"]["sigma_arcsec"].as_f64().unwrap() <= 18.0,
        "{out}"
    );
    // The orders that never reach it are stated at their best: the sequential floor.
    let short = j["floor_per_order_short_of_target"].as_array().unwrap();
    let seq_floor = short
        .iter()
        .find(|c| c["order"] == "sequential")
        .expect("sequential is short of 18\"");
    assert!(seq_floor["sigma_arcsec"].as_f64().unwrap() > 18.0, "{out}");
    assert!(short.iter().all(|c| c["order"] != "opposite-pairs"), "{out}");
    // A sequential run of the paper's size scatters far more than white noise says.
    let seq = j["budget_noise_model"]["gyro_arcsec"].as_f64().unwrap();
    assert!(seq > 2.0 * j["budget_exact"]["gyro_arcsec"].as_f64().unwrap(), "{out}");
    let (code, out, _) = nf(&args(&["--target", "3", "--max-time", "400"]));
    assert_eq!(code, 0);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(
        j["fastest"].is_null()
            && j["floor"]["sigma_arcsec"].as_f64().unwrap() > 3.0
            && j["floor"]["time_s"].as_f64().unwrap() <= 400.0,
        "{out}"
    );
    // The text names the limit the best run stands at: the time allowed, or the most positions.
    let text = |noise: [&'static str; 2], extra: &[&'static str]| {
        let mut v = vec!["plan", noise[0], noise[1]];
        v.extend_from_slice(&fast);
        v.extend_from_slice(extra);
        nf(&v).1
    };
    let out = text(["--bias-instability", "0.004"], &["--target", "3", "--max-time", "400"]);
    assert!(
        out.contains("target 3\": not reachable with this gyro and motor in runs up to 400 s (--max-time)"),
        "{out}"
    );
    // No run fits in the time allowed: the time is named, not the gyro and motor alone.
    let out = text(["--bias-instability", "0.004"], &["--target", "15", "--max-time", "5"]);
    assert!(
        out.contains("target 15\": not reachable with this gyro and motor in runs up to 5 s (--max-time): the shortest run searched takes"),
        "{out}"
    );
    // At the most positions and the longest run: a longer dwell still gains, so the time binds.
    let out = text(["--bias-instability", "0.004"], &["--target", "2.5"]);
    assert!(
        out.contains(
            "target 2.5\": not reachable with this gyro and motor in runs up to 14400 s (--max-time) at 720 positions"
        ),
        "{out}"
    );
    let out = text(["--rrw", "0.3"], &["--target", "5"]);
    assert!(
        out.contains("target 5\": not reachable with this gyro and motor in runs of up to 720 positions, the most a plan takes: the best is opposite-pairs order, n = 720"),
        "{out}"
    );
    let (code, _, err) = nf(&["plan", "--bias-instability", "-1"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--bias-instability"), "{err}");
    // A motor of fewer steps a turn than positions would visit one angle twice.
    let (code, _, err) = nf(&["plan", "--steps-per-rev", "3"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--steps-per-rev"), "{err}");
    let (code, _, err) = nf(&["plan", "--steps-per-rev", "16", "--n", "72"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--n 72: more positions than the motor's 16 steps a turn"),
        "{err}"
    );
    let (code, out, err) = nf(&[
        "plan",
        "--steps-per-rev",
        "16",
        "--n",
        "8",
        "--target",
        "15",
        "--mc-runs",
        "0",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let most = j["fastest_per_order"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["n"].as_u64().unwrap())
        .max();
    assert!(most.is_some_and(|n| n <= 16), "{out}");
    let (code, _, err) = nf(&["plan", "--order", "spiral"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = nf(&["plan", "--order", "0,2,4,6,1,3,5,7"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("visits 8 of the 72 positions, leaving the rest out"),
        "{err}"
    );
    let (code, _, err) = nf(&["plan", "--n", "4", "--order", "0,1,2,3,0"]);
    assert!(code == 2 && err.contains("some more often than others"), "{err}");
    let (code, out, err) = nf(&["plan", "--n", "4", "--order", "0,2,1,3,3,1,2,0"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains(", 2 visits and 4 s of dwell per position"), "{out}");
}
