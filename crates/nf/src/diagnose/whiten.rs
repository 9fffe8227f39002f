//! The transformation that makes the recording's noise white: `L^-1` of the Cholesky factor
//! of the dwell means' covariance under the noise model. Every test of `nf diagnose` is made
//! on whitened columns, so an F test there is a GLS likelihood-ratio test under the noise.

use crate::gls::Cov;

#[derive(Clone)]
pub struct Whitener {
    /// `None`: white noise, the identity.
    cov: Option<Cov>,
}

impl Whitener {
    pub fn identity() -> Whitener {
        Whitener { cov: None }
    }

    pub fn of(cov: Cov) -> Whitener {
        Whitener { cov: Some(cov) }
    }

    pub fn apply(&self, v: &[f64]) -> Vec<f64> {
        match &self.cov {
            Some(c) => c.whiten(v),
            None => v.to_vec(),
        }
    }

    /// `W^T v`.
    pub fn adjoint(&self, v: &[f64]) -> Vec<f64> {
        match &self.cov {
            Some(c) => c.adjoint(v),
            None => v.to_vec(),
        }
    }

    /// `|W e_i|^2` and `|W s_i|^2` of every row's indicator and of the step from it on.
    pub fn indicator_and_step_norms(&self, n: usize) -> (Vec<f64>, Vec<f64>) {
        match &self.cov {
            Some(c) => c.indicator_and_step_norms(),
            None => (vec![1.0; n], (0..n).map(|i| (n - i) as f64).collect()),
        }
    }
}
