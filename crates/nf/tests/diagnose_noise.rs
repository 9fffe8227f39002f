//! `nf diagnose` under the recording's own noise: clean recordings with flicker, random walk or
//! heavy-tailed dwell means are not named for catalogue effects (at the stated rate), the
//! colour and the tails are findings of their own, and a white-noise test on the same
//! recordings would have named effects that are not there.

use nf::diagnose::{Diagnosis, Kind, Options, diagnose};
use nf::noise_fit::NoiseChoice;
use nf::recording::Recording;
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_model::noise::NoiseModel;
use nf_twin::{Recorder, Rng, Shocks, TwinConfig, simulate};

const DWELL_S: f64 = 1.0;
const POSITIONS: u16 = 48;

/// A clean recording with `noise`: level, no effect, 1 s dwells.
fn clean(noise: NoiseModel, seed: u64) -> Recording {
    drifting(noise, 0.0, seed)
}

/// The same with a linear bias drift, deg/h per s.
fn drifting(noise: NoiseModel, drift: f64, seed: u64) -> Recording {
    let twin = TwinConfig {
        seed,
        noise,
        bias_drift_dph_per_s: drift,
        ..TwinConfig::default()
    };
    level_run(twin, POSITIONS, DWELL_S)
}

/// A run of `twin` at latitude 40, level, no settling transient: `positions` dwells of
/// `dwell_s`, psi from the seed.
fn level_run(mut twin: TwinConfig, positions: u16, dwell_s: f64) -> Recording {
    twin.settle_dph = 0.0;
    twin.instrument.tilt_deg = 0.0;
    twin.instrument.latitude_deg = 40.0;
    twin.instrument.psi_deg = (twin.seed as f64 * 47.0) % 360.0;
    let run = RunConfig {
        positions,
        dwell_ms: (dwell_s * 1000.0) as u32,
        settle_ms: 100,
        latitude_deg: 40.0,
        tilt_policy: TiltPolicy::Warn,
        tilt_correction: false,
        ..RunConfig::default()
    };
    let mut rec = Recorder::default();
    simulate(&twin, &run, &mut rec);
    Recording::parse(&rec.text()).unwrap()
}

fn white() -> NoiseModel {
    NoiseModel::white(0.005, 2.0)
}

/// Flicker with its floor `ratio` times the white noise of a dwell mean.
fn flicker(ratio: f64) -> NoiseModel {
    let w = white();
    NoiseModel {
        bias_instability_dph: ratio * w.white_mean_sd_dph(DWELL_S) / 0.664,
        ..w
    }
}

/// Rate random walk that wanders `ratio` times a dwell mean's white noise over the run.
fn random_walk(ratio: f64) -> NoiseModel {
    let w = white();
    let run_h = POSITIONS as f64 * 1.5 / 3600.0;
    NoiseModel {
        rrw_dph_rth: ratio * w.white_mean_sd_dph(DWELL_S) / (run_h / 3.0).sqrt(),
        ..w
    }
}

fn named(d: &Diagnosis, k: Kind) -> bool {
    d.findings.iter().any(|f| f.effect == k)
}

fn false_alarm(d: &Diagnosis) -> bool {
    d.findings.iter().any(|f| !f.effect.is_noise())
}

/// Over `runs` recordings of `noise(ratio)` with the ratio log-uniform in 0.5-5: false alarms
/// of the noise-aware diagnosis and of one told the noise is white.
fn false_alarms(noise: fn(f64) -> NoiseModel, runs: u64) -> (u32, u32) {
    let mut rng = Rng::new(17);
    let (mut ours, mut whites) = (0, 0);
    let told_white = Options {
        noise: NoiseChoice::Given(white(), "white".into()),
        ..Options::default()
    };
    for seed in 0..runs {
        let ratio = 0.5 * 10f64.powf(rng.unit());
        let rec = clean(noise(ratio), 100 + seed);
        let d = diagnose(&rec, &Options::default()).unwrap();
        ours += false_alarm(&d) as u32;
        whites += false_alarm(&diagnose(&rec, &told_white).unwrap()) as u32;
    }
    (ours, whites)
}

/// How often the colour is named at a given ratio, and how often any colour of the noise.
fn colour_found(noise: NoiseModel, colour: Kind, runs: u64) -> (u32, u32) {
    (0..runs)
        .map(|seed| {
            let d = diagnose(&clean(noise, 700 + seed), &Options::default()).unwrap();
            let any = d
                .findings
                .iter()
                .any(|f| f.effect.is_noise() && f.effect != Kind::HeavyTails);
            (named(&d, colour) as u32, any as u32)
        })
        .fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
}

#[test]
fn flicker_is_a_finding_not_a_catalogue_effect() {
    let (ours, whites) = false_alarms(flicker, 40);
    let (found, coloured) = colour_found(flicker(5.0), Kind::BiasInstability, 20);
    println!(
        "flicker: false alarms {ours}/40 (told white: {whites}/40); at 5 times, named {found}/20, a colour {coloured}/20"
    );
    // alpha = 0.05: 6 or more of 40 has probability 1.4 %.
    assert!(ours <= 5, "{ours} false alarms of 40");
    assert!(
        whites >= 2 * ours.max(3),
        "a white-noise test would not have done worse: {whites}"
    );
    assert!(found >= 10, "bias_instability named in {found} of 20");
    assert!(coloured >= 12, "no colour named in {} of 20", 20 - coloured);
}

#[test]
fn a_random_walk_is_a_finding_not_a_drift() {
    let (ours, whites) = false_alarms(random_walk, 40);
    let (found, coloured) = colour_found(random_walk(20.0), Kind::RateRandomWalk, 20);
    println!(
        "random walk: false alarms {ours}/40 (told white: {whites}/40); at 20 times, named {found}/20, a colour {coloured}/20"
    );
    // Over one run a random walk of this size and a drift are hard to tell apart: the goal of
    // 5 % is not met (5 of 40 today); what holds is that the noise model halves the rate of
    // a diagnosis told the noise is white, and no more than that is claimed here.
    assert!(ours <= 16, "{ours} false alarms of 40");
    assert!(
        2 * ours <= whites + 4,
        "the noise model does not help: {ours} against {whites}"
    );
    // Over one run a slow Gauss-Markov bias is a walk too: either is the right finding.
    assert!(found >= 10, "rate_random_walk named in {found} of 20");
    assert!(coloured >= 15, "no colour named in {} of 20", 20 - coloured);
}

#[test]
fn a_given_noise_model_is_also_checked_against_the_runs_wander() {
    // A noise model from a static log is the gyro's there: drift and its kind are also asked
    // of the wander test. A drift it does not confirm must not leave the amplitude it moved
    // to be named a scale factor.
    let told = Options {
        noise: NoiseChoice::Given(white(), "white".into()),
        ..Options::default()
    };
    let (mut drift, mut scale) = (0, 0);
    for seed in 0..20 {
        let d = diagnose(&drifting(white(), 4.4e-4, 500 + seed), &told).unwrap();
        assert!(d.wander_tested, "seed {seed}: the given model was not checked");
        drift += named(&d, Kind::BiasDrift) as u32;
        scale += named(&d, Kind::ScaleFactor) as u32;
    }
    println!("a drift under the given white model: named {drift}/20, a scale factor {scale}/20");
    assert!(drift >= 12, "the drift named in {drift} of 20");
    assert!(scale <= 1, "a scale factor stood in for the drift in {scale} of 20");
}

/// Student-t noise of 3 dof on the dwell means, or one burst on Gaussian noise. The quarter
/// means are dropped: they would not show the added noise.
fn heavy(rec: &mut Recording, rng: &mut Rng, burst: bool) {
    let sd = 0.004;
    let n = rec.rows.len();
    for (i, r) in rec.rows.iter_mut().enumerate() {
        r.quarters_dph = None;
        let e = if burst {
            sd * rng.gauss() + if i == n / 3 { 12.0 * sd } else { 0.0 }
        } else {
            let chi2: f64 = (0..3).map(|_| rng.gauss().powi(2)).sum();
            sd * rng.gauss() / (chi2 / 3.0).sqrt()
        };
        r.rate_dph += e;
    }
}

#[test]
fn heavy_tails_are_not_a_string_of_outliers_and_a_burst_is_an_outlier() {
    let mut rng = Rng::new(23);
    let quiet = NoiseModel::white(0.0005, 2.0);
    let (mut outliers, mut tails, mut burst_found, mut burst_tails) = (0, 0, 0, 0);
    for seed in 0..30 {
        let mut rec = clean(quiet, 300 + seed);
        heavy(&mut rec, &mut rng, false);
        let d = diagnose(&rec, &Options::default()).unwrap();
        outliers += named(&d, Kind::Outliers) as u32;
        tails += named(&d, Kind::HeavyTails) as u32;
        let mut rec = clean(quiet, 400 + seed);
        heavy(&mut rec, &mut rng, true);
        let d = diagnose(&rec, &Options::default()).unwrap();
        burst_found += named(&d, Kind::Outliers) as u32;
        burst_tails += named(&d, Kind::HeavyTails) as u32;
    }
    println!(
        "t3: outliers {outliers}/30, heavy_tails {tails}/30; burst: outliers {burst_found}/30, heavy_tails {burst_tails}/30"
    );
    assert!(outliers <= 4, "heavy-tailed noise named outliers in {outliers} of 30");
    // The tails of 48 dwell means are a weak test (the unit test of `tails` shows its power at
    // 200): what must hold is that the outlier test is not fooled by them.
    assert!(tails >= 1, "heavy_tails never named in 30 Student-t recordings");
    assert!(burst_found >= 27, "a 12-sigma burst found in {burst_found} of 30");
    assert!(burst_tails <= 4, "a burst taken for heavy tails in {burst_tails} of 30");
}

/// RMS of error / reported sigma of the final azimuth and of the selected model alone.
fn rms_z(noise: NoiseModel, runs: u64) -> (f64, f64) {
    let (mut fin, mut sel) = (0.0, 0.0);
    for seed in 0..runs {
        let d = diagnose(&clean(noise, 900 + seed), &Options::default()).unwrap();
        let truth = (((900 + seed) as f64) * 47.0) % 360.0;
        let z = |s: &nf::diagnose::Summary| nf_model::angle::wrap_180(s.azimuth_deg - truth) * 3600.0 / s.sigma_arcsec;
        fin += z(&d.final_).powi(2);
        sel += z(&d.selected).powi(2);
    }
    ((fin / runs as f64).sqrt(), (sel / runs as f64).sqrt())
}

#[test]
fn the_final_sigma_carries_the_noise_models_uncertainty() {
    let (fin, sel) = rms_z(flicker(3.0), 40);
    let (white_fin, _) = rms_z(white(), 40);
    println!("flicker: RMS error/sigma final {fin:.2}, selected model alone {sel:.2}; white: final {white_fin:.2}");
    // One estimate of the noise is a little too sure of itself (1.1 to 1.3 since it has a
    // Gauss-Markov family, 1.8 with flicker and walk alone); averaging over the models the
    // recording allows is not, and on white noise it stays within a factor two of exact.
    assert!(
        sel > fin,
        "averaging over the noise models made the sigma smaller: {fin:.2} against {sel:.2} alone"
    );
    assert!(
        (0.7..1.3).contains(&fin),
        "final RMS error/sigma {fin:.2} under flicker"
    );
    assert!(
        (0.5..1.2).contains(&white_fin),
        "final RMS error/sigma {white_fin:.2} on white noise"
    );
}

#[test]
fn the_final_sigma_holds_under_a_random_walk_in_a_sweep() {
    // In a sweep a walk shows most in harmonics 2-4 of the angle, which the tests' noise
    // estimate holds in its design; the final sigma takes the noise estimated under the final
    // model's own columns, calibrated by replicates (at 10: 1.34 before, 0.96 now). A walk
    // of 3 dwell sigmas, at the edge of what one run shows, is still at 1.75 (1.91 before;
    // docs/diagnose.md).
    for ratio in [10.0, 30.0] {
        let (fin, _) = rms_z(random_walk(ratio), 40);
        println!("random walk {ratio} dwell sigmas over the run: RMS error/sigma final {fin:.2}");
        assert!(
            (0.75..1.25).contains(&fin),
            "final RMS error/sigma {fin:.2} under a walk of {ratio}"
        );
    }
}

#[test]
fn a_gauss_markov_bias_of_half_a_dwell_is_not_all_read_as_flicker_in_the_final() {
    // Ten times the white noise of a dwell, correlated over half of one: flicker read it as
    // a wander at the run's own frequency (RMS error/sigma 0.2 to 0.3 in an outside audit's
    // sweeps); where a short Gauss-Markov bias shows, the final searches it as `nf fit` does.
    // Over 48 dwells it shows in some runs only: 0.28 before, 0.48 now (0.84 and 0.90 in
    // the audit's sweeps of 72 2 s dwells, docs/noise.md).
    let noise = NoiseModel {
        gm_sigma_dph: 0.05,
        gm_tau_s: 0.5,
        ..white()
    };
    let (fin, _) = rms_z(noise, 30);
    println!("Gauss-Markov 0.05 deg/h over 0.5 s: RMS error/sigma final {fin:.2}");
    assert!((0.4..1.3).contains(&fin), "final RMS error/sigma {fin:.2}");
}

/// One burst on flicker noise at the white level: the whitener is coloured.
#[test]
fn a_burst_in_coloured_noise_is_an_outlier_not_a_tail() {
    let noise = flicker(1.0);
    let size = 12.0 * noise.white_mean_sd_dph(DWELL_S);
    let (mut found, mut tails) = (0, 0);
    for seed in 0..30 {
        let mut rec = clean(noise, 600 + seed);
        let n = rec.rows.len();
        rec.rows[n / 3].rate_dph += size;
        let d = diagnose(&rec, &Options::default()).unwrap();
        found += named(&d, Kind::Outliers) as u32;
        tails += named(&d, Kind::HeavyTails) as u32;
    }
    println!("a 12-sigma burst under flicker: outliers {found}/30, heavy_tails {tails}/30");
    // Held out of the tails' fit by an unwhitened column, the burst's footprint stayed in the
    // residuals as a tail: outliers 13 of 30.
    assert!(found >= 17, "the burst named in {found} of 30");
    assert!(tails <= 3, "the burst taken for heavy tails in {tails} of 30");
}

/// Shocks on a white gyro, as `bench/shocks.py`'s case A: 72 dwells of 2 s, bursts of 2 s
/// at 146 an hour of sd 0.087 deg/h. The Gaussian estimates take the dwells' scatter beyond
/// their quarters for flicker (B 0.016 deg/h named in 3 of 6 such `nf simulate` runs); the
/// noise estimated again beside the shocks has none.
#[test]
fn shocks_are_heavy_tails_not_flicker() {
    let colours = [Kind::BiasInstability, Kind::RateRandomWalk, Kind::CorrelatedNoise];
    let (mut through, mut coloured) = (0, 0);
    for seed in 0..8 {
        let twin = TwinConfig {
            seed: 900 + seed,
            noise: white(),
            shocks: Shocks {
                per_hour: 146.0,
                size_dph: 0.0866,
                duration_s: 2.0,
            },
            ..TwinConfig::default()
        };
        let d = diagnose(&level_run(twin, 72, 2.0), &Options::default()).unwrap();
        if d.through_shocks {
            through += 1;
            let tails = d.findings.iter().find(|f| f.effect == Kind::HeavyTails);
            let struck = tails.and_then(|f| f.parameters.iter().find(|p| p.name == "struck_dwells"));
            assert!(struck.is_some_and(|p| p.value >= 1.0), "seed {seed}: {:?}", d.findings);
            // The same dwells are marked for the report's plot.
            let marked = d.points.iter().filter(|p| p.struck).count();
            assert_eq!(Some(marked as f64), struck.map(|p| p.value), "seed {seed}");
            coloured += colours.iter().any(|&k| named(&d, k)) as u32;
        }
    }
    println!("shocks: through them in {through} of 8, a colour named in {coloured}");
    assert!(through >= 6, "fitted through the shocks in {through} of 8");
    assert_eq!(
        coloured, 0,
        "a colour named beside the shocks in {coloured} of {through}"
    );
}

#[test]
fn a_clear_drift_is_named_or_noted_never_passed_over() {
    // About 12 dwell-mean sigmas of drift over the run. Where the wander test holds it back
    // (a random walk of the size this run allows explains it as well), the diagnosis says
    // so and gives its rate.
    let truth = 1.2e-3;
    let (mut named_n, mut held) = (0, 0);
    for seed in 0..12 {
        let d = diagnose(&drifting(white(), truth, 700 + seed), &Options::default()).unwrap();
        if named(&d, Kind::BiasDrift) {
            named_n += 1;
            continue;
        }
        let u = d.undecided.iter().find(|u| u.effect == Kind::BiasDrift);
        let u = u.unwrap_or_else(|| panic!("seed {seed}: the drift passed over in silence: {:?}", d.notes));
        assert!(u.own_p < u.level && u.p_value >= u.level, "seed {seed}: {u:?}");
        assert!(
            d.notes.iter().any(|n| n.starts_with("bias_drift not named")),
            "seed {seed}: no note: {:?}",
            d.notes
        );
        let rate = u.parameters.iter().find(|p| p.name == "rate_dph_per_s").unwrap();
        let sigma = rate.sigma.unwrap();
        println!(
            "seed {seed}: rate {:.3e} +- {sigma:.1e}, p {:.1e} then {:.1e}",
            rate.value, u.own_p, u.p_value
        );
        assert!((rate.value - truth).abs() < 3.0 * sigma, "seed {seed}: rate {rate:?}");
        held += 1;
    }
    println!("a clear drift: named {named_n}/12, held back and said {held}/12");
    assert!(held >= 1, "the held-back drift was not exercised");
}

/// Eight positions in opposite pairs, the dwell means alone (no quarters, no samples'
/// spread), white noise of `sd` deg/h, written here from the documented format; and the
/// true psi.
fn eight_in_pairs(seed: u64, sd: f64) -> (Recording, f64) {
    let mut rng = Rng::new(seed);
    let (lat, psi) = (rng.uniform(-70.0, 70.0), rng.uniform(0.0, 360.0));
    let amplitude = 15.041 * lat.to_radians().cos();
    let mut text =
        format!("# format = northfinder-recording/1\n# latitude_deg = {lat}\nindex,t_s,encoder_deg,rate_dph\n");
    for (k, p) in [0, 4, 1, 5, 2, 6, 3, 7].into_iter().enumerate() {
        let g = 45.0 * p as f64;
        let rate = 0.4 + amplitude * (g + psi).to_radians().cos() + sd * rng.gauss();
        text += &format!("{k},{},{g},{rate}\n", 3.0 * k as f64 + 1.0);
    }
    (Recording::parse(&text).unwrap(), psi)
}

#[test]
fn eight_dwell_means_alone_give_the_final_student_s_t_as_nf_fit() {
    // Five residual contrasts cannot tell a colour: the colour models' REML at times gave a
    // walk a fifth of the white sigma (an outside audit: RMS error/sigma 1.63, 6 of 60
    // beyond 3 sigma). Each model is white at its residual level, its sigma widened by t.
    let runs = 400;
    let (mut sum, mut within, mut beyond) = (0.0, 0, 0);
    for seed in 0..runs {
        let (rec, psi) = eight_in_pairs(7000 + seed, 0.01);
        let d = diagnose(&rec, &Options::default()).unwrap();
        if !false_alarm(&d) {
            assert_eq!(d.residual_dof, Some(5), "seed {seed}");
        }
        let z = nf_model::angle::wrap_180(d.final_.azimuth_deg - psi) * 3600.0 / d.final_.sigma_arcsec;
        sum += z * z;
        within += usize::from(z.abs() < 1.96);
        beyond += usize::from(z.abs() > 3.0);
    }
    let rms = (sum / runs as f64).sqrt();
    let share = within as f64 / runs as f64;
    println!(
        "eight positions in pairs: RMS error/sigma {rms:.2}, within 1.96 sigma {share:.3}, beyond 3 sigma {beyond}"
    );
    assert!((0.8..1.2).contains(&rms), "RMS error/sigma {rms:.2}");
    assert!((0.92..0.98).contains(&share), "within 1.96 sigma {share:.3}");
    assert!(beyond <= 12, "{beyond} of {runs} beyond 3 sigma");
}

#[test]
fn a_false_outlier_among_eight_dwell_means_does_not_carry_the_final() {
    // An outside audit's file (white noise, truth 332.8966 deg): seven of the eight dwell
    // means happen to lie close to a curve, so the eighth's studentised residual is 22.5 (p
    // 1.8e-4); with it and a second held out, three contrasts were left and the final read
    // 332.97719 deg +- 2.80", 100 of its sigmas off. Weighed by AICc, that model has no room.
    let text = "# format = northfinder-recording/1\n# latitude_deg = -69.500323853\nindex,t_s,encoder_deg,rate_dph\n\
        0,1.500,0,4.678626991\n1,4.750,45,5.024546323\n2,8.000,90,2.383736823\n3,11.250,135,-1.627868949\n\
        4,14.500,180,-4.689076873\n5,17.750,225,-5.006346043\n6,21.000,270,-2.393943579\n7,24.250,315,1.615003887\n";
    let d = diagnose(&Recording::parse(text).unwrap(), &Options::default()).unwrap();
    let z = nf_model::angle::wrap_180(d.final_.azimuth_deg - 332.8966) * 3600.0 / d.final_.sigma_arcsec;
    assert!(z.abs() < 2.0 && d.final_.sigma_arcsec > 100.0, "{:?}", d.final_);
}
