//! `shaft_tilt`: the vertical Earth rate a tilted shaft adds, from the inclinometer by `nf
//! fit`'s own path (`crate::tilt`). It is measured physics, so it is corrected before any test
//! whether or not it is significant; it is named when the inclinometer's tilt circle stands
//! out of the readings' noise (F test of the tilt against none).

use super::effect::{Change, Draws, Effect, Param, Proposal, State, param};
use super::kind::Kind;
use crate::analysis::TiltMethod;
use crate::recording::Recording;
use crate::tilt::{self, Sensitivity};

/// The tilt as measured, ready to be proposed.
pub struct ShaftTilt {
    pub p: f64,
    pub parameters: Vec<Param>,
    pub location: String,
    /// Rate to subtract from each position, deg/h.
    pub corrections: Vec<f64>,
    /// Why some inclinometer readings were not used, when they were not.
    pub warning: Option<String>,
    /// The azimuth's standard deviation (deg) that the circle's uncertainty carries, beside
    /// the gyro's.
    pub sigma_psi_deg: f64,
    /// How the fit's errors carry through the correction.
    pub sensitivity: Sensitivity,
}

impl ShaftTilt {
    /// The correction and its test; `None` without inclinometer readings. `fit` gives the
    /// azimuth (deg) and amplitude (deg/h) of the rates less a set of corrections.
    pub fn measure(
        rec: &Recording,
        fit: impl FnMut(&[f64]) -> Result<(f64, f64), String>,
    ) -> Result<Option<ShaftTilt>, String> {
        let method = tilt::auto_method(rec);
        if method == TiltMethod::None {
            return Ok(None);
        }
        let t = tilt::correct(rec, method, fit)?;
        let mut parameters = Vec::new();
        if let (Some(s), Some(c)) = (t.shaft, t.circle_test) {
            parameters.extend([
                param("tilt_deg", s.tilt_deg, Some(c.sigma_tilt_deg)),
                param("tilt_dir_deg", s.tilt_dir_deg, None),
                param("azimuth_sigma_arcsec", t.sigma_psi_deg * 3600.0, None),
            ]);
            // An axis never read has no offset to report.
            for (name, v) in [("offset_x_deg", s.offset_x_deg), ("offset_y_deg", s.offset_y_deg)] {
                if v.is_finite() {
                    parameters.push(param(name, v, None));
                }
            }
        }
        // One axis read alone is said: its circle holds the tilt, not the other's offset.
        let read = |y: bool| {
            rec.rows
                .iter()
                .any(|r| if y { r.tilt_y_deg } else { r.tilt_x_deg }.is_some())
        };
        let axes = match (read(false), read(true)) {
            (true, false) => ", from the X axis alone: no tilt_y_deg readings",
            (false, true) => ", from the Y axis alone: no tilt_x_deg readings",
            _ => "",
        };
        Ok(Some(ShaftTilt {
            p: t.circle_test.map_or(1.0, |c| c.p),
            parameters,
            location: format!(
                "the inclinometer's tilt circle ({}{axes}; {} positions bridged); a first harmonic of the gyro, invisible in its residuals",
                method.name(),
                t.bridged
            ),
            corrections: t.corrections,
            warning: t.warning,
            sigma_psi_deg: t.sigma_psi_deg,
            sensitivity: t.sensitivity,
        }))
    }
}

impl Effect for ShaftTilt {
    fn kind(&self) -> Kind {
        Kind::ShaftTilt
    }

    fn test(&self, s: &State) -> Vec<Proposal> {
        if s.is_named(Kind::ShaftTilt) {
            return Vec::new();
        }
        vec![Proposal {
            kind: Kind::ShaftTilt,
            p: self.p,
            change: Change::Nothing,
            parameters: self.parameters.clone(),
            location: self.location.clone(),
            scanned: 0,
            own_p: None,
            draws: Draws::No,
        }]
    }
}
