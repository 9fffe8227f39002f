//! The gyro's noise model as the firmware holds it: the terms the running azimuth needs, in
//! `f32` (the MCU computes no `f64`). The host's full model, with the covariances and Allan
//! variances, is [`NoiseModel`].

use crate::noise::{NoiseError, NoiseModel, check_terms};

/// The noise terms of a rate gyro in IEEE Std 952 units, as [`NoiseModel`] has them. Zero
/// switches a term off.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NoiseTerms {
    /// Angle random walk N, deg/sqrt(h).
    pub arw_deg_rth: f32,
    /// Bias instability B, deg/h.
    pub bias_instability_dph: f32,
    /// Rate random walk K, deg/h/sqrt(h).
    pub rrw_dph_rth: f32,
    /// First-order Gauss-Markov bias: standard deviation (deg/h) and correlation time (s).
    pub gm_sigma_dph: f32,
    pub gm_tau_s: f32,
    /// Quantisation Q of the integrated output, arcsec.
    pub quantization_arcsec: f32,
}

impl Default for NoiseTerms {
    fn default() -> Self {
        Self::NONE
    }
}

impl NoiseTerms {
    /// No noise at all.
    pub const NONE: NoiseTerms = NoiseTerms {
        arw_deg_rth: 0.0,
        bias_instability_dph: 0.0,
        rrw_dph_rth: 0.0,
        gm_sigma_dph: 0.0,
        gm_tau_s: 0.0,
        quantization_arcsec: 0.0,
    };

    /// The rules of [`NoiseModel::validate`]: every term finite and not negative, a
    /// Gauss-Markov sigma with a correlation time.
    pub fn validate(&self) -> Result<(), NoiseError> {
        check_terms(
            &[
                ("arw_deg_rth", self.arw_deg_rth),
                ("bias_instability_dph", self.bias_instability_dph),
                ("rrw_dph_rth", self.rrw_dph_rth),
                ("gm_sigma_dph", self.gm_sigma_dph),
                ("gm_tau_s", self.gm_tau_s),
                ("quantization_arcsec", self.quantization_arcsec),
            ],
            self.gm_sigma_dph,
            self.gm_tau_s,
        )
    }
}

/// The nearest `f32` of each term (the host's model for a run of the firmware's logic). The
/// Student-t degrees of freedom stay behind: they shape the samples, not the variances the
/// running azimuth weighs them by.
impl From<&NoiseModel> for NoiseTerms {
    fn from(m: &NoiseModel) -> Self {
        NoiseTerms {
            arw_deg_rth: m.arw_deg_rth as f32,
            bias_instability_dph: m.bias_instability_dph as f32,
            rrw_dph_rth: m.rrw_dph_rth as f32,
            gm_sigma_dph: m.gm_sigma_dph as f32,
            gm_tau_s: m.gm_tau_s as f32,
            quantization_arcsec: m.quantization_arcsec as f32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_follows_the_host_model() {
        assert_eq!(NoiseTerms::NONE.validate(), Ok(()));
        let bad = NoiseTerms {
            rrw_dph_rth: f32::NAN,
            ..NoiseTerms::NONE
        };
        assert_eq!(bad.validate(), Err(NoiseError::Invalid("rrw_dph_rth")));
        for v in [-1e-30, f32::INFINITY, f32::NEG_INFINITY] {
            let bad = NoiseTerms {
                quantization_arcsec: v,
                ..NoiseTerms::NONE
            };
            assert_eq!(bad.validate(), Err(NoiseError::Invalid("quantization_arcsec")), "{v}");
        }
        let gm = NoiseTerms {
            gm_sigma_dph: 0.1,
            ..NoiseTerms::NONE
        };
        assert_eq!(gm.validate(), Err(NoiseError::GmWithoutTau));
    }

    #[test]
    fn from_the_host_model_term_by_term() {
        let m = NoiseModel {
            arw_deg_rth: 0.0012,
            bias_instability_dph: 0.004,
            rrw_dph_rth: 0.3,
            gm_sigma_dph: 0.01,
            gm_tau_s: 60.0,
            quantization_arcsec: 0.5,
            student_t_dof: 5.0,
        };
        let t = NoiseTerms::from(&m);
        assert_eq!(
            t,
            NoiseTerms {
                arw_deg_rth: 0.0012,
                bias_instability_dph: 0.004,
                rrw_dph_rth: 0.3,
                gm_sigma_dph: 0.01,
                gm_tau_s: 60.0,
                quantization_arcsec: 0.5,
            }
        );
        assert_eq!(t.validate(), Ok(()));
        // Past f32's range a term is infinite, and refused.
        let huge = NoiseModel {
            arw_deg_rth: 1e300,
            ..m
        };
        assert!(NoiseTerms::from(&huge).validate().is_err());
    }
}
