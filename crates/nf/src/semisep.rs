//! The covariance of dwell means under a gyro noise model, factored in O(n r^2) instead of
//! O(n^3). Between two windows that do not overlap every term's covariance is semiseparable
//! (the structure of Foreman-Mackey et al. 2017, "celerite"):
//! - a Gauss-Markov term (variance `s^2`, time `tau`): `s^2 g_i g_j exp(-|c_i - c_j| / tau)`,
//!   with `g = sinh(x/2) / (x/2)`, `x = T / tau`, the gain of a window of length `T`;
//! - rate random walk started at `t0`: `K^2 (c_j - t0)` for window `j` before `i`;
//! - flicker: Gauss-Markov terms spread evenly in `ln tau`, two per decade, each of variance
//!   `h ln(10)` (a density of `2 h` per unit of `ln tau` makes the PSD `h / f`; at two per
//!   decade its ripple is `2 |Gamma(1 + 4 pi i / ln 10)|`, 0.2 %), from a thousandth of a dwell
//!   to 30 times the run. What is slower is a constant and a slope over the run: the constant
//!   changes no contrast (see `crate::gls`), the slope's part beyond 30 runs is a few percent
//!   of flicker's.
//!
//! Flicker's rungs faster than a quarter of a window go into the diagonal only (their
//! correlations across the gaps sum to under 1 % of a sigma), which keeps their gains below
//! `sinh(2)/2`. A Gauss-Markov term is exact down to [`GM_FASTEST`] of a window: before, from a
//! quarter down, it was left out between windows, and 0.5 s of it on 2.6 s dwells 0.07 s apart
//! made the azimuth's sigma 0.91 (a sweep) and 1.12 (opposite pairs) of the true one.

use nf_model::noise::NoiseModel;
use std::f64::consts::LN_10;
use std::sync::Arc;

/// Flicker's Gauss-Markov terms per decade of correlation time.
const PER_DECADE: i32 = 2;
/// A flicker rung faster than this fraction of the longest window enters the diagonal only.
const FAST: f64 = 0.25;
/// A Gauss-Markov term faster than this fraction of the longest window enters the diagonal
/// only: its gain, `sinh(x/2) / (x/2)` of `x = T / tau`, stays within `f64` (e^100) down to
/// here, and beyond adjacent means correlate by under `tau / 2T`, 0.25 %.
const GM_FASTEST: f64 = 1.0 / 200.0;

/// A Gauss-Markov term: variance (deg/h)^2 and correlation time, s.
struct Decay {
    var: f64,
    tau_s: f64,
}

/// The windows in time order and what every noise model shares about them: flicker's
/// ladder of correlation times, each slow rung's gain and its decay from one window to the
/// next. Built once; [`Windows::factor`] then costs O(n r^2) per model.
#[derive(Debug, Clone)]
pub struct Windows {
    /// Index in the caller's order of each window in time order.
    order: Vec<usize>,
    /// Per window in time order: length, centre from the first window's start, and the
    /// distance from the previous centre (0 for the first).
    len: Vec<f64>,
    centre: Vec<f64>,
    gap: Vec<f64>,
    longest: f64,
    /// Flicker's rungs slower than [`FAST`] windows, and per window (n x rungs) their gains
    /// and decays; the variance of the window mean that all rungs give, per unit of a rung's.
    rungs: Vec<f64>,
    gain: Vec<f64>,
    decay: Vec<f64>,
    ladder_var: Vec<f64>,
}

/// The `L D L^T` factor of a semiseparable covariance, windows in time order. `L`'s
/// generators, `L_ij = u_i . (phi_{j+1..i} w_j)`, are `r` per window: flicker's rungs first,
/// read from the shared windows (a million windows' rungs take a quarter of a gigabyte), then
/// the Gauss-Markov and walk terms, kept here.
#[derive(Debug, Clone)]
pub struct Semisep {
    windows: Arc<Windows>,
    /// Flicker's rungs in use (none or all of the windows'), and their common sd.
    rungs: usize,
    rung_sd: f64,
    /// Rank of the off-diagonal part.
    r: usize,
    /// `D`, and `w` (n x r, row-major).
    d: Vec<f64>,
    w: Vec<f64>,
    /// `u` and `phi` of the terms after the rungs (n x (r - rungs)).
    extra_u: Vec<f64>,
    extra_phi: Vec<f64>,
}

impl Windows {
    /// The means of windows centred at `t_s` with lengths `dwell_s`. `None` when two windows
    /// overlap (the structure needs them apart) or a time or length is not usable.
    pub fn new(t_s: &[f64], dwell_s: &[f64]) -> Option<Windows> {
        let n = t_s.len();
        let usable = t_s.iter().all(|v| v.is_finite()) && dwell_s.iter().all(|v| v.is_finite() && *v > 0.0);
        if n == 0 || dwell_s.len() != n || !usable {
            return None;
        }
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| t_s[a].total_cmp(&t_s[b]));
        let apart = order.windows(2).all(|p| {
            let (a, b) = (p[0], p[1]);
            t_s[b] - t_s[a] >= (dwell_s[a] + dwell_s[b]) / 2.0 * (1.0 - 1e-9)
        });
        if !apart {
            return None;
        }
        let t0 = t_s[order[0]] - dwell_s[order[0]] / 2.0;
        let len: Vec<f64> = order.iter().map(|&i| dwell_s[i]).collect();
        let centre: Vec<f64> = order.iter().map(|&i| t_s[i] - t0).collect();
        let gap = (0..n)
            .map(|k| if k == 0 { 0.0 } else { centre[k] - centre[k - 1] })
            .collect();
        let longest = len.iter().fold(0.0f64, |m, &v| m.max(v));
        let span = centre[n - 1] + len[n - 1] / 2.0;
        let ladder = ladder(longest, span);
        let rungs: Vec<f64> = ladder.iter().copied().filter(|&tau| tau >= FAST * longest).collect();
        let unit = |tau_s: f64| Decay { var: 1.0, tau_s };
        let mut w = Windows {
            ladder_var: len
                .iter()
                .map(|&l| ladder.iter().map(|&tau| unit(tau).mean_var(l)).sum())
                .collect(),
            gain: Vec::with_capacity(n * rungs.len()),
            decay: Vec::with_capacity(n * rungs.len()),
            order,
            len,
            centre,
            gap,
            longest,
            rungs,
        };
        for k in 0..n {
            for &tau in &w.rungs {
                w.gain.push(unit(tau).gain(w.len[k]));
                w.decay.push((-w.gap[k] / tau).exp());
            }
        }
        Some(w)
    }

    /// The covariance of the window means under `model`, with `extra[i]` added to window
    /// `i`'s variance (caller's order: a disturbance of that window's mean alone, as a
    /// shock's), factored. `None` when it is not numerically positive definite.
    pub fn factor(self: &Arc<Self>, model: &NoiseModel, extra: Option<&[f64]>) -> Option<Semisep> {
        // Every rung of flicker's ladder has the variance `h ln 10 / PER_DECADE`.
        let rung_var = 2.0 * model.flicker_h() * LN_10 / PER_DECADE as f64;
        let m = if rung_var > 0.0 { self.rungs.len() } else { 0 };
        let gm = (model.gm_sigma_dph > 0.0).then_some(Decay {
            var: model.gm_sigma_dph * model.gm_sigma_dph,
            tau_s: model.gm_tau_s,
        });
        let gm_slow = gm.as_ref().filter(|d| d.tau_s >= GM_FASTEST * self.longest);
        let walk = model.rrw_dph_rts();
        let r = m + usize::from(gm_slow.is_some()) + usize::from(walk > 0.0);
        let rung_sd = rung_var.sqrt();
        let fill = |k: usize, row: &mut Row| {
            let len = self.len[k];
            row.diag =
                model.independent_var(len) + rung_var * self.ladder_var[k] + extra.map_or(0.0, |e| e[self.order[k]]);
            for j in 0..m {
                row.u[j] = rung_sd * self.gain[k * self.rungs.len() + j];
                row.v[j] = row.u[j];
                row.phi[j] = self.decay[k * self.rungs.len() + j];
            }
            let mut j = m;
            if let Some(d) = &gm {
                row.diag += d.mean_var(len);
                if gm_slow.is_some() {
                    row.u[j] = d.var.sqrt() * d.gain(len);
                    row.v[j] = row.u[j];
                    row.phi[j] = (-self.gap[k] / d.tau_s).exp();
                    j += 1;
                }
            }
            if walk > 0.0 {
                // The walk from the first window's start: `K^2 c_j` between j and a later i.
                let c = self.centre[k];
                row.diag += walk * walk * (c - len / 6.0);
                row.u[j] = walk;
                row.v[j] = walk * c;
                row.phi[j] = 1.0;
            }
        };
        Semisep::factor(Arc::clone(self), m, rung_sd, r, fill)
    }
}

/// One window's row of the generators, before factoring.
struct Row {
    diag: f64,
    u: Vec<f64>,
    v: Vec<f64>,
    phi: Vec<f64>,
}

impl Semisep {
    /// The covariance of the means of windows centred at `t_s` with lengths `dwell_s` under
    /// `model`, factored; `None` as [`Windows::new`] and [`Windows::factor`] say. (The host
    /// goes through `gls::WindowSet`, which keeps the windows for other models.)
    #[cfg(test)]
    pub fn of_windows(model: &NoiseModel, t_s: &[f64], dwell_s: &[f64]) -> Option<Semisep> {
        Arc::new(Windows::new(t_s, dwell_s)?).factor(model, None)
    }

    /// The recursion of the `L D L^T` factor, one window at a time; `fill` writes a window's
    /// row of the generators, its first `rungs` as [`Semisep::generators`] reads them back.
    fn factor(
        windows: Arc<Windows>,
        rungs: usize,
        rung_sd: f64,
        r: usize,
        fill: impl Fn(usize, &mut Row),
    ) -> Option<Semisep> {
        let n = windows.order.len();
        let e = r - rungs;
        let mut f = Semisep {
            windows,
            rungs,
            rung_sd,
            r,
            d: Vec::with_capacity(n),
            w: Vec::with_capacity(n * r),
            extra_u: Vec::with_capacity(n * e),
            extra_phi: Vec::with_capacity(n * e),
        };
        let mut row = Row {
            diag: 0.0,
            u: vec![0.0; r],
            v: vec![0.0; r],
            phi: vec![0.0; r],
        };
        // S = sum over earlier windows of D_j w_j w_j^T, carried to the current one.
        let mut s = vec![0.0; r * r];
        let mut su = vec![0.0; r];
        for k in 0..n {
            fill(k, &mut row);
            // S carried on and S u summed in one pass: S is kept exactly symmetric (each
            // entry's factors in an order that commutes), so S u is the sum of its rows, each
            // added to every entry at once, which vectorises where a sum along each row
            // would wait on its own additions. (The hot loop of every factor.)
            su.fill(0.0);
            if k > 0 && r > 0 {
                let (d, w) = (f.d[k - 1], &f.w[(k - 1) * r..k * r]);
                for (a, s) in s.chunks_exact_mut(r).enumerate() {
                    let (phi_a, w_a, u_a) = (row.phi[a], w[a], row.u[a]);
                    for (((s, su), phi_b), w_b) in s.iter_mut().zip(su.iter_mut()).zip(&row.phi).zip(w) {
                        *s = phi_a * phi_b * (*s + w_a * w_b * d);
                        *su += *s * u_a;
                    }
                }
            }
            let d = row.diag - (0..r).map(|a| row.u[a] * su[a]).sum::<f64>();
            if d.is_nan() || d <= 1e-12 * row.diag {
                return None;
            }
            f.d.push(d);
            f.w.extend((0..r).map(|a| (row.v[a] - su[a]) / d));
            f.extra_u.extend_from_slice(&row.u[rungs..]);
            f.extra_phi.extend_from_slice(&row.phi[rungs..]);
        }
        Some(f)
    }

    /// Window `k`'s generators where they are kept (time order): the rungs' gain and decay,
    /// shared by every factor of the windows (a rung's `u` is `rung_sd` times its gain), and
    /// the other terms' `u` and `phi`.
    fn parts(&self, k: usize) -> (&[f64], &[f64], &[f64], &[f64]) {
        let (all, e) = (self.windows.rungs.len(), self.r - self.rungs);
        (
            &self.windows.gain[k * all..k * all + self.rungs],
            &self.windows.decay[k * all..k * all + self.rungs],
            &self.extra_u[k * e..(k + 1) * e],
            &self.extra_phi[k * e..(k + 1) * e],
        )
    }

    /// Window `k`'s `u` and `phi` (time order).
    fn generators(&self, k: usize, u: &mut [f64], phi: &mut [f64]) {
        let (gain, decay, xu, xphi) = self.parts(k);
        for j in 0..self.rungs {
            u[j] = self.rung_sd * gain[j];
            phi[j] = decay[j];
        }
        u[self.rungs..].copy_from_slice(xu);
        phi[self.rungs..].copy_from_slice(xphi);
    }

    /// A whitening of `v` (in the caller's order): `P^T D^-1/2 L^-1 P v`, whose Gram matrix is
    /// the covariance's inverse.
    pub fn whiten(&self, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; v.len()];
        self.whiten_into::<1>(|i| [v[i]], |i, [x]| out[i] = x);
        out
    }

    /// The inverse of [`Semisep::whiten`]: `v` with `whiten(v) = z`. From independent unit
    /// normals `z` it draws the windows' means under the covariance.
    pub fn colour(&self, z: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; z.len()];
        self.colour_into::<1>(|i| [z[i]], |i, [x]| out[i] = x);
        out
    }

    /// [`Semisep::whiten`] of `W` vectors at once, each window's row `[f64; W]`: the
    /// generators are read once for all of them, as they are too large for the cache when
    /// many factors whiten many vectors. The same arithmetic as one at a time.
    pub fn whiten_block<const W: usize>(&self, v: &[[f64; W]]) -> Vec<[f64; W]> {
        let mut out = vec![[0.0; W]; v.len()];
        self.whiten_into::<W>(|i| v[i], |i, x| out[i] = x);
        out
    }

    /// [`Semisep::colour`] of `W` vectors at once, as [`Semisep::whiten_block`].
    pub fn colour_block<const W: usize>(&self, z: &[[f64; W]]) -> Vec<[f64; W]> {
        let mut out = vec![[0.0; W]; z.len()];
        self.colour_into::<W>(|i| z[i], |i, x| out[i] = x);
        out
    }

    /// The whitening of the vectors `v` reads (the caller's `i`), handed to `put`.
    fn whiten_into<const W: usize>(&self, v: impl Fn(usize) -> [f64; W], mut put: impl FnMut(usize, [f64; W])) {
        self.forward::<W>(|k, i, carried| {
            let (scale, v) = (self.d[k].sqrt(), v(i));
            let z: [f64; W] = core::array::from_fn(|b| v[b] - carried[b]);
            put(i, z.map(|x| x / scale));
            z
        });
    }

    /// The colouring of the vectors `z` reads, handed to `put`.
    fn colour_into<const W: usize>(&self, z: impl Fn(usize) -> [f64; W], mut put: impl FnMut(usize, [f64; W])) {
        self.forward::<W>(|k, i, carried| {
            let scale = self.d[k].sqrt();
            let innovation = z(i).map(|x| x * scale);
            put(i, core::array::from_fn(|b| innovation[b] + carried[b]));
            innovation
        });
    }

    /// The recursion of `L`, forwards in time, on `W` vectors side by side: `step(k, i,
    /// u_k . f_k)` for window `k` (the caller's `i`) returns the window's innovations, which
    /// the carried vectors `f` take on.
    fn forward<const W: usize>(&self, mut step: impl FnMut(usize, usize, [f64; W]) -> [f64; W]) {
        // The hot loop of every whitening: the rungs are read in place, not copied.
        let (r, m) = (self.r, self.rungs);
        let e = r - m;
        let mut f = vec![[0.0; W]; r];
        let mut prev = [0.0; W];
        for (k, &i) in self.windows.order.iter().enumerate() {
            let (gain, decay, xu, xphi) = self.parts(k);
            if k > 0 {
                let w = &self.w[(k - 1) * r..k * r];
                for a in 0..m {
                    for b in 0..W {
                        f[a][b] = decay[a] * (f[a][b] + w[a] * prev[b]);
                    }
                }
                for a in 0..e {
                    for b in 0..W {
                        f[m + a][b] = xphi[a] * (f[m + a][b] + w[m + a] * prev[b]);
                    }
                }
            }
            // Summed term by term in this order, as `Iterator::sum` would.
            let mut carried = [-0.0; W];
            for a in 0..m {
                let u = self.rung_sd * gain[a];
                for b in 0..W {
                    carried[b] += u * f[a][b];
                }
            }
            for a in 0..e {
                for b in 0..W {
                    carried[b] += xu[a] * f[m + a][b];
                }
            }
            prev = step(k, i, carried);
        }
    }

    /// `ln det Sigma`.
    pub fn log_det(&self) -> f64 {
        self.d.iter().map(|d| d.ln()).sum()
    }

    /// `W^T v` for the whitening `W` of [`Semisep::whiten`]: its adjoint, backwards in time.
    pub fn adjoint(&self, v: &[f64]) -> Vec<f64> {
        let block: Vec<[f64; 1]> = v.iter().map(|&x| [x]).collect();
        self.adjoint_block(&block).into_iter().map(|[x]| x).collect()
    }

    /// [`Semisep::adjoint`] of `W` vectors side by side, as [`Semisep::whiten_block`].
    pub fn adjoint_block<const W: usize>(&self, v: &[[f64; W]]) -> Vec<[f64; W]> {
        let r = self.r;
        let n = self.d.len();
        let mut out = vec![[0.0; W]; n];
        // The costate of the whitening's carried vector `f`.
        let mut lambda = vec![[0.0; W]; r];
        let mut carried = vec![[0.0; W]; r];
        // `phi` of the window after this one.
        let (mut u, mut phi, mut next_phi) = (vec![0.0; r], vec![0.0; r], vec![0.0; r]);
        for k in (0..n).rev() {
            let i = self.windows.order[k];
            self.generators(k, &mut u, &mut phi);
            let w = &self.w[k * r..(k + 1) * r];
            for a in 0..r {
                for b in 0..W {
                    carried[a][b] = if k + 1 < n { next_phi[a] * lambda[a][b] } else { 0.0 };
                }
            }
            // Summed term by term in this order, as `Iterator::sum` would.
            let mut t = [-0.0; W];
            for a in 0..r {
                for b in 0..W {
                    t[b] += w[a] * carried[a][b];
                }
            }
            let sd = self.d[k].sqrt();
            let total: [f64; W] = core::array::from_fn(|b| v[i][b] / sd + t[b]);
            out[i] = total;
            for a in 0..r {
                for b in 0..W {
                    lambda[a][b] = carried[a][b] - u[a] * total[b];
                }
            }
            std::mem::swap(&mut phi, &mut next_phi);
        }
        out
    }

    /// `|W x|^2` for every indicator `x = e_i` and for every step `x = 1 (t >= t_i)`, both in
    /// the caller's order (`i` names where the indicator is, and where the step begins).
    /// One backward pass: the whitened cost of a constant input from window `m` on is a
    /// quadratic `f^T G f - 2 g^T f + c` of the carried vector `f` it meets there.
    pub fn indicator_and_step_norms(&self) -> (Vec<f64>, Vec<f64>) {
        let r = self.r;
        let n = self.d.len();
        let (mut ind, mut step) = (vec![0.0; n], vec![0.0; n]);
        let (mut gm, mut g, mut c) = (vec![0.0; r * r], vec![0.0; r], 0.0);
        let (mut y, mut yw, mut pg) = (vec![0.0; r * r], vec![0.0; r], vec![0.0; r]);
        let (mut u, mut phi_k, mut phi) = (vec![0.0; r], vec![0.0; r], vec![0.0; r]);
        for k in (0..n).rev() {
            self.generators(k, &mut u, &mut phi_k);
            let (w, d) = (&self.w[k * r..(k + 1) * r], self.d[k]);
            // Y = Phi G' Phi and Phi g' of the window after this one (none after the last).
            if k + 1 < n {
                for a in 0..r {
                    for b in 0..r {
                        y[a * r + b] = phi[a] * gm[a * r + b] * phi[b];
                    }
                    pg[a] = phi[a] * g[a];
                }
            } else {
                y.fill(0.0);
                pg.fill(0.0);
            }
            for a in 0..r {
                yw[a] = (0..r).map(|b| y[a * r + b] * w[b]).sum();
            }
            let s: f64 = (0..r).map(|a| w[a] * yw[a]).sum();
            let t: f64 = (0..r).map(|a| w[a] * pg[a]).sum();
            let i = self.windows.order[k];
            ind[i] = 1.0 / d + s;
            c += 1.0 / d + s - 2.0 * t;
            step[i] = c;
            for a in 0..r {
                for b in 0..r {
                    gm[a * r + b] = y[a * r + b] - u[a] * yw[b] - yw[a] * u[b] + (s + 1.0 / d) * u[a] * u[b];
                }
                g[a] = u[a] / d - (yw[a] - u[a] * s) + pg[a] - u[a] * t;
            }
            std::mem::swap(&mut phi_k, &mut phi);
        }
        (ind, step)
    }
}

impl Decay {
    /// Variance of one window mean of length `len`.
    fn mean_var(&self, len: f64) -> f64 {
        let x = len / self.tau_s;
        self.var * 2.0 * (x + (-x).exp_m1()) / (x * x)
    }

    /// Gain of a window mean: its covariance with a later window's is `var g_i g_j exp(-dt/tau)`.
    fn gain(&self, len: f64) -> f64 {
        let h = len / (2.0 * self.tau_s);
        h.sinh() / h
    }
}

/// Flicker's correlation times for windows up to `longest_s` over a run of `span_s`: from a
/// thousandth of a window to 30 runs, [`PER_DECADE`] to a decade.
fn ladder(longest_s: f64, span_s: f64) -> Vec<f64> {
    let step = 10f64.powf(1.0 / PER_DECADE as f64);
    let top = 30.0 * span_s.max(longest_s) * step;
    std::iter::successors(Some(longest_s / 1000.0), |tau| Some(tau * step))
        .take_while(|&tau| tau < top)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gls::{self, Cov, window_covariance};
    use nf_model::rng::Rng;

    /// GLS fits of a design with a constant under the two factors agree: slopes, their
    /// covariance, chi-square and REML likelihood (all invariant to the generalised
    /// covariance's free constant and, for the walk, its origin).
    fn agree(a: &Cov, b: &Cov, t: &[f64], rng: &mut Rng, tol: f64) {
        let n = t.len();
        let span = t[n - 1] - t[0];
        let cols = vec![
            vec![1.0; n],
            (0..n).map(|i| (i as f64 * 0.7).cos()).collect(),
            t.iter().map(|v| (v - t[0]) / span).collect(),
        ];
        let y: Vec<f64> = (0..n).map(|i| 0.1 * cols[1][i] + 0.01 * rng.gauss()).collect();
        let (f, g) = (gls::fit(&cols, &y, a).unwrap(), gls::fit(&cols, &y, b).unwrap());
        let close = |p: f64, q: f64, what: &str| {
            assert!((p - q).abs() <= tol * q.abs().max(1e-300), "n {n}, {what}: {p} vs {q}");
        };
        for k in 1..3 {
            close(f.cov[k][k], g.cov[k][k], "variance");
        }
        close(f.chi2, g.chi2, "chi-square");
        close(
            f.reml_loglik - f.chi2 * -0.5,
            g.reml_loglik - g.chi2 * -0.5,
            "REML log det",
        );
        // A coefficient is judged against its standard error.
        close(f.coef[1] / g.cov[1][1].sqrt(), g.coef[1] / g.cov[1][1].sqrt(), "slope");
    }

    /// Irregular times, as orders with long and short moves make them.
    fn times(rng: &mut Rng, n: usize, dwell: f64) -> Vec<f64> {
        let mut t = vec![10.0];
        for _ in 1..n {
            t.push(t.last().unwrap() + dwell + rng.uniform(0.2, 3.2));
        }
        t
    }

    #[test]
    fn exact_for_white_gauss_markov_and_random_walk() {
        // These terms are exact: the fits agree with the dense factor of the model's own
        // covariance to rounding.
        let mut rng = Rng::new(11);
        let model = NoiseModel {
            gm_sigma_dph: 0.02,
            gm_tau_s: 40.0,
            rrw_dph_rth: 0.05,
            quantization_arcsec: 0.3,
            ..NoiseModel::white(0.01, 2.0)
        };
        let n = 60;
        let t = times(&mut rng, n, 2.0);
        let dwell = vec![2.0; n];
        let f = Cov::of_windows(&model, &t, &dwell).unwrap();
        let dense = Cov::new(&window_covariance(&model, &t, &dwell), n).unwrap();
        agree(&f, &dense, &t, &mut rng, 1e-8);
        // With no walk the covariance is proper: the log determinants agree too.
        let stationary = NoiseModel {
            rrw_dph_rth: 0.0,
            ..model
        };
        let f = Semisep::of_windows(&stationary, &t, &dwell).unwrap();
        let dense = Cov::exact(&window_covariance(&stationary, &t, &dwell), n).unwrap();
        assert!((f.log_det() - dense.log_det()).abs() < 1e-8 * dense.log_det().abs());
    }

    #[test]
    fn a_gauss_markov_term_faster_than_a_window_is_exact_across_short_gaps() {
        // Dwells of 2.6 s 0.01-0.1 s apart (a fast motor, no settling), as an outside audit
        // had them: a term of 0.5 s left out between windows made the sigma 0.91 of the true.
        let mut rng = Rng::new(23);
        let n = 72;
        let mut t = vec![5.0];
        for _ in 1..n {
            t.push(t.last().unwrap() + 2.6 + rng.uniform(0.01, 0.1));
        }
        let dwell = vec![2.6; n];
        for tau in [0.05, 0.2, 0.5, 2.0] {
            let model = NoiseModel {
                gm_sigma_dph: 0.05,
                gm_tau_s: tau,
                ..NoiseModel::white(0.005, 2.0)
            };
            let f = Cov::of_windows(&model, &t, &dwell).unwrap();
            let dense = Cov::new(&window_covariance(&model, &t, &dwell), n).unwrap();
            agree(&f, &dense, &t, &mut rng, 1e-8);
        }
        // Faster than a two-hundredth of the window: the diagonal alone, and finite.
        let fastest = NoiseModel {
            gm_sigma_dph: 0.05,
            gm_tau_s: 1e-4,
            ..NoiseModel::white(0.005, 2.0)
        };
        let f = Cov::of_windows(&fastest, &t, &dwell).unwrap();
        let dense = Cov::new(&window_covariance(&fastest, &t, &dwell), n).unwrap();
        agree(&f, &dense, &t, &mut rng, 1e-6);
    }

    #[test]
    fn flicker_matches_the_exact_kernel() {
        // Flicker's ladder against the exact generalised covariance, over runs of 20 to 1000
        // dwells, flicker from a tenth to ten times the white noise of a dwell: to 0.3 %.
        let mut rng = Rng::new(5);
        for (n, b) in [(20, 0.01), (200, 0.001), (200, 0.1), (1000, 0.01)] {
            let model = NoiseModel {
                bias_instability_dph: b,
                ..NoiseModel::white(0.01, 1.5)
            };
            let t = times(&mut rng, n, 1.5);
            let dwell = vec![1.5; n];
            let f = Cov::of_windows(&model, &t, &dwell).unwrap();
            let dense = Cov::new(&window_covariance(&model, &t, &dwell), n).unwrap();
            agree(&f, &dense, &t, &mut rng, 0.005);
        }
    }

    #[test]
    fn blocks_whiten_colour_and_adjoin_as_one_vector_at_a_time() {
        let mut rng = Rng::new(12);
        let t = times(&mut rng, 40, 1.0);
        let model = NoiseModel {
            bias_instability_dph: 0.01,
            rrw_dph_rth: 0.02,
            gm_sigma_dph: 0.005,
            gm_tau_s: 30.0,
            ..NoiseModel::white(0.01, 1.0)
        };
        let s = Semisep::of_windows(&model, &t, &vec![1.0; t.len()]).unwrap();
        let block: Vec<[f64; 3]> = t.iter().map(|_| [rng.gauss(), rng.gauss(), rng.gauss()]).collect();
        let (white, coloured, back) = (s.whiten_block(&block), s.colour_block(&block), s.adjoint_block(&block));
        for b in 0..3 {
            let column: Vec<f64> = block.iter().map(|row| row[b]).collect();
            let by_block = |out: &[[f64; 3]]| -> Vec<f64> { out.iter().map(|row| row[b]).collect() };
            assert_eq!(by_block(&white), s.whiten(&column));
            assert_eq!(by_block(&coloured), s.colour(&column));
            assert_eq!(by_block(&back), s.adjoint(&column));
        }
    }

    #[test]
    fn the_order_of_the_windows_does_not_matter() {
        let mut rng = Rng::new(3);
        let model = NoiseModel {
            bias_instability_dph: 0.01,
            rrw_dph_rth: 0.02,
            ..NoiseModel::white(0.004, 1.0)
        };
        let n = 40;
        let t = times(&mut rng, n, 1.0);
        let mut shuffled: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            shuffled.swap(i, rng.next_u64() as usize % (i + 1));
        }
        let ts: Vec<f64> = shuffled.iter().map(|&i| t[i]).collect();
        let a = Semisep::of_windows(&model, &t, &vec![1.0; n]).unwrap();
        let b = Semisep::of_windows(&model, &ts, &vec![1.0; n]).unwrap();
        let x: Vec<f64> = (0..n).map(|_| rng.gauss()).collect();
        let xs: Vec<f64> = shuffled.iter().map(|&i| x[i]).collect();
        let form = |f: &Semisep, v: &[f64]| f.whiten(v).iter().map(|p| p * p).sum::<f64>();
        assert!((form(&a, &x) / form(&b, &xs) - 1.0).abs() < 1e-12);
        assert!((a.log_det() - b.log_det()).abs() < 1e-9);
    }

    #[test]
    fn adjoint_and_norms_match_the_explicit_whitening() {
        // W formed column by column from the whitening of unit vectors: the adjoint, the
        // indicator norms (diagonal of Sigma^-1) and the step norms must agree with it.
        let mut rng = Rng::new(21);
        let model = NoiseModel {
            bias_instability_dph: 0.02,
            rrw_dph_rth: 0.03,
            gm_sigma_dph: 0.01,
            gm_tau_s: 30.0,
            ..NoiseModel::white(0.01, 2.0)
        };
        let n = 50;
        let mut t = times(&mut rng, n, 2.0);
        t.swap(3, 17);
        let f = Semisep::of_windows(&model, &t, &vec![2.0; n]).unwrap();
        let unit = |i: usize| (0..n).map(|k| f64::from(u8::from(k == i))).collect::<Vec<f64>>();
        let cols: Vec<Vec<f64>> = (0..n).map(|i| f.whiten(&unit(i))).collect();
        let v: Vec<f64> = (0..n).map(|_| rng.gauss()).collect();
        let adj = f.adjoint(&v);
        let (ind, step) = f.indicator_and_step_norms();
        for i in 0..n {
            let want: f64 = (0..n).map(|k| cols[i][k] * v[k]).sum();
            assert!((adj[i] - want).abs() < 1e-9 * want.abs().max(1.0), "adjoint {i}");
            let norm: f64 = cols[i].iter().map(|x| x * x).sum();
            assert!(
                (ind[i] / norm - 1.0).abs() < 1e-9,
                "indicator {i}: {} vs {norm}",
                ind[i]
            );
            // The step from window i on, in time.
            let x: Vec<f64> = (0..n).map(|k| f64::from(u8::from(t[k] >= t[i]))).collect();
            let norm: f64 = f.whiten(&x).iter().map(|x| x * x).sum();
            assert!((step[i] / norm - 1.0).abs() < 1e-9, "step {i}: {} vs {norm}", step[i]);
        }
    }

    #[test]
    fn overlapping_or_bad_windows_are_refused() {
        let m = NoiseModel::white(0.01, 2.0);
        assert!(Semisep::of_windows(&m, &[0.0, 1.0], &[2.0, 2.0]).is_none());
        assert!(Semisep::of_windows(&m, &[0.0, f64::NAN], &[2.0, 2.0]).is_none());
        assert!(Semisep::of_windows(&m, &[0.0, 3.0], &[2.0, 0.0]).is_none());
        assert!(Semisep::of_windows(&m, &[], &[]).is_none());
        assert!(Semisep::of_windows(&m, &[0.0, 3.0], &[2.0, 2.0]).is_some());
    }
}
