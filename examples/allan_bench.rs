//! Benchmark of `nf allan`'s fit on twin static logs: for each noise case, over many seeds,
//! the mean and spread of the fitted N, B, K, the RMS of (fitted - true) / stated sigma, and
//! how often quantisation or a Gauss-Markov term was (falsely) kept.
//!
//! `cargo run --release --example allan_bench -- [seeds]` (default 100): 4 h logs at 10 Hz.

use nf::allan_fit::{AllanFit, Term, fit_series};
use nf::allan_model::Sampling;
use nf_model::noise::NoiseModel;
use nf_twin::StaticLog;

const TERMS: [(Term, &str); 3] = [(Term::Arw, "N"), (Term::BiasInstability, "B"), (Term::Rrw, "K")];

fn truth_of(m: &NoiseModel, t: Term) -> f64 {
    match t {
        Term::Arw => m.arw_deg_rth,
        Term::BiasInstability => m.bias_instability_dph,
        _ => m.rrw_dph_rth,
    }
}

fn fit(noise: NoiseModel, seed: u64) -> AllanFit {
    let log = StaticLog {
        noise,
        rate_dph: 7.3,
        sample_rate_hz: 10.0,
        duration_s: 4.0 * 3600.0,
        seed,
    };
    let mut y = Vec::new();
    log.samples(|_, r| y.push(r));
    fit_series(&[&y], Sampling::contiguous(0.1)).expect("a 4 h log fits").1
}

fn main() {
    let seeds: u64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let white = NoiseModel {
        arw_deg_rth: 0.002,
        ..NoiseModel::WHITE_NONE
    };
    let cases = [
        (
            "N + B + K",
            NoiseModel {
                bias_instability_dph: 0.02,
                rrw_dph_rth: 0.05,
                ..white
            },
        ),
        (
            "N + B",
            NoiseModel {
                bias_instability_dph: 0.02,
                ..white
            },
        ),
        ("N only", white),
    ];
    println!("{seeds} seeds per case, 4 h at 10 Hz; per term: true, mean fitted +- sd, RMS z (nonzero terms)");
    for (name, truth) in cases {
        let fits: Vec<AllanFit> = (0..seeds).map(|s| fit(truth, 1000 + s)).collect();
        let k = seeds as f64;
        let mut line = format!("{name:<10}");
        for (t, label) in TERMS {
            let v: Vec<(f64, f64)> = fits
                .iter()
                .map(|f| f.param(t).map_or((0.0, 0.0), |p| (p.value, p.sigma)))
                .collect();
            let mean = v.iter().map(|x| x.0).sum::<f64>() / k;
            let sd = (v.iter().map(|x| (x.0 - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
            let tv = truth_of(&truth, t);
            let z = (v.iter().map(|x| ((x.0 - tv) / x.1).powi(2)).sum::<f64>() / k).sqrt();
            let z = if tv > 0.0 { format!("z {z:.2}") } else { "-".into() };
            line += &format!(" | {label} {tv}: {mean:.6} +- {sd:.6} {z}");
        }
        let q = fits.iter().filter(|f| f.model.quantization_arcsec > 0.0).count();
        let gm = fits.iter().filter(|f| f.gm().is_some()).count();
        let chi = fits.iter().map(|f| f.chi2 / f.dof as f64).sum::<f64>() / k;
        println!("{line} | Q kept {q}, GM kept {gm}, mean chi2/dof {chi:.2}");
    }
}
