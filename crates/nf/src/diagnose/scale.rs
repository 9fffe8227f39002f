//! `scale_factor`: the first-harmonic amplitude against the latitude's `WE cos(lat)`. It
//! changes no residual, so it is judged on the complete model (see the selection). In a
//! sequential run the first harmonic is also the slowest wander of the bias: the amplitude is
//! judged under the cautious noise model there, under the estimate where the positions
//! alternate sides (opposite pairs).

use super::effect::{Change, Draws, Effect, Proposal, State, param};
use super::kind::Kind;
use crate::noise_fit::azimuth;
use crate::stats::t_sf2;
use crate::tilt::Sensitivity;
use nf_model::EARTH_RATE_DPH;

pub struct ScaleFactor {
    /// How the exact tilt correction carries the fit's errors: near the pole at a large tilt
    /// the amplitude sets the correction's size, and is known far less well than the fit of
    /// the corrected rates says (an outside audit: a scale factor named at p 1e-13 in 12 % of
    /// runs at 85 deg and 6-10 deg of tilt, where the scale was 1).
    pub sensitivity: Sensitivity,
}

impl Effect for ScaleFactor {
    fn kind(&self) -> Kind {
        Kind::ScaleFactor
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        if s.is_named(Kind::ScaleFactor) {
            return Vec::new();
        }
        let harmonic = s.data.harmonic(1);
        let f = if harmonic.iter().any(|c| s.data.slow_in_time(c)) {
            &s.cautious.fit
        } else {
            &s.main.fit
        };
        let amp = s.amplitude();
        let cov: Vec<Vec<f64>> = f
            .cov_unit
            .iter()
            .map(|r| r.iter().map(|c| c * f.s2()).collect())
            .collect();
        let fitted = azimuth(&f.coef, &cov);
        let (_, sd) = self
            .sensitivity
            .carried(fitted.sigma_psi_deg, fitted.sigma_amplitude_dph);
        let v = sd * sd;
        let pred = EARTH_RATE_DPH * s.data.rec.latitude_deg.to_radians().cos();
        let z = (amp - pred) / v.sqrt();
        vec![Proposal {
            kind: Kind::ScaleFactor,
            // The variance comes from the residuals: Student's t, not the normal tail.
            p: t_sf2(z, f.dof as f64),
            change: Change::Nothing,
            parameters: vec![
                param("scale", amp / pred, Some(v.sqrt() / pred)),
                param("amplitude_dph", amp, Some(v.sqrt())),
            ],
            location: format!("the first-harmonic amplitude, {amp:.5} deg/h against {pred:.5} predicted"),
            scanned: 0,
            own_p: None,
            draws: Draws::No,
        }]
    }
}
