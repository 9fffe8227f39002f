//! A fit whose noise only its own few residual contrasts can measure (a run of four to eight
//! positions without quarter means or the samples' spread): white at their level, and the
//! azimuth's error read off Student's t.
//!
//! Under white Gaussian noise the error over its least-squares sigma follows Student's t with
//! the residual degrees of freedom, exactly. With one or two that law has no finite
//! variance: replicates' RMS of error/sigma is then itself a draw from a heavy tail (a
//! four-position run's sigma was scaled 825 times by 40 of them and the Earth rate said
//! unresolved, 2.5 % of such runs). Nor can so few contrasts tell a colour: over five, a walk
//! without white noise was at times the most likely model, and in opposite pairs its sigma a
//! fifth of the white one's (an outside audit: 7 of 150 eight-position runs beyond 3 sigma).
//! No sigma has a finite RMS of error/sigma at one or two; the one given makes +-1.96 sigma
//! the 95 % interval, as for a normal error (the tails are heavier beyond, the middle
//! narrower).

use crate::linfit;
use crate::noise_calib::Verdict;
use crate::noise_fit::azimuth;
use crate::stats::t_quantile;
use nf_model::uncertainty::student_widening;

/// Residual degrees of freedom up to which [`fit`] is used (eight positions for Eq. 7).
pub const MOST_DOF: usize = 5;

/// `Phi(1)`: the share of a normal within one sigma.
const ONE_SIGMA: f64 = 0.841_344_746_068_543;

/// What the few contrasts give.
#[derive(Debug, Clone, PartialEq)]
pub struct StudentFit {
    pub coef: Vec<f64>,
    /// The azimuth and amplitude, their sigmas Student's t 95 % half-widths over 1.96.
    pub verdict: Verdict,
    /// A dwell mean's white sd the residuals show, deg/h.
    pub level_dph: f64,
    /// The residual degrees of freedom; the sigma over the least-squares one; and the
    /// 68.27 % half-width in sigmas (under 1: the middle is narrower than a normal's).
    pub dof: usize,
    pub widening: f64,
    pub one_sigma: f64,
    /// Residual sum of squares over the level squared (the degrees of freedom, or 0 when
    /// the fit is exact).
    pub chi2: f64,
}

/// Least squares of `y ~ cols`; `None` when the columns are dependent or leave no contrast.
pub fn fit(cols: &[Vec<f64>], y: &[f64]) -> Option<StudentFit> {
    let ls = linfit::fit(cols, y)?;
    let nu = ls.dof as f64;
    let s2 = ls.rss / nu;
    // The firmware's rule, so that its sigma and the host's of one run agree.
    let widening = student_widening::<f64>(ls.dof as u32);
    let cov: Vec<Vec<f64>> = ls
        .cov_unit
        .iter()
        .map(|row| row.iter().map(|c| c * s2 * widening * widening).collect())
        .collect();
    Some(StudentFit {
        verdict: azimuth(&ls.coef, &cov),
        coef: ls.coef,
        level_dph: s2.sqrt(),
        dof: ls.dof,
        widening,
        one_sigma: t_quantile(ONE_SIGMA, nu) / widening,
        chi2: if s2 > 0.0 { ls.rss / s2 } else { 0.0 },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nf_model::angle::wrap_180;
    use nf_model::rng::Rng;

    /// The normal's 95 % half-width.
    const Z95: f64 = 1.959_963_984_540_054;

    /// `n` positions over a turn at azimuth 30 deg, amplitude 11.5 deg/h, bias 0.5 deg/h,
    /// white noise of `sd` deg/h.
    fn run(n: usize, sd: f64, rng: &mut Rng) -> (Vec<Vec<f64>>, Vec<f64>) {
        let g: Vec<f64> = (0..n).map(|i| (360.0 * i as f64 / n as f64).to_radians()).collect();
        let psi = 30f64.to_radians();
        let cols = vec![
            vec![1.0; n],
            g.iter().map(|g| g.cos()).collect(),
            g.iter().map(|g| g.sin()).collect(),
        ];
        let y = g
            .iter()
            .map(|g| 0.5 + 11.5 * (g + psi).cos() + sd * rng.gauss())
            .collect();
        (cols, y)
    }

    #[test]
    fn one_and_two_contrasts_widen_by_students_95_percent_half_width() {
        let mut rng = Rng::new(1);
        // t(0.975) / 1.96 and t(0.8413) / that, from Student's tables.
        for (n, widening, one) in [(4, 12.706 / 1.96, 1.8373), (5, 4.3027 / 1.96, 1.3213)] {
            let (cols, y) = run(n, 0.01, &mut rng);
            let f = fit(&cols, &y).unwrap();
            assert_eq!((f.dof, f.chi2.round()), (n - 3, (n - 3) as f64));
            assert!((f.widening - widening).abs() < 1e-3, "{}", f.widening);
            assert!((f.one_sigma * f.widening - one).abs() < 1e-3, "{}", f.one_sigma);
            let ls = linfit::fit(&cols, &y).unwrap();
            let plain = azimuth(&ls.coef, &ls.cov_unit).sigma_psi_deg * (ls.rss / ls.dof as f64).sqrt();
            assert!((f.verdict.sigma_psi_deg / plain - f.widening).abs() < 1e-9);
        }
    }

    #[test]
    fn the_error_is_within_1_96_sigma_in_95_percent_of_runs_and_within_the_68_percent_width_in_68() {
        // 4000 runs a row: the shares are known to 0.4 % and 0.8 % (binomial sd).
        let mut rng = Rng::new(7);
        for n in [4, 5] {
            let (mut ninety_five, mut one) = (0, 0);
            for _ in 0..4000 {
                let (cols, y) = run(n, 0.05, &mut rng);
                let f = fit(&cols, &y).unwrap();
                let z = (wrap_180(f.verdict.psi_deg - 30.0) / f.verdict.sigma_psi_deg).abs();
                ninety_five += usize::from(z < Z95);
                one += usize::from(z < f.one_sigma);
            }
            let (ninety_five, one) = (ninety_five as f64 / 4000.0, one as f64 / 4000.0);
            assert!((ninety_five - 0.95).abs() < 0.012, "{n} positions: {ninety_five}");
            assert!((one - 0.6827).abs() < 0.025, "{n} positions: {one}");
        }
    }

    #[test]
    fn an_exact_fit_has_no_width_and_dependent_columns_no_fit() {
        let mut rng = Rng::new(3);
        let (cols, y) = run(4, 0.0, &mut rng);
        let f = fit(&cols, &y).unwrap();
        assert!(f.verdict.sigma_psi_deg < 1e-9);
        assert!((f.verdict.psi_deg - 30.0).abs() < 1e-9);
        let twice = vec![cols[0].clone(), cols[1].clone(), cols[1].clone()];
        assert!(fit(&twice, &y).is_none());
        let (cols, y) = run(3, 0.01, &mut rng);
        assert!(fit(&cols, &y).is_none(), "no contrast left");
    }
}
