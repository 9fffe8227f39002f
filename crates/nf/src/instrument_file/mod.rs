//! Instrument files: the twin's configuration as TOML (`docs/instrument-file.md`). `nf simulate
//! --config` reads one, `nf diagnose --sim` compares a recording with it and `--fix` writes one.
//! A wrong key or value is named with its line.

mod bounds;
mod sections;

pub use sections::{
    Disturbance, Drift, Encoder, EncoderError, Gyro, Inclinometer, Jump, Motor, Noise, Run, Settling, Shaft, Shocks,
    Site, Temperature,
};

use crate::textfile::{Error, err};
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_model::exact::Instrument;
use nf_model::noise::NoiseError;
use nf_model::order::Order;
use nf_twin::{BiasJump, EncoderHarmonic, TwinConfig};
use serde::{Deserialize, Serialize};

pub const FORMAT: &str = "northfinder-instrument/1";

/// Encoder error terms the twin has room for.
const ENCODER_TERMS: usize = 2;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InstrumentFile {
    // Required: empty when missing.
    #[serde(default)]
    pub format: String,
    pub seed: u64,
    pub site: Site,
    pub gyro: Gyro,
    pub noise: Noise,
    pub drift: Drift,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump: Option<Jump>,
    pub temperature: Temperature,
    pub settling: Settling,
    pub shaft: Shaft,
    pub encoder: Encoder,
    pub inclinometer: Inclinometer,
    pub motor: Motor,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub disturbance: Vec<Disturbance>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shocks: Option<Shocks>,
    pub run: Run,
}

impl Default for InstrumentFile {
    fn default() -> Self {
        InstrumentFile {
            format: FORMAT.into(),
            seed: 1,
            site: Site::default(),
            gyro: Gyro::default(),
            noise: Noise::default(),
            drift: Drift::default(),
            jump: None,
            temperature: Temperature::default(),
            settling: Settling::default(),
            shaft: Shaft::default(),
            encoder: Encoder::default(),
            inclinometer: Inclinometer::default(),
            motor: Motor::default(),
            disturbance: Vec::new(),
            shocks: None,
            run: Run::default(),
        }
    }
}

/// The line (from 1) of byte `at` in `text`.
fn line_at(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())]
        .iter()
        .filter(|&&c| c == b'\n')
        .count()
        + 1
}

/// The first line that sets `key` (0 when none does: the default was wrong).
fn line_of(text: &str, key: &str) -> usize {
    text.lines()
        .position(|l| {
            l.trim_start()
                .strip_prefix(key)
                .is_some_and(|r| r.trim_start().starts_with('='))
        })
        .map_or(0, |i| i + 1)
}

impl InstrumentFile {
    pub fn parse(text: &str) -> Result<Self, Error> {
        let f: InstrumentFile = toml::from_str(text).map_err(|e| {
            let line = e.span().map_or(0, |s| line_at(text, s.start));
            let mut what = e.message().trim().to_string();
            let at = text.lines().nth(line.saturating_sub(1)).unwrap_or("").trim();
            // In TOML a key after `[table]` belongs to that table.
            if ["format", "seed"]
                .iter()
                .any(|k| what.starts_with(&format!("unknown field `{k}`")))
            {
                what += "; `format` and `seed` go before the first [table]";
            }
            Error {
                line,
                what: if line == 0 { what } else { format!("`{at}`: {what}") },
            }
        })?;
        f.check(text)?;
        Ok(f)
    }

    pub fn read(path: &str) -> Result<Self, String> {
        let text = crate::textfile::read_text(path).map_err(|e| e.at(path))?;
        Self::parse(&text).map_err(|e| e.at(path))
    }

    /// What ranges per value cannot say.
    fn check(&self, text: &str) -> Result<(), Error> {
        if self.format != FORMAT {
            let line = line_of(text, "format");
            return err(
                line,
                if line == 0 {
                    format!("format is missing: the first key is `format = \"{FORMAT}\"`")
                } else {
                    format!("format `{}` is not `{FORMAT}`", self.format)
                },
            );
        }
        if let Err(e) = self.noise.model().validate() {
            let key = match e {
                NoiseError::Invalid(key) => key,
                NoiseError::GmWithoutTau => "gm_sigma_dph",
                NoiseError::DofTooSmall => "student_t_dof",
            };
            return err(line_of(text, key), format!("[noise]: {e}"));
        }
        if let Err(e) = self.order().and_then(|o| o.check(self.run.positions).map(|()| o)) {
            return err(line_of(text, "order"), format!("[run] order `{}`: {e}", self.run.order));
        }
        if self.encoder.error.len() > ENCODER_TERMS {
            return err(
                line_of(text, "harmonic"),
                format!(
                    "{} [[encoder.error]] terms: the twin has {ENCODER_TERMS}",
                    self.encoder.error.len()
                ),
            );
        }
        if let Some(e) = self.shocks_too_dense() {
            return err(line_of(text, "per_hour"), e);
        }
        if let Some(d) = self.disturbance.iter().find(|d| d.to_s <= d.from_s) {
            return err(
                line_of(text, "to_s"),
                format!(
                    "a disturbance from {} s to {} s ends before it begins",
                    d.from_s, d.to_s
                ),
            );
        }
        Ok(())
    }

    /// Why the shocks are refused, if they are so dense that many are under way at once.
    pub fn shocks_too_dense(&self) -> Option<String> {
        let s = self.shocks?.twin();
        (s.under_way() > nf_twin::Shocks::MAX_UNDER_WAY).then(|| {
            format!(
                "[shocks]: {} bursts per hour of {} s are {:.0} under way at once, more than {}: that is a Gaussian wander, not shocks",
                s.per_hour,
                s.duration_s,
                s.under_way(),
                nf_twin::Shocks::MAX_UNDER_WAY
            )
        })
    }

    pub(crate) fn order(&self) -> Result<Order, nf_model::order::OrderError> {
        Order::parse(&self.run.order)
    }

    /// The file, with `comments` (one per line) at the top.
    pub fn write(&self, comments: &[String]) -> String {
        let mut out = String::from("# north-finder instrument, docs/instrument-file.md\n");
        for c in comments {
            out += &format!("# {c}\n");
        }
        // Serialising plain numbers, strings and tables cannot fail.
        out + &toml::to_string(self).unwrap_or_default()
    }

    pub fn twin(&self) -> TwinConfig {
        let enc = |i: usize| {
            self.encoder
                .error
                .get(i)
                .map_or(EncoderHarmonic::NONE, |e| EncoderHarmonic {
                    harmonic: e.harmonic,
                    amplitude_arcsec: e.amplitude_arcsec,
                    phase_deg: e.phase_deg,
                })
        };
        TwinConfig {
            instrument: Instrument {
                latitude_deg: self.site.latitude_deg,
                psi_deg: self.site.azimuth_deg,
                tilt_deg: self.shaft.tilt_deg,
                tilt_dir_deg: self.shaft.tilt_dir_deg,
                gyro_elev_deg: self.gyro.elevation_deg,
                scale: self.gyro.scale,
                bias_dph: self.gyro.bias_dph,
            },
            noise: self.noise.model(),
            bias_drift_dph_per_s: self.drift.linear_dph_per_s,
            bias_drift2_dph_per_s2: self.drift.quadratic_dph_per_s2,
            bias_jump: self.jump.map(|j| BiasJump {
                time_s: j.time_s,
                size_dph: j.size_dph,
            }),
            nonlinearity_per_dph: self.gyro.nonlinearity_per_dph,
            disturbances: self
                .disturbance
                .iter()
                .map(|d| nf_twin::Disturbance {
                    from_s: d.from_s,
                    to_s: d.to_s,
                    size_dph: d.size_dph,
                })
                .collect(),
            shocks: self.shocks.map_or(nf_twin::Shocks::NONE, |s| s.twin()),
            bias_temp_dph_per_c: self.temperature.bias_dph_per_c,
            temp0_c: self.temperature.start_c,
            temp_ramp_c_per_s: self.temperature.ramp_c_per_s,
            temp_swing: self.temperature.swing(),
            settle_dph: self.settling.size_dph,
            settle_tau_s: self.settling.tau_s,
            encoder_bits: self.encoder.bits,
            encoder_error: [enc(0), enc(1)],
            incl_noise_deg: self.inclinometer.noise_deg,
            incl_offset_deg: (self.inclinometer.offset_x_deg, self.inclinometer.offset_y_deg),
            motor: self.motor.config(),
            start_deg: self.shaft.start_deg,
            sample_rate_hz: self.run.sample_rate_hz,
            seed: self.seed,
            ..TwinConfig::default()
        }
    }

    /// The firmware's run configuration; the order was checked when the file was read.
    pub fn run_config(&self) -> RunConfig {
        RunConfig {
            positions: self.run.positions,
            order: self.order().unwrap_or(Order::Sequential),
            noise: (&self.noise.model()).into(),
            target_arcsec: self.run.target_arcsec.unwrap_or(0.0) as f32,
            dwell_ms: (self.run.dwell_s * 1000.0).round() as u32,
            settle_ms: (self.run.settle_s * 1000.0).round() as u32,
            sample_rate_hz: self.run.sample_rate_hz,
            latitude_deg: self.site.latitude_deg as f32,
            tilt_policy: TiltPolicy::Warn,
            ..RunConfig::default()
        }
    }
}

#[cfg(test)]
mod tests;
