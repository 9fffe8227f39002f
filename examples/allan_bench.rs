//! Benchmark of `nf allan`'s fit on twin static logs: for each noise case, over many seeds,
//! the mean and spread of the fitted N, B, K, the RMS of (fitted - true) over the side of the
//! stated interval towards the truth, how often that 68 % interval holds the truth, and how
//! often quantisation or a Gauss-Markov term was (falsely) kept.
//!
//! `cargo run --release --example allan_bench -- [seeds] [hours] [rate_hz]` (default 100 seeds
//! of 4 h logs at 10 Hz); `CASE="N + GM"` runs one case.

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

/// How long the logs are and how fast they are sampled.
#[derive(Clone, Copy)]
struct Length {
    hours: f64,
    rate_hz: f64,
}

fn fit(noise: NoiseModel, seed: u64, len: Length) -> AllanFit {
    let log = StaticLog {
        noise,
        rate_dph: 7.3,
        sample_rate_hz: len.rate_hz,
        duration_s: len.hours * 3600.0,
        seed,
    };
    let mut y = Vec::new();
    log.samples(|_, r| y.push(r));
    fit_series(&[&y], Sampling::contiguous(1.0 / len.rate_hz), None)
        .expect("the log fits")
        .1
}

fn main() {
    let arg = |i: usize| std::env::args().nth(i).and_then(|s| s.parse::<f64>().ok());
    let seeds = arg(1).unwrap_or(100.0) as u64;
    let only = std::env::var("CASE").ok();
    let len = Length {
        hours: arg(2).unwrap_or(4.0),
        rate_hz: arg(3).unwrap_or(10.0),
    };
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
            "N + K",
            NoiseModel {
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
        (
            "N + GM",
            NoiseModel {
                gm_sigma_dph: 0.01,
                gm_tau_s: 300.0,
                ..white
            },
        ),
        ("N only", white),
    ];
    println!(
        "{seeds} seeds per case, {} h at {} Hz; per term: true, mean fitted +- sd, RMS z and how many 68 % intervals hold the truth (nonzero terms)",
        len.hours, len.rate_hz
    );
    for (name, truth) in cases {
        if only.as_deref().is_some_and(|c| c != name) {
            continue;
        }
        let fits: Vec<AllanFit> = (0..seeds).map(|s| fit(truth, 1000 + s, len)).collect();
        let k = seeds as f64;
        let mut line = format!("{name:<10}");
        for (t, label) in TERMS {
            let params: Vec<_> = fits.iter().filter_map(|f| f.param(t)).collect();
            let mean = params.iter().map(|p| p.value).sum::<f64>() / k;
            let sd = (params.iter().map(|p| (p.value - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
            let tv = truth_of(&truth, t);
            let z2 = params.iter().map(|p| p.error_over_sigma(tv).powi(2)).sum::<f64>();
            let inside = params.iter().filter(|p| p.holds(tv)).count();
            let z = if tv > 0.0 {
                format!("z {:.2}, in {inside}", (z2 / k).sqrt())
            } else {
                "-".into()
            };
            line += &format!(" | {label} {tv}: {mean:.6} +- {sd:.6} {z}");
        }
        let q = fits.iter().filter(|f| f.model.quantization_arcsec > 0.0).count();
        let gm = fits.iter().filter(|f| f.gm().is_some()).count();
        let ramp = fits.iter().filter(|f| f.ramp().is_some()).count();
        let chi = fits.iter().map(|f| f.chi2 / f.dof as f64).sum::<f64>() / k;
        println!("{line} | Q kept {q}, GM kept {gm}, ramp kept {ramp}, mean chi2/dof {chi:.2}");
    }
}
