//! `nf diagnose` and `nf fit` on runs far longer than the twin's: the noise is estimated from
//! one dwell mean in k (and the quarters of every dwell), so that a long run costs what 2000
//! positions do, and the result must still hold under the run's own noise.

use nf::analysis::{self, analyse};
use nf::diagnose::{Options, diagnose};
use nf::recording::Recording;
use nf_model::angle::wrap_180;
use nf_model::rng::Rng;
use nf_twin::QuarteredRecording;

const LATITUDE_DEG: f64 = 43.8;
const PSI_DEG: f64 = 65.5;
/// White noise of a quarter-dwell mean, and the walk's step per position (1.2 s), deg/h.
const QUARTER_SD: f64 = 0.02;
const WALK_STEP: f64 = 0.0005;

/// An azimuth's error against the truth, arcsec.
fn error_arcsec(psi_deg: f64) -> f64 {
    wrap_180(psi_deg - PSI_DEG) * 3600.0
}

/// A sequential run turning 0.5 deg per position, 1 s dwells 1.2 s apart, white noise and a
/// rate random walk, in the recording format.
fn walk_run(n: usize, seed: u64) -> Recording {
    run(n, seed, WALK_STEP, 0.5)
}

/// The same with a walk of `step` deg/h per position, turning `turn_deg` per position.
fn run(n: usize, seed: u64, step: f64, turn_deg: f64) -> Recording {
    let mut rng = Rng::new(seed);
    let amplitude = 15.041_067 * LATITUDE_DEG.to_radians().cos();
    let mut rec = QuarteredRecording::new(LATITUDE_DEG, 1.0, 1000.0);
    let mut bias = 0.7;
    for i in 0..n {
        let gamma = (i as f64 * turn_deg) % 360.0;
        bias += step * rng.gauss();
        let rate = amplitude * (gamma + PSI_DEG).to_radians().cos() + bias;
        let q: [f64; 4] = core::array::from_fn(|_| rate + QUARTER_SD * rng.gauss());
        rec.position(5.0 + 1.2 * i as f64, gamma, q);
    }
    Recording::parse(rec.text()).unwrap()
}

#[test]
fn a_long_random_walk_run_is_estimated_from_a_thinned_series_and_names_nothing() {
    // The walk in IEEE units: a step of WALK_STEP per 1.2 s.
    let k_true = WALK_STEP / (1.2f64 / 3600.0).sqrt();
    let (mut z2, runs) = (0.0, 4);
    for seed in 0..runs {
        let d = diagnose(&walk_run(6000, 40 + seed), &Options::default()).unwrap();
        assert!(
            d.noise_source.contains("2000 of the 6000 (one in 3)"),
            "{}",
            d.noise_source
        );
        let named: Vec<&str> = d
            .findings
            .iter()
            .filter(|f| !f.effect.is_noise())
            .map(|f| f.effect.name())
            .collect();
        assert!(named.is_empty(), "seed {seed}: {named:?}");
        // The drift and jump tests' model keeps the walk: flicker and walk only.
        let k = d.drift_model.rrw_dph_rth;
        assert!((k / k_true - 1.0).abs() < 0.3, "seed {seed}: K {k} against {k_true}");
        let err = error_arcsec(d.final_.azimuth_deg);
        z2 += (err / d.final_.sigma_arcsec).powi(2);
    }
    let z = (z2 / runs as f64).sqrt();
    assert!(z < 1.6, "RMS error/sigma {z}");
}

/// On white noise past 2000 positions diagnose's final sigma is, as `nf fit`'s, the likeliest
/// noise model's variance and the models' spread: the likelihood-weighted mean of their
/// variances made it 2.2 times `nf fit`'s on an outside audit's white run of 5000 positions in
/// one turn, where the azimuth is at the run's own frequency and the unlikely walks'
/// variances are large.
#[test]
fn a_long_white_runs_final_sigma_stays_near_the_bound() {
    let n = 5000;
    let amplitude = 15.041_067 * LATITUDE_DEG.to_radians().cos();
    let bound = QUARTER_SD / 2.0 * (2.0 / n as f64).sqrt() / amplitude * 180.0 / std::f64::consts::PI * 3600.0;
    let mut over: Vec<f64> = (0..12)
        .map(|seed| {
            let d = diagnose(&run(n, 60 + seed, 0.0, 360.0 / n as f64), &Options::default()).unwrap();
            d.final_.sigma_arcsec / bound
        })
        .collect();
    over.sort_by(f64::total_cmp);
    let median = (over[5] + over[6]) / 2.0;
    println!("final sigma over the white bound: {over:.2?}");
    assert!(median < 1.6, "median {median}");
}

#[test]
fn nf_fit_of_a_long_random_walk_run_estimates_from_a_thinned_series_and_fits_every_row() {
    // The default options: past 2000 positions no replicates are drawn (each would cost a
    // long run's noise estimate), as in `nf diagnose`.
    let opt = analysis::Options::default();
    let (mut z2, runs) = (0.0, 4);
    for seed in 0..runs {
        let g = analyse(&walk_run(6000, 60 + seed), &opt).unwrap().gls;
        let source = g.source.describe();
        assert!(source.contains("one in 3 of the dwell means"), "{source}");
        assert!(
            source.contains("not calibrated by replicates (past 2000 positions"),
            "{source}"
        );
        // Every row is fitted: the dof of the whitened residuals are those of 6000 positions.
        assert_eq!(g.dof, 6000 - 3);
        let err = error_arcsec(g.psi_deg);
        z2 += (err / (g.sigma_psi_deg * 3600.0)).powi(2);
    }
    let z = (z2 / runs as f64).sqrt();
    assert!(z < 1.6, "RMS error/sigma {z}");
}

/// A sequential white-noise run like [`walk_run`]'s in which a sixth of the dwells are
/// shifted whole by ten times a dwell mean's noise (shocks), and which they are.
fn shocked_run(n: usize, seed: u64) -> (Recording, Vec<bool>) {
    let mut rng = Rng::new(seed);
    let amplitude = 15.041_067 * LATITUDE_DEG.to_radians().cos();
    let mut rec = QuarteredRecording::new(LATITUDE_DEG, 1.0, 1000.0);
    let mut struck = Vec::with_capacity(n);
    for i in 0..n {
        let gamma = (i as f64 * 0.5) % 360.0;
        let hit = rng.unit() < 1.0 / 6.0;
        let shift = if hit {
            10.0 * QUARTER_SD / 2.0 * rng.gauss()
        } else {
            0.0
        };
        let rate = amplitude * (gamma + PSI_DEG).to_radians().cos() + 0.7 + shift;
        let q: [f64; 4] = core::array::from_fn(|_| rate + QUARTER_SD * rng.gauss());
        rec.position(5.0 + 1.2 * i as f64, gamma, q);
        struck.push(hit);
    }
    (Recording::parse(rec.text()).unwrap(), struck)
}

#[test]
fn nf_fit_of_a_long_shocked_run_goes_through_the_shocks() {
    let opt = analysis::Options::default();
    let (mut z2, runs) = (0.0, 3);
    for seed in 0..runs {
        let (rec, truth) = shocked_run(3000, 80 + seed);
        let a = analyse(&rec, &opt).unwrap();
        let g = &a.gls;
        let shocks = g
            .shocks
            .as_ref()
            .expect("a long shocked run is fitted through its shocks");
        // A dwell is found where the fit reads it as struck or holds it out as wild.
        let mut found: Vec<usize> = shocks.struck.clone();
        found.extend(a.wild.iter().filter(|w| w.held_out).map(|w| w.line));
        let hits = (0..rec.rows.len())
            .filter(|&i| truth[i] && found.contains(&rec.rows[i].line))
            .count();
        let shifted = truth.iter().filter(|&&t| t).count();
        // Shifts are N(0, 10 s): a fifth of them are within 2.5 s and hide in the noise.
        assert!(
            hits as f64 > 0.7 * shifted as f64,
            "seed {seed}: {hits} of {shifted} found"
        );
        assert!(
            found.len() < shifted * 11 / 10,
            "seed {seed}: {} read as struck or wild",
            found.len()
        );
        let err = error_arcsec(g.psi_deg);
        z2 += (err / (g.sigma_psi_deg * 3600.0)).powi(2);
    }
    let z = (z2 / runs as f64).sqrt();
    assert!((0.4..1.6).contains(&z), "RMS error/sigma {z}");
}
