//! The running azimuth under the gyro's noise model, dwell by dwell: a filter whose state is
//! the first harmonic (A, B), the bias C (a random walk under rate random walk), a
//! Gauss-Markov bias and a bank of Gauss-Markov members that together make flicker. It is
//! generalised least squares under that model without the covariance matrix of all dwells, so
//! the firmware can run it in two kilobytes and stop a run once the target is reached. A dwell
//! mean is exact: each Markov state is carried from the dwell's start to its end, and the
//! mean over the dwell is the bridge between the two (half of each for a walk) plus a part
//! of its own. Taken as the bias at the dwell's centre, dwells of opposite angles close
//! together (opposite pairs on a fast motor) made the sigma up to 1.31 times dense GLS's.
//!
//! A square-root information filter, so that it runs in `f32` on the MCU: the priors of A, B
//! and C are some 10^9 times the variance of a dwell mean. A covariance filter subtracts nearly
//! equal numbers of that size at every dwell, more than `f32`'s seven digits hold; information
//! only adds, and the rotations that keep its square root `R` triangular neither square nor
//! subtract it. The states run members, Gauss-Markov, C, A, B: the time update acts on the
//! first ones, and `R`'s last 2x2 block is the information of (A, B) alone.

// Index loops read as the matrix algebra they implement.
#![allow(clippy::needless_range_loop)]

use crate::angle::{atan2_deg, sincos_deg};
use crate::fit::hypot;
use crate::noise_terms::NoiseTerms;
use crate::{EARTH_RATE_DPH, Float, c, positive, sqrt};

/// Flicker members: two per decade from [`FLICKER_TAU_MIN_DWELLS`] of the dwell to
/// [`FLICKER_TAU_MAX_S`].
const MAX_FLICKER: usize = 16;
const FLICKER_RATIO: f64 = 3.162_277_660_168_379_5;
/// `ln(FLICKER_RATIO)`, half of `ln(10)`.
const LN_FLICKER_RATIO: f64 = 1.151_292_546_497_022_8;
const FLICKER_TAU_MAX_S: f64 = 1.0e5;
/// The fastest member, in dwells: the flicker within a dwell shows in how two close dwells
/// differ (from the dwell on, opposite pairs on a fast motor had 0.94 of dense GLS's sigma;
/// from a hundredth, 0.999).
const FLICKER_TAU_MIN_DWELLS: f64 = 0.01;
/// The time constant (s) the bias walk is carried as a Gauss-Markov state with: over any gap
/// the two differ by less than `f32` resolves.
const WALK_TAU_S: f64 = 1.0e20;
const STATES: usize = 5 + MAX_FLICKER;
/// Seconds per hour, and its root: IEEE units are per hour.
const S_PER_H: f64 = 3600.0;
const SQRT_S_PER_H: f64 = 60.0;

/// Why a dwell was not taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RunningError {
    /// The noise model is not valid, or the dwell is not positive.
    BadModel,
    /// A non-finite angle or rate, or a variance that is not a positive number.
    NonFinite,
    /// Time went backwards.
    TimeOrder,
}

/// The filter.
#[derive(Debug, Clone, Copy)]
pub struct RunningGls<F> {
    /// Upper-triangular square root of the information matrix, rows of `dim` states, with
    /// `R x = z` in column `dim`.
    r: [[F; STATES + 1]; STATES],
    dim: usize,
    /// The states the time update carries, first in `R`: the flicker members, the
    /// Gauss-Markov bias, and C where it walks; each a Gauss-Markov state of this variance,
    /// (deg/h)^2, and time constant, s.
    dynamic: usize,
    var: [F; STATES],
    tau_s: [F; STATES],
    /// Variance of a dwell mean's independent part under the model, (deg/h)^2.
    model_white_var: F,
    /// The window each mean is over, s.
    dwell_s: F,
    t_last_us: Option<u64>,
    dwells: u32,
}

/// The azimuth so far.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Running<F> {
    pub psi_deg: F,
    pub sigma_psi_deg: F,
    pub amplitude_dph: F,
    pub dwells: u32,
}

/// `x` in the working float type.
fn of<F: Float>(x: f32) -> F {
    F::from(x).unwrap_or_else(F::nan)
}

/// Rotates rows `a` and `b` from column `from` on so that `b[from]` becomes zero (a Givens
/// rotation: lengths kept; `hypot` rescales where the squares would leave the float's range).
fn rotate<F: Float>(a: &mut [F], b: &mut [F], from: usize) {
    let (x, y) = (a[from], b[from]);
    if y == F::zero() {
        return;
    }
    let h = hypot(x, y);
    let (cos, sin) = (x / h, y / h);
    for k in from..a.len() {
        let (u, v) = (a[k], b[k]);
        a[k] = cos * u + sin * v;
        b[k] = cos * v - sin * u;
    }
    b[from] = F::zero();
}

/// `e^-x` for `x >= 0`: halved below 1/2, a Taylor series there, squared back (within
/// `1e-6 (1 + x)` of itself in `f32`, the squarings doubling the rounding). libm's `expf`
/// is 420 bytes of the firmware's flash, which the filter's decays were its only use of.
fn exp_neg<F: Float>(x: F) -> F {
    if x >= c(88.0) {
        return F::zero();
    }
    let (mut y, mut halvings) = (x, 0);
    while y > c(0.5) {
        y = y / c(2.0);
        halvings += 1;
    }
    let (mut term, mut sum, mut k) = (F::one(), F::one(), F::one());
    while k < c(11.0) {
        term = -term * y / k;
        sum = sum + term;
        k = k + F::one();
    }
    for _ in 0..halvings {
        sum = sum * sum;
    }
    sum
}

/// A Markov state over a dwell: its decay `phi` from the dwell's start to its end, the
/// variance `q` it gains, the weight `coef` of each end in the dwell's mean, and the
/// variance `own` of the mean's part that neither end holds.
struct Window<F> {
    phi: F,
    q: F,
    coef: F,
    own: F,
}

impl<F: Float> Window<F> {
    /// A Gauss-Markov state of variance `var` over `x` correlation times: the mean is
    /// `a x0 + u`, the end `phi x0 + w`, `a = (1 - phi) / x`, `cov(u, w) = a var (1 - phi)`;
    /// `u` less its regression on `w` leaves the bridge `a / (1 + phi)` on each end.
    fn markov(var: F, x: F) -> Self {
        let phi = exp_neg(x);
        // Where `1 - phi` and the part of its own (`share - 2 a^2 / (1 + phi)`, `share = 2 (x -
        // 1 + phi) / x^2` the variance the mean keeps) cancel, their series (to 4e-6).
        let (a, own) = if x < c(0.3) {
            let x2 = x * x;
            (
                F::one() - x * (c::<F>(0.5) - x * (c::<F>(1.0 / 6.0) - x * (c::<F>(1.0 / 24.0) - x / c(120.0)))),
                x * (c::<F>(1.0 / 6.0) - x2 * (c::<F>(1.0 / 60.0) - c::<F>(17.0 / 10080.0) * x2)),
            )
        } else {
            let a = (F::one() - phi) / x;
            let share = c::<F>(2.0) * (x - F::one() + phi) / (x * x);
            (a, share - c::<F>(2.0) * a * a / (F::one() + phi))
        };
        Window {
            phi,
            // 1 - phi^2 as a x (1 + phi): no cancellation for small x.
            q: var * a * x * (F::one() + phi),
            coef: a / (F::one() + phi),
            own: var * own.max(F::zero()),
        }
    }
}

/// A dwell mean's row of the information while its Markov states are carried over the dwell,
/// and the weight its own equation, `(h . x - rate) / sd`, has in it.
struct Pending<F> {
    row: [F; STATES + 1],
    scale: F,
}

/// Moves column 0 of `row` behind its next `m - 1` columns.
#[inline(always)]
fn turn<F: Float>(row: &mut [F], m: usize) {
    // Swaps, not `rotate_left`, whose `memmove` is 1.5 KiB on the MCU.
    for j in 1..m {
        row.swap(j - 1, j);
    }
}

impl<F: Float> RunningGls<F> {
    /// A filter for dwells of `dwell_s` under the noise `terms`.
    pub fn new(terms: &NoiseTerms, dwell_s: F) -> Result<Self, RunningError> {
        if terms.validate().is_err() || !(positive(dwell_s) && dwell_s.is_finite()) {
            return Err(RunningError::BadModel);
        }
        let (b, rrw) = (of::<F>(terms.bias_instability_dph), of::<F>(terms.rrw_dph_rth));
        let (w, q) = (
            of::<F>(terms.arw_deg_rth) * c(SQRT_S_PER_H),
            of::<F>(terms.quantization_arcsec),
        );
        let (gm_sigma, gm_tau) = (of::<F>(terms.gm_sigma_dph), of::<F>(terms.gm_tau_s));
        // The state is the bias at an instant; a term so fast that a dwell's mean keeps none
        // of it within the float's range (about `2 tau / dwell` of it) is no term.
        let gm_var = gm_sigma * gm_sigma;
        let gm_kept = gm_var * (gm_tau / dwell_s).min(F::one());
        let mut f = RunningGls {
            r: [[F::zero(); STATES + 1]; STATES],
            dim: 0,
            dynamic: 0,
            var: [F::zero(); STATES],
            tau_s: [F::zero(); STATES],
            model_white_var: w * w / dwell_s + c::<F>(2.0) * q * q / (dwell_s * dwell_s),
            dwell_s,
            t_last_us: None,
            dwells: 0,
        };
        // Equal variances (B^2 / pi) ln r give the flicker PSD over the bank's band, with the
        // Allan floor 0.664 B.
        let member_var = b * b / c(core::f64::consts::PI) * c(LN_FLICKER_RATIO);
        let mut tau = dwell_s * c(FLICKER_TAU_MIN_DWELLS);
        while positive(member_var) && f.dim < MAX_FLICKER && tau < c(FLICKER_TAU_MAX_S) {
            f.push(member_var, tau);
            tau = tau * c(FLICKER_RATIO);
        }
        if positive(gm_kept) {
            f.push(gm_var, gm_tau);
        }
        // Priors, as 1/sd on the diagonal: the Markov states at their variance, the bias C
        // within 100 deg/h and the harmonic within twice the Earth rate.
        for i in 0..f.dim {
            f.r[i][i] = F::one() / sqrt(f.var[i]);
        }
        let rrw_var_per_s = rrw * rrw / c(S_PER_H);
        if positive(rrw_var_per_s) {
            f.var[f.dim] = rrw_var_per_s * c(WALK_TAU_S / 2.0);
            f.tau_s[f.dim] = c(WALK_TAU_S);
            f.dynamic = f.dim + 1;
        }
        f.r[f.dim][f.dim] = c(0.01);
        f.r[f.dim + 1][f.dim + 1] = c(0.5 / EARTH_RATE_DPH);
        f.r[f.dim + 2][f.dim + 2] = c(0.5 / EARTH_RATE_DPH);
        f.dim += 3;
        Ok(f)
    }

    /// A Markov state of variance `var` and time constant `tau_s`, next in `R`.
    // Inlined, as `turn`: at `opt-level = "z"` the call took more flash than the body.
    #[inline(always)]
    fn push(&mut self, var: F, tau_s: F) {
        self.var[self.dim] = var;
        self.tau_s[self.dim] = tau_s;
        self.dim += 1;
        self.dynamic = self.dim;
    }

    /// Dynamic state `k` over `dt_s`: a Gauss-Markov state, the walk as one whose time
    /// constant is [`WALK_TAU_S`] (over any gap it gains `rate dt`, keeps half of each end
    /// in a dwell's mean and `rate T / 12` of its own).
    fn over(&self, k: usize, dt_s: F) -> Window<F> {
        Window::markov(self.var[k], dt_s / self.tau_s[k])
    }

    /// Carries the state over `dt_s`: the bias walks, the Markov parts decay.
    fn predict(&mut self, dt_s: F) {
        let mut none = Pending {
            row: [F::zero(); STATES + 1],
            scale: F::zero(),
        };
        self.carry(&mut none, |f, k| f.over(k, dt_s));
    }

    /// Carries each dynamic state over `step(k)`, `pending` with it: each in turn is brought
    /// to the front, carried there, and moved to the back of the dynamic block; after all of
    /// them the order is the original one.
    fn carry(&mut self, pending: &mut Pending<F>, step: impl Fn(&Self, usize) -> Window<F>) {
        let m = self.dynamic;
        for k in 0..m {
            let w = step(self, k);
            self.window_front(pending, &w);
            self.cycle_front(m);
            turn(&mut pending.row, m);
        }
    }

    /// Carries state 0 over `w`, `x0' = phi x0 + v` with `v` of variance `q`, `pending` (a
    /// dwell mean's row in the states before, or zero) taking `coef` of the new `x0` as of
    /// the old: the old `x0` is eliminated between row 0 (the only row of `R` with it), the
    /// process noise's row `(x0' - phi x0) / sd` and `pending`'s `mu0 x0 + scale coef x0'`,
    /// by two rotations in its column.
    fn window_front(&mut self, pending: &mut Pending<F>, w: &Window<F>) {
        // An exact transition (a variance below the float's range) as the stiffest one.
        let sd = sqrt(w.q.max(F::min_positive_value()));
        let (r00, old, mu0) = (self.r[0][0], -w.phi / sd, pending.row[0]);
        let h1 = hypot(r00, old);
        let h2 = hypot(h1, mu0);
        // Row 0 and the noise row turned by (r00, old) / h1: (h1, old / (h1 sd), r00 rho / h1)
        // and (0, r00 / (h1 sd), -old rho / h1); `pending` turned by (h1, mu0) / h2 against
        // the first of them; the second is the new row 0.
        let (cos2, sin2) = (h1 / h2, mu0 / h2);
        pending.row[0] = cos2 * pending.scale * w.coef - sin2 * old / (h1 * sd);
        self.r[0][0] = r00 / (h1 * sd);
        let (to_pending, to_row0) = (sin2 * r00 / h1, old / h1);
        for j in 1..=self.dim {
            let rho = self.r[0][j];
            pending.row[j] = cos2 * pending.row[j] - to_pending * rho;
            self.r[0][j] = -to_row0 * rho;
        }
        pending.scale = pending.scale * cos2;
    }

    /// Moves state 0 behind the first `m - 1` states and makes `R` triangular again: its
    /// columns turn left by one, and rotations of rows `p, p + 1` clear the subdiagonal.
    fn cycle_front(&mut self, m: usize) {
        for row in &mut self.r[..m] {
            turn(row, m);
        }
        for p in 0..m.saturating_sub(1) {
            let (top, bottom) = self.r.split_at_mut(p + 1);
            rotate(&mut top[p][..=self.dim], &mut bottom[0][..=self.dim], p);
        }
    }

    /// Takes one dwell mean: at `gamma_deg`, centred at `t_us` (microseconds on any clock),
    /// `rate_dph` with the tilt's vertical Earth rate already removed. `white_var` is the
    /// variance of its independent part, (deg/h)^2; `None` takes it from the noise model.
    pub fn add(&mut self, gamma_deg: F, t_us: u64, rate_dph: F, white_var: Option<F>) -> Result<(), RunningError> {
        let var = white_var.unwrap_or(self.model_white_var);
        if !(gamma_deg.is_finite() && rate_dph.is_finite() && positive(var) && var.is_finite()) {
            return Err(RunningError::NonFinite);
        }
        if let Some(t0) = self.t_last_us {
            if t_us < t0 {
                return Err(RunningError::TimeOrder);
            }
            // From the last dwell's end to this one's start.
            let dt_us = F::from(t_us - t0).unwrap_or_else(F::infinity);
            let gap_s = dt_us * c(1e-6) - self.dwell_s;
            if gap_s > F::zero() {
                self.predict(gap_s);
            }
        }
        self.t_last_us = Some(t_us);
        // The dwell as a row of the information: (h . x - rate) / sd, h the weights of the
        // Markov states' starts (their ends come in as they are carried over the dwell), 1
        // for a constant C, (cos, sin) for (A, B); the parts of the mean no end holds are
        // noise beside the white.
        let (m, d) = (self.dynamic, self.dim);
        let own = (0..m).fold(F::zero(), |sum, k| sum + self.over(k, self.dwell_s).own);
        let sd = sqrt(var + own);
        let (s, co) = sincos_deg(gamma_deg);
        let mut pending = Pending {
            row: [F::zero(); STATES + 1],
            scale: F::one() / sd,
        };
        for k in 0..d - 2 {
            pending.row[k] = if k < m {
                self.over(k, self.dwell_s).coef
            } else {
                F::one()
            } / sd;
        }
        pending.row[d - 2] = co / sd;
        pending.row[d - 1] = s / sd;
        pending.row[d] = rate_dph / sd;
        self.carry(&mut pending, |f, k| f.over(k, f.dwell_s));
        for p in 0..d {
            rotate(&mut self.r[p][..=d], &mut pending.row[..=d], p);
        }
        self.dwells += 1;
        Ok(())
    }

    /// The azimuth and its standard error under the noise model.
    pub fn azimuth(&self) -> Running<F> {
        let (ia, ib, d) = (self.dim - 2, self.dim - 1, self.dim);
        // (A, B)'s own information block [[ra, rab], [0, rb]] and its right-hand side.
        let (ra, rab, rb) = (self.r[ia][ia], self.r[ia][ib], self.r[ib][ib]);
        let b = self.r[ib][d] / rb;
        let a = (self.r[ia][d] - rab * b) / ra;
        let h2 = a * a + b * b;
        // psi = atan2(-B, A): its gradient g in (A, B) is (B, -A) / H^2, and its variance
        // |R^-T g|^2.
        let (ga, gb) = (b / h2, -a / h2);
        let ua = ga / ra;
        let ub = (gb - rab * ua) / rb;
        Running {
            psi_deg: atan2_deg(-b, a),
            sigma_psi_deg: sqrt(ua * ua + ub * ub).to_degrees(),
            amplitude_dph: sqrt(h2),
            dwells: self.dwells,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::NoiseModel;
    use crate::rng::Rng;
    use std::eprintln;
    use std::vec::Vec;

    const LAT: f64 = 43.8;
    const DWELL_S: f64 = 2.0;

    fn h() -> f64 {
        EARTH_RATE_DPH * LAT.to_radians().cos()
    }

    /// A sequential run: `n` dwells of [`DWELL_S`], one every `cycle_s`: (gamma, centre in us).
    fn schedule(n: usize, cycle_s: f64) -> Vec<(f64, u64)> {
        (0..n)
            .map(|k| {
                let t_s = k as f64 * cycle_s + DWELL_S / 2.0;
                (k as f64 * 360.0 / n as f64, (t_s * 1e6).round() as u64)
            })
            .collect()
    }

    /// Opposite pairs on a fast motor: `n` dwells of [`DWELL_S`], a half turn taking 0.8 s and
    /// a step to the next pair 0.4 s.
    fn pairs(n: usize) -> Vec<(f64, u64)> {
        let mut t_s = DWELL_S / 2.0;
        (0..n)
            .map(|k| {
                let g = (k / 2) as f64 * 360.0 / n as f64 + if k % 2 == 1 { 180.0 } else { 0.0 };
                let at = (g, (t_s * 1e6).round() as u64);
                t_s += DWELL_S + if k % 2 == 0 { 0.8 } else { 0.4 };
                at
            })
            .collect()
    }

    fn wrap_180(d: f64) -> f64 {
        (d + 180.0).rem_euclid(360.0) - 180.0
    }

    /// The dense generalised covariance of the dwell means (a constant added makes it positive
    /// definite and changes nothing beside C), as its Cholesky factor.
    fn dense_cholesky(model: &NoiseModel, dwells: &[(f64, u64)]) -> Vec<Vec<f64>> {
        let n = dwells.len();
        let t = |i: usize| dwells[i].1 as f64 * 1e-6;
        let mut l: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| 0.01 + model.mean_cov((t(i) - t(j)).abs(), DWELL_S, DWELL_S, i == j))
                    .collect()
            })
            .collect();
        for j in 0..n {
            let d = (l[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>()).sqrt();
            l[j][j] = d;
            for i in j + 1..n {
                l[i][j] = (l[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / d;
            }
            for i in 0..j {
                l[i][j] = 0.0;
            }
        }
        l
    }

    /// Rates of an instrument at `psi` with a bias of 3 deg/h, and noise of the model's
    /// covariance drawn with `rng` (none without).
    fn rates(model: &NoiseModel, psi: f64, dwells: &[(f64, u64)], rng: Option<&mut Rng>) -> Vec<f64> {
        let truth = dwells.iter().map(|&(g, _)| h() * (g + psi).to_radians().cos() + 3.0);
        let Some(rng) = rng else { return truth.collect() };
        let l = dense_cholesky(model, dwells);
        let z: Vec<f64> = (0..dwells.len()).map(|_| rng.gauss()).collect();
        truth
            .enumerate()
            .map(|(i, r)| r + (0..=i).map(|k| l[i][k] * z[k]).sum::<f64>())
            .collect()
    }

    /// The batch fit, computed independently: generalised least squares of (C, cos, sin) under
    /// the dense covariance; the azimuth and its sigma, deg.
    fn dense_gls(model: &NoiseModel, dwells: &[(f64, u64)], y: &[f64]) -> (f64, f64) {
        let n = dwells.len();
        let l = dense_cholesky(model, dwells);
        // Whitened columns and data: L^-1 X, L^-1 y.
        let whiten = |v: Vec<f64>| {
            let mut z = v;
            for i in 0..n {
                z[i] = (z[i] - (0..i).map(|k| l[i][k] * z[k]).sum::<f64>()) / l[i][i];
            }
            z
        };
        let col = |c: usize| {
            whiten(
                dwells
                    .iter()
                    .map(|&(g, _)| [1.0, g.to_radians().cos(), g.to_radians().sin()][c])
                    .collect(),
            )
        };
        let (x, wy) = ([col(0), col(1), col(2)], whiten(y.to_vec()));
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
        let m: Vec<Vec<f64>> = (0..3).map(|a| (0..3).map(|b| dot(&x[a], &x[b])).collect()).collect();
        let rhs: Vec<f64> = (0..3).map(|a| dot(&x[a], &wy)).collect();
        // The inverse of the 3x3 information by cofactors.
        let cof = |i: usize, j: usize| {
            let (r, c): (Vec<usize>, Vec<usize>) = (
                (0..3).filter(|&k| k != i).collect(),
                (0..3).filter(|&k| k != j).collect(),
            );
            let minor = m[r[0]][c[0]] * m[r[1]][c[1]] - m[r[0]][c[1]] * m[r[1]][c[0]];
            if (i + j).is_multiple_of(2) { minor } else { -minor }
        };
        let det: f64 = (0..3).map(|j| m[0][j] * cof(0, j)).sum();
        let inv = |i: usize, j: usize| cof(j, i) / det;
        let beta: Vec<f64> = (0..3).map(|i| (0..3).map(|j| inv(i, j) * rhs[j]).sum()).collect();
        let (a, b) = (beta[1], beta[2]);
        let h2 = a * a + b * b;
        let (ga, gb) = (b / h2, -a / h2);
        let var = ga * ga * inv(1, 1) + 2.0 * ga * gb * inv(1, 2) + gb * gb * inv(2, 2);
        ((-b).atan2(a).to_degrees().rem_euclid(360.0), var.sqrt().to_degrees())
    }

    fn filter<F: Float>(model: &NoiseModel, dwells: &[(f64, u64)], y: &[f64]) -> Running<F> {
        let mut f = RunningGls::<F>::new(&model.into(), F::from(DWELL_S).unwrap()).unwrap();
        for (&(g, t_us), &r) in dwells.iter().zip(y) {
            f.add(F::from(g).unwrap(), t_us, F::from(r).unwrap(), None).unwrap();
        }
        f.azimuth()
    }

    fn models() -> [(&'static str, NoiseModel); 6] {
        let white = NoiseModel::white(0.005, DWELL_S);
        [
            ("white", white),
            (
                "flicker",
                NoiseModel {
                    bias_instability_dph: 0.004,
                    ..white
                },
            ),
            (
                "random walk",
                NoiseModel {
                    rrw_dph_rth: 0.3,
                    ..white
                },
            ),
            (
                "Gauss-Markov",
                NoiseModel {
                    gm_sigma_dph: 0.015,
                    gm_tau_s: 60.0,
                    ..white
                },
            ),
            (
                "Gauss-Markov faster than a dwell",
                NoiseModel {
                    gm_sigma_dph: 0.05,
                    gm_tau_s: 0.2,
                    ..white
                },
            ),
            (
                "all of them",
                NoiseModel {
                    bias_instability_dph: 0.003,
                    rrw_dph_rth: 0.1,
                    gm_sigma_dph: 0.01,
                    gm_tau_s: 30.0,
                    quantization_arcsec: 0.2,
                    ..white
                },
            ),
        ]
    }

    #[test]
    fn the_decay_follows_the_exponential() {
        for k in 0..=2000 {
            let x = k as f64 * 0.05;
            let want = (-x).exp();
            // Beyond 88, below `f32`'s range: none.
            if x >= 88.0 {
                assert_eq!(exp_neg(x), 0.0);
                continue;
            }
            assert!(
                (exp_neg(x) / want - 1.0).abs() < 1e-8 * (1.0 + x),
                "{x}: {}",
                exp_neg(x)
            );
            if want > 1e-37 {
                let got = exp_neg(x as f32) as f64;
                assert!(
                    (got / want - 1.0).abs() < 1e-6 * (1.0 + x),
                    "{x} in f32: {got} vs {want}"
                );
            }
        }
        assert_eq!(exp_neg(88.0f32), 0.0);
        assert_eq!(exp_neg(f32::INFINITY), 0.0);
    }

    #[test]
    fn a_dwell_mean_is_the_bridge_of_its_ends_and_a_part_of_its_own() {
        // Against the variance a mean over x correlation times keeps, integrated numerically,
        // (2/x^2) int_0^x (x - u) e^-u du, and the regression of the mean on the start,
        // a = (1 - e^-x) / x: each end's weight is a / (1 + phi), the rest of the variance
        // the mean's own.
        for x in [1e-4, 0.05, 0.2999, 0.3, 2.0, 10.0, 100.0] {
            let steps = 200_000;
            let du = x / steps as f64;
            let int: f64 = (0..steps)
                .map(|k| {
                    let u = (k as f64 + 0.5) * du;
                    (x - u) * (-u).exp() * du
                })
                .sum();
            let (share, a, phi) = (2.0 * int / (x * x), -(-x).exp_m1() / x, (-x).exp());
            let w = Window::markov(1.0f64, x);
            assert!((w.coef / (a / (1.0 + phi)) - 1.0).abs() < 5e-5, "{x}: {}", w.coef);
            let own = share - 2.0 * a * a / (1.0 + phi);
            assert!((w.own / own - 1.0).abs() < 2e-5, "{x}: {} vs {own}", w.own);
            assert!((w.q / (1.0 - phi * phi) - 1.0).abs() < 5e-5, "{x}");
            // f32 loses a few digits just above the series' end.
            let w32 = Window::markov(1.0f32, x as f32);
            assert!((w32.own as f64 / w.own - 1.0).abs() < 1e-4, "{x} in f32: {}", w32.own);
            assert!(
                (w32.coef as f64 / w.coef - 1.0).abs() < 1e-5,
                "{x} in f32: {}",
                w32.coef
            );
        }
    }

    #[test]
    fn white_noise_gives_the_least_squares_sigma_and_the_exact_azimuth() {
        let m = NoiseModel::white(0.005, DWELL_S);
        let dwells = schedule(72, 2.6);
        let y = rates(&m, 65.5, &dwells, None);
        let ls = (DWELL_S / 72.0).sqrt() * 0.005 / h();
        let f64_ = filter::<f64>(&m, &dwells, &y);
        assert!((f64_.psi_deg - 65.5).abs() < 1e-9, "{}", f64_.psi_deg);
        assert!((f64_.amplitude_dph / h() - 1.0).abs() < 1e-9);
        assert!((f64_.sigma_psi_deg.to_radians() / ls - 1.0).abs() < 1e-6);
        // In f32: the azimuth to 0.05" (one unit in f32's last place at 65.5 deg is 0.027"),
        // sigma to 1e-5 of itself.
        let f32_ = filter::<f32>(&m, &dwells, &y);
        assert!((f32_.psi_deg as f64 - 65.5).abs() * 3600.0 < 0.05, "{}", f32_.psi_deg);
        assert!((f32_.amplitude_dph as f64 / h() - 1.0).abs() < 1e-5);
        let r = (f32_.sigma_psi_deg as f64).to_radians() / ls;
        assert!((r - 1.0).abs() < 1e-5, "{r}");
        assert_eq!(f32_.dwells, 72);
    }

    #[test]
    fn coloured_noise_gives_the_dense_gls_sigma() {
        // The dense GLS has the exact covariance of window means; the filter's flicker is a
        // bank of Gauss-Markov members, two per decade.
        for ((name, m), tol) in models().into_iter().zip([1e-6, 2e-3, 1e-4, 1e-4, 1e-4, 1e-3]) {
            for (order, dwells) in [("sequential", schedule(48, 2.8)), ("opposite pairs", pairs(72))] {
                let y = rates(&m, 65.5, &dwells, None);
                let (_, dense) = dense_gls(&m, &dwells, &y);
                for (float, sigma) in [
                    ("f64", filter::<f64>(&m, &dwells, &y).sigma_psi_deg),
                    ("f32", filter::<f32>(&m, &dwells, &y).sigma_psi_deg as f64),
                ] {
                    eprintln!("{name}, {order}, {float}: filter / dense GLS {:.5}", sigma / dense);
                    assert!(
                        (sigma / dense - 1.0).abs() < tol,
                        "{name} {order} {float}: {sigma} vs {dense}"
                    );
                }
            }
        }
    }

    #[test]
    fn over_many_seeds_f32_follows_f64_and_both_the_batch_fit() {
        for (name, m) in models() {
            let (mut worst_f32, mut worst_dense, mut worst_sigma) = (f64::MIN, 0.0f64, 0.0f64);
            for seed in 0..40 {
                let mut rng = Rng::new(seed);
                let psi = rng.uniform(0.0, 360.0);
                let n = [24, 36, 72][seed as usize % 3];
                let dwells = schedule(n, rng.uniform(2.2, 6.0));
                let y = rates(&m, psi, &dwells, Some(&mut rng));
                let (a, b) = (filter::<f64>(&m, &dwells, &y), filter::<f32>(&m, &dwells, &y));
                let (dense_psi, dense_sigma) = dense_gls(&m, &dwells, &y);
                // Beyond one unit of f32's last place near 360 deg (0.11"), in units of sigma.
                let beyond_ulp = wrap_180(b.psi_deg as f64 - a.psi_deg).abs() * 3600.0 - 0.11;
                worst_f32 = worst_f32.max(beyond_ulp / (a.sigma_psi_deg * 3600.0));
                worst_sigma = worst_sigma.max((b.sigma_psi_deg as f64 / a.sigma_psi_deg - 1.0).abs());
                worst_dense = worst_dense.max(wrap_180(a.psi_deg - dense_psi).abs() / dense_sigma);
            }
            eprintln!(
                "{name}: f32 - f64 {worst_f32:.1e} sigma beyond 0.11\", sigmas {worst_sigma:.1e} apart; f64 - dense GLS {worst_dense:.3} sigma"
            );
            assert!(worst_f32 < 1e-3 && worst_sigma < 1e-5, "{name}");
            assert!(worst_dense < 0.01, "{name}");
        }
    }

    #[test]
    fn long_gaps_short_gaps_and_extreme_variances_stay_finite() {
        let m = models()[5].1;
        let mut f = RunningGls::<f32>::new(&(&m).into(), 2.0).unwrap();
        let mut t = 0u64;
        for (k, gap_us) in [0u64, 1, 1_000_000_000_000, 2_600_000, 1, 0, 10_000_000]
            .into_iter()
            .enumerate()
        {
            t += gap_us;
            let g = k as f32 * 60.0;
            let rate = (h() * (g as f64 + 65.5).to_radians().cos()) as f32;
            let var = [None, Some(1e-30), Some(1e6), None, Some(f32::MIN_POSITIVE), None, None][k];
            f.add(g, t, rate, var).unwrap();
            let a = f.azimuth();
            assert!(a.sigma_psi_deg.is_finite() && a.psi_deg.is_finite(), "{k}: {a:?}");
        }
        let a = f.azimuth();
        assert!((a.psi_deg - 65.5).abs() < 1e-3, "{a:?}");
        // A Gauss-Markov term so fast that the share an hour's dwell keeps is below `f32`'s
        // range: no term, not an infinite prior.
        let tiny = NoiseTerms {
            gm_sigma_dph: 1e-9,
            gm_tau_s: 1e-30,
            ..NoiseTerms::from(&NoiseModel::white(0.005, 3600.0))
        };
        let mut f = RunningGls::<f32>::new(&tiny, 3600.0).unwrap();
        for k in 0..8u64 {
            let g = k as f32 * 45.0;
            let rate = (h() * (g as f64 + 65.5).to_radians().cos()) as f32;
            f.add(g, k * 3_700_000_000, rate, None).unwrap();
        }
        let a = f.azimuth();
        assert!(a.sigma_psi_deg.is_finite() && (a.psi_deg - 65.5).abs() < 1e-3, "{a:?}");
    }

    #[test]
    fn bad_input_is_refused() {
        let m = NoiseTerms::from(&NoiseModel::white(0.005, 2.0));
        for dwell in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert_eq!(RunningGls::new(&m, dwell).unwrap_err(), RunningError::BadModel);
        }
        let bad = NoiseTerms { gm_sigma_dph: 1.0, ..m };
        assert_eq!(RunningGls::new(&bad, 2.0f32).unwrap_err(), RunningError::BadModel);
        let bad = NoiseTerms {
            arw_deg_rth: f32::NAN,
            ..m
        };
        assert_eq!(RunningGls::new(&bad, 2.0f32).unwrap_err(), RunningError::BadModel);
        let mut f = RunningGls::new(&m, 2.0f32).unwrap();
        for (g, r, v) in [
            (f32::NAN, 1.0, None),
            (f32::INFINITY, 1.0, None),
            (0.0, f32::NAN, None),
            (0.0, f32::NEG_INFINITY, None),
            (0.0, 1.0, Some(-1.0)),
            (0.0, 1.0, Some(0.0)),
            (0.0, 1.0, Some(f32::NAN)),
            (0.0, 1.0, Some(f32::INFINITY)),
        ] {
            assert_eq!(f.add(g, 1_000_000, r, v), Err(RunningError::NonFinite), "{g} {r} {v:?}");
        }
        assert_eq!(f.azimuth().dwells, 0);
        f.add(0.0, 5_000_000, 1.0, None).unwrap();
        assert_eq!(f.add(5.0, 4_999_999, 1.0, None), Err(RunningError::TimeOrder));
        // No white level in the model and none given: no variance to weigh the dwell by.
        let mut silent = RunningGls::new(&NoiseTerms::NONE, 2.0f32).unwrap();
        assert_eq!(silent.add(0.0, 0, 1.0, None), Err(RunningError::NonFinite));
    }
}
