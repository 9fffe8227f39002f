//! The linear model as it grows: Eq. 7's columns and those of the effects named so far, each
//! kept raw (for residuals and plots) and whitened (for the fit), and the rates it explains.

use super::kind::Kind;
use super::whiten::Whitener;
use crate::linfit::{self, Ls};
use nf_model::angle::atan2_deg;

#[derive(Clone)]
pub struct Column {
    /// The effect the column belongs to; `None` for Eq. 7's own.
    pub kind: Option<Kind>,
    pub raw: Vec<f64>,
    pub white: Vec<f64>,
}

#[derive(Clone)]
pub struct Model {
    pub cols: Vec<Column>,
    pub y: Vec<f64>,
    pub y_white: Vec<f64>,
}

/// Azimuth and uncertainty of a fit.
#[derive(Debug, Clone, Copy)]
pub struct Summary {
    pub azimuth_deg: f64,
    /// Residual sum of squares of the rates, (deg/h)^2.
    pub rss: f64,
    pub sigma_arcsec: f64,
}

impl Model {
    pub fn new(base: Vec<Vec<f64>>, y: Vec<f64>, w: &Whitener) -> Model {
        let m = Model {
            cols: Vec::new(),
            y_white: w.apply(&y),
            y,
        };
        m.with(None, base, w)
    }

    pub fn with(&self, kind: Option<Kind>, cols: Vec<Vec<f64>>, w: &Whitener) -> Model {
        let mut m = self.clone();
        m.cols.extend(cols.into_iter().map(|raw| Column {
            kind,
            white: w.apply(&raw),
            raw,
        }));
        m
    }

    pub fn with_y(&self, y: Vec<f64>, w: &Whitener) -> Model {
        Model {
            cols: self.cols.clone(),
            y_white: w.apply(&y),
            y,
        }
    }

    /// The same model whitened by another noise model.
    pub fn rewhiten(&self, w: &Whitener) -> Model {
        Model {
            cols: self
                .cols
                .iter()
                .map(|c| Column {
                    kind: c.kind,
                    raw: c.raw.clone(),
                    white: w.apply(&c.raw),
                })
                .collect(),
            y: self.y.clone(),
            y_white: w.apply(&self.y),
        }
    }

    /// The whitened fit, with `extra` whitened columns appended.
    pub fn fit_plus(&self, extra: &[Vec<f64>]) -> Option<Ls> {
        let cols: Vec<&[f64]> = self
            .cols
            .iter()
            .map(|c| c.white.as_slice())
            .chain(extra.iter().map(Vec::as_slice))
            .collect();
        linfit::fit_slices(&cols, &self.y_white)
    }

    pub fn fit(&self) -> Option<Ls> {
        self.fit_plus(&[])
    }

    /// `y - X beta` in deg/h, and the part of it the columns of `kind` explain.
    pub fn raw_residuals(&self, ls: &Ls) -> Vec<f64> {
        (0..self.y.len())
            .map(|i| self.y[i] - self.cols.iter().zip(&ls.coef).map(|(c, b)| c.raw[i] * b).sum::<f64>())
            .collect()
    }

    /// The fitted contribution of every effect column (not Eq. 7's), deg/h.
    pub fn effects_fitted(&self, ls: &Ls) -> Vec<f64> {
        (0..self.y.len())
            .map(|i| {
                self.cols
                    .iter()
                    .zip(&ls.coef)
                    .filter(|(c, _)| c.kind.is_some())
                    .map(|(c, b)| c.raw[i] * b)
                    .sum::<f64>()
            })
            .collect()
    }

    /// The columns as recorded, not whitened.
    pub fn raw_cols(&self) -> Vec<Vec<f64>> {
        self.cols.iter().map(|c| c.raw.clone()).collect()
    }

    /// Columns beyond Eq. 7's.
    pub fn extra(&self) -> usize {
        self.cols.len() - 3
    }
}

/// The azimuth of `ls`, a fit of `m` whose columns begin with `1, cos, sin`, the RSS of its
/// residuals in rate units, and its sigma with the noise level rescaled by the residuals.
pub fn summary(m: &Model, ls: &Ls) -> Summary {
    let (a, b) = (ls.coef[1], ls.coef[2]);
    let r2 = a * a + b * b;
    let v =
        ls.s2() * (b * b * ls.cov_unit[1][1] + a * a * ls.cov_unit[2][2] - 2.0 * a * b * ls.cov_unit[1][2]) / (r2 * r2);
    Summary {
        azimuth_deg: atan2_deg(-b, a),
        rss: m.raw_residuals(ls).iter().map(|r| r * r).sum(),
        sigma_arcsec: v.max(0.0).sqrt().to_degrees() * 3600.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gls::Cov;
    use nf_model::noise::NoiseModel;
    use nf_model::rng::Rng;

    /// The summary's RSS is of the rates, (deg/h)^2, whatever the whitening: under a walk it
    /// is the GLS coefficients' residuals, not the whitened ones (about the dof, unitless).
    #[test]
    fn the_rss_is_of_the_rates_under_any_noise() {
        let mut rng = Rng::new(3);
        let n = 48;
        let t: Vec<f64> = (0..n).map(|i| 2.5 * i as f64).collect();
        let gamma: Vec<f64> = (0..n).map(|i| (i as f64 * 7.5).to_radians()).collect();
        let base = vec![
            vec![1.0; n],
            gamma.iter().map(|g| g.cos()).collect(),
            gamma.iter().map(|g| g.sin()).collect(),
        ];
        let y: Vec<f64> = (0..n).map(|i| 0.4 + 10.0 * base[1][i] + 0.02 * rng.gauss()).collect();
        let walk = NoiseModel {
            rrw_dph_rth: 0.5,
            ..NoiseModel::white(0.02, 2.0)
        };
        for w in [
            Whitener::identity(),
            Whitener::of(Cov::of_windows(&walk, &t, &vec![2.0; n]).unwrap()),
        ] {
            let m = Model::new(base.clone(), y.clone(), &w);
            let f = m.fit().unwrap();
            let rss: f64 = (0..n)
                .map(|i| y[i] - (0..3).map(|k| base[k][i] * f.coef[k]).sum::<f64>())
                .map(|r| r * r)
                .sum();
            let s = summary(&m, &f);
            assert!((s.rss / rss - 1.0).abs() < 1e-12, "{} {rss}", s.rss);
            // 48 residuals of 0.02 deg/h: about 0.02 (deg/h)^2.
            assert!((0.005..0.08).contains(&s.rss), "{}", s.rss);
        }
    }
}
