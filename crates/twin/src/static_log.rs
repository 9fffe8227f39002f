//! A static gyro log (`shared/recording-format.md`, `northfinder-static/1`): the gyro held
//! still, one row per sample, for noise characterisation.

use crate::noise::{GyroNoise, Quantiser};
use nf_model::noise::NoiseModel;
use std::io::Write;

/// What to log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticLog {
    pub noise: NoiseModel,
    /// The constant rate the gyro sees: bias plus the Earth rate's projection, deg/h.
    pub rate_dph: f64,
    pub sample_rate_hz: f64,
    pub duration_s: f64,
    pub seed: u64,
}

impl StaticLog {
    /// The samples `(t_s, rate_dph)`, in time order, handed to `row` one at a time.
    pub fn samples(&self, mut row: impl FnMut(f64, f64)) {
        let period = 1.0 / self.sample_rate_hz;
        let mut g = GyroNoise::new(self.noise, self.sample_rate_hz, self.seed);
        let mut q = Quantiser::default();
        let n = (self.duration_s * self.sample_rate_hz).floor() as u64;
        for i in 0..n {
            let t = i as f64 * period;
            let r = self.rate_dph + g.bias_dph(t, period) + g.white_dph(period);
            row(t, q.output_dph(self.noise.quantization_arcsec, r, period));
        }
    }

    /// Writes the log as CSV.
    pub fn write(&self, out: &mut impl Write) -> std::io::Result<()> {
        writeln!(out, "# format = northfinder-static/1")?;
        writeln!(out, "# sample_rate_hz = {}", self.sample_rate_hz)?;
        writeln!(out, "# instrument = nf-twin")?;
        writeln!(out, "t_s,rate_dph")?;
        let mut res = Ok(());
        self.samples(|t, r| {
            if res.is_ok() {
                res = writeln!(out, "{t:.6},{r:.9}");
            }
        });
        res
    }
}
