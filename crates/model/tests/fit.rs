//! The azimuth fit against independent reference values, f64 and properties over many seeds.

use nf_model::angle::wrap_180;
use nf_model::exact::Instrument;
use nf_model::fit::{AzimuthFit, Drift, FitConfig, FitError, Obs};
use nf_model::paper::eq24_arcsec;
use nf_model::rng::Rng;

const REFERENCE: &str = include_str!("reference/reference.txt");

fn lines(kind: &str) -> impl Iterator<Item = Vec<f64>> + '_ {
    REFERENCE
        .lines()
        .filter(move |l| l.split_whitespace().next() == Some(kind))
        .map(|l| l.split_whitespace().skip(1).map(|v| v.parse().unwrap()).collect())
}

#[test]
fn exact_model_matches_the_independent_matrix_formulation() {
    let mut count = 0;
    for v in lines("rate") {
        let m = Instrument {
            latitude_deg: v[0],
            psi_deg: v[1],
            tilt_deg: v[2],
            tilt_dir_deg: v[3],
            gyro_elev_deg: v[4],
            scale: v[5],
            bias_dph: v[6],
        };
        assert!((m.rate_dph(v[7]) - v[8]).abs() < 1e-12, "{v:?}: {}", m.rate_dph(v[7]));
        count += 1;
    }
    assert_eq!(count, 30);
}

#[test]
fn fit_matches_the_independent_normal_equations() {
    let obs: Vec<Obs<f64>> = lines("obs").map(|v| Obs::new(v[0], v[1])).collect();
    let want = lines("fit").next().unwrap();
    let r = AzimuthFit::fit_all(FitConfig::default(), &obs).unwrap();
    assert_eq!(r.n, 37);
    assert!((r.psi_deg - want[0]).abs() < 1e-10);
    assert!((r.amplitude_dph - want[1]).abs() < 1e-12);
    assert!((r.offset_dph - want[2]).abs() < 1e-12);
    assert!((r.rss - want[3]).abs() < 1e-14);
    assert!((r.sigma_psi_deg - want[4]).abs() < 1e-12);
}

/// A realistic run: exact model, random instrument, white noise, a bias offset.
fn run(rng: &mut Rng, n: usize, noise: f64, equal: bool) -> (Instrument<f64>, Vec<Obs<f64>>) {
    let inst = Instrument {
        latitude_deg: rng.uniform(-70.0, 70.0),
        psi_deg: rng.uniform(0.0, 360.0),
        bias_dph: rng.uniform(-5.0, 5.0),
        scale: rng.uniform(0.99, 1.01),
        ..Instrument::level(0.0, 0.0)
    };
    let start = rng.uniform(0.0, 360.0);
    let obs = (0..n)
        .map(|i| {
            let step = 360.0 / n as f64;
            let jitter = if equal { 0.0 } else { rng.uniform(-0.3, 0.3) * step };
            let g = (start + i as f64 * step + jitter).rem_euclid(360.0);
            Obs {
                t_s: i as f64 * 2.2,
                ..Obs::new(g, inst.rate_dph(g) + noise * rng.gauss())
            }
        })
        .collect();
    (inst, obs)
}

/// The azimuth fitted in `f32` and in `f64` from the same inputs (rounded to `f32`, so that what
/// differs is the arithmetic), and their difference in arcsec.
fn f32_minus_f64(obs: &[Obs<f64>]) -> (f64, f64, f64) {
    let o32: Vec<Obs<f32>> = obs
        .iter()
        .map(|o| Obs {
            t_s: o.t_s as f32,
            ..Obs::new(o.gamma_deg as f32, o.rate_dph as f32)
        })
        .collect();
    let o64: Vec<Obs<f64>> = o32
        .iter()
        .map(|o| Obs {
            t_s: o.t_s as f64,
            ..Obs::new(o.gamma_deg as f64, o.rate_dph as f64)
        })
        .collect();
    let psi32 = AzimuthFit::fit_all(FitConfig::default(), &o32).unwrap().psi_deg as f64;
    let psi64 = AzimuthFit::fit_all(FitConfig::default(), &o64).unwrap().psi_deg;
    (psi32, psi64, wrap_180(psi32 - psi64).abs() * 3600.0)
}

#[test]
fn f32_azimuth_within_0_1_arcsec_of_f64_for_4_to_720_positions() {
    let mut rng = Rng::new(7);
    let mut worst = 0.0f64;
    for n in [4, 5, 7, 12, 36, 72, 90, 120, 180, 360, 720] {
        let mut worst_n = 0.0f64;
        for _ in 0..40 {
            let noise = rng.uniform(0.0005, 0.05);
            let equal = rng.next_u64().is_multiple_of(2);
            let (_, obs) = run(&mut rng, n, noise, equal);
            worst_n = worst_n.max(f32_minus_f64(&obs).2);
        }
        println!("n = {n:3}: worst f32 - f64 azimuth difference {worst_n:.4}\"");
        worst = worst.max(worst_n);
    }
    println!("worst f32 - f64 azimuth difference: {worst:.4} arcsec");
    assert!(worst < 0.1, "{worst}");
}

#[test]
fn a_run_that_starts_on_two_opposite_angles_fits_as_well_in_f32() {
    // Visits 0, 180, 180, 0 first, as measured by an encoder (180 deg to within a count): the
    // sine column is nearly zero until the third angle, and a solver that takes its tiny
    // pivot as a solution carries a huge B into every later row.
    let inst = Instrument {
        latitude_deg: 43.8,
        psi_deg: 65.5378,
        bias_dph: 3.0,
        ..Instrument::level(0.0, 0.0)
    };
    let mut rng = Rng::new(5);
    let visits = [0.0, 180.0001, 180.0001, 0.0, 45.0, 225.0, 90.0, 270.0, 135.0, 315.0];
    for start in [0.0, 10.0, 123.4] {
        let obs: Vec<Obs<f64>> = visits
            .iter()
            .enumerate()
            .map(|(i, g)| {
                let g = (g + start) % 360.0;
                Obs {
                    t_s: i as f64 * 2.5,
                    ..Obs::new(g, inst.rate_dph(g) + 0.005 * rng.gauss())
                }
            })
            .collect();
        let (psi32, psi64, d) = f32_minus_f64(&obs);
        assert!(d < 0.1, "start {start}: f32 {psi32} against f64 {psi64} ({d}\")",);
        assert!(wrap_180(psi64 - inst.psi_deg).abs() < 0.1, "{psi64}");
    }
}

#[test]
fn incremental_fit_equals_batch_fit_of_every_prefix() {
    let mut rng = Rng::new(11);
    let (_, obs) = run(&mut rng, 40, 0.01, false);
    let cfg = FitConfig {
        drift: Drift::Linear,
        ..FitConfig::default()
    };
    let mut inc = AzimuthFit::new(cfg).unwrap();
    for (k, o) in obs.iter().enumerate() {
        inc.add(o).unwrap();
        match (inc.solve(), AzimuthFit::fit_all(cfg, &obs[..=k])) {
            (Ok(a), Ok(b)) => {
                assert!((a.psi_deg - b.psi_deg).abs() < 1e-9 && (a.rss - b.rss).abs() < 1e-12);
            }
            (Err(a), Err(b)) => assert_eq!(a, b),
            (a, b) => panic!("prefix {k}: {a:?} vs {b:?}"),
        }
    }
}

#[test]
fn recovers_a_noise_free_model_exactly_on_arbitrary_angles_and_weights() {
    let mut rng = Rng::new(3);
    for _ in 0..200 {
        let (inst, mut obs) = run(&mut rng, 9, 0.0, false);
        for o in &mut obs {
            o.weight = rng.uniform(0.1, 10.0);
        }
        let r = AzimuthFit::fit_all(FitConfig::default(), &obs).unwrap();
        assert!(wrap_180(r.psi_deg - inst.psi_deg).abs() < 1e-9);
        let amp = inst.scale * 15.041 * inst.latitude_deg.to_radians().cos();
        assert!((r.amplitude_dph - amp).abs() < 1e-10 && (r.offset_dph - inst.bias_dph).abs() < 1e-10);
        assert!(r.rss < 1e-20);
    }
}

#[test]
fn reported_sigma_is_honest_and_equals_eq24_on_equal_steps() {
    let mut rng = Rng::new(5);
    let (n, noise) = (72, 0.005);
    let mut z = Vec::new();
    let lat = 43.8;
    for _ in 0..3000 {
        let inst = Instrument {
            bias_dph: rng.uniform(-1.0, 1.0),
            ..Instrument::level(lat, rng.uniform(0.0, 360.0))
        };
        let obs: Vec<Obs<f64>> = (0..n)
            .map(|i| {
                let g = i as f64 * 5.0;
                Obs::new(g, inst.rate_dph(g) + noise * rng.gauss())
            })
            .collect();
        let r = AzimuthFit::fit_all(FitConfig::default(), &obs).unwrap();
        z.push(wrap_180(r.psi_deg - inst.psi_deg) / r.sigma_psi_deg);
        // With the true noise in place of the residual estimate, the covariance is Eq. 24.
        let model_sigma = r.sigma_psi_deg / r.s2.sqrt() * noise * 3600.0;
        // (up to the fitted amplitude standing in for WE cos(lat)).
        assert!((model_sigma / eq24_arcsec(n as u32, noise, lat) - 1.0).abs() < 2e-3);
    }
    let sd = (z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64).sqrt();
    println!("sd of error / sigma over {} runs: {sd:.3}", z.len());
    assert!((0.95..1.05).contains(&sd), "{sd}");
}

/// 15 uneven positions fitted with a quadratic drift and the second harmonic.
fn curved_fit() -> (Vec<Obs<f64>>, FitConfig<f64>, nf_model::fit::FitResult<f64>) {
    let mut rng = Rng::new(9);
    let (_, obs) = run(&mut rng, 15, 0.01, false);
    let cfg = FitConfig {
        drift: Drift::Quadratic,
        harmonics: 2,
        ..FitConfig::default()
    };
    let base = AzimuthFit::fit_all(cfg, &obs).unwrap();
    (obs, cfg, base)
}

#[test]
fn sensitivity_matches_a_numerical_refit() {
    let (obs, cfg, base) = curved_fit();
    for i in 0..obs.len() {
        let h = 1e-4;
        let mut up = obs.clone();
        up[i].rate_dph += h;
        let mut dn = obs.clone();
        dn[i].rate_dph -= h;
        let num = (AzimuthFit::fit_all(cfg, &up).unwrap().psi_deg - AzimuthFit::fit_all(cfg, &dn).unwrap().psi_deg)
            / (2.0 * h);
        let ana = base.psi_sensitivity(obs[i].gamma_deg, obs[i].t_s, 1.0);
        assert!((num - ana).abs() < 1e-6 * (1.0 + ana.abs()), "{i}: {num} vs {ana}");
    }
}

#[test]
fn prediction_variance_is_the_leverage_and_three_over_n_on_equal_steps() {
    // Equal steps: X'X = diag(n, n/2, n/2), so x' (X'X)^-1 x = 3 / n at any angle.
    let n = 12;
    let obs: Vec<Obs<f64>> = (0..n)
        .map(|k| Obs::new(k as f64 * 30.0, (k as f64 * 0.5).cos()))
        .collect();
    let fit = AzimuthFit::fit_all(FitConfig::default(), &obs).unwrap();
    for gamma in [0.0, 17.0, 200.0] {
        assert!((fit.prediction_variance_unit(gamma, 0.0) - 0.25).abs() < 1e-12);
    }
    // At a fitted row it is the leverage: how far the fitted value follows the row's rate.
    let (obs, cfg, base) = curved_fit();
    for (i, o) in obs.iter().enumerate() {
        let mut up = obs.clone();
        up[i].rate_dph += 1e-3;
        let moved = AzimuthFit::fit_all(cfg, &up).unwrap().predict(o.gamma_deg, o.t_s, None);
        let num = (moved - base.predict(o.gamma_deg, o.t_s, None)) / 1e-3;
        let ana = base.prediction_variance_unit(o.gamma_deg, o.t_s);
        assert!(
            (num - ana).abs() < 1e-8 && (0.0..=1.0).contains(&ana),
            "{i}: {num} vs {ana}"
        );
    }
}

#[test]
fn drift_harmonics_and_predict() {
    let inst = Instrument::level(43.8, 120.0);
    let (k1, k2) = (2e-4, -3e-7);
    let obs: Vec<Obs<f64>> = (0..36)
        .map(|i| {
            let g = i as f64 * 10.0;
            let t = 1000.0 + i as f64 * 2.2;
            let tt = t - 1000.0;
            let r = inst.rate_dph(g) + 0.3 + k1 * tt + k2 * tt * tt + 0.01 * (2.0 * g).to_radians().cos()
                - 0.02 * (3.0 * g).to_radians().sin();
            Obs {
                t_s: t,
                ..Obs::new(g, r)
            }
        })
        .collect();
    let cfg = FitConfig {
        drift: Drift::Quadratic,
        harmonics: 3,
        ..FitConfig::default()
    };
    let r = AzimuthFit::fit_all(cfg, &obs).unwrap();
    assert!(wrap_180(r.psi_deg - 120.0).abs() < 1e-9);
    let (d1, d2) = r.drift();
    assert!((d1 - k1).abs() < 1e-12 && (d2 - k2).abs() < 1e-14, "{d1} {d2}");
    let (c2, s2) = r.harmonic(2).unwrap();
    let (c3, s3) = r.harmonic(3).unwrap();
    assert!((c2 - 0.01).abs() < 1e-10 && s2.abs() < 1e-10 && c3.abs() < 1e-10 && (s3 + 0.02).abs() < 1e-10);
    assert!(r.harmonic(4).is_none() && r.harmonic(1).is_none());
    for o in &obs {
        assert!(r.residual(o).abs() < 1e-10);
    }
}

#[test]
fn one_way_sweep_turns_a_linear_drift_into_k_t_over_pi_h() {
    let (n, dt, k) = (72, 2.2, 1e-4);
    let inst = Instrument::level(43.8, 0.0);
    let obs: Vec<Obs<f64>> = (0..n)
        .map(|i| {
            let (g, t) = (i as f64 * 360.0 / n as f64, i as f64 * dt);
            Obs {
                t_s: t,
                ..Obs::new(g, inst.rate_dph(g) + k * t)
            }
        })
        .collect();
    let plain = AzimuthFit::fit_all(FitConfig::default(), &obs).unwrap();
    let h = 15.041 * 43.8f64.to_radians().cos();
    let want = (k * n as f64 * dt / (std::f64::consts::PI * h)).to_degrees();
    let got = wrap_180(plain.psi_deg);
    assert!((got / want - 1.0).abs() < 0.02, "{got} vs {want}");
    let with_drift = AzimuthFit::fit_all(
        FitConfig {
            drift: Drift::Linear,
            ..FitConfig::default()
        },
        &obs,
    )
    .unwrap();
    assert!(wrap_180(with_drift.psi_deg).abs() < 1e-9);
}

#[test]
fn every_bad_input_is_refused_with_its_reason() {
    let cfg = FitConfig::<f64>::default();
    let ok = |g: f64| Obs::new(g, g.to_radians().cos());
    assert_eq!(
        AzimuthFit::fit_all(cfg, &[ok(0.0), ok(90.0)]).unwrap_err(),
        FitError::TooFewPositions { n: 2, needed: 3 }
    );
    assert_eq!(
        AzimuthFit::fit_all(cfg, &[ok(10.0), ok(10.0), ok(10.0), ok(10.0)]).unwrap_err(),
        FitError::Singular { column: 1 }
    );
    let mut f = AzimuthFit::new(cfg).unwrap();
    f.add(&ok(0.0)).unwrap();
    assert_eq!(f.add(&Obs::new(f64::NAN, 1.0)), Err(FitError::NonFinite { index: 1 }));
    assert_eq!(
        f.add(&Obs { weight: 0.0, ..ok(5.0) }),
        Err(FitError::BadWeight { index: 1 })
    );
    assert_eq!(f.positions(), 1, "a refused position leaves the fit as it was");
    let tilt = FitConfig {
        tilt_correction_lat_deg: Some(40.0),
        ..cfg
    };
    assert_eq!(
        AzimuthFit::fit_all(tilt, &[ok(0.0)]).unwrap_err(),
        FitError::MissingTilt { index: 0 }
    );
    assert_eq!(
        AzimuthFit::fit_all(FitConfig { harmonics: 4, ..cfg }, &[]).unwrap_err(),
        FitError::BadConfig
    );
    let flat: Vec<Obs<f64>> = (0..8).map(|i| Obs::new(i as f64 * 45.0, 1.0)).collect();
    assert_eq!(AzimuthFit::fit_all(cfg, &flat).unwrap_err(), FitError::NoSignal);
}

#[test]
fn zero_degrees_of_freedom_leave_the_sigmas_undefined() {
    // Three positions for C, A and B: the azimuth is exact, the noise is not measured.
    let rate = |g: f64| 0.3 + 10.0 * (g + 65.0).to_radians().cos();
    let obs: Vec<Obs<f64>> = [0.0, 120.0, 240.0].iter().map(|&g| Obs::new(g, rate(g))).collect();
    let r = AzimuthFit::fit_all(FitConfig::default(), &obs).unwrap();
    assert_eq!((r.n, r.dof), (3, 0));
    assert!((wrap_180(r.psi_deg - 65.0)).abs() < 1e-9);
    assert!(r.s2.is_nan() && r.sigma_psi_deg.is_nan(), "{}", r.sigma_psi_deg);
    assert!(r.sigma_amplitude_dph.is_nan() && r.sigma_offset_dph.is_nan());
    let obs32: Vec<Obs<f32>> = obs
        .iter()
        .map(|o| Obs::new(o.gamma_deg as f32, o.rate_dph as f32))
        .collect();
    assert!(
        AzimuthFit::fit_all(FitConfig::default(), &obs32)
            .unwrap()
            .sigma_psi_deg
            .is_nan()
    );
}

#[test]
fn f32_fit_of_rows_whose_squares_are_subnormal() {
    // A weight of 1e-39 leaves the weighted rows near 3e-20, whose squares are subnormal: the
    // rotations must rescale (the plain sum of squares gave NaN here).
    let obs: Vec<Obs<f32>> = (0..360)
        .map(|i| {
            let g = i as f32;
            Obs {
                weight: 1e-39,
                ..Obs::new(g, 10.0 * (g + 40.0).to_radians().cos())
            }
        })
        .collect();
    let r = AzimuthFit::fit_all(FitConfig::default(), &obs).unwrap();
    assert!((r.psi_deg - 40.0).abs() < 1e-3, "{}", r.psi_deg);
}
