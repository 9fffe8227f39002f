//! The distributions of the host's tests, from `statrs`, with the edge cases the callers rely
//! on: a statistic that is not a number, or not positive, gives p = 1; degrees of freedom
//! that make no distribution give NaN, which no test counts as significant.

use statrs::distribution::{ChiSquared, ContinuousCDF, FisherSnedecor, StudentsT};

pub use statrs::function::beta::beta_reg as beta_inc;
pub use statrs::function::gamma::ln_gamma;

/// `P(F > f)` for an F distribution with `(d1, d2)` degrees of freedom.
pub fn f_sf(f: f64, d1: f64, d2: f64) -> f64 {
    if f.is_nan() || f <= 0.0 {
        return 1.0;
    }
    FisherSnedecor::new(d1, d2).map_or(f64::NAN, |d| d.sf(f))
}

/// Two-sided `P(|T| > t)` for Student's t with `nu` degrees of freedom.
pub fn t_sf2(t: f64, nu: f64) -> f64 {
    if t.is_nan() {
        return 1.0;
    }
    StudentsT::new(0.0, 1.0, nu).map_or(f64::NAN, |d| 2.0 * d.sf(t.abs()))
}

/// The `p` quantile of Student's t with `nu` degrees of freedom.
pub fn t_quantile(p: f64, nu: f64) -> f64 {
    StudentsT::new(0.0, 1.0, nu).map_or(f64::NAN, |d| d.inverse_cdf(p))
}

/// Upper tail of the chi-square distribution with `k` degrees of freedom.
pub fn chi2_sf(x: f64, k: f64) -> f64 {
    if x.is_nan() || x <= 0.0 {
        return 1.0;
    }
    ChiSquared::new(k).map_or(f64::NAN, |d| d.sf(x))
}

/// The `p` quantile of chi-square with `k > 0` degrees of freedom (`k` need not be whole), by
/// bisection on `statrs`'s distribution function to 1e-13 (its own inverse stops sooner).
pub fn chi2_quantile(p: f64, k: f64) -> f64 {
    let Ok(d) = ChiSquared::new(k) else { return f64::NAN };
    let (mut lo, mut hi) = (0.0, k.max(1.0));
    while d.cdf(hi) < p {
        hi *= 2.0;
    }
    for _ in 0..300 {
        let mid = 0.5 * (lo + hi);
        if d.cdf(mid) < p {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-13 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// The sigma of normal deviations estimated robustly: 1.4826 times the median of their
/// absolute values (the upper median for an even count); 0 for none.
pub fn robust_sigma(deviations: impl IntoIterator<Item = f64>) -> f64 {
    let mut abs: Vec<f64> = deviations.into_iter().map(f64::abs).collect();
    if abs.is_empty() {
        return 0.0;
    }
    abs.sort_by(f64::total_cmp);
    1.4826 * abs[abs.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn robust_sigma_is_the_scaled_median_absolute_value() {
        assert_eq!(robust_sigma([3.0, -1.0, 2.0]), 1.4826 * 2.0);
        assert_eq!(robust_sigma([-4.0, 1.0, 1e9, -2.0]), 1.4826 * 4.0);
        assert_eq!(robust_sigma([]), 0.0);
    }

    #[test]
    fn reference_values() {
        // Values from standard tables.
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!((t_sf2(2.228, 10.0) - 0.05).abs() < 2e-4);
        assert!((t_sf2(1.96, 1e7) - 0.05).abs() < 1e-4);
        // Student's tables; one and two dof in closed form (tan, and (2p - 1) / sqrt(2p(1 - p))).
        assert!((t_quantile(0.975, 1.0) - 12.7062).abs() < 1e-3);
        assert!((t_quantile(0.975, 2.0) - 4.3027).abs() < 1e-3);
        assert!((t_quantile(0.975, 10.0) - 2.2281).abs() < 1e-3);
        let p = 0.841_344_746;
        assert!((t_quantile(p, 1.0) - (std::f64::consts::PI * (p - 0.5)).tan()).abs() < 1e-6);
        assert!((t_quantile(p, 2.0) - (2.0 * p - 1.0) / (2.0 * p * (1.0 - p)).sqrt()).abs() < 1e-6);
        assert!((f_sf(3.10, 3.0, 20.0) - 0.05).abs() < 1e-3);
        assert!((f_sf(4.35, 1.0, 20.0) - 0.05).abs() < 1e-3);
        assert_eq!(f_sf(0.0, 2.0, 10.0), 1.0);
        assert!((beta_inc(2.0, 3.0, 0.4) - 0.5248).abs() < 1e-4);
        assert!(t_sf2(1.0, 0.0).is_nan() && f_sf(2.0, 1.0, 0.0).is_nan());
    }

    #[test]
    fn chi_square_tails_and_quantiles_match_scipy() {
        // scipy.stats.chi2.sf and scipy.stats.chi2.ppf (scipy 1.17).
        let rel = |a: f64, b: f64| (a / b - 1.0).abs();
        assert!(rel(chi2_sf(4.0, 3.0), 0.26146412994911117) < 1e-12);
        assert!(rel(chi2_sf(90.0, 100.0), 0.7531979655998298) < 1e-10);
        for (p, k, want) in [
            (0.158655, 1.0, 0.04006937464241438),
            (0.841345, 1.0, 1.9869991364434345),
            (0.158655, 10.0, 5.680614504724601),
            (0.841345, 10.0, 14.325512320132137),
            (0.5, 2.5, 1.8738477677808791),
            (0.158655, 0.4, 0.00013120037398231527),
            (0.975, 200.0, 241.05789550631093),
        ] {
            assert!(
                rel(chi2_quantile(p, k), want) < 1e-9,
                "{p} {k}: {}",
                chi2_quantile(p, k)
            );
        }
    }
}
