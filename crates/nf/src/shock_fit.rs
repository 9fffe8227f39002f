//! GLS through shocks: dwell means struck by a shock (a knock, a vibration burst) are drawn
//! from a wider normal than the rest, so the fit weighs each dwell by how likely it was
//! struck, instead of spreading the shocks' variance over every dwell as a Gaussian model
//! must. The model: the gyro's noise (any [`NoiseModel`]) plus, per dwell and independently,
//! a shift that is 0 with probability `1 - share` and `N(0, shift^2)` otherwise; fitted by
//! EM, each dwell judged by its deletion residual (its rate against what the others predict
//! for it under the noise model), so that a slow wander is not read as shocks.

use crate::gls::{self, Cov, Gls, WindowSet};
use crate::noise_est::scaled;
use crate::stats::robust_sigma;
use nf_model::noise::NoiseModel;

/// The fit and what it made of the shocks.
#[derive(Debug, Clone)]
pub struct ShockFit {
    pub gls: Gls,
    /// The share of dwells struck and the sd of a shock's shift, deg/h.
    pub share: f64,
    pub shift_dph: f64,
    /// Dwells more likely struck than not (the caller's order).
    pub struck: Vec<usize>,
    /// The noise model's variances were multiplied by this to fit the dwells no shock struck.
    pub scale: f64,
    /// Per dwell, the variance the fit added to its mean: the shocks' share of it, weighed by
    /// how likely one struck (the caller's order).
    pub extra: Vec<f64>,
}

/// EM's iterations at most, and the change of the coefficients (in units of their sigma)
/// that ends it.
const ITERATIONS: usize = 200;
const CONVERGED: f64 = 1e-6;

/// The largest share of dwells the shocks may strike.
const MOST: f64 = 0.5;

/// Fits `y ~ cols` under `model` (with `rescale`, its scale refitted to the dwells no shock
/// struck) and shocks. `None` where the mixture collapses to the noise model alone (no dwell
/// stands out) or a fit fails.
pub fn fit(windows: &WindowSet, model: &NoiseModel, rescale: bool, cols: &[Vec<f64>], y: &[f64]) -> Option<ShockFit> {
    let n = y.len();
    let mut extra = vec![0.0; n];
    let mut cov = windows.cov(model)?;
    let mut g = gls::fit(cols, y, &cov)?;
    // The calm dwells' scale starts from the deletion residuals' robust one: a Gaussian
    // estimate that took the shocks for its own fast noise may have left its white level
    // near zero.
    let first = deletion(&cov, &extra, &g)?;
    let mut scale = match rescale {
        true => robust_sigma(first.iter().map(|d| d.resid / d.var.sqrt())).powi(2),
        false => 1.0,
    };
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    let calm: f64 = scale * first.iter().map(|d| d.var).sum::<f64>() / n as f64;
    // A tenth of the dwells struck by three times the calm sd, as `tails::shock_mix` starts.
    let (mut share, mut shift2) = (0.1, 9.0 * calm);
    let mut post = vec![0.0; n];
    // The fit is the same under any scale of its covariance; the deletion variances are not.
    cov = windows.cov(&scaled(model, scale))?;
    for _ in 0..ITERATIONS {
        let del = deletion(&cov, &extra, &g)?;
        for (p, d) in post.iter_mut().zip(&del) {
            let struck = share * density(d.resid, d.var + shift2);
            let calm = (1.0 - share) * density(d.resid, d.var);
            *p = if struck + calm > 0.0 {
                struck / (struck + calm)
            } else {
                1.0
            };
        }
        let sp: f64 = post.iter().sum();
        if sp < 0.5 || n as f64 - sp < 0.5 {
            return None;
        }
        // Shocks strike the fewer dwells: a majority would be the noise itself.
        share = (sp / n as f64).min(MOST);
        let calm_ratio = del
            .iter()
            .zip(&post)
            .map(|(d, p)| (1.0 - p) * d.resid * d.resid / d.var)
            .sum::<f64>();
        if rescale {
            scale *= calm_ratio / (n as f64 - sp);
        }
        let mean_var = del.iter().map(|d| d.var).sum::<f64>() / n as f64;
        shift2 = (del
            .iter()
            .zip(&post)
            .map(|(d, p)| p * (d.resid * d.resid - d.var))
            .sum::<f64>()
            / sp)
            .max(1e-3 * mean_var);
        // The variance whose weight is the expected precision of the two laws.
        for ((e, d), p) in extra.iter_mut().zip(&del).zip(&post) {
            *e = 1.0 / ((1.0 - p) / d.var + p / (d.var + shift2)) - d.var;
        }
        cov = windows.cov_plus(&scaled(model, scale), Some(&extra))?;
        let next = gls::fit(cols, y, &cov)?;
        let moved = (0..next.coef.len())
            .map(|k| (next.coef[k] - g.coef[k]).abs() / next.cov[k][k].sqrt())
            .fold(0.0, f64::max);
        g = next;
        if moved < CONVERGED {
            break;
        }
    }
    Some(ShockFit {
        struck: (0..n).filter(|&i| post[i] > 0.5).collect(),
        gls: g,
        share,
        shift_dph: shift2.sqrt(),
        scale,
        extra,
    })
}

/// A dwell's rate less what the fit and the other dwells predict for it, and that
/// prediction's variance without the dwell's own shock.
struct Deletion {
    resid: f64,
    var: f64,
}

/// The deletion residuals of `g`'s residuals under `cov`, the noise model plus `extra`:
/// `(S^-1 r)_i / (S^-1)_ii`, of variance `1 / (S^-1)_ii`, less the dwell's own `extra`.
fn deletion(cov: &Cov, extra: &[f64], g: &Gls) -> Option<Vec<Deletion>> {
    let precise = cov.adjoint(&cov.whiten(&g.resid));
    let (diag, _) = cov.indicator_and_step_norms();
    (0..extra.len())
        .map(|i| {
            let var = 1.0 / diag[i];
            (var.is_finite() && var > extra[i]).then(|| Deletion {
                resid: precise[i] * var,
                var: var - extra[i],
            })
        })
        .collect()
}

/// The normal density of `x` with variance `v`, without its constant.
fn density(x: f64, v: f64) -> f64 {
    (-0.5 * x * x / v).exp() / v.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nf_model::rng::Rng;

    const SD: f64 = 0.005;

    /// A sweep of `n` dwells of 1 s, 1.5 s apart: `C + A cos g + B sin g` plus white noise of
    /// `SD` per dwell mean, and `shift` on the dwells in `struck`.
    fn sweep(rng: &mut Rng, n: usize, struck: &[usize], shift: f64) -> (WindowSet, Vec<Vec<f64>>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|i| 1.5 * i as f64).collect();
        let g: Vec<f64> = (0..n).map(|i| (360.0 * i as f64 / n as f64).to_radians()).collect();
        let cols = vec![
            vec![1.0; n],
            g.iter().map(|v| v.cos()).collect(),
            g.iter().map(|v| v.sin()).collect(),
        ];
        let y = (0..n)
            .map(|i| {
                let hit = if struck.contains(&i) { shift } else { 0.0 };
                0.3 + 10.0 * cols[1][i] - 2.0 * cols[2][i] + SD * rng.gauss() + hit
            })
            .collect();
        (WindowSet::new(&t, &vec![1.0; n]), cols, y)
    }

    #[test]
    fn the_struck_dwells_are_named_and_count_little() {
        let struck = [3, 17, 30, 41, 55, 60];
        let model = NoiseModel::white(SD, 1.0);
        let (mut plain, mut through) = (0.0, 0.0);
        for seed in 0..20 {
            let mut rng = Rng::new(seed);
            let (w, cols, y) = sweep(&mut rng, 72, &struck, 30.0 * SD);
            let g = gls::fit(&cols, &y, &w.cov(&model).unwrap()).unwrap();
            let f = fit(&w, &model, true, &cols, &y).expect("shocks found");
            // A calm dwell 3.4 sd off is as likely struck as not (one in some 20 runs here).
            let named = struck.iter().all(|i| f.struck.contains(i)) && f.struck.len() <= struck.len() + 1;
            assert!(named, "seed {seed}: {:?}", f.struck);
            assert!((f.scale - 1.0).abs() < 0.5, "seed {seed}: scale {}", f.scale);
            plain += (g.coef[2] + 2.0).powi(2);
            through += (f.gls.coef[2] + 2.0).powi(2);
        }
        // Six of 72 dwells 30 sd off: least squares loses most of its precision.
        assert!(through < 0.25 * plain, "{through} vs {plain}");
    }

    #[test]
    fn gaussian_dwells_keep_the_gaussian_fit() {
        let model = NoiseModel::white(SD, 1.0);
        for seed in 0..20 {
            let mut rng = Rng::new(100 + seed);
            let (w, cols, y) = sweep(&mut rng, 72, &[], 0.0);
            let g = gls::fit(&cols, &y, &w.cov(&model).unwrap()).unwrap();
            if let Some(f) = fit(&w, &model, false, &cols, &y) {
                for k in 0..3 {
                    let moved = (f.gls.coef[k] - g.coef[k]).abs() / g.cov[k][k].sqrt();
                    assert!(moved < 0.3, "seed {seed}: coefficient {k} moved {moved} sigma");
                }
            }
        }
    }
}
