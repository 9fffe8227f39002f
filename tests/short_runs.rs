//! `nf fit` on runs of three to eight positions: where the noise comes from when the dwell
//! means leave a few contrasts or none.

mod common;
use common::{nf, tmp};

#[test]
fn three_positions_take_their_noise_from_inside_the_dwells() {
    // 0, 120 and 240 deg, 10 s dwells with white noise of 0.03 deg/h a dwell mean: the
    // quarters (0.06 deg/h each) or the samples' spread (0.6 deg/h over 400) measure it, and
    // a sigma of sqrt(2 / 3) 0.03 / 11.52 rad (439") follows, though the fit has no residual.
    let head =
        "# format = northfinder-recording/1\n# latitude_deg = 40\n# dwell_s = 10\nindex,t_s,encoder_deg,rate_dph";
    let quarters = [
        [0.05, -0.07, 0.02, 0.06],
        [-0.04, 0.01, 0.08, -0.05],
        [0.07, 0.03, -0.06, -0.04],
    ];
    let spreads = [0.61, 0.58, 0.6];
    let mut with_quarters = format!("{head},q1_dph,q2_dph,q3_dph,q4_dph\n");
    let mut with_spread = format!("{head},rate_sd_dph,samples\n");
    let mut bare = format!("{head}\n");
    for k in 0..3 {
        let g = 120.0 * k as f64;
        let rate = 15.041 * 40f64.to_radians().cos() * (g + 30.0f64).to_radians().cos() + 0.5;
        let q = quarters[k].map(|e| rate + e);
        let mean = q.iter().sum::<f64>() / 4.0;
        let t = 5 + 12 * k;
        with_quarters += &format!("{k},{t},{g},{mean},{},{},{},{}\n", q[0], q[1], q[2], q[3]);
        with_spread += &format!("{k},{t},{g},{mean},{},400\n", spreads[k]);
        bare += &format!("{k},{t},{g},{mean}\n");
    }
    for (name, text, from) in [
        ("three_quarters.csv", &with_quarters, "quarter means of 3 dwells"),
        ("three_spread.csv", &with_spread, "the samples' spread in 3 dwells"),
    ] {
        let file = tmp(name);
        std::fs::write(&file, text).unwrap();
        let (code, out, err) = nf(&["fit", &file, "--json"]);
        assert_eq!(code, 0, "{name}: {err}");
        let j: serde_json::Value = serde_json::from_str(&out).unwrap();
        let source = j["noise_model"]["source"].as_str().unwrap();
        assert!(
            source.contains(from) && source.contains("white: as many positions as unknowns"),
            "{source}"
        );
        assert_eq!(j["noise_model"]["bias_instability_dph"].as_f64(), Some(0.0), "{name}");
        assert!(
            (29.9..30.1).contains(&j["azimuth_deg"].as_f64().unwrap()),
            "{name}: {out}"
        );
        let sigma = j["sigma_arcsec"].as_f64().unwrap();
        assert!((250.0..800.0).contains(&sigma), "{name}: {sigma}");
        // No residual, so no white least-squares sigma, and nothing far off.
        assert!(
            j["ols"]["sigma_arcsec"].is_null() && j["far_off"] == serde_json::json!([]),
            "{out}"
        );
        let svg = tmp("three.svg");
        let (_, text, _) = nf(&["fit", &file, "--plot", &svg]);
        assert!(
            text.contains("residuals      none: the fit passes through every position"),
            "{text}"
        );
        assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
        // Nor a residual panel of rounding errors.
        let svg = std::fs::read_to_string(&svg).unwrap();
        assert!(svg.contains("gyro output") && !svg.contains("residuals"), "{name}");
    }
    // Without them, a given model does; else the noise cannot be measured.
    let file = tmp("three_bare.csv");
    std::fs::write(&file, &bare).unwrap();
    let (code, out, err) = nf(&["fit", &file, "--arw", "0.00158", "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!((430.0..450.0).contains(&j["sigma_arcsec"].as_f64().unwrap()), "{out}");
    let (code, out, err) = nf(&["fit", &file]);
    assert_eq!((code, out.as_str()), (2, ""));
    assert!(err.contains("3 positions") && err.contains("needs at least 4"), "{err}");
    // A second harmonic has five unknowns: three positions cannot give them, quarters or not.
    let file = tmp("three_quarters.csv");
    let (code, _, err) = nf(&["fit", &file, "--harmonics", "2"]);
    assert_eq!(code, 2);
    assert!(err.contains("needs at least 5"), "{err}");
}

#[test]
fn a_short_run_uses_the_spreads_that_tell_one_and_says_so() {
    // Four positions, no quarters: `rate_sd_dph` with 400 samples on two dwells, and on the
    // others 0 samples and a spread of 0, which say nothing.
    let mut text = String::from(
        "# format = northfinder-recording/1\n# latitude_deg = 40\n# dwell_s = 10\nindex,t_s,encoder_deg,rate_dph,rate_sd_dph,samples\n",
    );
    let noise = [0.02, -0.01, 0.015, -0.03];
    for (k, e) in noise.iter().enumerate() {
        let g = 90.0 * k as f64;
        let rate = 15.041 * 40f64.to_radians().cos() * (g + 30.0f64).to_radians().cos() + 0.5 + e;
        let (sd, samples) = [(0.6, 400), (0.62, 400), (0.5, 0), (0.0, 400)][k];
        text += &format!("{k},{},{g},{rate},{sd},{samples}\n", 5 + 12 * k);
    }
    let file = tmp("short_spread.csv");
    std::fs::write(&file, &text).unwrap();
    let (code, out, err) = nf(&["fit", &file, "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let source = j["noise_model"]["source"].as_str().unwrap();
    assert!(source.contains("the samples' spread in 2 dwells"), "{source}");
    // 0.03 deg/h a dwell mean over an amplitude of 11.5 deg/h, four positions: 0.0037 rad.
    let sigma = j["sigma_arcsec"].as_f64().unwrap();
    assert!((400.0..1500.0).contains(&sigma), "{sigma}");
    // The mean's standard error written in place of the samples' spread (0.6 / sqrt(400)):
    // the dwell means scatter hundreds of times what it gives, and it is left out.
    std::fs::write(
        &file,
        text.replace(",0.6,400", ",0.03,400").replace(",0.62,400", ",0.031,400"),
    )
    .unwrap();
    let (code, out, err) = nf(&["fit", &file, "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let source = j["noise_model"]["source"].as_str().unwrap();
    assert!(
        source.contains("the samples' spread left out: the dwell means scatter"),
        "{source}"
    );
    assert!(
        source.contains("Student's t of 1 dof, which has no finite variance"),
        "{source}"
    );
    assert!(j["sigma_arcsec"].as_f64().unwrap() > 400.0, "{out}");
}

#[test]
fn four_bare_positions_read_their_sigma_off_students_t_and_are_never_said_unresolved_for_it() {
    // One residual contrast, no quarters or spread: the 40 replicates' RMS of error/sigma was
    // a draw from a Cauchy tail (a sigma scaled 825 times, 25.6 deg, said unresolved).
    let mut text = String::from(
        "# format = northfinder-recording/1\n# latitude_deg = -0.89\n# dwell_s = 1\nindex,t_s,encoder_deg,rate_dph\n",
    );
    for (k, rate) in [-7.359758930, -11.781728188, 9.041126886, 13.440634517]
        .iter()
        .enumerate()
    {
        text += &format!("{k},{},{},{rate}\n", 0.5 + 3.0 * k as f64, 90 * k);
    }
    let file = tmp("four_bare.csv");
    std::fs::write(&file, &text).unwrap();
    let (code, out, err) = nf(&["fit", &file, "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["earth_rate_resolved"], true, "{out}");
    // Student's t of one dof: 12.706 / 1.96 times the least-squares sigma.
    let ratio = j["sigma_arcsec"].as_f64().unwrap() / j["ols"]["sigma_arcsec"].as_f64().unwrap();
    assert!((ratio - 6.4827).abs() < 1e-3, "{ratio}");
    assert_eq!(j["noise_model"]["sigma_calibration"], serde_json::Value::Null);
    let source = j["noise_model"]["source"].as_str().unwrap();
    assert!(
        source.contains("Student's t of 1 dof") && source.contains("1.96 sigma"),
        "{source}"
    );
    let (code, text_out, _) = nf(&["fit", &file]);
    assert_eq!(code, 0);
    assert!(
        text_out.contains("widened 6.48 times: Student's t of 1 dof"),
        "{text_out}"
    );
}

#[test]
fn eight_bare_positions_in_opposite_pairs_take_no_walk_for_their_noise() {
    // White noise of 0.005 deg/h a dwell mean (an outside audit's writer). Over five contrasts
    // a walk without white noise was the most likely model, and in opposite pairs it gave
    // 27" where white least squares gives 127" and the error was 70".
    let mut text = String::from(
        "# format = northfinder-recording/1\n# latitude_deg = -69.64232738407402\n# dwell_s = 2\nindex,t_s,encoder_deg,rate_dph\n",
    );
    let rates = [
        5.4101041, -4.7966624, 3.0901379, -2.4834177, -0.8626281, 1.4613279, -4.1389231, 4.7251761,
    ];
    for (k, rate) in rates.iter().enumerate() {
        let (t, g) = (2.0 + 2.7 * k as f64, 45 * (k / 2) + 180 * (k % 2));
        text += &format!("{k},{t},{g},{rate}\n");
    }
    let file = tmp("eight_bare_pairs.csv");
    std::fs::write(&file, &text).unwrap();
    let (code, out, err) = nf(&["fit", &file, "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    // Student's t of five dof: 2.5706 / 1.96 times the least-squares sigma.
    let ratio = j["sigma_arcsec"].as_f64().unwrap() / j["ols"]["sigma_arcsec"].as_f64().unwrap();
    assert!((ratio - 1.3116).abs() < 1e-3, "{ratio}");
    let source = j["noise_model"]["source"].as_str().unwrap();
    assert!(
        source.contains("Student's t of 5 dof, whose variance is 1.67 times the normal's"),
        "{source}"
    );
}
