//! Dwells of different lengths: each dwell mean weighed by its own white variance, which its
//! `samples` give. An outside audit's run of alternating 0.5 s and 8 s dwells was fitted as if
//! every dwell were alike: 37.1" RMS where weighted least squares gives 19.7".

mod common;
use common::{nf, tmp};
use nf_model::rng::Rng;

const WE: f64 = 15.041;

/// A sweep of 36 positions, dwells alternating 100 and 1600 samples at 200 Hz, white noise of
/// 0.004 deg/h for the 8 s mean, quarter means written: this writer's own, from the format.
fn recording(seed: u64, psi: f64) -> String {
    let mut rng = Rng::new(seed);
    let lat: f64 = 40.0;
    let mut text = String::from(
        "# format = northfinder-recording/1\n# latitude_deg = 40\n# sample_rate_hz = 200\nindex,t_s,encoder_deg,rate_dph,samples,q1_dph,q2_dph,q3_dph,q4_dph\n",
    );
    let mut t = 0.0;
    for i in 0..36 {
        let samples = if i % 2 == 0 { 100 } else { 1600 };
        let dwell = f64::from(samples) / 200.0;
        let gamma = 10.0 * i as f64;
        let rate = WE * lat.to_radians().cos() * (gamma + psi).to_radians().cos() + 0.5;
        // A quarter has four times the variance of its dwell's mean.
        let sd_quarter = 2.0 * 0.004 * (8.0 / dwell).sqrt();
        let q: Vec<f64> = (0..4).map(|_| rate + sd_quarter * rng.gauss()).collect();
        let mean = q.iter().sum::<f64>() / 4.0;
        t += 1.0 + dwell / 2.0;
        text += &format!(
            "{i},{t:.3},{gamma},{mean:.7},{samples},{:.7},{:.7},{:.7},{:.7}\n",
            q[0], q[1], q[2], q[3]
        );
        t += dwell / 2.0;
    }
    text
}

#[test]
fn each_dwell_mean_is_weighed_by_its_samples() {
    let mut rng = Rng::new(3);
    let (mut err2, mut ols2, mut z2, runs) = (0.0, 0.0, 0.0, 30);
    for seed in 0..runs {
        let psi = rng.uniform(0.0, 360.0);
        let file = tmp(&format!("dwells_{seed}.csv"));
        std::fs::write(&file, recording(100 + seed, psi)).unwrap();
        let (code, out, err) = nf(&["fit", &file, "--json"]);
        assert_eq!(code, 0, "{err}");
        let j: serde_json::Value = serde_json::from_str(&out).unwrap();
        let off = |v: &serde_json::Value| ((v.as_f64().unwrap() - psi + 540.0).rem_euclid(360.0) - 180.0) * 3600.0;
        let e = off(&j["azimuth_deg"]);
        err2 += e * e;
        ols2 += off(&j["ols"]["azimuth_deg"]).powi(2);
        z2 += (e / j["sigma_arcsec"].as_f64().unwrap()).powi(2);
        assert_eq!(j["noise_model"]["dwell_range_s"], serde_json::json!([0.5, 8.0]));
    }
    let (rms, ols, z) = (
        (err2 / runs as f64).sqrt(),
        (ols2 / runs as f64).sqrt(),
        (z2 / runs as f64).sqrt(),
    );
    println!("RMS error {rms:.1}\" (unweighted least squares {ols:.1}\"), RMS error/sigma {z:.2}");
    // Weighted, the azimuth's variance is about a third of the unweighted one's here.
    assert!(rms < 0.75 * ols, "{rms} {ols}");
    assert!((0.7..1.3).contains(&z), "{z}");
}
