//! Dwell means far off the fit of the others: a glitch or a fill value. One of them moves a
//! least-squares azimuth by any amount while the residual-based sigma barely grows, so `nf
//! fit` holds them out (and `nf diagnose` tests them as outliers).

use crate::recording::Recording;
use crate::stats;

/// Far enough that no Gaussian dwell of a run of a million gets there (p 1e-15 each).
pub const WILD_SIGMAS: f64 = 8.0;

/// A run of Gaussian dwells holds a dwell this far off its fit, by the Student-t of the fit's
/// degrees of freedom, once in a million runs: where the fit's sigma is poorly known (a run of
/// a dozen dwells), a dwell must lie further than [`WILD_SIGMAS`] to be called far off.
pub const WILD_RUN_P: f64 = 1e-6;

/// Fits and searches at most: a large glitch drags the fit and hides a smaller one, which the
/// fit without it shows.
pub const PASSES: usize = 3;

/// A dwell mean [`WILD_SIGMAS`] robust sigmas or more off the fit of the others.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wild {
    /// Its place among the recording's rows.
    pub row: usize,
    pub line: usize,
    pub index: u32,
    pub rate_dph: f64,
    /// Its residual in robust sigmas (1.4826 times the median absolute residual of the rows
    /// fitted).
    pub sigmas: f64,
    /// Left out of the fit; `false` when so many lie this far off that they are the data, or
    /// the rest would leave no degree of freedom.
    pub held_out: bool,
}

/// The robust sigma of the residuals of the rows `kept`.
fn robust_sigma(residuals: &[f64], kept: &[usize]) -> f64 {
    stats::robust_sigma(kept.iter().map(|&i| residuals[i]))
}

/// The rows, of all, whose residual is [`WILD_SIGMAS`] robust sigmas of the rows `kept` or
/// more, in row order. Where the rows kept fit exactly (sigma 0), any other residual is.
pub fn find(residuals: &[f64], kept: &[usize]) -> Vec<usize> {
    if kept.is_empty() {
        return Vec::new();
    }
    let sigma = robust_sigma(residuals, kept);
    (0..residuals.len())
        .filter(|&i| residuals[i] != 0.0 && residuals[i].abs() >= WILD_SIGMAS * sigma)
        .collect()
}

/// A row the fit left out, `residual` off it, in a run of `n` rows: far off when it lies
/// [`WILD_SIGMAS`] or more of its own sigma from the fit and the Student-t of the fit's `dof`
/// gives such a value in fewer than [`WILD_RUN_P`] of runs. Its sigma is `s sqrt(1 + v)`: `s`
/// the fit's residual sigma, `v` the fitted value's variance per unit (an externally
/// studentised residual). In a short run one glitch drags the fit of all rows so far that no
/// residual of it stands out; against the fit of the others it does.
pub fn studentised_wild(residual: f64, s: f64, v: f64, dof: u32, n: usize) -> bool {
    if dof == 0 || residual == 0.0 {
        return false;
    }
    if s <= 0.0 {
        return true;
    }
    let t = residual.abs() / (s * (1.0 + v).sqrt());
    t >= WILD_SIGMAS && stats::t_sf2(t, dof as f64) * n as f64 <= WILD_RUN_P
}

/// The rows to hold out of a run of `n` fitted with `terms` unknowns: those found, unless they
/// are more than one and more than a tenth of the run (then they are the data: a model the
/// fit lacks, a tilt left uncorrected, heavy tails; not glitches) or the rest would leave no
/// degree of freedom.
pub fn to_hold(found: &[usize], n: usize, terms: usize) -> Vec<usize> {
    if (found.len() > 1 && found.len() * 10 > n) || n - found.len() <= terms {
        Vec::new()
    } else {
        found.to_vec()
    }
}

/// The rows found far off, and those held out, as the report names them.
pub fn describe(rec: &Recording, residuals: &[f64], kept: &[usize], found: &[usize], out: &[usize]) -> Vec<Wild> {
    let sigma = robust_sigma(residuals, kept);
    let mut rows: Vec<usize> = found.iter().chain(out).copied().collect();
    rows.sort_unstable();
    rows.dedup();
    rows.into_iter()
        .map(|i| Wild {
            row: i,
            line: rec.rows[i].line,
            index: rec.rows[i].index,
            rate_dph: rec.rows[i].rate_dph,
            sigmas: residuals[i].abs() / sigma,
            held_out: out.contains(&i),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Residuals of a standard normal's quantiles at 41 points: robust sigma close to 1.
    fn gaussian_like() -> Vec<f64> {
        (1..=41)
            .map(|k| {
                let p = k as f64 / 42.0;
                // Logistic approximation of the normal quantile (scale 0.5513 matches the sd).
                0.5513 * (p / (1.0 - p)).ln()
            })
            .collect()
    }

    #[test]
    fn a_residual_ten_robust_sigmas_off_is_found_and_six_is_not() {
        let mut r = gaussian_like();
        let all: Vec<usize> = (0..r.len()).collect();
        let sigma = robust_sigma(&r, &all);
        assert!((0.8..1.2).contains(&sigma), "{sigma}");
        assert!(find(&r, &all).is_empty());
        r[3] = 6.0 * sigma;
        r[20] = -10.0 * sigma;
        assert_eq!(find(&r, &all), vec![20]);
    }

    #[test]
    fn the_sigma_comes_from_the_rows_fitted_and_every_row_is_judged() {
        let mut r = gaussian_like();
        r.push(1e6);
        let kept: Vec<usize> = (0..r.len() - 1).collect();
        assert_eq!(find(&r, &kept), vec![r.len() - 1]);
        // All residuals zero (a noise-free run): nothing is far off; a glitch held out of
        // one stays far off the exact fit of the others.
        assert!(find(&[0.0; 10], &[0, 1, 2]).is_empty());
        assert_eq!(find(&[0.0, 0.0, 0.0, 5.0], &[0, 1, 2]), vec![3]);
        assert!(find(&[1.0, 2.0], &[]).is_empty());
    }

    #[test]
    fn a_left_out_row_must_be_further_off_where_the_fit_has_few_degrees_of_freedom() {
        // 22 s, 19.7 of its own sigma: far off with 8 dof (the bar is 18.3 in a run of 12),
        // not with 4 (83 in a run of 8); 8 is the floor however many.
        assert!(studentised_wild(22.0, 1.0, 0.25, 8, 12));
        assert!(!studentised_wild(20.0, 1.0, 0.25, 8, 12));
        assert!(!studentised_wild(22.0, 1.0, 0.25, 4, 8));
        assert!(studentised_wild(-100.0, 1.0, 0.25, 4, 8));
        assert!(!studentised_wild(7.9, 1.0, 0.0, 100_000, 100_004));
        assert!(studentised_wild(8.1, 1.0, 0.0, 100_000, 100_004));
        // Its own sigma counts the fitted value's: 9 of s is 7.8 of sqrt(1 + 1/3) s.
        assert!(!studentised_wild(9.0, 1.0, 1.0 / 3.0, 100_000, 100_004));
        // A fit that is exact calls any other value far off; no dof, none.
        assert!(studentised_wild(1e-9, 0.0, 0.25, 5, 9));
        assert!(!studentised_wild(5.0, 1.0, 0.25, 0, 4));
    }

    #[test]
    fn more_than_a_tenth_far_off_are_the_data_and_none_is_held_out() {
        assert_eq!(to_hold(&[3, 9], 20, 3), vec![3, 9]);
        assert_eq!(to_hold(&[1, 2, 3], 20, 3), Vec::<usize>::new());
        assert_eq!(to_hold(&[], 20, 3), Vec::<usize>::new());
        // One glitch in a run of eight is still a glitch.
        assert_eq!(to_hold(&[5], 8, 3), vec![5]);
        assert_eq!(to_hold(&[2, 5], 8, 3), Vec::<usize>::new());
    }

    #[test]
    fn a_dwell_is_not_held_out_when_the_rest_would_leave_no_degree_of_freedom() {
        assert_eq!(to_hold(&[4], 10, 8), vec![4]);
        assert_eq!(to_hold(&[4], 10, 9), Vec::<usize>::new());
    }
}
