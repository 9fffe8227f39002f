//! Why the twin's gyro ADC saturated: what one sample carries against the converter's full
//! scale, and the noise terms that fit within it at this sample rate.

use crate::stats::t_quantile;
use nf_instrument::run::RunConfig;
use nf_model::EARTH_RATE_DPH;
use nf_twin::TwinConfig;

/// One ADC sample's rate budget, deg/h.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdcBudget {
    pub sample_rate_hz: f64,
    /// The smaller of the two rates the ADC's +-2^23 counts stand for.
    pub full_scale_dph: f64,
    /// White noise of one sample: the ARW density over the sample period.
    pub white_sd_dph: f64,
    /// Student-t degrees of freedom of the white noise (0: Gaussian).
    pub student_t_dof: f64,
    /// One quantisation step of the angle read over one sample period.
    pub quant_step_dph: f64,
    /// Bias plus the largest Earth rate the scaled gyro can see.
    pub steady_dph: f64,
    /// Standard deviation of a shock's rate offset (0: none).
    pub shock_sd_dph: f64,
    /// The samples the run's dwells read.
    pub samples: f64,
}

/// Gaussian sample noise up to this many standard deviations is taken to fit.
const NOISE_SDS: f64 = 6.0;

/// A Student-t's samples fit where the run expects fewer than this many beyond the full
/// scale (about its chance of ending saturated).
const TAIL_RISK: f64 = 0.1;

impl AdcBudget {
    pub fn of(twin: &TwinConfig, run: &RunConfig) -> Self {
        let rate_hz = f64::from(twin.sample_rate_hz.max(1));
        let full = 2f64.powi(23);
        let cal = &twin.calibration;
        let noise = &twin.noise;
        let ins = &twin.instrument;
        AdcBudget {
            sample_rate_hz: rate_hz,
            full_scale_dph: cal.rate_of_counts(full).abs().min(cal.rate_of_counts(-full).abs()),
            white_sd_dph: noise.white_dph_rts() * rate_hz.sqrt(),
            student_t_dof: noise.student_t_dof,
            // deg/h times s is arcsec.
            quant_step_dph: noise.quantization_arcsec * 12f64.sqrt() * rate_hz,
            steady_dph: ins.bias_dph.abs() + ins.scale.abs() * EARTH_RATE_DPH,
            shock_sd_dph: if twin.shocks.per_hour > 0.0 {
                twin.shocks.size_dph
            } else {
                0.0
            },
            samples: f64::from(run.order.visits(run.positions)) * f64::from(run.dwell_ms) * 1e-3 * rate_hz,
        }
    }

    /// How many of its standard deviations a sample's white noise may reach: [`NOISE_SDS`]
    /// when Gaussian; a Student-t's level that the run's samples pass [`TAIL_RISK`] times.
    fn noise_sds(&self) -> f64 {
        let nu = self.student_t_dof;
        if nu <= 0.0 {
            return NOISE_SDS;
        }
        // The twin scales a t sample by sqrt((nu - 2) / nu) to the white noise's sd.
        let p = (TAIL_RISK / self.samples.max(1.0)).min(0.5);
        -t_quantile(p / 2.0, nu) * ((nu - 2.0) / nu).sqrt()
    }

    /// Whether every sample must saturate the ADC, whatever the noise draws: the steady rate
    /// alone fills the full scale, or one quantisation step is beyond what is left.
    pub fn always_saturates(&self) -> bool {
        let room = self.room_dph();
        room <= 0.0 || self.quant_step_dph > room
    }

    /// Whether the white noise alone reaches the full scale within [`NOISE_SDS`] of its sd (a
    /// run of some 10^5 samples would then saturate almost surely: at 4 sd, one sample in
    /// 16 000), or a Student-t's tails would in one run in ten: it is refused before it
    /// starts, at the largest noise that [`explain`] says fits. Shocks strike at random and
    /// are left to the run.
    ///
    /// [`explain`]: AdcBudget::explain
    pub fn noise_overflows(&self) -> bool {
        self.noise_sds() * self.white_sd_dph > self.room_dph()
    }

    /// What the steady rate leaves of the full scale for the noise, deg/h.
    fn room_dph(&self) -> f64 {
        self.full_scale_dph - self.steady_dph
    }

    /// The budget in words, and which term leaves no room.
    pub fn explain(&self) -> String {
        let tails = if self.student_t_dof > 0.0 {
            format!(
                " (Student-t of {} dof: far beyond {NOISE_SDS} sd at times)",
                self.student_t_dof
            )
        } else {
            String::new()
        };
        let mut s = format!(
            "one sample at {} Hz carries white noise of sd {:.3} deg/h{tails}",
            self.sample_rate_hz, self.white_sd_dph
        );
        if self.quant_step_dph > 0.0 {
            s += &format!(", a quantisation step of {:.3} deg/h", self.quant_step_dph);
        }
        if self.shock_sd_dph > 0.0 {
            s += &format!(", shocks of sd {:.3} deg/h", self.shock_sd_dph);
        }
        s += &format!(
            " and a steady rate up to {:.3} deg/h (bias and Earth rate), against the gyro ADC's full scale of +-{:.3} deg/h",
            self.steady_dph, self.full_scale_dph
        );
        let room = self.room_dph();
        if room <= 0.0 {
            return s + "; the steady rate alone leaves no room";
        }
        let mut fits = Vec::new();
        if self.quant_step_dph > room {
            // A step of `room` deg/h over one period is `room / rate` arcsec, Q sqrt(12).
            let q = room / self.sample_rate_hz / 12f64.sqrt();
            fits.push(format!("a quantisation Q of at most {} arcsec", at_most(q)));
        }
        if self.noise_sds() * self.white_sd_dph > room || self.student_t_dof > 0.0 {
            // sd = 60 N sqrt(rate), N in deg/sqrt(h).
            let n = |sds: f64| room / sds / 60.0 / self.sample_rate_hz.sqrt();
            if self.student_t_dof > 0.0 {
                fits.push(format!(
                    "Student-t ({} dof) white noise of at most {} deg/sqrt(h) over this run's {:.0} samples",
                    self.student_t_dof,
                    at_most(n(self.noise_sds())),
                    self.samples
                ));
            }
            fits.push(format!(
                "Gaussian white noise of at most {} deg/sqrt(h)",
                at_most(n(NOISE_SDS))
            ));
        }
        if NOISE_SDS * self.shock_sd_dph > room {
            let shock = room / NOISE_SDS;
            fits.push(format!("shocks of sd at most {shock:.3} deg/h"));
        }
        if fits.is_empty() {
            s + "; the terms are within it, so the input (a drift, a disturbance) went beyond"
        } else {
            s + &format!(
                "; {} fit at this sample rate (an instrument file's `[run] sample_rate_hz`, --config, sets it)",
                fits.join(", ")
            )
        }
    }
}

/// `x` in four significant digits rounded down, so that the value printed as the largest
/// that fits does fit.
fn at_most(x: f64) -> String {
    let unit = 10f64.powi(x.log10().floor() as i32 - 3);
    format!("{:.3e}", (x / unit).floor() * unit)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_coarse_quantisation_is_named_with_the_largest_q_that_fits() {
        let mut twin = TwinConfig::default();
        twin.noise.quantization_arcsec = 0.5;
        let b = AdcBudget::of(&twin, &RunConfig::default());
        // 0.5 arcsec sqrt(12) read every millisecond: 1732 deg/h per step.
        assert!((b.quant_step_dph - 1732.05).abs() < 0.01, "{b:?}");
        assert!((b.full_scale_dph - 50.0).abs() < 1e-6, "{b:?}");
        let room = 50.0 - b.steady_dph;
        // 1.0005e-2, printed below it.
        let q = room / 1000.0 / 12f64.sqrt();
        let text = b.explain();
        assert!((q - 1.0005e-2).abs() < 1e-6, "{q}");
        assert!(text.contains("a quantisation Q of at most 1.000e-2 arcsec"), "{text}");
        assert!(!text.contains("white noise of at most"), "{text}");
        assert!(b.always_saturates());
    }

    #[test]
    fn a_noisy_gyro_is_named_with_the_largest_arw_that_fits() {
        let mut twin = TwinConfig::default();
        // 0.01 deg/sqrt(h) is 0.6 deg/h/sqrt(Hz): 19 deg/h in one sample at 1 kHz.
        twin.noise = nf_model::noise::NoiseModel {
            arw_deg_rth: 0.01,
            ..twin.noise
        };
        let b = AdcBudget::of(&twin, &RunConfig::default());
        assert!((b.white_sd_dph - 0.6 * 1000f64.sqrt()).abs() < 1e-9, "{b:?}");
        let text = b.explain();
        assert!(text.contains("Gaussian white noise of at most"), "{text}");
        assert!(!text.contains("quantisation Q"), "{text}");
        assert!(b.noise_overflows() && !b.always_saturates());
        // The largest ARW the text gives fits.
        let n: f64 = text
            .split("white noise of at most ")
            .nth(1)
            .and_then(|t| t.split(' ').next())
            .and_then(|v| v.parse().ok())
            .unwrap();
        twin.noise.arw_deg_rth = n;
        assert!(!AdcBudget::of(&twin, &RunConfig::default()).noise_overflows(), "{n}");
    }

    #[test]
    fn heavy_tails_are_refused_where_they_would_saturate_one_run_in_ten() {
        // The default white noise (0.224 deg/h a sample at 1 kHz) as a Student-t of 3 dof: a
        // sample beyond the 34.7 deg/h left is 1e-7 likely (155 sd), 0.016 times in 72 dwells
        // of 2 s, 0.16 times in 720 (an outside audit's runs aborted in one of five).
        let mut twin = TwinConfig::default();
        twin.noise.student_t_dof = 3.0;
        let run = |positions| RunConfig {
            positions,
            dwell_ms: 2000,
            ..RunConfig::default()
        };
        assert!(!AdcBudget::of(&twin, &run(72)).noise_overflows());
        let long = AdcBudget::of(&twin, &run(720));
        assert!(long.noise_overflows() && !long.always_saturates());
        let text = long.explain();
        let n: f64 = text
            .split("Student-t (3 dof) white noise of at most ")
            .nth(1)
            .and_then(|t| t.split(' ').next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{text}"));
        twin.noise.arw_deg_rth = n;
        assert!(!AdcBudget::of(&twin, &run(720)).noise_overflows(), "{n}");
        // Gaussian noise at that level fits with room to spare.
        assert!(text.contains("Gaussian white noise of at most"), "{text}");
    }

    #[test]
    fn large_shocks_are_named_with_the_largest_size_that_fits() {
        let twin = TwinConfig {
            shocks: nf_twin::Shocks {
                per_hour: 3000.0,
                size_dph: 80.0,
                duration_s: 1.0,
            },
            ..TwinConfig::default()
        };
        let text = AdcBudget::of(&twin, &RunConfig::default()).explain();
        assert!(
            text.contains("shocks of sd at most") && !text.contains("white noise of at most"),
            "{text}"
        );
    }

    #[test]
    fn a_quiet_gyro_leaves_the_blame_on_the_input() {
        let b = AdcBudget::of(&TwinConfig::default(), &RunConfig::default());
        assert!(!b.always_saturates() && !b.noise_overflows());
        let text = b.explain();
        assert!(
            text.ends_with("went beyond") && !text.contains("quantisation"),
            "{text}"
        );
    }
}
