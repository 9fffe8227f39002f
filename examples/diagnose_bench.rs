//! Benchmark of `nf diagnose` on long recordings: the CPU time of one diagnosis against the
//! number of positions, which the semiseparable noise likelihood makes linear.
//!
//! `cargo run --release --example diagnose_bench -- [n ...]` (default 720 2000 5000 20000).
//! Each recording turns the shaft by 0.5 deg per position (so runs past 720 positions make
//! several turns), 1 s dwells 1.2 s apart, with white noise of 0.02 deg/h per quarter dwell
//! and a rate random walk of 0.0005 deg/h per position; written in the recording format and
//! read back by its reader, as `nf diagnose` reads a file.

use nf::diagnose::{Options, diagnose};
use nf::recording::Recording;
use nf_model::rng::Rng;
use std::fmt::Write;
use std::time::Instant;

const LATITUDE_DEG: f64 = 43.8;
const PSI_DEG: f64 = 65.5;

fn recording(n: usize, seed: u64) -> String {
    let mut rng = Rng::new(seed);
    let amplitude = 15.041_067 * LATITUDE_DEG.to_radians().cos();
    let mut text = format!(
        "# format = northfinder-recording/1\n# latitude_deg = {LATITUDE_DEG}\n# dwell_s = 1.000\n\
         # sample_rate_hz = 1000\n# positions = {n}\nindex,t_s,encoder_deg,rate_dph,q1_dph,q2_dph,q3_dph,q4_dph\n"
    );
    let mut bias = 3.0;
    for i in 0..n {
        let gamma = (i as f64 * 0.5) % 360.0;
        bias += 0.0005 * rng.gauss();
        let rate = amplitude * (gamma + PSI_DEG).to_radians().cos() + bias;
        let q: [f64; 4] = core::array::from_fn(|_| rate + 0.02 * rng.gauss());
        let mean = q.iter().sum::<f64>() / 4.0;
        let _ = writeln!(
            text,
            "{i},{:.3},{gamma:.7},{mean:.6},{:.6},{:.6},{:.6},{:.6}",
            5.0 + 1.2 * i as f64,
            q[0],
            q[1],
            q[2],
            q[3]
        );
    }
    text
}

fn main() {
    let sizes: Vec<usize> = std::env::args().skip(1).filter_map(|s| s.parse().ok()).collect();
    let sizes = if sizes.is_empty() {
        vec![720, 2000, 5000, 20000]
    } else {
        sizes
    };
    println!("positions   seconds   final psi error   final sigma");
    for n in sizes {
        let rec = Recording::parse(&recording(n, n as u64)).expect("the bench writes the format");
        let start = Instant::now();
        let d = diagnose(&rec, &Options::default()).expect("a long sequential run diagnoses");
        let secs = start.elapsed().as_secs_f64();
        let err = ((d.final_.azimuth_deg - PSI_DEG + 540.0) % 360.0 - 180.0) * 3600.0;
        println!("{n:>9} {secs:>9.2} {err:>16.1}\" {:>12.1}\"", d.final_.sigma_arcsec);
    }
}
