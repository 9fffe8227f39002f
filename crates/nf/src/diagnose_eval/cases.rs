//! One recording of the suite: a random instrument on the twin, the firmware's run settings,
//! and what is done to the dwells and to the text before it is read.

use super::damage::Damage;
use crate::recording::Recording;
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_model::noise::NoiseModel;
use nf_model::order::Order;
use nf_twin::{Disturbance, Recorder, Rng, TempSwing, TwinConfig, simulate};

/// Dwell of every run, s. The suite's effect sizes are relative to its mean's white noise.
pub const DWELL_S: f64 = 1.0;

/// Where the instrument stands and how level it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site {
    /// Range of |latitude|, deg; the hemisphere is random.
    pub abs_lat_deg: (f64, f64),
    /// Range of the shaft tilt, deg, drawn log-uniform; `None` for a level shaft.
    pub tilt_deg: Option<(f64, f64)>,
}

impl Site {
    /// A level shaft anywhere up to 60 deg of latitude.
    pub const ORDINARY: Site = Site {
        abs_lat_deg: (0.0, 60.0),
        tilt_deg: None,
    };
}

/// A constant rate added over one whole dwell (an outlier, or a dwell-level noise tail).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DwellShift {
    /// Visit number, from 0.
    pub visit: usize,
    pub dph: f64,
}

#[derive(Debug, Clone)]
pub struct Case {
    pub twin: TwinConfig,
    pub run: RunConfig,
    /// Placed on the dwells' twin times when the recording is made.
    pub dwell_shifts: Vec<DwellShift>,
    pub damage: Damage,
}

/// Log-uniform in `[lo, hi]`.
pub fn log_uniform(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    rng.uniform(lo.ln(), hi.ln()).exp()
}

/// A random instrument with white gyro noise, visiting 36, 48 or 72 positions in `order`.
pub fn random_case(rng: &mut Rng, site: &Site, order: Order) -> Case {
    let mut twin = TwinConfig {
        seed: rng.next_u64(),
        ..TwinConfig::default()
    };
    let sign = if rng.unit() < 0.5 { -1.0 } else { 1.0 };
    twin.instrument.latitude_deg = sign * rng.uniform(site.abs_lat_deg.0, site.abs_lat_deg.1);
    twin.instrument.psi_deg = rng.uniform(0.0, 360.0);
    twin.instrument.tilt_deg = site.tilt_deg.map_or(0.0, |(lo, hi)| log_uniform(rng, lo, hi));
    twin.instrument.tilt_dir_deg = rng.uniform(0.0, 360.0);
    twin.instrument.bias_dph = rng.uniform(-1.0, 1.0);
    twin.noise = NoiseModel::white(rng.uniform(0.003, 0.008), 2.0);
    twin.settle_dph = 0.0;
    twin.start_deg = rng.uniform(0.0, 360.0);
    let positions = [36u16, 48, 72][(rng.next_u64() % 3) as usize];
    let run = RunConfig {
        positions,
        order,
        dwell_ms: (DWELL_S * 1000.0) as u32,
        settle_ms: 100,
        latitude_deg: twin.instrument.latitude_deg as f32,
        tilt_policy: TiltPolicy::Warn,
        tilt_correction: false,
        ..RunConfig::default()
    };
    // The temperature wanders a little in every run (a warm-up ramp and a slow cycle) and moves
    // the bias only where a thermal drift is concealed: the thermal test's false alarms.
    let duration = run_duration_s(&run);
    twin.temp_ramp_c_per_s = rng.uniform(-0.5, 0.5) / duration;
    twin.temp_swing = TempSwing {
        amplitude_c: log_uniform(rng, 0.05, 1.0),
        period_s: duration / rng.uniform(0.5, 3.0),
        phase_deg: 0.0,
    };
    Case {
        twin,
        run,
        dwell_shifts: Vec::new(),
        damage: Damage::Intact,
    }
}

impl Case {
    /// White noise of a dwell mean, deg/h: the unit of every concealed effect and noise term.
    pub fn sigma(&self) -> f64 {
        self.twin.noise.white_mean_sd_dph(DWELL_S)
    }

    /// The Earth rate's amplitude over the turn, deg/h.
    pub fn amplitude(&self) -> f64 {
        nf_model::EARTH_RATE_DPH * self.twin.instrument.latitude_deg.to_radians().cos()
    }

    /// Dwells in the run.
    pub fn visits(&self) -> usize {
        self.run.order.visits(self.run.positions) as usize
    }

    /// The run's length, s (see [`run_duration_s`]).
    pub fn duration_s(&self) -> f64 {
        run_duration_s(&self.run)
    }

    /// The recording as the host reads it, after the dwell shifts and the damage.
    #[cfg(test)]
    pub fn record(&self) -> Recording {
        // The twin always writes a valid recording; a failed parse would be a bug of the suite.
        Recording::parse(&self.text()).expect("twin recordings parse")
    }

    /// The recording's text (the recording format).
    pub fn text(&self) -> String {
        let mut twin = self.twin.clone();
        if !self.dwell_shifts.is_empty() {
            let windows = dwell_windows(&self.twin, &self.run);
            for s in &self.dwell_shifts {
                if let Some(&(from, to)) = windows.get(s.visit) {
                    twin.disturbances.push(Disturbance {
                        from_s: from,
                        to_s: to,
                        size_dph: s.dph,
                    });
                }
            }
        }
        self.damage.apply(&simulate_text(&twin, &self.run).0)
    }
}

/// A run's length, s, near enough for sizing drifts (a move and settling take about 0.35 s).
fn run_duration_s(run: &RunConfig) -> f64 {
    run.order.visits(run.positions) as f64 * (DWELL_S + 0.35)
}

/// The recording's text, and the twin time (s) at which its `t_s` is 0.
fn simulate_text(twin: &TwinConfig, run: &RunConfig) -> (String, f64) {
    let mut rec = Recorder::default();
    let (_, world) = simulate(twin, run, &mut rec);
    let text = rec.text();
    // The run ends with the last dwell; levelling comes before t_s = 0.
    let last_t = text
        .lines()
        .last()
        .and_then(|l| l.split(',').nth(1))
        .and_then(|t| t.parse::<f64>().ok())
        .unwrap_or(0.0);
    let t0 = world.t_s() - last_t - DWELL_S / 2.0;
    (text, t0)
}

/// Twin times `(from, to)` of each dwell, from a run of the same schedule: the timing does
/// not depend on the gyro's output.
fn dwell_windows(twin: &TwinConfig, run: &RunConfig) -> Vec<(f64, f64)> {
    let (text, t0) = simulate_text(twin, run);
    let rec = Recording::parse(&text).expect("twin recordings parse");
    // A margin for the first sample's wait and the rounding of t_s; the settling between
    // dwells (0.1 s) is longer, and its samples are not used.
    let half = DWELL_S / 2.0 + 0.03;
    rec.rows
        .iter()
        .map(|r| (t0 + r.t_s - half, t0 + r.t_s + half))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dwell_shifts_land_on_their_own_dwells() {
        let mut rng = Rng::new(11);
        for (order, rate_hz) in [(Order::Sequential, 100), (Order::ForwardBack, 1000)] {
            let mut case = random_case(&mut rng, &Site::ORDINARY, order);
            case.twin.noise = NoiseModel::WHITE_NONE;
            (case.twin.sample_rate_hz, case.run.sample_rate_hz) = (rate_hz, rate_hz);
            let plain = case.record();
            let shifts = [(0, 5.0), (7, -3.0), (case.visits() - 1, 2.0)];
            case.dwell_shifts = shifts.map(|(visit, dph)| DwellShift { visit, dph }).to_vec();
            let shifted = case.record();
            for (k, (a, b)) in plain.rows.iter().zip(&shifted.rows).enumerate() {
                let want = shifts.iter().find(|s| s.0 == k).map_or(0.0, |s| s.1);
                let got = b.rate_dph - a.rate_dph;
                assert!((got - want).abs() < 1e-3, "{} visit {k}: {got} vs {want}", order.name());
            }
        }
    }
}
