//! Benchmark of `nf fit` through gyro noise: for white, flicker-dominated, random-walk-dominated
//! and Gauss-Markov noise, over many twin runs of the paper's instrument (72 positions of 2 s at
//! 43.8 deg), the RMS of error/sigma and the RMS error of the GLS fit (noise estimated from the
//! recording), of white-noise least squares, and of GLS that knows the true noise model.
//!
//! `cargo run --release --example noise_bench -- [seeds]` (default 100).

use nf::analysis::{Options, analyse};
use nf::noise_fit::NoiseChoice;
use nf::recording::Recording;
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_model::angle::wrap_180;
use nf_model::noise::NoiseModel;
use nf_twin::{Recorder, Rng, TwinConfig, simulate};

/// The paper's gyro: 0.005 deg/h for a 2 s dwell mean.
const SW: f64 = 0.005;

#[derive(Default)]
struct Acc {
    z2: f64,
    e2: f64,
}

impl Acc {
    fn add(&mut self, err: f64, sigma: f64) {
        self.z2 += (err / sigma).powi(2);
        self.e2 += err * err;
    }
    fn rms(&self, k: f64) -> (f64, f64) {
        ((self.z2 / k).sqrt(), (self.e2 / k).sqrt())
    }
}

fn main() {
    let seeds: u64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let white = NoiseModel::white(SW, 2.0);
    let cases = [
        ("white", white),
        (
            "flicker B = 0.8 sw (the paper's Table 1)",
            NoiseModel {
                bias_instability_dph: 0.004,
                ..white
            },
        ),
        (
            "flicker B = 3 sw",
            NoiseModel {
                bias_instability_dph: 3.0 * SW,
                ..white
            },
        ),
        (
            "random walk K = 0.3 deg/h/rt(h)",
            NoiseModel {
                rrw_dph_rth: 0.3,
                ..white
            },
        ),
        (
            "Gauss-Markov 3 sw, 60 s",
            NoiseModel {
                gm_sigma_dph: 3.0 * SW,
                gm_tau_s: 60.0,
                ..white
            },
        ),
    ];
    println!("{seeds} twin runs per case: 72 positions, 2 s dwell, lat 43.8, sequential order");
    println!(
        "{:<42} {:>20} {:>20} {:>20}",
        "noise", "GLS estimated z|err", "white LS z|err", "GLS known z|err"
    );
    for (name, noise) in cases {
        let mut rng = Rng::new(5);
        let (mut est, mut ols, mut known) = (Acc::default(), Acc::default(), Acc::default());
        for seed in 0..seeds {
            let mut twin = TwinConfig {
                seed,
                noise,
                ..TwinConfig::default()
            };
            twin.instrument.psi_deg = rng.uniform(0.0, 360.0);
            twin.start_deg = rng.uniform(0.0, 360.0);
            let cfg = RunConfig {
                tilt_policy: TiltPolicy::Warn,
                ..RunConfig::default()
            };
            let mut rec = Recorder::default();
            let (report, _) = simulate(&twin, &cfg, &mut rec);
            if report.result.is_err() {
                eprintln!("seed {seed}: run failed: {:?}", report.result);
                continue;
            }
            let Ok(r) = Recording::parse(&rec.text()) else { continue };
            let err = |psi: f64| wrap_180(psi - twin.instrument.psi_deg) * 3600.0;
            let Ok(a) = analyse(&r, &Options::default()) else {
                continue;
            };
            est.add(err(a.gls.psi_deg), a.gls.sigma_psi_deg * 3600.0);
            ols.add(err(a.fit.psi_deg), a.fit.sigma_psi_deg * 3600.0);
            let k = Options {
                noise: NoiseChoice::Given(noise, "truth".into()),
                ..Options::default()
            };
            if let Ok(b) = analyse(&r, &k) {
                known.add(err(b.gls.psi_deg), b.gls.sigma_psi_deg * 3600.0);
            }
        }
        let k = seeds as f64;
        let f = |a: &Acc| {
            let (z, e) = a.rms(k);
            format!("{z:.2} | {e:.1}\"")
        };
        println!("{name:<42} {:>20} {:>20} {:>20}", f(&est), f(&ols), f(&known));
    }
}
