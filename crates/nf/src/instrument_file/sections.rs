//! The sections of an instrument file. Every key is optional; a missing one takes the value
//! `nf simulate` uses without flags.

use super::bounds as b;
use nf_instrument::stepper;
use nf_model::noise::NoiseModel;
use nf_twin::TempSwing;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Site {
    #[serde(deserialize_with = "b::latitude")]
    pub latitude_deg: f64,
    /// The azimuth psi of Eq. 7.
    #[serde(deserialize_with = "b::angle")]
    pub azimuth_deg: f64,
}

impl Default for Site {
    fn default() -> Self {
        Site {
            latitude_deg: 43.8,
            azimuth_deg: 65.5378,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Gyro {
    #[serde(deserialize_with = "b::rate")]
    pub bias_dph: f64,
    #[serde(deserialize_with = "b::scale")]
    pub scale: f64,
    /// Gyro axis elevation above the platform (misalignment).
    #[serde(deserialize_with = "b::small_angle")]
    pub elevation_deg: f64,
    /// The output gains `k2 * rate^2`.
    #[serde(deserialize_with = "b::nonlinearity")]
    pub nonlinearity_per_dph: f64,
}

impl Default for Gyro {
    fn default() -> Self {
        Gyro {
            bias_dph: 0.3,
            scale: 1.0,
            elevation_deg: 0.01,
            nonlinearity_per_dph: 0.0,
        }
    }
}

/// The noise model's terms, with the keys of the noise files.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Noise {
    #[serde(deserialize_with = "b::noise_term")]
    pub arw_deg_rth: f64,
    #[serde(deserialize_with = "b::noise_term")]
    pub bias_instability_dph: f64,
    #[serde(deserialize_with = "b::noise_term")]
    pub rrw_dph_rth: f64,
    #[serde(deserialize_with = "b::noise_term")]
    pub gm_sigma_dph: f64,
    #[serde(deserialize_with = "b::noise_term")]
    pub gm_tau_s: f64,
    #[serde(deserialize_with = "b::noise_term")]
    pub quantization_arcsec: f64,
    #[serde(deserialize_with = "b::noise_term")]
    pub student_t_dof: f64,
}

impl Noise {
    pub fn model(&self) -> NoiseModel {
        NoiseModel {
            arw_deg_rth: self.arw_deg_rth,
            bias_instability_dph: self.bias_instability_dph,
            rrw_dph_rth: self.rrw_dph_rth,
            gm_sigma_dph: self.gm_sigma_dph,
            gm_tau_s: self.gm_tau_s,
            quantization_arcsec: self.quantization_arcsec,
            student_t_dof: self.student_t_dof,
        }
    }

    pub fn of(m: &NoiseModel) -> Self {
        Noise {
            arw_deg_rth: m.arw_deg_rth,
            bias_instability_dph: m.bias_instability_dph,
            rrw_dph_rth: m.rrw_dph_rth,
            gm_sigma_dph: m.gm_sigma_dph,
            gm_tau_s: m.gm_tau_s,
            quantization_arcsec: m.quantization_arcsec,
            student_t_dof: m.student_t_dof,
        }
    }
}

impl Default for Noise {
    /// White noise of 0.005 deg/h on a 2 s dwell mean.
    fn default() -> Self {
        Noise::of(&NoiseModel::white(0.005, 2.0))
    }
}

#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Drift {
    #[serde(deserialize_with = "b::drift")]
    pub linear_dph_per_s: f64,
    #[serde(deserialize_with = "b::drift2")]
    pub quadratic_dph_per_s2: f64,
}

/// A step of the bias.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Jump {
    #[serde(deserialize_with = "b::time")]
    pub time_s: f64,
    #[serde(deserialize_with = "b::rate")]
    pub size_dph: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Temperature {
    #[serde(deserialize_with = "b::celsius")]
    pub start_c: f64,
    #[serde(deserialize_with = "b::temp_ramp")]
    pub ramp_c_per_s: f64,
    /// A heater's cycle: amplitude, period and phase.
    #[serde(deserialize_with = "b::temp_swing")]
    pub swing_c: f64,
    #[serde(deserialize_with = "b::period")]
    pub swing_period_s: f64,
    /// Where the cycle starts: `swing_c sin(2 pi t / swing_period_s + swing_phase_deg)`.
    #[serde(deserialize_with = "b::angle")]
    pub swing_phase_deg: f64,
    /// Bias change per degree away from `start_c`.
    #[serde(deserialize_with = "b::temp_coef")]
    pub bias_dph_per_c: f64,
}

impl Temperature {
    /// The heater's swing, as the twin takes it.
    pub fn swing(&self) -> TempSwing {
        TempSwing {
            amplitude_c: self.swing_c,
            period_s: self.swing_period_s,
            phase_deg: self.swing_phase_deg,
        }
    }

    /// The temperature at `t_s` on the file's clock, C.
    pub fn at(&self, t_s: f64) -> f64 {
        self.start_c + self.ramp_c_per_s * t_s + self.swing().at(t_s)
    }
}

impl Default for Temperature {
    fn default() -> Self {
        Temperature {
            start_c: 40.0,
            ramp_c_per_s: 0.0,
            swing_c: 0.0,
            swing_period_s: 600.0,
            swing_phase_deg: 0.0,
            bias_dph_per_c: 0.0,
        }
    }
}

/// The rebalance loop's decaying response to each stop.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Settling {
    #[serde(deserialize_with = "b::rate")]
    pub size_dph: f64,
    #[serde(deserialize_with = "b::tau")]
    pub tau_s: f64,
}

impl Default for Settling {
    fn default() -> Self {
        Settling {
            size_dph: 0.02,
            tau_s: 0.05,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Shaft {
    #[serde(deserialize_with = "b::tilt")]
    pub tilt_deg: f64,
    /// Direction the platform is lowest towards, counter-clockwise from gamma = 0.
    #[serde(deserialize_with = "b::angle")]
    pub tilt_dir_deg: f64,
    /// The shaft's angle when the run starts.
    #[serde(deserialize_with = "b::turn")]
    pub start_deg: f64,
}

impl Default for Shaft {
    fn default() -> Self {
        Shaft {
            tilt_deg: 0.002,
            tilt_dir_deg: 140.0,
            start_deg: 17.3,
        }
    }
}

/// A periodic encoder error `amplitude sin(harmonic gamma + phase)` added to the reading.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EncoderError {
    #[serde(deserialize_with = "b::harmonic")]
    pub harmonic: u8,
    #[serde(deserialize_with = "b::arcsec")]
    pub amplitude_arcsec: f64,
    #[serde(default, deserialize_with = "b::angle")]
    pub phase_deg: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Encoder {
    #[serde(deserialize_with = "b::encoder_bits")]
    pub bits: u8,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub error: Vec<EncoderError>,
}

impl Default for Encoder {
    fn default() -> Self {
        Encoder {
            bits: 23,
            error: Vec::new(),
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Inclinometer {
    #[serde(deserialize_with = "b::incl_noise")]
    pub noise_deg: f64,
    /// Mounting offsets of the X and Y readings.
    #[serde(deserialize_with = "b::small_angle")]
    pub offset_x_deg: f64,
    #[serde(deserialize_with = "b::small_angle")]
    pub offset_y_deg: f64,
}

impl Default for Inclinometer {
    fn default() -> Self {
        Inclinometer {
            noise_deg: 0.0005,
            offset_x_deg: 0.01,
            offset_y_deg: -0.02,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Motor {
    #[serde(deserialize_with = "b::steps_per_rev")]
    pub steps_per_rev: u32,
    #[serde(deserialize_with = "b::speed")]
    pub start_sps: f64,
    #[serde(deserialize_with = "b::speed")]
    pub max_sps: f64,
    #[serde(deserialize_with = "b::accel")]
    pub accel_sps2: f64,
    #[serde(deserialize_with = "b::pulse_us")]
    pub pulse_us: u32,
}

impl Motor {
    pub fn config(&self) -> stepper::Config {
        stepper::Config {
            steps_per_rev: self.steps_per_rev,
            start_sps: self.start_sps as f32,
            max_sps: self.max_sps as f32,
            accel_sps2: self.accel_sps2 as f32,
            pulse_us: self.pulse_us,
        }
    }

    /// The motor with every move taking 1 / `factor` of its time: the speeds times the
    /// factor, the acceleration times its square, each within the file's bounds.
    pub fn sped_up(&self, factor: f64) -> Motor {
        Motor {
            start_sps: (self.start_sps * factor).min(1e6),
            max_sps: (self.max_sps * factor).min(1e6),
            accel_sps2: (self.accel_sps2 * factor * factor).min(1e8),
            ..self.clone()
        }
    }
}

impl Default for Motor {
    fn default() -> Self {
        let c = stepper::Config::default();
        Motor {
            steps_per_rev: c.steps_per_rev,
            start_sps: c.start_sps as f64,
            max_sps: c.max_sps as f64,
            accel_sps2: c.accel_sps2 as f64,
            pulse_us: c.pulse_us,
        }
    }
}

/// A rate added to the gyro output over a span of time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Disturbance {
    #[serde(deserialize_with = "b::time")]
    pub from_s: f64,
    #[serde(deserialize_with = "b::time")]
    pub to_s: f64,
    #[serde(deserialize_with = "b::rate")]
    pub size_dph: f64,
}

/// Bursts of disturbance at random times (vibration, knocks): the dwell means' heavy tails.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shocks {
    /// Mean number of bursts per hour.
    #[serde(deserialize_with = "b::per_hour")]
    pub per_hour: f64,
    /// Standard deviation of a burst's rate offset.
    #[serde(deserialize_with = "b::noise_term")]
    pub size_dph: f64,
    #[serde(deserialize_with = "b::tau")]
    pub duration_s: f64,
}

impl Shocks {
    pub fn twin(&self) -> nf_twin::Shocks {
        nf_twin::Shocks {
            per_hour: self.per_hour,
            size_dph: self.size_dph,
            duration_s: self.duration_s,
        }
    }

    pub fn of(s: nf_twin::Shocks) -> Shocks {
        Shocks {
            per_hour: s.per_hour,
            size_dph: s.size_dph,
            duration_s: s.duration_s,
        }
    }
}

/// The run plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Run {
    #[serde(deserialize_with = "b::positions")]
    pub positions: u16,
    /// A named order or a comma-separated list of positions.
    pub order: String,
    #[serde(deserialize_with = "b::dwell")]
    pub dwell_s: f64,
    #[serde(deserialize_with = "b::settle")]
    pub settle_s: f64,
    #[serde(deserialize_with = "b::sample_rate")]
    pub sample_rate_hz: u32,
    /// End the run once the running sigma reaches this, arcsec.
    #[serde(skip_serializing_if = "Option::is_none", deserialize_with = "b::target_opt")]
    pub target_arcsec: Option<f64>,
}

impl Default for Run {
    fn default() -> Self {
        Run {
            positions: 72,
            order: "sequential".into(),
            dwell_s: 2.0,
            settle_s: 0.3,
            sample_rate_hz: 1000,
            target_arcsec: None,
        }
    }
}
