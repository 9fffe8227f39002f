//! The diagnose test suite: twin recordings with each effect concealed (from barely
//! detectable to clear) in random instruments, and clean ones for the false-alarm rate.

mod cases;
mod conceal;
mod damage;
mod metrics;
mod noise_kinds;

pub use metrics::{Tally, Truth};

use crate::diagnose::{EFFECTS, diagnose};
use crate::recording::Recording;
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_model::angle::wrap_180;
use nf_model::noise::NoiseModel;
use nf_twin::{Recorder, Rng, TwinConfig, simulate};

/// What the suite needs of one diagnosis.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Catalogue effects named, in the order found (e.g. "bias_drift", "encoder_error", "unexplained").
    pub effects: Vec<&'static str>,
    /// Noise findings named (e.g. "bias_instability", "rate_random_walk", "correlated_noise",
    /// "heavy_tails"); never false alarms.
    pub noise_terms: Vec<&'static str>,
    pub baseline_deg: f64,
    pub baseline_sigma_arcsec: f64,
    pub final_deg: f64,
    pub final_sigma_arcsec: f64,
}

/// Magnitude levels, named.
pub const LEVELS: [&str; 3] = ["barely", "moderate", "clear"];

/// Results of one (effect, level) cell.
#[derive(Debug, Clone, Default)]
pub struct Cell {
    pub runs: u32,
    /// Runs whose first finding is the concealed effect.
    pub named_first: u32,
    /// Runs that name the effect anywhere.
    pub named: u32,
    /// RMS azimuth error (arcsec) of the baseline fit and of the final one.
    pub rms_before: f64,
    pub rms_after: f64,
}

#[derive(Debug, Clone, Default)]
pub struct Evaluation {
    pub cells: Vec<(&'static str, &'static str, Cell)>,
    pub clean_runs: u32,
    /// Clean runs with any finding.
    pub false_alarms: u32,
    /// How often each effect was wrongly named on clean runs.
    pub false_by_effect: Vec<(&'static str, u32)>,
}

const DWELL_S: f64 = 1.0;

struct Case {
    twin: TwinConfig,
    run: RunConfig,
}

fn random_case(rng: &mut Rng, seed: u64) -> Case {
    let mut twin = TwinConfig {
        seed,
        ..TwinConfig::default()
    };
    twin.instrument.latitude_deg = rng.uniform(-60.0, 60.0);
    twin.instrument.psi_deg = rng.uniform(0.0, 360.0);
    twin.instrument.tilt_deg = 0.0;
    twin.instrument.bias_dph = rng.uniform(-1.0, 1.0);
    twin.noise = NoiseModel::white(rng.uniform(0.003, 0.008), 2.0);
    twin.settle_dph = 0.0;
    twin.start_deg = rng.uniform(0.0, 360.0);
    let n = [36u16, 48, 72][(rng.next_u64() % 3) as usize];
    let run = RunConfig {
        positions: n,
        dwell_ms: (DWELL_S * 1000.0) as u32,
        settle_ms: 100,
        latitude_deg: twin.instrument.latitude_deg as f32,
        tilt_policy: TiltPolicy::Warn,
        tilt_correction: false,
        ..RunConfig::default()
    };
    Case { twin, run }
}

/// Per-position gyro noise of a dwell mean.
fn sigma(c: &Case) -> f64 {
    c.twin.noise.white_mean_sd_dph(DWELL_S)
}

fn amplitude(c: &Case) -> f64 {
    15.041 * c.twin.instrument.latitude_deg.to_radians().cos()
}

fn record(c: &Case) -> Recording {
    let mut rec = Recorder::default();
    simulate(&c.twin, &c.run, &mut rec);
    // The twin always writes a valid recording; a failed run would be a bug of the suite.
    Recording::parse(&rec.text()).expect("twin recordings parse")
}

/// Conceals `effect` at `level` (0, 1, 2) in the case.
fn conceal(c: &mut Case, effect: &str, level: usize, rng: &mut Rng) {
    let s = sigma(c);
    let n = c.run.positions as f64;
    let r = amplitude(c);
    let pick = |v: [f64; 3]| v[level];
    let duration = n * (DWELL_S + 0.35);
    match effect {
        "bias_drift" => c.twin.bias_drift_dph_per_s = pick([1.5, 4.0, 12.0]) * s / duration,
        "bias_jump" => c.twin.bias_jump = Some((rng.uniform(0.3, 0.7) * duration, pick([1.5, 3.0, 8.0]) * s)),
        "thermal_drift" => {
            c.twin.temp_wave = (2.0, duration / rng.uniform(1.5, 3.0));
            c.twin.bias_temp_dph_per_c = pick([1.0, 2.5, 8.0]) * s / 2.0;
        }
        "shaft_tilt" => {
            c.twin.instrument.tilt_deg = pick([0.0006, 0.002, 0.01]);
            c.twin.instrument.tilt_dir_deg = rng.uniform(0.0, 360.0);
        }
        "encoder_error" => {
            c.twin.encoder_error[0] = (2, pick([2.0, 4.0, 12.0]) * s / r * 206_264.8, rng.uniform(0.0, 360.0))
        }
        "scale_factor" => {
            let sr = s * (2.0 / n).sqrt() / r;
            c.twin.instrument.scale = 1.0 + if rng.unit() < 0.5 { -1.0 } else { 1.0 } * pick([3.0, 5.0, 10.0]) * sr;
        }
        "nonlinearity" => c.twin.nonlinearity_per_dph = pick([3.0, 5.0, 10.0]) * 2.0 * s * (2.0 / n).sqrt() / (r * r),
        "settling_transient" => {
            // About `f` quarter-noise of excess in the first quarter of each dwell.
            let quarter_noise = c.twin.noise.white_mean_sd_dph(DWELL_S / 4.0);
            let tau = 0.05;
            c.twin.settle_tau_s = tau;
            c.twin.settle_dph = pick([0.4, 0.8, 2.0]) * quarter_noise * (DWELL_S / 4.0) / tau * (0.1f64 / tau).exp();
        }
        "outliers" => {
            // One dwell, found from a clean run of the same schedule.
            let clean = record(c);
            let k = (rng.next_u64() % clean.rows.len() as u64) as usize;
            let t = clean.rows[k].t_s;
            c.twin
                .disturbances
                .push((t - 0.6 * DWELL_S, t + 0.6 * DWELL_S, pick([4.0, 6.0, 10.0]) * s));
        }
        _ => {}
    }
}

/// Runs the suite: `seeds` recordings per (effect, level) for the `levels` (indices into
/// [`LEVELS`]) and `clean` recordings.
pub fn evaluate(seeds: u32, clean: u32, levels: &[usize], alpha: f64, mut tick: impl FnMut()) -> Evaluation {
    let mut ev = Evaluation::default();
    let mut rng = Rng::new(0xD1A6);
    let mut seed = 1000;
    let err = |rec: &Recording, psi: f64| -> Option<(Vec<&'static str>, f64, f64)> {
        let dg = diagnose(rec, alpha).ok()?;
        let e = |a: f64| wrap_180(a - psi) * 3600.0;
        Some((
            dg.findings.iter().map(|f| f.effect).collect(),
            e(dg.baseline.azimuth_deg),
            e(dg.final_.azimuth_deg),
        ))
    };
    for effect in EFFECTS {
        for (level, name) in LEVELS.iter().enumerate().filter(|(l, _)| levels.contains(l)) {
            let mut cell = Cell::default();
            let (mut b2, mut a2) = (0.0, 0.0);
            for _ in 0..seeds {
                seed += 1;
                let mut c = random_case(&mut rng, seed);
                conceal(&mut c, effect, level, &mut rng);
                if let Some((found, before, after)) = err(&record(&c), c.twin.instrument.psi_deg) {
                    cell.runs += 1;
                    cell.named_first += (found.first() == Some(&effect)) as u32;
                    cell.named += found.contains(&effect) as u32;
                    b2 += before * before;
                    a2 += after * after;
                }
                tick();
            }
            let k = cell.runs.max(1) as f64;
            (cell.rms_before, cell.rms_after) = ((b2 / k).sqrt(), (a2 / k).sqrt());
            ev.cells.push((effect, name, cell));
        }
    }
    let mut by: Vec<(&'static str, u32)> = EFFECTS.iter().map(|e| (*e, 0)).collect();
    for _ in 0..clean {
        seed += 1;
        let c = random_case(&mut rng, seed);
        if let Some((found, _, _)) = err(&record(&c), c.twin.instrument.psi_deg) {
            ev.clean_runs += 1;
            ev.false_alarms += (!found.is_empty()) as u32;
            for f in found {
                if let Some(e) = by.iter_mut().find(|e| e.0 == f) {
                    e.1 += 1;
                }
            }
        }
        tick();
    }
    ev.false_by_effect = by;
    ev
}
