//! Benchmark of `nf fit` through gyro noise: for white, flicker-dominated, random-walk-dominated
//! and Gauss-Markov noise and each visiting order, over many twin runs of the paper's
//! instrument (72 dwells of 2 s at 43.8 deg), the RMS of error/sigma and the RMS error of the
//! GLS fit (noise estimated from the recording), of white-noise least squares, and of GLS that
//! knows the true noise model; the bias a linear drift leaves in each order; and the time to
//! 18" for the paper's gyro with flicker on a fast motor.
//!
//! `cargo run --release --example noise_bench -- [seeds] [filter]` (default 60 seeds; a filter
//! keeps the noise-table rows whose noise or order name contains it, and skips the rest;
//! `time-to-18` prints the plan table alone).

use nf::analysis::{Options, analyse};
use nf::noise_fit::NoiseChoice;
use nf::plan_noise::{Budget, Space, search};
use nf::recording::Recording;
use nf::schedule::Timing;
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_instrument::stepper;
use nf_model::angle::wrap_180;
use nf_model::noise::NoiseModel;
use nf_model::order::Order;
use nf_twin::{Recorder, Rng, TwinConfig, simulate};

/// The paper's gyro: 0.005 deg/h for a 2 s dwell mean.
const SW: f64 = 0.005;

#[derive(Default)]
struct Acc {
    z2: f64,
    e2: f64,
    k: f64,
}

impl Acc {
    fn add(&mut self, err: f64, sigma: f64) {
        self.z2 += (err / sigma).powi(2);
        self.e2 += err * err;
        self.k += 1.0;
    }
    fn show(&self) -> String {
        let k = self.k.max(1.0);
        format!("{:.2} | {:.1}\"", (self.z2 / k).sqrt(), (self.e2 / k).sqrt())
    }
}

/// 72 dwells in `order` (forward-back: 36 positions, each twice).
fn run_config(order: Order) -> RunConfig {
    RunConfig {
        positions: if order == Order::ForwardBack { 36 } else { 72 },
        order,
        tilt_policy: TiltPolicy::Warn,
        ..RunConfig::default()
    }
}

fn main() {
    let seeds: u64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(60);
    let filter = std::env::args().nth(2);
    if filter.as_deref() == Some("time-to-18") {
        time_to_18();
        return;
    }
    noise_table(seeds, filter.as_deref());
    if filter.is_none() {
        drift_table();
        time_to_18();
    }
}

fn noise_table(seeds: u64, filter: Option<&str>) {
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
    println!("{seeds} twin runs per case: 72 dwells of 2 s, lat 43.8; RMS error/sigma | RMS error");
    println!(
        "{:<42} {:<18} {:>16} {:>16} {:>16}",
        "noise", "order", "GLS estimated", "white LS", "GLS known"
    );
    for (name, noise) in cases {
        for order in Order::NAMED {
            let row = format!("{name} {}", order.name());
            if filter.is_some_and(|f| !row.contains(f)) {
                continue;
            }
            let (est, ols, known) = noise_case(noise, order, seeds);
            println!(
                "{name:<42} {:<18} {:>16} {:>16} {:>16}",
                order.name(),
                est.show(),
                ols.show(),
                known.show()
            );
        }
    }
}

fn noise_case(noise: NoiseModel, order: Order, seeds: u64) -> (Acc, Acc, Acc) {
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
        let cfg = run_config(order);
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
    (est, ols, known)
}

/// The shift of psi by a linear drift of 0.05 deg/h over the run, noise-free, white LS and GLS.
fn drift_table() {
    println!("\nlinear drift of 0.05 deg/h over the run, no noise: shift of psi, white LS and GLS (estimated)");
    for order in Order::NAMED {
        let mut twin = TwinConfig {
            noise: NoiseModel::WHITE_NONE,
            incl_noise_deg: 0.0,
            ..TwinConfig::default()
        };
        twin.instrument.tilt_deg = 0.0;
        let cfg = run_config(order);
        let fit = |twin: &TwinConfig| {
            let mut rec = Recorder::default();
            let (_, world) = simulate(twin, &cfg, &mut rec);
            let r = Recording::parse(&rec.text()).expect("the twin writes valid recordings");
            let a = analyse(&r, &Options::default()).expect("a noise-free run fits");
            (a.fit.psi_deg, a.gls.psi_deg, world.t_s())
        };
        let (ols0, gls0, span) = fit(&twin);
        twin.bias_drift_dph_per_s = 0.05 / span;
        let (ols1, gls1, _) = fit(&twin);
        let shift = |a: f64, b: f64| wrap_180(b - a) * 3600.0;
        println!(
            "  {:<18} {:>8.2}\" {:>8.2}\"",
            order.name(),
            shift(ols0, ols1),
            shift(gls0, gls1)
        );
    }
}

/// The planner's fastest run to 18" per order: the paper's gyro with the flicker that makes
/// Table 1 scatter, a half turn with settling in 0.8 s and a small step in 0.4 s.
fn time_to_18() {
    let model = NoiseModel {
        bias_instability_dph: 0.004,
        ..NoiseModel::white(SW, 2.0)
    };
    let timing = Timing {
        motor: stepper::Config {
            max_sps: 40_000.0,
            accel_sps2: 400_000.0,
            ..Default::default()
        },
        ..Timing::default()
    };
    let budget = Budget {
        latitude_deg: 43.8,
        encoder_deg: 0.0,
        tilt_deg: 0.0,
    };
    let levelling_s = 2.0 * (timing.move_s(timing.motor.steps_per_rev / 2) + timing.settle_s + timing.per_position_s);
    println!("\ntime to 18\" (paper's gyro, B = 0.004 deg/h, fast motor), fastest run per order:");
    for order in Order::NAMED {
        let p = search(&model, &budget, &timing, &[order], &Space::default(), 18.0, levelling_s);
        match (p.fastest, p.floor) {
            (Some(c), _) => println!(
                "  {:<18} n = {:>3}, dwell {:>4} s: {:.1}\" in {:.0} s",
                c.order, c.n, c.dwell_s, c.sigma_arcsec, c.time_s
            ),
            (None, Some(f)) => println!(
                "  {:<18} out of reach: floor {:.1}\" (n = {}, dwell {} s, {:.0} s)",
                order.name(),
                f.sigma_arcsec,
                f.n,
                f.dwell_s,
                f.time_s
            ),
            (None, None) => println!("  {:<18} no run", order.name()),
        }
    }
}
