//! A planned run checked on the twin: the firmware's run logic, the gyro's noise model and the
//! motor's profile, fitted as `nf fit` does with the same noise model; the scatter of the
//! azimuth against the plan's stated sigma.

use crate::analysis::{Options, analyse};
use crate::noise_fit::NoiseChoice;
use crate::recording::Recording;
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_instrument::stepper;
use nf_model::angle::wrap_180;
use nf_model::noise::NoiseModel;
use nf_model::order::Order;
use nf_twin::{Recorder, Rng, TwinConfig, simulate};

/// The run to check.
#[derive(Debug, Clone, Copy)]
pub struct RunSpec {
    pub order: Order,
    pub n: u16,
    pub dwell_s: f64,
    pub settle_s: f64,
    pub motor: stepper::Config,
    pub latitude_deg: f64,
}

/// What the twin runs gave.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwinCheck {
    pub runs: u32,
    /// RMS of the azimuth error, arcsec.
    pub rms_error_arcsec: f64,
    /// RMS of the error over the fit's own sigma.
    pub rms_z: f64,
    /// Mean length of a run in virtual time, s.
    pub mean_time_s: f64,
}

/// `runs` twin runs of `spec` with a level shaft and the gyro's `model`, each with its own
/// azimuth and noise.
pub fn check(
    model: &NoiseModel,
    spec: &RunSpec,
    runs: u32,
    seed: u64,
    mut tick: impl FnMut(),
) -> Result<TwinCheck, String> {
    let cfg = RunConfig {
        positions: spec.n,
        order: spec.order,
        dwell_ms: (spec.dwell_s * 1000.0).round() as u32,
        settle_ms: (spec.settle_s * 1000.0).round() as u32,
        latitude_deg: spec.latitude_deg as f32,
        tilt_policy: TiltPolicy::Warn,
        ..RunConfig::default()
    };
    let opt = Options {
        noise: NoiseChoice::Given(*model, "the plan's".into()),
        ..Options::default()
    };
    let mut rng = Rng::new(seed);
    let (mut e2, mut z2, mut time) = (0.0, 0.0, 0.0);
    for k in 0..runs {
        let mut twin = TwinConfig {
            seed: seed.wrapping_mul(1_000_003).wrapping_add(k as u64),
            noise: *model,
            motor: spec.motor,
            ..TwinConfig::default()
        };
        twin.instrument.latitude_deg = spec.latitude_deg;
        twin.instrument.psi_deg = rng.uniform(0.0, 360.0);
        twin.instrument.tilt_deg = 0.0;
        let mut rec = Recorder::default();
        let (report, world) = simulate(&twin, &cfg, &mut rec);
        report
            .result
            .map_err(|e| format!("twin run {k} failed at {:?}: {:?}", e.stage, e.fault))?;
        let r = Recording::parse(&rec.text()).map_err(|e| format!("twin run {k}: {e}"))?;
        let a = analyse(&r, &opt)?;
        let err = wrap_180(a.gls.psi_deg - twin.instrument.psi_deg);
        e2 += err * err;
        z2 += (err / a.gls.sigma_psi_deg).powi(2);
        time += world.t_s();
        tick();
    }
    let r = runs.max(1) as f64;
    Ok(TwinCheck {
        runs,
        rms_error_arcsec: (e2 / r).sqrt() * 3600.0,
        rms_z: (z2 / r).sqrt(),
        mean_time_s: time / r,
    })
}
