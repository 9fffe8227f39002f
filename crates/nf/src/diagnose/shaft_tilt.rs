//! `shaft_tilt`: the vertical Earth rate a tilted shaft adds, from the inclinometer by `nf
//! fit`'s own path (`crate::tilt`). It is measured physics, so it is corrected before any test
//! whether or not it is significant; it is named when the inclinometer's tilt circle stands
//! out of the readings' noise (F test of the circle against constant readings).

use super::effect::{Change, Effect, Param, Proposal, State, param};
use super::kind::Kind;
use crate::analysis::TiltMethod;
use crate::linfit;
use crate::recording::Recording;
use crate::stats::f_sf;
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
        let column = |y: bool| -> Vec<(f64, f64)> {
            rec.rows
                .iter()
                .filter_map(|r| Some((r.encoder_deg, if y { r.tilt_y_deg? } else { r.tilt_x_deg? })))
                .collect()
        };
        // The axes read over enough of the turn to draw a circle.
        let axes: Vec<Vec<(f64, f64)>> = match method {
            TiltMethod::Exact => vec![column(false), column(true)],
            _ => vec![column(false)],
        }
        .into_iter()
        .filter(|a| a.len() >= 3)
        .collect();
        let mut parameters = Vec::new();
        if let Some(s) = t.shaft {
            let sigma_tilt = s.rms_deg * (2.0 / (rec.rows.len() - t.bridged) as f64).sqrt();
            parameters.extend([
                param("tilt_deg", s.tilt_deg, Some(sigma_tilt)),
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
        Ok(Some(ShaftTilt {
            p: circle_p(&axes),
            parameters,
            location: format!(
                "the inclinometer's tilt circle ({}; {} positions bridged); a first harmonic of the gyro, invisible in its residuals",
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
        }]
    }
}

/// F test of a circle `C + A cos + B sin` in every axis against constant readings.
fn circle_p(axes: &[Vec<(f64, f64)>]) -> f64 {
    let (mut rss0, mut rss1, mut dof) = (0.0, 0.0, 0usize);
    for axis in axes {
        let n = axis.len();
        let cols = vec![
            vec![1.0; n],
            axis.iter().map(|(g, _)| g.to_radians().cos()).collect(),
            axis.iter().map(|(g, _)| g.to_radians().sin()).collect(),
        ];
        let y: Vec<f64> = axis.iter().map(|(_, v)| *v).collect();
        let Some(ls) = linfit::fit(&cols, &y) else { return 1.0 };
        let mean = y.iter().sum::<f64>() / n as f64;
        rss0 += y.iter().map(|v| (v - mean).powi(2)).sum::<f64>();
        rss1 += ls.rss;
        dof += n.saturating_sub(3);
    }
    let q = 2.0 * axes.len() as f64;
    if dof == 0 {
        return 1.0;
    }
    let f = ((rss0 - rss1) / q) / (rss1 / dof as f64).max(1e-300);
    f_sf(f, q, dof as f64)
}
