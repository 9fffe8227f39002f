//! The simulated instrument: the physical state and what each sensor sees.

use crate::bias_step::{BiasJump, Disturbance};
use crate::encoder_error::EncoderHarmonic;
use crate::noise::{GyroNoise, Quantiser};
use crate::shocks::{ShockTrain, Shocks};
use crate::temp_swing::TempSwing;
use nf_instrument::adc::{CODE_MAX, CODE_MIN};
use nf_instrument::stepper;
use nf_model::dwell::Calibration;
use nf_model::exact::Instrument;
use nf_model::noise::NoiseModel;
use nf_model::rng::Rng;
use std::cell::Cell;

thread_local! {
    static NOW_US: Cell<u64> = const { Cell::new(0) };
}

/// Virtual time of the twin running on this thread (for log time stamps).
pub fn virtual_now_us() -> u64 {
    NOW_US.with(|c| c.get())
}

/// How the inclinometer misbehaves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InclinometerFault {
    #[default]
    None,
    /// Sends bytes, never a valid line.
    Garbage,
    /// Sends nothing.
    Silent,
}

/// Faults to inject.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Faults {
    /// The motor stops turning from this move on (0 is the first move).
    pub stall_from_move: Option<u32>,
    /// The encoder stops answering at this time (s).
    pub encoder_dead_from_s: Option<f64>,
    /// Probability that an encoder frame has a flipped bit.
    pub encoder_crc_error_prob: f64,
    /// The inclinometer fails from this time on (s).
    pub inclinometer: InclinometerFault,
    pub inclinometer_fault_from_s: f64,
    /// A rate this large (deg/h) is added from this time (s): the ADC clips.
    pub adc_overload_from_s: Option<f64>,
    /// The ADC stops converting at this time (s).
    pub adc_dead_from_s: Option<f64>,
}

/// Everything about the simulated instrument.
#[derive(Debug, Clone, PartialEq)]
pub struct TwinConfig {
    /// The exact-model physics: latitude, azimuth, tilt, gyro misalignment, scale, bias.
    pub instrument: Instrument<f64>,
    /// The gyro's noise: white, flicker, random walk, Gauss-Markov, quantisation, tails.
    pub noise: NoiseModel,
    /// Linear bias drift, deg/h per s.
    pub bias_drift_dph_per_s: f64,
    /// Quadratic bias drift, deg/h per s^2.
    pub bias_drift2_dph_per_s2: f64,
    /// A step of the bias.
    pub bias_jump: Option<BiasJump>,
    /// Scale-factor nonlinearity: output gains `k2 * rate^2`, 1/(deg/h).
    pub nonlinearity_per_dph: f64,
    /// Disturbances added to the gyro output.
    pub disturbances: Vec<Disturbance>,
    /// Bursts of disturbance at random times.
    pub shocks: Shocks,
    /// Bias change per degree C away from `temp0_c`.
    pub bias_temp_dph_per_c: f64,
    pub temp0_c: f64,
    /// Temperature ramp, C per s.
    pub temp_ramp_c_per_s: f64,
    /// Temperature swing, as from a cycling heater.
    pub temp_swing: TempSwing,
    /// A measured temperature history `(s, C)`, in time order and linearly interpolated: when
    /// given it replaces the ramp and the swing (to replay a recording's thermometer).
    pub temp_trace: Vec<(f64, f64)>,
    /// Decaying disturbance after each move (the rebalance loop's response to the stop):
    /// initial size (deg/h, signed) and time constant (s).
    pub settle_dph: f64,
    pub settle_tau_s: f64,
    /// Encoder bits per turn.
    pub encoder_bits: u8,
    /// Periodic encoder error.
    pub encoder_error: [EncoderHarmonic; 2],
    /// Inclinometer noise (deg) and mounting offsets of X and Y (deg).
    pub incl_noise_deg: f64,
    pub incl_offset_deg: (f64, f64),
    /// The motor and its driver's profile (steps per shaft turn, speed, acceleration): a move's
    /// time depends on the angle moved. And the shaft's start angle.
    pub motor: stepper::Config,
    pub start_deg: f64,
    pub calibration: Calibration,
    pub sample_rate_hz: u32,
    pub faults: Faults,
    pub seed: u64,
}

impl Default for TwinConfig {
    /// The paper's instrument after levelling: 43.8 deg latitude, 0.005 deg/h per position.
    fn default() -> Self {
        TwinConfig {
            instrument: Instrument {
                latitude_deg: 43.8,
                psi_deg: 65.5378,
                tilt_deg: 0.002,
                tilt_dir_deg: 140.0,
                gyro_elev_deg: 0.01,
                scale: 1.0,
                bias_dph: 0.3,
            },
            // 0.005 deg/h for a 2 s dwell mean, and a slow random walk of the bias.
            noise: NoiseModel {
                rrw_dph_rth: 6e-4,
                ..NoiseModel::white(0.005, 2.0)
            },
            bias_drift_dph_per_s: 0.0,
            bias_drift2_dph_per_s2: 0.0,
            bias_jump: None,
            nonlinearity_per_dph: 0.0,
            disturbances: Vec::new(),
            shocks: Shocks::NONE,
            bias_temp_dph_per_c: 0.0,
            temp0_c: 40.0,
            temp_ramp_c_per_s: 0.0,
            temp_swing: TempSwing::NONE,
            temp_trace: Vec::new(),
            settle_dph: 0.02,
            settle_tau_s: 0.05,
            encoder_bits: 23,
            encoder_error: [EncoderHarmonic::NONE; 2],
            incl_noise_deg: 0.0005,
            incl_offset_deg: (0.01, -0.02),
            motor: stepper::Config::default(),
            start_deg: 17.3,
            calibration: Calibration::default(),
            sample_rate_hz: 1000,
            faults: Faults::default(),
            seed: 1,
        }
    }
}

/// `trace` at `t`, held constant beyond its ends; `None` when it is empty.
fn interpolate(trace: &[(f64, f64)], t: f64) -> Option<f64> {
    let i = trace.partition_point(|p| p.0 <= t);
    Some(match (i.checked_sub(1).map(|j| trace[j]), trace.get(i)) {
        (Some(a), Some(b)) => a.1 + (b.1 - a.1) * (t - a.0) / (b.0 - a.0),
        (Some(a), None) => a.1,
        (None, Some(b)) => b.1,
        (None, None) => return None,
    })
}

/// The state of the simulated instrument.
#[derive(Debug, Clone)]
pub struct World {
    pub cfg: TwinConfig,
    pub rng: Rng,
    pub now_us: u64,
    /// True shaft angle, deg (encoder frame).
    pub shaft_deg: f64,
    pub moves: u32,
    pub dir_ccw: bool,
    /// Time the last move ended, s.
    pub last_move_end_s: f64,
    pub noise: GyroNoise,
    shocks: ShockTrain,
    quantiser: Quantiser,
    /// Time of the next ADC conversion, us.
    next_sample_us: u64,
    /// Time of the last sample read, us.
    last_sample_us: Option<u64>,
    in_move: bool,
}

impl World {
    pub fn new(cfg: TwinConfig) -> Self {
        let rng = Rng::new(cfg.seed);
        let noise = GyroNoise::new(cfg.noise, cfg.sample_rate_hz as f64, cfg.seed);
        let shocks = ShockTrain::new(cfg.shocks, cfg.seed);
        World {
            shaft_deg: cfg.start_deg,
            cfg,
            rng,
            now_us: 0,
            moves: 0,
            dir_ccw: true,
            last_move_end_s: -1e9,
            noise,
            shocks,
            quantiser: Quantiser::default(),
            next_sample_us: 0,
            last_sample_us: None,
            in_move: false,
        }
    }

    pub fn t_s(&self) -> f64 {
        self.now_us as f64 * 1e-6
    }

    pub fn advance(&mut self, us: u64) {
        self.now_us += us;
        NOW_US.with(|c| c.set(self.now_us));
    }

    /// One step pulse.
    pub fn step(&mut self) {
        if !self.in_move {
            self.in_move = true;
            self.moves += 1;
        }
        let stalled = self.cfg.faults.stall_from_move.is_some_and(|m| self.moves > m);
        if !stalled {
            let d = 360.0 / self.cfg.motor.steps_per_rev as f64;
            self.shaft_deg = (self.shaft_deg + if self.dir_ccw { d } else { -d }).rem_euclid(360.0);
        }
        self.last_move_end_s = self.t_s();
    }

    pub fn set_dir(&mut self, ccw: bool) {
        self.in_move = false;
        self.dir_ccw = ccw;
    }

    /// The encoder's counts, or `None` when it is dead.
    pub fn encoder_counts(&mut self) -> Option<u32> {
        if self.cfg.faults.encoder_dead_from_s.is_some_and(|t| self.t_s() >= t) {
            return None;
        }
        self.in_move = false;
        let err: f64 = self.cfg.encoder_error.iter().map(|e| e.at_deg(self.shaft_deg)).sum();
        let per = (1u64 << self.cfg.encoder_bits) as f64;
        Some((((self.shaft_deg + err) / 360.0 * per).round() as u64 % per as u64) as u32)
    }

    /// Whether this encoder frame gets a flipped bit.
    pub fn encoder_frame_corrupt(&mut self) -> bool {
        self.rng.unit() < self.cfg.faults.encoder_crc_error_prob
    }

    pub fn temperature_c(&self) -> f64 {
        let t = self.t_s();
        if let Some(c) = interpolate(&self.cfg.temp_trace, t) {
            return c;
        }
        self.cfg.temp0_c + self.cfg.temp_ramp_c_per_s * t + self.cfg.temp_swing.at(t)
    }

    /// The gyro rate (deg/h) of the sample the ADC converts now, before white noise: the
    /// wandering bias as its mean over the sample period, the rest at this instant.
    pub fn rate_dph(&mut self) -> f64 {
        let t = self.t_s();
        let period = 1.0 / self.cfg.sample_rate_hz.max(1) as f64;
        let bias_noise = self.noise.bias_dph(t, period) + self.shocks.at(t);
        let c = &self.cfg;
        let since = t - self.last_move_end_s;
        let settle = c.settle_dph * (-since / c.settle_tau_s).exp();
        let overload = if c.faults.adc_overload_from_s.is_some_and(|s| t >= s) {
            1000.0
        } else {
            0.0
        };
        let jump = c.bias_jump.map_or(0.0, |j| j.at(t));
        let disturbance: f64 = c.disturbances.iter().map(|d| d.at(t)).sum();
        let earth = c.instrument.rate_dph(self.shaft_deg);
        earth
            + c.nonlinearity_per_dph * earth * earth
            + c.bias_drift_dph_per_s * t
            + c.bias_drift2_dph_per_s2 * t * t
            + jump
            + disturbance
            + bias_noise
            + c.bias_temp_dph_per_c * (self.temperature_c() - c.temp0_c)
            + settle
            + overload
    }

    /// Advances to the next ADC conversion; `None` if the ADC is dead.
    pub fn wait_conversion(&mut self) -> Option<()> {
        if self.cfg.faults.adc_dead_from_s.is_some_and(|t| self.t_s() >= t) {
            return None;
        }
        let period = 1_000_000 / self.cfg.sample_rate_hz.max(1) as u64;
        let next = self.next_sample_us.max(self.now_us.div_ceil(period) * period);
        let next = if next <= self.now_us { next + period } else { next };
        self.advance(next - self.now_us);
        self.next_sample_us = next + period;
        Some(())
    }

    /// One ADC sample: rate plus noise, quantised and clipped at the codes' limits.
    pub fn adc_sample(&mut self) -> i32 {
        let period = 1.0 / self.cfg.sample_rate_hz.max(1) as f64;
        let rate = self.rate_dph() + self.noise.white_dph(period);
        let q = self.cfg.noise.quantization_arcsec;
        // The gyro's angle counts on between the samples read (through a move).
        let since = self.last_sample_us.map(|t| (self.now_us - t) as f64 * 1e-6);
        self.last_sample_us = Some(self.now_us);
        if let Some(gap) = since.map(|s| s - period).filter(|g| q > 0.0 && *g > 0.5 * period) {
            let white = self.noise.white_dph(gap);
            self.quantiser.run_on(q, (rate + white) * gap);
        }
        let rate = self.quantiser.output_dph(q, rate, period);
        let counts = self.cfg.calibration.counts(rate).round();
        counts.clamp(CODE_MIN as f64, CODE_MAX as f64) as i32
    }

    /// Inclinometer readings `(x, y)` now.
    pub fn inclinometer(&mut self) -> (f64, f64) {
        let (ox, oy) = self.cfg.incl_offset_deg;
        let (x, y) = self.cfg.instrument.inclinometer_deg(self.shaft_deg, ox, oy);
        let n = self.cfg.incl_noise_deg;
        (x + n * self.rng.gauss(), y + n * self.rng.gauss())
    }

    pub fn inclinometer_fault(&self) -> InclinometerFault {
        if self.t_s() >= self.cfg.faults.inclinometer_fault_from_s {
            self.cfg.faults.inclinometer
        } else {
            InclinometerFault::None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_temperature_trace_is_interpolated_and_held_beyond_its_ends() {
        let cfg = TwinConfig {
            temp_trace: vec![(10.0, 20.0), (20.0, 30.0), (30.0, 30.0)],
            temp_swing: TempSwing {
                amplitude_c: 5.0,
                period_s: 60.0,
                phase_deg: 0.0,
            },
            ..TwinConfig::default()
        };
        let mut w = World::new(cfg);
        let mut at = |s: f64| {
            w.advance((s * 1e6) as u64 - w.now_us);
            w.temperature_c()
        };
        assert_eq!(at(0.0), 20.0);
        assert_eq!(at(15.0), 25.0);
        assert_eq!(at(25.0), 30.0);
        assert_eq!(at(100.0), 30.0);
        let plain = World::new(TwinConfig::default());
        assert_eq!(plain.temperature_c(), 40.0);
    }
}
