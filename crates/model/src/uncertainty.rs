//! Azimuth uncertainty: closed forms that hold for the exact model, numerical propagation
//! through it (the reference the closed forms are tested against), and the inverse questions.

use crate::angle::sincos_deg;
use crate::exact::Instrument;
use crate::fit::{AzimuthFit, FitConfig, FitError, FitResult, Obs};
use crate::{ARCSEC_PER_DEG, EARTH_RATE_DPH, Float, c, positive};

/// First-harmonic amplitude `WE cos(lat)` a level ideal gyro sees.
pub fn amplitude_dph<F: Float>(lat_deg: F) -> F {
    c::<F>(EARTH_RATE_DPH) * sincos_deg(lat_deg).1
}

/// First-harmonic amplitudes, over `WE cos(lat)`, that can be the Earth rate's (a gyro's scale
/// factor and the fit's own error leave far less than this).
pub const EARTH_RATE_RATIOS: (f64, f64) = (0.5, 1.5);

/// An azimuth's sigma, deg, from which the Earth rate is not resolved: the gyro's noise hides
/// it (three positions bunched in a few degrees gave 137 deg and an amplitude 13 times the
/// Earth rate's).
pub const RESOLVED_SIGMA_DEG: f64 = 10.0;

/// Whether a fitted first-harmonic amplitude (deg/h, with its sd) can be the Earth rate's,
/// `predicted_dph`: within [`EARTH_RATE_RATIOS`] of it, or within 3 of its sds of it. Off it,
/// the rates are not what the fit takes them for (a calibration's scale wrong by orders, rates
/// in other units, the wrong latitude) and neither the azimuth nor its sigma can be trusted.
pub fn amplitude_is_earth_rate<F: Float>(amplitude_dph: F, sigma_amplitude_dph: F, predicted_dph: F) -> bool {
    let (lo, hi) = (c::<F>(EARTH_RATE_RATIOS.0), c::<F>(EARTH_RATE_RATIOS.1));
    let ratio = amplitude_dph / predicted_dph;
    (ratio >= lo && ratio <= hi) || (amplitude_dph - predicted_dph).abs() <= c::<F>(3.0) * sigma_amplitude_dph
}

/// Student's t 95 % half-width over the normal's, `t(0.975, dof) / 1.96`: a sigma read from
/// `dof` residual degrees of freedom, times this, covers 95 % of errors at 1.96 of it as a
/// known sigma does (at 5 dof, 1.31). 1 at 0 dof (no sigma). Student's table to 8 dof, the
/// Cornish-Fisher expansion beyond (within 0.012 %); no `f64` for the MCU. The host's
/// few-contrast fit takes it too, so both give one run one sigma.
pub fn student_widening<F: Float>(dof: u32) -> F {
    const Z: f64 = 1.959_963_984_540_054;
    const TABLE: [f64; 8] = [
        12.706_204_736,
        4.302_652_730,
        3.182_446_305,
        2.776_445_105,
        2.570_581_836,
        2.446_911_851,
        2.364_624_252,
        2.306_004_135,
    ];
    let t: F = match dof {
        0 => return F::one(),
        1..=8 => c(TABLE[dof as usize - 1]),
        _ => {
            let nu = F::from(dof).unwrap_or_else(F::infinity);
            let z = c::<F>(Z);
            let (z2, z3) = (z * z, z * z * z);
            let g1 = (z3 + z) / c(4.0);
            let g2 = (c::<F>(5.0) * z3 * z2 + c::<F>(16.0) * z3 + c::<F>(3.0) * z) / c(96.0);
            let g3 =
                (c::<F>(3.0) * z3 * z2 * z2 + c::<F>(19.0) * z3 * z2 + c::<F>(17.0) * z3 - c::<F>(15.0) * z) / c(384.0);
            z + g1 / nu + g2 / (nu * nu) + g3 / (nu * nu * nu)
        }
    };
    t / c(Z)
}

/// White gyro noise `sigma_w` (deg/h, per position) on `n` equal steps: Eq. 24, in arcsec.
pub fn gyro_arcsec<F: Float>(n: u32, sigma_w_dph: F, lat_deg: F) -> F {
    crate::paper::eq24_arcsec(n, sigma_w_dph, lat_deg)
}

/// Independent encoder errors `sigma_gamma` at each of `n` equal steps, in arcsec:
/// `sigma_gamma sqrt(3 / (2 n))` (the paper's Eq. 26 says `sigma_gamma`).
pub fn encoder_arcsec<F: Float>(n: u32, sigma_gamma_deg: F) -> F {
    sigma_gamma_deg * c(ARCSEC_PER_DEG) * (c::<F>(1.5) / c(n as f64)).sqrt()
}

/// Worst case, over the tilt direction, of an unknown shaft tilt `sigma_eta`: the vertical
/// Earth rate becomes a first harmonic of relative size `tan(lat) sigma_eta`. Arcsec.
pub fn tilt_arcsec<F: Float>(sigma_eta_deg: F, lat_deg: F) -> F {
    let (s, co) = sincos_deg(lat_deg);
    sigma_eta_deg * c(ARCSEC_PER_DEG) * (s / co).abs()
}

/// One-sigma uncertainties of what goes into a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sigmas<F> {
    /// Gyro noise of one position's dwell mean.
    pub gyro_dph: F,
    /// Encoder error, independent at each position.
    pub encoder_deg: F,
    /// Shaft tilt left after levelling (or the inclinometer's uncertainty when corrected).
    pub tilt_deg: F,
}

/// An azimuth uncertainty budget, in arcsec.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget<F> {
    pub gyro_arcsec: F,
    pub encoder_arcsec: F,
    /// Worst case over the tilt direction.
    pub tilt_arcsec: F,
    pub total_arcsec: F,
}

impl<F: Float> Budget<F> {
    fn new(gyro: F, encoder: F, tilt: F) -> Self {
        Budget {
            gyro_arcsec: gyro,
            encoder_arcsec: encoder,
            tilt_arcsec: tilt,
            total_arcsec: crate::paper::eq31(gyro, encoder, tilt),
        }
    }

    /// The closed forms for the exact model on `n` equal steps.
    pub fn closed_form(n: u32, s: &Sigmas<F>, lat_deg: F) -> Self {
        Budget::new(
            gyro_arcsec(n, s.gyro_dph, lat_deg),
            encoder_arcsec(n, s.encoder_deg),
            tilt_arcsec(s.tilt_deg, lat_deg),
        )
    }

    /// The paper's budget: Eq. 24, Eq. 26 and Eq. 30 (with `eta = sigma_eta`), summed by Eq. 31.
    pub fn paper(n: u32, s: &Sigmas<F>, lat_deg: F, psi_deg: F, eps_deg: F) -> Self {
        use crate::paper::{eq24_arcsec, eq26_arcsec, eq30_arcsec};
        let shaft = eq30_arcsec(n, lat_deg, psi_deg, s.tilt_deg, eps_deg, s.tilt_deg);
        Budget::new(eq24_arcsec(n, s.gyro_dph, lat_deg), eq26_arcsec(s.encoder_deg), shaft)
    }
}

/// Numerical propagation through the exact model: the fit `cfg` is applied to the noise-free
/// output of `inst` at `gammas`, and each input's effect on the fitted azimuth is found from
/// the fit's sensitivity and the model's analytic Jacobian. The tilt term is the worst case
/// over 72 tilt directions.
pub fn propagate<F: Float>(
    inst: &Instrument<F>,
    gammas: &[F],
    cfg: FitConfig<F>,
    s: &Sigmas<F>,
) -> Result<Budget<F>, FitError> {
    let fit = fit_noise_free(inst, gammas, cfg)?;
    let (mut gyro, mut enc) = (F::zero(), F::zero());
    for &g in gammas {
        let k = fit.psi_sensitivity(g, F::zero(), F::one());
        gyro = gyro + k * k;
        let e = k * inst.jacobian(g).gamma;
        enc = enc + e * e;
    }
    let mut tilt = F::zero();
    for d in 0..72 {
        let probe = Instrument {
            tilt_dir_deg: c(d as f64 * 5.0),
            ..*inst
        };
        let f = fit_noise_free(&probe, gammas, cfg)?;
        let dpsi = gammas.iter().fold(F::zero(), |acc, &g| {
            acc + f.psi_sensitivity(g, F::zero(), F::one()) * probe.jacobian(g).tilt
        });
        tilt = tilt.max(dpsi.abs());
    }
    let arc = c::<F>(ARCSEC_PER_DEG);
    Ok(Budget::new(
        gyro.sqrt() * s.gyro_dph * arc,
        enc.sqrt() * s.encoder_deg * arc,
        tilt * s.tilt_deg * arc,
    ))
}

fn fit_noise_free<F: Float>(inst: &Instrument<F>, gammas: &[F], cfg: FitConfig<F>) -> Result<FitResult<F>, FitError> {
    let mut fit = AzimuthFit::new(FitConfig {
        tilt_correction_lat_deg: None,
        ..cfg
    })?;
    for &g in gammas {
        fit.add(&Obs::new(g, inst.rate_dph(g)))?;
    }
    fit.solve()
}

/// The smallest number of equal steps whose closed-form budget reaches `target_arcsec`, or
/// `None` when the tilt term alone is already over the target (or more than `max_n` steps
/// would be needed).
pub fn min_positions<F: Float>(target_arcsec: F, s: &Sigmas<F>, lat_deg: F, max_n: u32) -> Option<u32> {
    let one = Budget::closed_form(1, s, lat_deg);
    let per_n = one.gyro_arcsec * one.gyro_arcsec + one.encoder_arcsec * one.encoder_arcsec;
    let room = target_arcsec * target_arcsec - one.tilt_arcsec * one.tilt_arcsec;
    if !positive(room) {
        return None;
    }
    let n = (per_n / room).ceil().max(c(4.0));
    let n = n.to_u32()?;
    (n <= max_n).then_some(n)
}

/// The smallest `n` for which the paper's Eq. 31 budget reaches `target_arcsec`.
pub fn min_positions_paper<F: Float>(
    target_arcsec: F,
    s: &Sigmas<F>,
    lat_deg: F,
    psi_deg: F,
    eps_deg: F,
    max_n: u32,
) -> Option<u32> {
    (4..=max_n).find(|&n| Budget::paper(n, s, lat_deg, psi_deg, eps_deg).total_arcsec <= target_arcsec)
}

/// Gyro, encoder and levelling allowances that each take a third of the variance of
/// `target_arcsec` on `n` equal steps.
pub fn allocate<F: Float>(target_arcsec: F, n: u32, lat_deg: F) -> Sigmas<F> {
    let share = target_arcsec / c::<F>(3.0).sqrt();
    let unit = Sigmas {
        gyro_dph: F::one(),
        encoder_deg: F::one(),
        tilt_deg: F::one(),
    };
    let b = Budget::closed_form(n, &unit, lat_deg);
    Sigmas {
        gyro_dph: share / b.gyro_arcsec,
        encoder_deg: share / b.encoder_arcsec,
        tilt_deg: share / b.tilt_arcsec,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steps(n: u32) -> impl Iterator<Item = f64> {
        (0..n).map(move |i| i as f64 * 360.0 / n as f64)
    }

    #[test]
    fn an_amplitude_far_from_the_earth_rate_s_is_not_it_unless_its_sd_allows() {
        let e = amplitude_dph(43.8f64);
        assert!(amplitude_is_earth_rate(1.3 * e, 0.0, e) && amplitude_is_earth_rate(0.5 * e, 0.0, e));
        assert!(!amplitude_is_earth_rate(0.3 * e, 0.01 * e, e) && !amplitude_is_earth_rate(1e-6 * e, 0.0, e));
        // A noisy run: 0.3 of it, but within 3 of its sds.
        assert!(amplitude_is_earth_rate(0.3 * e, 0.3 * e, e));
        assert!(!amplitude_is_earth_rate(2.0f32 * 10.86, 0.1, 10.86));
    }

    #[test]
    fn closed_forms_match_numerical_propagation() {
        let s = Sigmas {
            gyro_dph: 0.005,
            encoder_deg: 0.001,
            tilt_deg: 0.003,
        };
        for n in [8u32, 72, 180] {
            for psi in [0.0, 45.0, 200.0] {
                let g: std::vec::Vec<f64> = steps(n).collect();
                let inst = Instrument::level(43.8, psi);
                let num = propagate(&inst, g.as_slice(), FitConfig::default(), &s).unwrap();
                let cf = Budget::closed_form(n, &s, 43.8);
                for (a, b) in [
                    (num.gyro_arcsec, cf.gyro_arcsec),
                    (num.encoder_arcsec, cf.encoder_arcsec),
                    (num.tilt_arcsec, cf.tilt_arcsec),
                ] {
                    assert!((a - b).abs() < 1e-3 * b, "n {n} psi {psi}: {a} vs {b}");
                }
            }
        }
    }

    #[test]
    fn tilt_of_0_003_deg_costs_10_4_arcsec_where_eq30_says_0_7() {
        let s = Sigmas {
            gyro_dph: 0.0,
            encoder_deg: 0.0,
            tilt_deg: 0.003,
        };
        let exact = Budget::closed_form(180, &s, 43.8f64).tilt_arcsec;
        // 0.003 deg x tan(43.8 deg) = 10.36", the 10.4".
        assert!((exact - 10.357).abs() < 0.005, "{exact}");
        let paper = Budget::paper(180, &s, 43.8, 45.0, 0.01).tilt_arcsec;
        assert!((paper - 0.683).abs() < 0.01, "{paper}");
    }

    #[test]
    fn encoder_term_is_not_eq26() {
        // The paper's own setting: sigma_gamma = 0.001 deg gives 3.6" by Eq. 26, 0.52" at n = 72.
        let e = encoder_arcsec(72, 0.001f64);
        assert!((e - 0.5196).abs() < 1e-3, "{e}");
        assert!((crate::paper::eq26_arcsec(0.001f64) - 3.6).abs() < 1e-12);
    }

    #[test]
    fn inverse_questions_round_trip() {
        let s = Sigmas {
            gyro_dph: 0.005,
            encoder_deg: 0.001,
            tilt_deg: 0.0005,
        };
        for target in [12.0f64, 15.0, 20.0] {
            let n = min_positions(target, &s, 43.8, 100_000).unwrap();
            assert!(Budget::closed_form(n, &s, 43.8).total_arcsec <= target);
            assert!(Budget::closed_form(n - 1, &s, 43.8).total_arcsec > target || n == 4);
        }
        assert_eq!(
            min_positions(1.0f64, &Sigmas { tilt_deg: 0.01, ..s }, 43.8, 100_000),
            None
        );
        let p = min_positions_paper(16.0f64, &s, 43.8, 45.0, 0.01, 10_000).unwrap();
        assert!(Budget::paper(p, &s, 43.8, 45.0, 0.01).total_arcsec <= 16.0);
        let a = allocate(10.0f64, 90, 43.8);
        let b = Budget::closed_form(90, &a, 43.8);
        assert!((b.total_arcsec - 10.0).abs() < 1e-9);
        assert!((b.gyro_arcsec - b.tilt_arcsec).abs() < 1e-9 && (b.gyro_arcsec - b.encoder_arcsec).abs() < 1e-9);
    }

    #[test]
    fn students_widening_against_the_table() {
        // t(0.975, dof) from Student's tables.
        for (dof, t) in [
            (1, 12.706205),
            (2, 4.302653),
            (4, 2.776445),
            (5, 2.570582),
            (6, 2.446912),
            (8, 2.306004),
            (9, 2.262157),
            (10, 2.228139),
            (30, 2.042272),
            (100, 1.983972),
        ] {
            let w: f64 = student_widening(dof);
            assert!((w * 1.959964 / t - 1.0).abs() < 1.2e-4, "{dof}: {}", w * 1.959964);
            let w32: f32 = student_widening(dof);
            assert!((f64::from(w32) / w - 1.0).abs() < 1e-6);
        }
        assert_eq!(student_widening::<f64>(0), 1.0);
        assert!((student_widening::<f64>(100_000) - 1.0).abs() < 1e-4);
    }
}
