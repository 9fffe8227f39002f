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
    /// Whitened residual sum of squares.
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

/// The azimuth of a fit whose columns begin with `1, cos, sin`, its whitened RSS, and its
/// sigma with the noise level rescaled by the residuals.
pub fn summary(ls: &Ls) -> Summary {
    let (a, b) = (ls.coef[1], ls.coef[2]);
    let r2 = a * a + b * b;
    let v =
        ls.s2() * (b * b * ls.cov_unit[1][1] + a * a * ls.cov_unit[2][2] - 2.0 * a * b * ls.cov_unit[1][2]) / (r2 * r2);
    Summary {
        azimuth_deg: atan2_deg(-b, a),
        rss: ls.rss,
        sigma_arcsec: v.max(0.0).sqrt().to_degrees() * 3600.0,
    }
}
