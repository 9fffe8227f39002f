//! Benchmark of `nf diagnose` on long recordings: the CPU time of one diagnosis against the
//! number of positions, which the semiseparable noise likelihood makes linear.
//!
//! `cargo run --release --example diagnose_bench -- [n ...]` (default 720 2000 5000 20000).
//! Each recording turns the shaft by 0.5 deg per position (so runs past 720 positions make
//! several turns), 1 s dwells 1.2 s apart, with white noise of 0.02 deg/h per quarter dwell
//! and a rate random walk of 0.0005 deg/h per position; written in the recording format and
//! read back by its reader, as `nf diagnose` reads a file.
//!
//! `cargo run --release --example diagnose_bench -- file REC...`: the same times for recordings
//! on disk, with their replicates skipped (as `nf diagnose --replicates 0`).
//!
//! `cargo run --release --example diagnose_bench -- honesty N RUNS`: the RMS of final
//! error/sigma over RUNS recordings of N positions with white noise only, with the walk, and
//! with five Gauss-Markov terms of 0.01 deg/h, one per decade of time from 10 s to 10^5 s
//! (flicker-like).

use nf::diagnose::{Options, diagnose};
use nf::recording::Recording;
use nf_model::rng::Rng;
use nf_twin::QuarteredRecording;
use std::collections::BTreeMap;
use std::time::Instant;

const LATITUDE_DEG: f64 = 43.8;
const PSI_DEG: f64 = 65.5;

/// The bias wander of a bench recording (`White`: none, white noise only).
#[derive(Debug, Clone, Copy)]
enum Wander {
    White,
    Walk,
    Decades,
}

fn recording(n: usize, seed: u64, wander: Wander) -> String {
    let mut rng = Rng::new(seed);
    let amplitude = 15.041_067 * LATITUDE_DEG.to_radians().cos();
    let mut rec = QuarteredRecording::new(LATITUDE_DEG, 1.0, 1000.0);
    let mut bias = 3.0;
    let mut terms = [0.0f64; 5];
    for i in 0..n {
        let gamma = (i as f64 * 0.5) % 360.0;
        match wander {
            Wander::White => {}
            Wander::Walk => bias += 0.0005 * rng.gauss(),
            Wander::Decades => {
                for (k, g) in terms.iter_mut().enumerate() {
                    let a = (-1.2 / 10f64.powi(k as i32 + 1)).exp();
                    *g = a * *g + 0.01 * (1.0 - a * a).sqrt() * rng.gauss();
                }
                bias = 3.0 + terms.iter().sum::<f64>();
            }
        }
        let rate = amplitude * (gamma + PSI_DEG).to_radians().cos() + bias;
        let q: [f64; 4] = core::array::from_fn(|_| rate + 0.02 * rng.gauss());
        rec.position(5.0 + 1.2 * i as f64, gamma, q);
    }
    rec.text().to_string()
}

/// Final azimuth error against the truth, arcsec.
fn error_arcsec(azimuth_deg: f64) -> f64 {
    ((azimuth_deg - PSI_DEG + 540.0) % 360.0 - 180.0) * 3600.0
}

fn honesty(n: usize, runs: u64) {
    println!("{n} positions, {runs} runs: RMS error, RMS sigma, RMS error/sigma, effects named");
    for wander in [Wander::White, Wander::Walk, Wander::Decades] {
        let (mut e2, mut s2, mut z2) = (0.0, 0.0, 0.0);
        let mut named: BTreeMap<&str, usize> = BTreeMap::new();
        for seed in 1..=runs {
            let rec = Recording::parse(&recording(n, 1000 + seed, wander)).expect("the bench writes the format");
            let d = diagnose(&rec, &Options::default()).expect("a long sequential run diagnoses");
            let err = error_arcsec(d.final_.azimuth_deg);
            e2 += err * err;
            s2 += d.final_.sigma_arcsec.powi(2);
            z2 += (err / d.final_.sigma_arcsec).powi(2);
            for f in d.findings.iter().filter(|f| !f.effect.is_noise()) {
                *named.entry(f.effect.name()).or_default() += 1;
            }
        }
        let rms = |v: f64| (v / runs as f64).sqrt();
        println!(
            "{:>9?} {:>8.1}\" {:>8.1}\" {:>6.2}   {named:?}",
            wander,
            rms(e2),
            rms(s2),
            rms(z2)
        );
    }
}

fn files(paths: &[String]) {
    println!("recording   seconds   noise estimate   selection (steps)   per step");
    for path in paths {
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let rec = Recording::parse(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
        let opt = Options {
            replicates: 0,
            ..Options::default()
        };
        let start = Instant::now();
        let d = diagnose(&rec, &opt).unwrap_or_else(|e| panic!("{path}: {e}"));
        let secs = start.elapsed().as_secs_f64();
        let t = d.timing;
        println!(
            "{path} {secs:>9.2} {:>14.1}ms {:>13.1}ms ({}) {:>9.1}ms",
            t.noise_s * 1e3,
            t.selection_s * 1e3,
            t.selection_steps,
            t.selection_s * 1e3 / t.selection_steps.max(1) as f64
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("honesty") {
        let n = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(5000);
        let runs = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20);
        honesty(n, runs);
        return;
    }
    if args.first().map(String::as_str) == Some("file") {
        files(&args[1..]);
        return;
    }
    let sizes: Vec<usize> = args.iter().filter_map(|s| s.parse().ok()).collect();
    let sizes = if sizes.is_empty() {
        vec![720, 2000, 5000, 20000]
    } else {
        sizes
    };
    println!("positions   seconds   noise estimate   selection (steps)   final psi error   final sigma");
    for n in sizes {
        let rec = Recording::parse(&recording(n, n as u64, Wander::Walk)).expect("the bench writes the format");
        let start = Instant::now();
        let d = diagnose(&rec, &Options::default()).expect("a long sequential run diagnoses");
        let secs = start.elapsed().as_secs_f64();
        let err = error_arcsec(d.final_.azimuth_deg);
        let t = d.timing;
        println!(
            "{n:>9} {secs:>9.2} {:>14.1}ms {:>13.1}ms ({}) {err:>16.1}\" {:>12.1}\"",
            t.noise_s * 1e3,
            t.selection_s * 1e3,
            t.selection_steps,
            d.final_.sigma_arcsec
        );
    }
}
