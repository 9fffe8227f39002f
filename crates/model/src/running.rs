//! The running azimuth under the gyro's noise model, dwell by dwell: a Kalman filter whose
//! state is the first harmonic (A, B), the bias C (a random walk under rate random walk), a
//! Gauss-Markov bias and a bank of Gauss-Markov members that together make flicker. It is
//! generalised least squares under that model without the covariance matrix of all dwells, so
//! the firmware can run it in a few hundred bytes and stop a run once the target is reached.
//!
//! In `f64`: the priors of A, B and C are some 10^9 times the variance of a dwell mean, more
//! than `f32` resolves. The dwell mean is treated as the bias at its centre (each member's
//! correlation time is at least the dwell).

// Index loops read as the matrix algebra they implement.
#![allow(clippy::needless_range_loop)]

use crate::EARTH_RATE_DPH;
use crate::angle::{atan2_deg, sincos_deg};
use crate::noise::NoiseModel;
use crate::noise_terms::NoiseTerms;
use num_traits::Float;

/// Flicker members: two per decade from the dwell to [`FLICKER_TAU_MAX_S`].
const MAX_FLICKER: usize = 12;
const FLICKER_RATIO: f64 = 3.162_277_660_168_379_5;
const FLICKER_TAU_MAX_S: f64 = 1.0e5;
const STATES: usize = 4 + MAX_FLICKER;
/// State indices: harmonic, bias, Gauss-Markov; flicker members follow.
const A: usize = 0;
const B: usize = 1;
const C: usize = 2;
const GM: usize = 3;

/// Why a dwell was not taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RunningError {
    /// The noise model is not valid, or the dwell is not positive.
    BadModel,
    /// A non-finite angle, time, rate or variance.
    NonFinite,
    /// Time went backwards.
    TimeOrder,
}

/// The filter.
#[derive(Debug, Clone, Copy)]
pub struct RunningGls {
    x: [f64; STATES],
    p: [[f64; STATES]; STATES],
    /// Flicker members in use, their correlation times and variance each.
    members: usize,
    tau_s: [f64; MAX_FLICKER],
    member_var: f64,
    model: NoiseModel,
    dwell_s: f64,
    t_last_s: Option<f64>,
    dwells: u32,
}

/// The azimuth so far.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Running {
    pub psi_deg: f64,
    pub sigma_psi_deg: f64,
    pub amplitude_dph: f64,
    pub dwells: u32,
}

impl RunningGls {
    /// A filter for dwells of `dwell_s` under the noise `terms`.
    pub fn new(terms: &NoiseTerms, dwell_s: f64) -> Result<Self, RunningError> {
        let model = &NoiseModel {
            arw_deg_rth: terms.arw_deg_rth as f64,
            bias_instability_dph: terms.bias_instability_dph as f64,
            rrw_dph_rth: terms.rrw_dph_rth as f64,
            gm_sigma_dph: terms.gm_sigma_dph as f64,
            gm_tau_s: terms.gm_tau_s as f64,
            quantization_arcsec: terms.quantization_arcsec as f64,
            student_t_dof: 0.0,
        };
        if model.validate().is_err() || !(dwell_s > 0.0 && dwell_s.is_finite()) {
            return Err(RunningError::BadModel);
        }
        let mut f = RunningGls {
            x: [0.0; STATES],
            p: [[0.0; STATES]; STATES],
            members: 0,
            tau_s: [0.0; MAX_FLICKER],
            // Equal variances (B^2 / pi) ln r give the flicker PSD over the bank's band, with
            // the Allan floor 0.664 B.
            member_var: model.bias_instability_dph.powi(2) / core::f64::consts::PI * FLICKER_RATIO.ln(),
            model: *model,
            dwell_s,
            t_last_s: None,
            dwells: 0,
        };
        if model.bias_instability_dph > 0.0 {
            let mut tau = dwell_s;
            while f.members < MAX_FLICKER && tau < FLICKER_TAU_MAX_S {
                f.tau_s[f.members] = tau;
                f.members += 1;
                tau *= FLICKER_RATIO;
            }
        }
        // The harmonic within twice the Earth rate, the bias within 100 deg/h: loose priors.
        f.p[A][A] = (2.0 * EARTH_RATE_DPH).powi(2);
        f.p[B][B] = f.p[A][A];
        f.p[C][C] = 1.0e4;
        f.p[GM][GM] = model.gm_sigma_dph.powi(2);
        for i in 0..f.members {
            f.p[4 + i][4 + i] = f.member_var;
        }
        Ok(f)
    }

    fn dim(&self) -> usize {
        4 + self.members
    }

    /// Carries the state over `dt_s`: the bias walks, the Markov parts decay.
    fn predict(&mut self, dt_s: f64) {
        let d = self.dim();
        let mut phi = [1.0; STATES];
        let mut q = [0.0; STATES];
        q[C] = self.model.rrw_dph_rts().powi(2) * dt_s;
        if self.model.gm_sigma_dph > 0.0 {
            phi[GM] = Float::exp(-dt_s / self.model.gm_tau_s);
            q[GM] = self.model.gm_sigma_dph.powi(2) * (1.0 - phi[GM] * phi[GM]);
        }
        for i in 0..self.members {
            phi[4 + i] = Float::exp(-dt_s / self.tau_s[i]);
            q[4 + i] = self.member_var * (1.0 - phi[4 + i] * phi[4 + i]);
        }
        for i in 0..d {
            self.x[i] *= phi[i];
            for j in 0..d {
                self.p[i][j] *= phi[i] * phi[j];
            }
            self.p[i][i] += q[i];
        }
    }

    /// Takes one dwell mean: at `gamma_deg`, centred at `t_s`, `rate_dph` with the tilt's
    /// vertical Earth rate already removed. `white_var` is the variance of its independent
    /// part, (deg/h)^2; `None` takes it from the noise model.
    pub fn add(&mut self, gamma_deg: f64, t_s: f64, rate_dph: f64, white_var: Option<f64>) -> Result<(), RunningError> {
        let r = white_var.unwrap_or_else(|| self.model.independent_var(self.dwell_s));
        if !(gamma_deg.is_finite() && t_s.is_finite() && rate_dph.is_finite() && r.is_finite() && r >= 0.0) {
            return Err(RunningError::NonFinite);
        }
        if let Some(t0) = self.t_last_s {
            if t_s < t0 {
                return Err(RunningError::TimeOrder);
            }
            self.predict(t_s - t0);
        }
        self.t_last_s = Some(t_s);
        let d = self.dim();
        // f32 trigonometry: the firmware then carries no f64 sine, and 1e-7 of the Earth rate
        // is far below any gyro's noise.
        let (s, c) = sincos_deg(gamma_deg as f32);
        let (s, c) = (s as f64, c as f64);
        let mut h = [1.0; STATES];
        h[A] = c;
        h[B] = s;
        let mut ph = [0.0; STATES];
        for i in 0..d {
            ph[i] = (0..d).map(|j| self.p[i][j] * h[j]).sum();
        }
        let innovation_var = (0..d).map(|i| h[i] * ph[i]).sum::<f64>() + r;
        let predicted: f64 = (0..d).map(|i| h[i] * self.x[i]).sum();
        let k: [f64; STATES] = core::array::from_fn(|i| if i < d { ph[i] / innovation_var } else { 0.0 });
        for i in 0..d {
            self.x[i] += k[i] * (rate_dph - predicted);
        }
        // P - K S K^T, kept symmetric.
        for i in 0..d {
            for j in 0..=i {
                let v = self.p[i][j] - k[i] * k[j] * innovation_var;
                self.p[i][j] = v;
                self.p[j][i] = v;
            }
        }
        self.dwells += 1;
        Ok(())
    }

    /// The azimuth and its standard error under the noise model.
    pub fn azimuth(&self) -> Running {
        let (a, b) = (self.x[A], self.x[B]);
        let h2 = a * a + b * b;
        // psi = atan2(-B, A): its gradient in (A, B) is (B, -A) / H^2.
        let (ga, gb) = (b / h2, -a / h2);
        let var = ga * ga * self.p[A][A] + 2.0 * ga * gb * self.p[A][B] + gb * gb * self.p[B][B];
        Running {
            psi_deg: atan2_deg(-b as f32, a as f32) as f64,
            sigma_psi_deg: Float::sqrt(var.max(0.0)).to_degrees(),
            amplitude_dph: Float::sqrt(h2),
            dwells: self.dwells,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::eprintln;
    use std::vec::Vec;

    const LAT: f64 = 43.8;

    fn h() -> f64 {
        EARTH_RATE_DPH * LAT.to_radians().cos()
    }

    /// Dwell centres of a sequential run: `n` dwells of `dwell_s`, one every `cycle_s`.
    fn run(n: usize, dwell_s: f64, cycle_s: f64) -> Vec<(f64, f64)> {
        (0..n)
            .map(|k| (k as f64 * 360.0 / n as f64, k as f64 * cycle_s + dwell_s / 2.0))
            .collect()
    }

    fn filter(model: &NoiseModel, dwell_s: f64, psi: f64, dwells: &[(f64, f64)]) -> Running {
        let mut f = RunningGls::new(&model.into(), dwell_s).unwrap();
        for &(g, t) in dwells {
            let rate = h() * (g + psi).to_radians().cos() + 3.0;
            f.add(g, t, rate, None).unwrap();
        }
        f.azimuth()
    }

    /// GLS sigma of psi from the dense covariance of the model's closed form (a generalised
    /// covariance: a constant added makes it positive definite and changes nothing beside C).
    fn dense_sigma_deg(model: &NoiseModel, dwell_s: f64, dwells: &[(f64, f64)]) -> f64 {
        let n = dwells.len();
        let mut cov: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| 0.01 + model.mean_cov((dwells[i].1 - dwells[j].1).abs(), dwell_s, dwell_s, i == j))
                    .collect()
            })
            .collect();
        // Cholesky, then the information matrix X^T cov^-1 X of (C, cos, sin).
        for j in 0..n {
            let d = (cov[j][j] - (0..j).map(|k| cov[j][k] * cov[j][k]).sum::<f64>()).sqrt();
            cov[j][j] = d;
            for i in j + 1..n {
                cov[i][j] = (cov[i][j] - (0..j).map(|k| cov[i][k] * cov[j][k]).sum::<f64>()) / d;
            }
        }
        let cols: Vec<Vec<f64>> = (0..3)
            .map(|c| {
                let mut z: Vec<f64> = dwells
                    .iter()
                    .map(|&(g, _)| [1.0, g.to_radians().cos(), g.to_radians().sin()][c])
                    .collect();
                for i in 0..n {
                    z[i] = (z[i] - (0..i).map(|k| cov[i][k] * z[k]).sum::<f64>()) / cov[i][i];
                }
                z
            })
            .collect();
        let info = |a: usize, b: usize| (0..n).map(|i| cols[a][i] * cols[b][i]).sum::<f64>();
        let m = [
            [info(0, 0), info(0, 1), info(0, 2)],
            [info(1, 0), info(1, 1), info(1, 2)],
            [info(2, 0), info(2, 1), info(2, 2)],
        ];
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        let var_a = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
        let var_b = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
        let cov_ab = -(m[0][0] * m[1][2] - m[0][2] * m[1][0]) / det;
        let psi: f64 = 65.5;
        // psi = atan2(-B, A) at A = H cos psi, B = -H sin psi.
        let (ga, gb) = (-psi.to_radians().sin() / h(), -psi.to_radians().cos() / h());
        (ga * ga * var_a + 2.0 * ga * gb * cov_ab + gb * gb * var_b)
            .sqrt()
            .to_degrees()
    }

    #[test]
    fn white_noise_gives_the_least_squares_sigma_and_the_exact_azimuth() {
        let m = NoiseModel::white(0.005, 2.0);
        let r = filter(&m, 2.0, 65.5, &run(72, 2.0, 2.6));
        // f32 trigonometry: to 0.04".
        assert!((r.psi_deg - 65.5).abs() < 1e-5, "{}", r.psi_deg);
        assert!((r.amplitude_dph / h() - 1.0).abs() < 1e-6);
        let ls = (2.0f64 / 72.0).sqrt() * 0.005 / h();
        assert!(
            (r.sigma_psi_deg.to_radians() / ls - 1.0).abs() < 1e-6,
            "{} vs {ls}",
            r.sigma_psi_deg.to_radians()
        );
        assert_eq!(r.dwells, 72);
    }

    #[test]
    fn coloured_noise_gives_the_dense_gls_sigma() {
        let white = NoiseModel::white(0.005, 2.0);
        let cases = [
            (
                "flicker",
                NoiseModel {
                    bias_instability_dph: 0.004,
                    ..white
                },
                0.05,
            ),
            (
                "random walk",
                NoiseModel {
                    rrw_dph_rth: 0.3,
                    ..white
                },
                0.03,
            ),
            (
                "Gauss-Markov",
                NoiseModel {
                    gm_sigma_dph: 0.015,
                    gm_tau_s: 60.0,
                    ..white
                },
                0.03,
            ),
        ];
        for (name, m, tol) in cases {
            let dwells = run(48, 2.0, 2.8);
            let kalman = filter(&m, 2.0, 65.5, &dwells).sigma_psi_deg;
            let dense = dense_sigma_deg(&m, 2.0, &dwells);
            eprintln!("{name}: Kalman / dense GLS {:.4}", kalman / dense);
            assert!((kalman / dense - 1.0).abs() < tol, "{name}: {kalman} vs {dense}");
        }
    }

    #[test]
    fn bad_input_is_refused() {
        let m = NoiseModel::white(0.005, 2.0);
        assert_eq!(RunningGls::new(&(&m).into(), 0.0).unwrap_err(), RunningError::BadModel);
        let bad = NoiseModel { gm_sigma_dph: 1.0, ..m };
        assert_eq!(
            RunningGls::new(&(&bad).into(), 2.0).unwrap_err(),
            RunningError::BadModel
        );
        let mut f = RunningGls::new(&(&m).into(), 2.0).unwrap();
        assert_eq!(f.add(f64::NAN, 1.0, 1.0, None), Err(RunningError::NonFinite));
        assert_eq!(f.add(0.0, 1.0, 1.0, Some(-1.0)), Err(RunningError::NonFinite));
        f.add(0.0, 5.0, 1.0, None).unwrap();
        assert_eq!(f.add(5.0, 4.0, 1.0, None), Err(RunningError::TimeOrder));
    }
}
