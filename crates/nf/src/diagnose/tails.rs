//! Heavy tails of the whitened noise: a Student-t fitted by maximum likelihood to the
//! whitened residuals, leaving out the largest (a single burst is an outlier, not a tail),
//! against the normal by a likelihood-ratio test; and, as the physics behind such tails, the
//! share of dwells a shock disturbed and by how much.

use crate::stats::{chi2_sf, ln_gamma, robust_sigma};

/// Degrees of freedom tried; the normal is the limit.
const DOF: [f64; 8] = [2.5, 3.0, 4.0, 5.0, 7.0, 10.0, 15.0, 30.0];

pub struct Tails {
    /// Degrees of freedom of the most likely Student-t; infinite when the normal is more
    /// likely than any. The outlier test is judged under it, significant or not: a tail too
    /// weak to be named is still no reason to call its largest value an outlier.
    pub dof: f64,
    /// The likelihood-ratio test against the normal.
    pub p: f64,
}

/// `(1 - share) N(0, s^2) + share N(0, s^2 + shift^2)`, deg/h.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShockMix {
    pub share: f64,
    pub shift: f64,
}

impl Tails {
    /// Heavy tails are a finding at `level`.
    pub fn heavy(&self, level: f64) -> bool {
        self.p < level
    }
}

/// The tails of `resid`.
pub fn estimate(resid: &[f64]) -> Tails {
    let mut r: Vec<f64> = resid.to_vec();
    if let Some((i, _)) = r.iter().enumerate().max_by(|a, b| a.1.abs().total_cmp(&b.1.abs())) {
        r.swap_remove(i);
    }
    let m = r.len() as f64;
    let s2 = r.iter().map(|v| v * v).sum::<f64>() / m;
    if m < 8.0 || s2 <= 0.0 {
        return Tails {
            dof: f64::INFINITY,
            p: 1.0,
        };
    }
    let normal = -0.5 * m * ((2.0 * std::f64::consts::PI * s2).ln() + 1.0);
    let (dof, best) = DOF
        .iter()
        .map(|&nu| (nu, student_loglik(&r, nu, s2)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((f64::INFINITY, normal));
    // The normal is the boundary nu = infinity: half a chi-square of 1 dof.
    let p = 0.5 * chi2_sf(2.0 * (best - normal).max(0.0), 1.0);
    Tails {
        dof: if best > normal { dof } else { f64::INFINITY },
        p,
    }
}

/// The shocks behind heavy tails in `r`, residuals of the rates: a dwell a shock shifted
/// stands out of its neighbours there, where the whitening of a colour the shocks mimic
/// would spread it over them. Every residual counts: the largest is as much the tails' as
/// the rest. The mixture by EM, from a plain tenth of the dwells shifted by three times the
/// robust scale; `None` where it collapses to one normal.
pub fn shock_mix(r: &[f64]) -> Option<ShockMix> {
    if r.len() < 8 {
        return None;
    }
    let robust = robust_sigma(r.iter().copied());
    let (mut share, mut v0, mut v1) = (0.1, robust * robust, 10.0 * robust * robust);
    if v0 <= 0.0 {
        return None;
    }
    let density = |x2: f64, v: f64| (-0.5 * x2 / v).exp() / v.sqrt();
    for _ in 0..500 {
        let w: Vec<f64> = r
            .iter()
            .map(|x| {
                let (a, b) = (share * density(x * x, v1), (1.0 - share) * density(x * x, v0));
                if a + b > 0.0 { a / (a + b) } else { 1.0 }
            })
            .collect();
        let sw: f64 = w.iter().sum();
        let n = r.len() as f64;
        if sw < 0.5 || n - sw < 0.5 {
            return None;
        }
        share = sw / n;
        v0 = r.iter().zip(&w).map(|(x, w)| (1.0 - w) * x * x).sum::<f64>() / (n - sw);
        v1 = (r.iter().zip(&w).map(|(x, w)| w * x * x).sum::<f64>() / sw).max(v0 * 1.0001);
    }
    Some(ShockMix {
        share,
        shift: (v1 - v0).sqrt(),
    })
}

/// Log-likelihood of a Student-t with `nu` dof at its maximum-likelihood scale (by EM).
fn student_loglik(r: &[f64], nu: f64, s2_start: f64) -> f64 {
    let mut s2 = s2_start;
    for _ in 0..50 {
        s2 = r.iter().map(|v| v * v * (nu + 1.0) / (nu + v * v / s2)).sum::<f64>() / r.len() as f64;
    }
    let c = ln_gamma((nu + 1.0) / 2.0) - ln_gamma(nu / 2.0) - 0.5 * (nu * std::f64::consts::PI * s2).ln();
    r.iter()
        .map(|v| c - (nu + 1.0) / 2.0 * (1.0 + v * v / (nu * s2)).ln())
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nf_model::rng::Rng;

    fn student(rng: &mut Rng, nu: usize) -> f64 {
        let chi2: f64 = (0..nu).map(|_| rng.gauss().powi(2)).sum();
        rng.gauss() / (chi2 / nu as f64).sqrt()
    }

    #[test]
    fn a_burst_is_not_a_tail_and_student_noise_is() {
        let mut rng = Rng::new(7);
        let mut r: Vec<f64> = (0..200).map(|_| rng.gauss()).collect();
        r[50] = 12.0;
        assert!(!estimate(&r).heavy(0.025));
        let t: Vec<f64> = (0..200).map(|_| student(&mut rng, 3)).collect();
        let e = estimate(&t);
        assert!(e.heavy(0.025) && e.dof <= 5.0, "dof {} p {}", e.dof, e.p);
    }

    #[test]
    fn a_share_of_shifted_dwells_is_measured_as_one() {
        let mut rng = Rng::new(3);
        let (mut share, mut shift) = (Vec::new(), Vec::new());
        for _ in 0..20 {
            let r: Vec<f64> = (0..400)
                .map(|_| rng.gauss() + if rng.unit() < 0.1 { 5.0 * rng.gauss() } else { 0.0 })
                .collect();
            let m = shock_mix(&r).unwrap();
            share.push(m.share);
            shift.push(m.shift);
        }
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        assert!((mean(&share) - 0.1).abs() < 0.02, "share {share:?}");
        assert!((mean(&shift) - 5.0).abs() < 0.5, "shift {shift:?}");
    }

    #[test]
    fn gaussian_noise_keeps_the_normal_at_about_the_level() {
        let mut rng = Rng::new(11);
        let hits = (0..400)
            .filter(|_| {
                let r: Vec<f64> = (0..72).map(|_| rng.gauss()).collect();
                estimate(&r).heavy(0.05)
            })
            .count();
        assert!(hits <= 32, "{hits} of 400 Gaussian samples called heavy-tailed at 5 %");
    }
}
