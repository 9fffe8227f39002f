//! Least squares of `A cos(gamma) + B sin(gamma) + C` (and optional terms) to the dwell means.
//!
//! The solver is an incremental Givens QR: each position is rotated into an upper-triangular
//! factor as it arrives, so the firmware keeps a running azimuth in `O(p^2)` per position with
//! no normal equations (whose squared condition number would cost `f32` its accuracy).
//!
//! Rounding in the rotations grows with the size of what is rotated. So after each position the
//! solver moves its reference onto the current solution (kept as an exact sum of two floats)
//! and from then on rotates only residuals from it, which are at the noise level: in `f32` the
//! azimuth then stays within a few hundredths of an arcsecond of `f64` up to 720 positions.

// Index loops read as the matrix algebra they implement.
#![allow(clippy::needless_range_loop)]

use crate::angle::{atan2_deg, sincos_deg};
use crate::{EARTH_RATE_DPH, Float, c, positive, sqrt};

/// Most unknowns a fit can have: C, A, B, two drift terms and two more harmonics.
pub const MAX_TERMS: usize = 9;

/// Smallest pivot, relative to the largest, at which the solver moves its reference.
const RECENTER_CONDITION: f64 = 1e-3;

/// Why a fit could not be made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FitError {
    /// Fewer positions than unknowns.
    TooFewPositions { n: u32, needed: u32 },
    /// The angles (or times) do not tell these terms apart; `column` is the first dependent one.
    Singular { column: u8 },
    /// A value of position `index` is NaN or infinite.
    NonFinite { index: u32 },
    /// The weight of position `index` is not positive.
    BadWeight { index: u32 },
    /// The tilt correction is on but position `index` has no inclinometer X reading.
    MissingTilt { index: u32 },
    /// The fitted first harmonic is zero to working precision: there is no azimuth.
    NoSignal,
    /// More terms than [`MAX_TERMS`], or no harmonic at all.
    BadConfig,
}

impl core::fmt::Display for FitError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            FitError::TooFewPositions { n, needed } => write!(f, "{n} positions, the fit needs at least {needed}"),
            FitError::Singular { column } => write!(f, "the positions do not determine fit term {column}"),
            FitError::NonFinite { index } => write!(f, "position {index}: value is not finite"),
            FitError::BadWeight { index } => write!(f, "position {index}: weight must be positive"),
            FitError::MissingTilt { index } => write!(f, "position {index}: tilt correction needs tilt_x"),
            FitError::NoSignal => write!(f, "the first harmonic is zero, the azimuth is undefined"),
            FitError::BadConfig => write!(f, "harmonics must be 1 to 3"),
        }
    }
}

/// A linear least-squares problem with up to [`MAX_TERMS`] unknowns, solved by Givens QR.
#[derive(Clone, Debug)]
pub struct Lsq<F> {
    p: usize,
    n: u32,
    r: [[F; MAX_TERMS]; MAX_TERMS],
    z: [F; MAX_TERMS],
    rss: F,
    /// The reference solution, `hi + lo`; `z` holds the rotated residuals from it.
    base_hi: [F; MAX_TERMS],
    base_lo: [F; MAX_TERMS],
}

/// `a + b` as `(sum, rounding error)`, exactly (Knuth's two-sum).
fn two_sum<F: Float>(a: F, b: F) -> (F, F) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `sqrt(a^2 + b^2)` for `b != 0`. Not `libm`'s `hypotf`: it computes in `f64`, which the
/// Cortex-M4F does in software (450 instructions a call, three calls a position). The plain
/// sum gives the `f32` fit the same worst case as `hypotf` (`tests/fit.rs`); it is scaled by
/// the larger value only when the squares leave the normal range.
pub(crate) fn hypot<F: Float>(a: F, b: F) -> F {
    let h = sqrt(a * a + b * b);
    if h.is_normal() {
        return h;
    }
    let m = a.abs().max(b.abs());
    let (a, b) = (a / m, b / m);
    m * sqrt(a * a + b * b)
}

/// Solution of an [`Lsq`]: coefficients and the inverse of the triangular factor.
#[derive(Clone, Debug)]
pub struct LsqSolution<F> {
    pub p: usize,
    pub n: u32,
    pub coef: [F; MAX_TERMS],
    /// `R^-1`: the covariance of the coefficients is `s2 * rinv * rinv^T`.
    pub rinv: [[F; MAX_TERMS]; MAX_TERMS],
    /// Weighted residual sum of squares.
    pub rss: F,
}

impl<F: Float> Lsq<F> {
    pub fn new(p: usize) -> Self {
        let zero = [F::zero(); MAX_TERMS];
        Lsq {
            p: p.min(MAX_TERMS),
            n: 0,
            r: [zero; MAX_TERMS],
            z: zero,
            rss: F::zero(),
            base_hi: zero,
            base_lo: zero,
        }
    }

    pub fn terms(&self) -> usize {
        self.p
    }

    pub fn rows(&self) -> u32 {
        self.n
    }

    /// Adds the row `x . beta = y` with weight `w`; `x` holds the first `p` columns.
    pub fn add_row(&mut self, x: &[F], y: F, w: F) {
        let sw = sqrt(w);
        let mut row = [F::zero(); MAX_TERMS];
        for (d, s) in row.iter_mut().zip(x.iter().take(self.p)) {
            *d = *s * sw;
        }
        let hi = (0..self.p).fold(F::zero(), |s, j| s + row[j] * self.base_hi[j]);
        let lo = (0..self.p).fold(F::zero(), |s, j| s + row[j] * self.base_lo[j]);
        let mut y = y * sw - hi - lo;
        for i in 0..self.p {
            if row[i] == F::zero() {
                continue;
            }
            let h = hypot(self.r[i][i], row[i]);
            let (co, si) = (self.r[i][i] / h, row[i] / h);
            self.r[i][i] = h;
            for j in i + 1..self.p {
                let (a, b) = (self.r[i][j], row[j]);
                self.r[i][j] = co * a + si * b;
                row[j] = co * b - si * a;
            }
            let zi = self.z[i];
            self.z[i] = co * zi + si * y;
            y = co * y - si * zi;
        }
        self.rss = self.rss + y * y;
        self.n += 1;
        self.recenter();
    }

    /// Moves the reference onto the current solution, leaving `z = 0`; not while the factor
    /// is near singular (a run that starts on two opposite angles has a sine column of
    /// rounding size), whose solution would put a huge reference into every later row.
    fn recenter(&mut self) {
        let p = self.p;
        let scale = (0..p).map(|i| self.r[i][i].abs()).fold(F::zero(), F::max);
        if (self.n as usize) < p || (0..p).any(|i| self.r[i][i].abs() <= scale * c(RECENTER_CONDITION)) {
            return;
        }
        let mut d = [F::zero(); MAX_TERMS];
        for i in (0..p).rev() {
            let s = (i + 1..p).fold(self.z[i], |s, k| s - self.r[i][k] * d[k]);
            d[i] = s / self.r[i][i];
        }
        if d.iter().any(|v| !v.is_finite()) {
            return;
        }
        for i in 0..p {
            let (h, e) = two_sum(self.base_hi[i], d[i]);
            let (h, l) = two_sum(h, self.base_lo[i] + e);
            self.base_hi[i] = h;
            self.base_lo[i] = l;
            self.z[i] = F::zero();
        }
    }

    pub fn solve(&self) -> Result<LsqSolution<F>, FitError> {
        let p = self.p;
        if (self.n as usize) < p {
            return Err(FitError::TooFewPositions {
                n: self.n,
                needed: p as u32,
            });
        }
        let scale = (0..p).map(|i| self.r[i][i].abs()).fold(F::zero(), F::max);
        let tol = scale * F::epsilon() * c(1e3);
        for i in 0..p {
            if self.r[i][i].abs() <= tol {
                return Err(FitError::Singular { column: i as u8 });
            }
        }
        let mut rinv = [[F::zero(); MAX_TERMS]; MAX_TERMS];
        for j in 0..p {
            rinv[j][j] = F::one() / self.r[j][j];
            for i in (0..j).rev() {
                let s = (i + 1..=j).fold(F::zero(), |s, k| s + self.r[i][k] * rinv[k][j]);
                rinv[i][j] = -s / self.r[i][i];
            }
        }
        let mut coef = [F::zero(); MAX_TERMS];
        for i in 0..p {
            let d = (i..p).fold(F::zero(), |s, k| s + rinv[i][k] * self.z[k]);
            coef[i] = self.base_hi[i] + (self.base_lo[i] + d);
        }
        Ok(LsqSolution {
            p,
            n: self.n,
            coef,
            rinv,
            rss: self.rss,
        })
    }
}

impl<F: Float> LsqSolution<F> {
    /// `(R^-1 R^-T)[i][j]`: the coefficient covariance per unit residual variance.
    pub fn cov_unit(&self, i: usize, j: usize) -> F {
        (i.max(j)..self.p).fold(F::zero(), |s, k| s + self.rinv[i][k] * self.rinv[j][k])
    }

    /// Degrees of freedom of the residuals.
    pub fn dof(&self) -> u32 {
        self.n - self.p as u32
    }
}

/// Time terms of the fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Drift {
    #[default]
    None,
    /// A bias linear in time.
    Linear,
    /// A bias quadratic in time.
    Quadratic,
}

/// What the azimuth fit models besides `A cos + B sin + C`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitConfig<F> {
    pub drift: Drift,
    /// Highest harmonic of gamma: 1 is the paper's model, 2 and 3 add `cos/sin(k gamma)`.
    pub harmonics: u8,
    /// Latitude for the tilt correction: the vertical Earth rate `WE sin(lat) sin(tilt_x)` that
    /// a tilted shaft puts on the gyro axis is removed from each rate before the fit.
    pub tilt_correction_lat_deg: Option<F>,
    /// Drift columns use `(t - t0) / t_scale_s`, which keeps them well scaled.
    pub t_scale_s: F,
}

impl<F: Float> Default for FitConfig<F> {
    fn default() -> Self {
        FitConfig {
            drift: Drift::None,
            harmonics: 1,
            tilt_correction_lat_deg: None,
            t_scale_s: c(100.0),
        }
    }
}

impl<F: Float> FitConfig<F> {
    /// Number of unknowns, or `None` if the configuration is not valid.
    pub fn terms(&self) -> Option<usize> {
        if !(1..=3).contains(&self.harmonics) || !positive(self.t_scale_s) {
            return None;
        }
        let drift = match self.drift {
            Drift::None => 0,
            Drift::Linear => 1,
            Drift::Quadratic => 2,
        };
        Some(3 + drift + 2 * (self.harmonics as usize - 1))
    }
}

/// One rotation position: the dwell mean and where and when it was taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Obs<F> {
    pub gamma_deg: F,
    pub t_s: F,
    pub rate_dph: F,
    pub tilt_x_deg: Option<F>,
    pub weight: F,
}

impl<F: Float> Obs<F> {
    pub fn new(gamma_deg: F, rate_dph: F) -> Self {
        Obs {
            gamma_deg,
            t_s: F::zero(),
            rate_dph,
            tilt_x_deg: None,
            weight: F::one(),
        }
    }
}

/// The vertical Earth rate a gyro axis raised by `elev_deg` sees: what the tilt correction removes.
pub fn vertical_earth_rate_dph<F: Float>(latitude_deg: F, elev_deg: F) -> F {
    c::<F>(EARTH_RATE_DPH) * sincos_deg(latitude_deg).0 * sincos_deg(elev_deg).0
}

/// The azimuth fit, fed one position at a time.
#[derive(Clone, Debug)]
pub struct AzimuthFit<F> {
    cfg: FitConfig<F>,
    lsq: Lsq<F>,
    t0: Option<F>,
}

/// The fitted model and its uncertainty from the residuals.
#[derive(Clone, Debug)]
pub struct FitResult<F> {
    pub cfg: FitConfig<F>,
    /// Azimuth `psi` of Eq. 7, in `[0, 360)`.
    pub psi_deg: F,
    /// First-harmonic amplitude `sqrt(A^2 + B^2)`.
    pub amplitude_dph: F,
    /// The constant `C` (bias plus the gyro-misalignment term).
    pub offset_dph: F,
    /// Residual sum of squares (weighted), in (deg/h)^2.
    pub rss: F,
    /// Residual variance `rss / dof` (NaN without degrees of freedom).
    pub s2: F,
    pub n: u32,
    pub dof: u32,
    /// Standard errors from the residuals: NaN, undefined, when `dof` is 0 (as many unknowns
    /// as positions leave no residual to measure the noise by; zero would claim perfection).
    pub sigma_psi_deg: F,
    pub sigma_amplitude_dph: F,
    pub sigma_offset_dph: F,
    /// Time origin of the drift columns.
    pub t0_s: F,
    pub sol: LsqSolution<F>,
}

impl<F: Float> AzimuthFit<F> {
    pub fn new(cfg: FitConfig<F>) -> Result<Self, FitError> {
        let p = cfg.terms().ok_or(FitError::BadConfig)?;
        Ok(AzimuthFit {
            cfg,
            lsq: Lsq::new(p),
            t0: None,
        })
    }

    pub fn config(&self) -> &FitConfig<F> {
        &self.cfg
    }

    pub fn positions(&self) -> u32 {
        self.lsq.rows()
    }

    /// Adds one position; a bad one is refused and leaves the fit as it was.
    pub fn add(&mut self, o: &Obs<F>) -> Result<(), FitError> {
        let index = self.lsq.rows();
        let finite = o.gamma_deg.is_finite() && o.t_s.is_finite() && o.rate_dph.is_finite() && o.weight.is_finite();
        if !finite || o.tilt_x_deg.is_some_and(|t| !t.is_finite()) {
            return Err(FitError::NonFinite { index });
        }
        if !positive(o.weight) {
            return Err(FitError::BadWeight { index });
        }
        let y = match self.cfg.tilt_correction_lat_deg {
            Some(lat) => {
                let tx = o.tilt_x_deg.ok_or(FitError::MissingTilt { index })?;
                o.rate_dph - vertical_earth_rate_dph(lat, tx)
            }
            None => o.rate_dph,
        };
        let t0 = *self.t0.get_or_insert(o.t_s);
        let row = design_row(&self.cfg, o.gamma_deg, (o.t_s - t0) / self.cfg.t_scale_s);
        self.lsq.add_row(&row, y, o.weight);
        Ok(())
    }

    pub fn solve(&self) -> Result<FitResult<F>, FitError> {
        let sol = self.lsq.solve()?;
        let (cc, a, b) = (sol.coef[0], sol.coef[1], sol.coef[2]);
        let r2 = a * a + b * b;
        let size = cc.abs().max(a.abs()).max(b.abs()).max(sqrt(sol.rss / c(sol.n as f64)));
        if sqrt(r2) <= size * F::epsilon() * c(1e3) {
            return Err(FitError::NoSignal);
        }
        let dof = sol.dof();
        let s2 = if dof > 0 { sol.rss / c(dof as f64) } else { F::nan() };
        let (vaa, vbb, vab) = (
            sol.cov_unit(1, 1) * s2,
            sol.cov_unit(2, 2) * s2,
            sol.cov_unit(1, 2) * s2,
        );
        let var_psi = (b * b * vaa + a * a * vbb - c::<F>(2.0) * a * b * vab) / (r2 * r2);
        let var_amp = (a * a * vaa + b * b * vbb + c::<F>(2.0) * a * b * vab) / r2;
        // Rounding can leave a variance a hair below zero; NaN (no dof) must stay NaN.
        let sd = |v: F| if v.is_nan() { v } else { sqrt(v.max(F::zero())) };
        Ok(FitResult {
            cfg: self.cfg,
            psi_deg: atan2_deg(-b, a),
            amplitude_dph: sqrt(r2),
            offset_dph: cc,
            rss: sol.rss,
            s2,
            n: sol.n,
            dof,
            sigma_psi_deg: sd(var_psi).to_degrees(),
            sigma_amplitude_dph: sd(var_amp),
            sigma_offset_dph: sd(sol.cov_unit(0, 0) * s2),
            t0_s: self.t0.unwrap_or(F::zero()),
            sol,
        })
    }

    /// Fits a whole set of positions at once.
    pub fn fit_all(cfg: FitConfig<F>, obs: &[Obs<F>]) -> Result<FitResult<F>, FitError> {
        let mut f = Self::new(cfg)?;
        for o in obs {
            f.add(o)?;
        }
        f.solve()
    }
}

/// The fit's columns at one position: `1, cos, sin`, then the drift and harmonic terms of `cfg`;
/// `tau` is the time from the first position over `cfg.t_scale_s`.
pub fn design_row<F: Float>(cfg: &FitConfig<F>, gamma_deg: F, tau: F) -> [F; MAX_TERMS] {
    let mut x = [F::zero(); MAX_TERMS];
    let (s1, c1) = sincos_deg(gamma_deg);
    x[0] = F::one();
    x[1] = c1;
    x[2] = s1;
    let mut k = 3;
    if cfg.drift != Drift::None {
        x[k] = tau;
        k += 1;
    }
    if cfg.drift == Drift::Quadratic {
        x[k] = tau * tau;
        k += 1;
    }
    for h in 2..=cfg.harmonics {
        let (s, co) = sincos_deg(gamma_deg * c(h as f64));
        x[k] = co;
        x[k + 1] = s;
        k += 2;
    }
    x
}

impl<F: Float> FitResult<F> {
    /// The fitted model at `(gamma, t)`, including the tilt correction if it is on.
    pub fn predict(&self, gamma_deg: F, t_s: F, tilt_x_deg: Option<F>) -> F {
        let row = design_row(&self.cfg, gamma_deg, (t_s - self.t0_s) / self.cfg.t_scale_s);
        let lin = (0..self.sol.p).fold(F::zero(), |s, k| s + row[k] * self.sol.coef[k]);
        match (self.cfg.tilt_correction_lat_deg, tilt_x_deg) {
            (Some(lat), Some(tx)) => lin + vertical_earth_rate_dph(lat, tx),
            _ => lin,
        }
    }

    /// Residual of one position (measured minus fitted).
    pub fn residual(&self, o: &Obs<F>) -> F {
        o.rate_dph - self.predict(o.gamma_deg, o.t_s, o.tilt_x_deg)
    }

    /// Fitted drift: `(deg/h per s, deg/h per s^2)`, zero for the terms not fitted.
    pub fn drift(&self) -> (F, F) {
        let ts = self.cfg.t_scale_s;
        match self.cfg.drift {
            Drift::None => (F::zero(), F::zero()),
            Drift::Linear => (self.sol.coef[3] / ts, F::zero()),
            Drift::Quadratic => (self.sol.coef[3] / ts, self.sol.coef[4] / (ts * ts)),
        }
    }

    /// Amplitude and phase-free coefficients `(cos, sin)` of harmonic `k` (2 or 3), if fitted.
    pub fn harmonic(&self, k: u8) -> Option<(F, F)> {
        if k < 2 || k > self.cfg.harmonics {
            return None;
        }
        let base = self.sol.p - 2 * (self.cfg.harmonics as usize - 1) + 2 * (k as usize - 2);
        Some((self.sol.coef[base], self.sol.coef[base + 1]))
    }

    /// `d psi / d rate` of one position (deg per deg/h): how the estimate moves when that
    /// position's rate moves. Weighted by the position's weight.
    pub fn psi_sensitivity(&self, gamma_deg: F, t_s: F, weight: F) -> F {
        let p = self.sol.p;
        // d beta / d y = (R^-1 R^-T) x w.
        let u = self.r_inv_t_row(gamma_deg, t_s);
        let d = |j: usize| (j..p).fold(F::zero(), |s, k| s + self.sol.rinv[j][k] * u[k]) * weight;
        let (a, b) = (self.sol.coef[1], self.sol.coef[2]);
        ((b * d(1) - a * d(2)) / (a * a + b * b)).to_degrees()
    }

    /// `x' (X'X)^-1 x` of the columns `x` at `(gamma, t)` (weights as fitted): the variance of
    /// the fitted value there per unit residual variance. A position the fit left out differs
    /// from it by `sigma^2 (1 + this)`.
    pub fn prediction_variance_unit(&self, gamma_deg: F, t_s: F) -> F {
        self.r_inv_t_row(gamma_deg, t_s)
            .iter()
            .fold(F::zero(), |s, v| s + *v * *v)
    }

    /// `R^-T x` of the columns at `(gamma, t)`.
    fn r_inv_t_row(&self, gamma_deg: F, t_s: F) -> [F; MAX_TERMS] {
        let row = design_row(&self.cfg, gamma_deg, (t_s - self.t0_s) / self.cfg.t_scale_s);
        let mut u = [F::zero(); MAX_TERMS];
        for (k, uk) in u.iter_mut().enumerate().take(self.sol.p) {
            *uk = (0..=k).fold(F::zero(), |s, i| s + self.sol.rinv[i][k] * row[i]);
        }
        u
    }
}
