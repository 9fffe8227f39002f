//! `nf diagnose --sim`: a recording from one instrument file, diagnosed against the same file
//! with one effect taken out, must name that effect as missing, `--fix` must put it back at
//! its size, and the replays of the fixed file must match the recording.

use nf::diagnose::{Kind, Options, diagnose};
use nf::instrument_file::{Disturbance, EncoderError, InstrumentFile, Jump, Shocks};
use nf::recording::Recording;
use nf::sim_compare::{self, Quantity, SimReport, Verdict};

fn recording(file: &InstrumentFile) -> Recording {
    let mut rec = nf_twin::Recorder::default();
    nf_twin::simulate(&file.twin(), &file.run_config(), &mut rec);
    Recording::parse(&rec.text()).unwrap()
}

fn against(rec: &Recording, file: &InstrumentFile) -> SimReport {
    let d = diagnose(rec, &Options::default()).unwrap();
    let opt = sim_compare::Options {
        replays: 10,
        ..sim_compare::Options::default()
    };
    sim_compare::against(rec, &d, file, &opt).unwrap()
}

/// The instrument of the tests: the paper's, with a heater cycle on the thermometer.
fn base() -> InstrumentFile {
    let mut f = InstrumentFile::default();
    f.temperature.swing_c = 2.0;
    f.temperature.swing_period_s = 50.0;
    f.seed = 3;
    f
}

struct Case {
    kind: Kind,
    /// Puts the effect in, given the middle of one dwell on the file's clock.
    add: fn(&mut InstrumentFile, f64),
    /// The effect's size in a file.
    size: fn(&InstrumentFile) -> f64,
}

fn cases() -> Vec<Case> {
    vec![
        Case {
            kind: Kind::BiasDrift,
            // 15 dwell-mean sigmas over the run; half that passes for a random walk of the
            // size one run allows (the wander test's draws: docs/diagnose.md).
            add: |f, _| f.drift.linear_dph_per_s = 4e-4,
            size: |f| f.drift.linear_dph_per_s,
        },
        Case {
            kind: Kind::BiasJump,
            add: |f, _| {
                f.jump = Some(Jump {
                    time_s: 95.0,
                    size_dph: 0.04,
                })
            },
            size: |f| f.jump.map_or(0.0, |j| j.size_dph),
        },
        Case {
            kind: Kind::ThermalDrift,
            add: |f, _| f.temperature.bias_dph_per_c = 0.02,
            size: |f| f.temperature.bias_dph_per_c,
        },
        Case {
            kind: Kind::ShaftTilt,
            add: |f, _| f.shaft.tilt_deg = 1.0,
            size: |f| f.shaft.tilt_deg,
        },
        Case {
            kind: Kind::EncoderError,
            add: |f, _| {
                f.encoder.error = vec![EncoderError {
                    harmonic: 2,
                    amplitude_arcsec: 400.0,
                    phase_deg: 30.0,
                }]
            },
            size: |f| f.encoder.error.iter().map(|e| e.amplitude_arcsec).sum(),
        },
        Case {
            kind: Kind::ScaleFactor,
            add: |f, _| f.gyro.scale = 1.01,
            size: |f| f.gyro.scale - 1.0,
        },
        Case {
            kind: Kind::Nonlinearity,
            add: |f, _| f.gyro.nonlinearity_per_dph = 5e-4,
            size: |f| f.gyro.nonlinearity_per_dph,
        },
        Case {
            kind: Kind::SettlingTransient,
            add: |f, _| {
                f.settling.size_dph = 0.3;
                f.settling.tau_s = 0.3;
            },
            size: |f| nf::sim_compare::settling_offset(f, f.run.dwell_s),
        },
        Case {
            kind: Kind::Outliers,
            add: |f, t| {
                f.disturbance = vec![Disturbance {
                    from_s: t - 0.8,
                    to_s: t + 0.8,
                    size_dph: 0.1,
                }]
            },
            size: |f| f.disturbance.iter().map(|d| d.size_dph).sum(),
        },
    ]
}

#[test]
fn each_effect_left_out_of_the_simulation_is_named_and_put_back() {
    let plain = recording(&base());
    let dwell_20 = plain.rows[20].t_s + sim_compare::run_origin_s(&base());
    for c in cases() {
        let mut with = base();
        (c.add)(&mut with, dwell_20);
        let rec = recording(&with);
        let s = against(&rec, &base());
        let name = c.kind.name();
        let p = s.physics.iter().find(|p| p.kind == c.kind);
        let p = p.unwrap_or_else(|| panic!("{name} not named: {:?}", s.physics));
        assert!(
            matches!(p.verdict, Verdict::Missing | Verdict::Different),
            "{name}: {:?}",
            p.verdict
        );
        let (truth, fixed) = ((c.size)(&with), (c.size)(&s.fixed.file));
        eprintln!(
            "{name:<20} {:<10} truth {truth:<12.4e} fixed {fixed:<12.4e} mismatches {} -> {}",
            format!("{:?}", p.verdict),
            s.before.mismatches(),
            s.fixed.after.mismatches()
        );
        assert!(
            (fixed - truth).abs() <= 0.25 * truth.abs(),
            "{name}: fixed {fixed}, truth {truth}"
        );
        assert!(s.before.mismatches() >= 1, "{name}: no mismatch before");
        // The site is the file's: what the fitted effects miss does not move it.
        assert_eq!(
            s.fixed.file.site.azimuth_deg,
            base().site.azimuth_deg,
            "{name}: {:?}",
            s.fixed.changes
        );
        if c.kind != Kind::ScaleFactor {
            assert_eq!(s.fixed.file.gyro.scale, 1.0, "{name}: {:?}", s.fixed.changes);
        }
        assert!(
            s.fixed.after.mismatches() <= 1,
            "{name}: {} mismatches after the fix: {:?}",
            s.fixed.after.mismatches(),
            s.fixed.after.lines.iter().filter(|l| l.mismatch).collect::<Vec<_>>()
        );
    }
}

#[test]
fn a_recording_of_the_simulated_instrument_lacks_nothing() {
    let mut quiet = 0;
    for seed in 1..=4 {
        let mut f = base();
        f.seed = seed;
        let s = against(&recording(&f), &f);
        let lacking: Vec<_> = s.physics.iter().filter(|p| p.verdict != Verdict::Modelled).collect();
        if lacking.is_empty() && s.before.mismatches() == 0 {
            quiet += 1;
        }
    }
    assert!(quiet >= 3, "{quiet} of 4 clean");
}

#[test]
fn a_temperature_ramp_the_simulation_lacks_is_judged_under_the_files_noise() {
    // A ramp of 0.015 C/s at 0.01 deg/h per C: under the recording's own noise estimate the
    // run's wander explains it as well; under the file's white noise it is named. A
    // temperature that follows time is a drift as much (the averaging shares the two): either
    // goes in, at 1.5e-4 deg/h per s. In one of these three the ramp's residual departs in an
    // Allan deviation (over 4 positions): the noise does not match the file's, but the ramp
    // found under the file's noise, put in, leaves fewer quantities departing.
    let plain = InstrumentFile::default();
    let mut ramp = plain.clone();
    ramp.temperature.ramp_c_per_s = 0.015;
    ramp.temperature.bias_dph_per_c = 0.01;
    let mut departed = 0;
    for seed in 1..=3 {
        ramp.seed = seed;
        let rec = recording(&ramp);
        let own = diagnose(&rec, &Options::default()).unwrap();
        let slope = |k: Kind| own.findings.iter().any(|f| f.effect == k);
        assert!(!slope(Kind::ThermalDrift) && !slope(Kind::BiasDrift), "seed {seed}");
        let s = against(&rec, &plain);
        departed += usize::from(s.before.any(|q| q.is_scatter()));
        assert!(s.under_file_noise, "seed {seed}");
        let missing = |k: Kind| s.physics.iter().any(|p| p.kind == k && p.verdict == Verdict::Missing);
        assert!(
            missing(Kind::ThermalDrift) || missing(Kind::BiasDrift),
            "seed {seed}: {:?}",
            s.physics
        );
        let f = &s.fixed.file;
        let put_in = f.temperature.bias_dph_per_c * 0.015 + f.drift.linear_dph_per_s;
        assert!(
            (put_in / 1.5e-4 - 1.0).abs() < 0.3,
            "seed {seed}: {put_in} {:?}",
            s.fixed.changes
        );
        assert_eq!(s.fixed.after.mismatches(), 0, "seed {seed}: {:?}", s.fixed.after);
    }
    assert_eq!(departed, 1);
}

#[test]
fn flicker_noise_the_simulation_lacks_is_named_and_put_in() {
    let mut with = base();
    with.noise.bias_instability_dph = 0.01;
    let s = against(&recording(&with), &base());
    // Its noise departs from the file's: judged under the recording's own estimate.
    assert!(!s.under_file_noise);
    let p = s.physics.iter().find(|p| p.kind == Kind::BiasInstability);
    assert!(p.is_some_and(|p| p.verdict == Verdict::Missing), "{:?}", s.physics);
    assert!(s.fixed.file.noise.bias_instability_dph > 0.0);
    assert!(s.fixed.after.mismatches() <= s.before.mismatches());
    // The white level is the samples' (thousands a dwell), not the estimate's from the dwell
    // means, which trades it against the flicker: 4 %, 7 % and 2 % off in these three.
    for seed in 101..=103 {
        let mut flicker = InstrumentFile::default();
        flicker.noise.bias_instability_dph = 0.01;
        flicker.seed = seed;
        let fixed = against(&recording(&flicker), &InstrumentFile::default()).fixed;
        let arw = fixed.file.noise.arw_deg_rth / flicker.noise.arw_deg_rth;
        assert!((arw - 1.0).abs() < 0.01, "seed {seed}: {arw} {:?}", fixed.changes);
    }
    // A recording of the fixed file, against it: its colour is the file's, whatever name one
    // run gives it, and nothing is taken out.
    let mut fixed = s.fixed.file.clone();
    fixed.seed = 11;
    let again = against(&recording(&fixed), &s.fixed.file);
    assert!(
        again
            .physics
            .iter()
            .all(|p| !p.verdict.needs_change() || p.kind == Kind::ShaftTilt),
        "{:?}",
        again.physics
    );
    assert!(
        again.fixed.file.noise.bias_instability_dph > 0.0,
        "{:?}",
        again.fixed.changes
    );
}

#[test]
fn an_effect_only_a_replay_names_stays_unless_the_recording_contradicts_it() {
    // A heater cycle at the edge of what one run shows: in these two runs the recording of
    // the same file does not name it (28 of seeds 1-30 do, judged under the file's noise).
    // That is no evidence against the file's cycle (before, the fix took it out).
    let mut f = InstrumentFile::default();
    f.temperature.swing_c = 2.0;
    f.temperature.swing_period_s = 100.0;
    f.temperature.bias_dph_per_c = 2.5e-3;
    for seed in [14, 30] {
        f.seed = seed;
        let s = against(&recording(&f), &f);
        assert!(
            s.physics.iter().all(|p| p.kind != Kind::ThermalDrift),
            "{:?}",
            s.physics
        );
        assert_eq!(s.fixed.file.temperature.bias_dph_per_c, 2.5e-3, "{:?}", s.fixed.changes);
    }
    // A drift the recording's run would show beyond doubt, and does not: taken out.
    let mut strong = base();
    strong.drift.linear_dph_per_s = 1e-3;
    let s = against(&recording(&base()), &strong);
    let p = s.physics.iter().find(|p| p.kind == Kind::BiasDrift);
    assert!(
        p.is_some_and(|p| p.verdict == Verdict::OnlyInSimulation),
        "{:?}",
        s.physics
    );
    assert_eq!(s.fixed.file.drift.linear_dph_per_s, 0.0);
}

#[test]
fn a_white_level_off_within_the_dwells_is_scaled_from_the_samples() {
    // The simulation's angle random walk 5 % high: the samples' spread shows it, far more
    // precisely than the dwell means would.
    let f = base();
    let mut high = base();
    high.noise.arw_deg_rth *= 1.05;
    let s = against(&recording(&f), &high);
    assert!(
        s.before
            .line(sim_compare::Quantity::SampleSd)
            .is_some_and(|l| l.mismatch)
    );
    let arw = s.fixed.file.noise.arw_deg_rth / f.noise.arw_deg_rth;
    assert!((arw - 1.0).abs() < 0.01, "{arw} {:?}", s.fixed.changes);
    assert_eq!(s.fixed.after.mismatches(), 0, "{:?}", s.fixed.after);
}

#[test]
fn the_recording_s_plan_goes_into_the_fixed_file() {
    let mut with = base();
    with.run.positions = 24;
    with.run.order = "forward-back".into();
    with.run.dwell_s = 1.0;
    with.run.sample_rate_hz = 200;
    let s = against(&recording(&with), &base());
    let run = &s.fixed.file.run;
    assert_eq!(
        (run.positions, run.order.as_str(), run.dwell_s, run.sample_rate_hz),
        (24, "forward-back", 1.0, 200)
    );
    // Replayed at the recording's sample rate: the samples' spread is the recording's.
    let samples = s.before.line(sim_compare::Quantity::SampleSd).unwrap();
    assert!(!samples.mismatch, "{samples:?}");
    assert!(
        s.fixed.changes.iter().any(|c| c.starts_with("run: 24 positions")),
        "{:?}",
        s.fixed.changes
    );
    assert!(s.fixed.after.mismatches() <= 1);
}

/// Mean time from one dwell to the next, s.
fn pace_s(rec: &Recording) -> f64 {
    let t: Vec<f64> = rec.rows.iter().map(|r| r.t_s).collect();
    (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64
}

/// The recording's pace, from a longer settling or a faster motor: the fixed file's run takes
/// its time, which the drift and the wander act over.
#[test]
fn the_recording_s_pace_goes_into_the_fixed_file() {
    let mut slow = base();
    slow.run.settle_s = 1.2;
    let mut fast = base();
    fast.run.positions = 24;
    fast.run.order = "opposite-pairs".into();
    for m in [&mut fast.motor.max_sps, &mut fast.motor.start_sps] {
        *m *= 8.0;
    }
    fast.motor.accel_sps2 *= 64.0;
    for (with, faster) in [(slow, false), (fast, true)] {
        let rec = recording(&with);
        let s = against(&rec, &base());
        let fixed = &s.fixed.file;
        let again = pace_s(&recording(fixed));
        assert!(
            (again / pace_s(&rec) - 1.0).abs() < 0.01,
            "{again} against {}: {:?}",
            pace_s(&rec),
            s.fixed.changes
        );
        assert_eq!(
            fixed.motor.max_sps > base().motor.max_sps,
            faster,
            "{:?}",
            s.fixed.changes
        );
    }
}

/// Each inclinometer's offset is its own: a Y offset the file has wrong is found and moved.
#[test]
fn the_y_inclinometer_s_offset_goes_into_the_fixed_file() {
    let mut with = base();
    with.inclinometer.offset_y_deg = 0.05;
    let s = against(&recording(&with), &base());
    let line = s.before.line(sim_compare::Quantity::TiltOffsetY).unwrap();
    assert!(line.mismatch, "{line:?}");
    let y = s.fixed.file.inclinometer.offset_y_deg;
    assert!((y - 0.05).abs() < 1e-3, "{y}: {:?}", s.fixed.changes);
    assert_eq!(s.fixed.file.inclinometer.offset_x_deg, base().inclinometer.offset_x_deg);
}

#[test]
fn a_heater_swing_the_simulation_lacks_goes_into_the_fixed_file() {
    // The recording's thermometer cycles and the bias follows it; the file has neither.
    let mut with = base();
    with.temperature.swing_phase_deg = 40.0;
    with.temperature.bias_dph_per_c = 0.02;
    let rec = recording(&with);
    let mut without = base();
    without.temperature.swing_c = 0.0;
    let s = against(&rec, &without);
    let t = &s.fixed.file.temperature;
    assert!((t.swing_c / 2.0 - 1.0).abs() < 0.05, "{t:?}");
    assert!((t.swing_period_s / 50.0 - 1.0).abs() < 0.02, "{t:?}");
    assert!((t.bias_dph_per_c / 0.02 - 1.0).abs() < 0.25, "{t:?}");
    // `nf simulate --config` of the fixed file: its thermometer reads the recording's.
    let again = recording(&s.fixed.file);
    let sq: Vec<f64> = rec
        .rows
        .iter()
        .zip(&again.rows)
        .map(|(a, b)| (a.temp_c.unwrap() - b.temp_c.unwrap()).powi(2))
        .collect();
    let rms = (sq.iter().sum::<f64>() / sq.len() as f64).sqrt();
    assert!(
        rms < 0.05,
        "the fixed file's temperature misses the recording's by {rms} C RMS"
    );
    assert!(
        s.fixed.changes.iter().any(|c| c.contains("a swing of")),
        "{:?}",
        s.fixed.changes
    );
}

#[test]
fn shocks_the_simulation_lacks_are_named_and_put_in() {
    // A sixth of the dwells shifted by about ten times a dwell mean's noise; enough dwells
    // that the few shifted ones size the shocks.
    let dwell = base().run.dwell_s;
    let long = |seed: u64| {
        let mut f = base();
        f.seed = seed;
        f.run.positions = 240;
        f
    };
    let asked = nf_twin::WindowShift {
        share: 0.15,
        shift_dph: 0.05,
    };
    let truth = asked.share.sqrt() * asked.shift_dph;
    let mut named = 0;
    for seed in 1..=4 {
        let mut with = long(seed);
        with.shocks = Some(Shocks::of(nf_twin::Shocks::for_window(asked, dwell)));
        let s = against(&recording(&with), &long(seed));
        let Some(p) = s.physics.iter().find(|p| p.kind == Kind::HeavyTails) else {
            continue;
        };
        named += 1;
        assert_eq!(p.verdict, Verdict::Missing);
        let fixed = sim_compare::shock_rms(&s.fixed.file, dwell);
        eprintln!(
            "seed {seed}: shock rms truth {truth:.4} found {:.4} fixed {fixed:.4}, mismatches {} -> {}",
            p.parameter.value,
            s.before.mismatches(),
            s.fixed.after.mismatches()
        );
        assert!((0.5..=2.0).contains(&(fixed / truth)), "fixed {fixed}, truth {truth}");
        assert!(s.fixed.after.mismatches() <= s.before.mismatches());
        // Beside the shocks the noise is white: their scatter is not written as flicker (seed
        // 3 was given B 0.013 deg/h, one mismatch left, before the noise terms came from the
        // estimate beside the shocks).
        let noise = &s.fixed.file.noise;
        assert!(
            noise.bias_instability_dph == 0.0 && noise.rrw_dph_rth == 0.0 && noise.gm_sigma_dph == 0.0,
            "seed {seed}: {noise:?}"
        );
        // The fixed file's own recording has the tails the recording had.
        let again = diagnose(&recording(&s.fixed.file), &Options::default()).unwrap();
        assert!(again.findings.iter().any(|f| f.effect == Kind::HeavyTails));
    }
    assert!(named >= 3, "heavy tails named in {named} of 4");
    // The other way: shocks only the simulation has are taken out.
    let mut with = long(1);
    with.shocks = Some(Shocks::of(nf_twin::Shocks::for_window(asked, dwell)));
    let s = against(&recording(&long(1)), &with);
    let p = s.physics.iter().find(|p| p.kind == Kind::HeavyTails);
    assert!(
        p.is_some_and(|p| p.verdict == Verdict::OnlyInSimulation),
        "{:?}",
        s.physics
    );
    assert_eq!(s.fixed.file.shocks, None);
}

#[test]
fn a_random_walk_the_simulation_lacks_is_put_in_and_the_site_left_alone() {
    // The walk put in widens the replays' azimuth and bias: one run's wander, which the
    // replays of the file with the walk show as often, is no reason to move the site (before,
    // the Eq. 7 numbers were judged against replays of the white file and moved in 2 of 3).
    for seed in 11..=13 {
        let mut walk = InstrumentFile::default();
        walk.noise.rrw_dph_rth = 0.3;
        walk.seed = seed;
        let s = against(&recording(&walk), &InstrumentFile::default());
        let f = &s.fixed.file;
        assert!(f.noise.rrw_dph_rth > 0.0, "seed {seed}: {:?}", s.fixed.changes);
        let site = InstrumentFile::default();
        assert_eq!(
            (f.site.azimuth_deg, f.gyro.bias_dph, f.gyro.scale),
            (site.site.azimuth_deg, site.gyro.bias_dph, site.gyro.scale),
            "seed {seed}: {:?}",
            s.fixed.changes
        );
    }
}

#[test]
fn a_file_for_another_latitude_is_said_to_be_so() {
    let rec = recording(&base());
    assert!(against(&rec, &base()).warnings.is_empty());
    let mut north = base();
    north.site.latitude_deg = 60.0;
    let s = against(&rec, &north);
    assert!(
        s.warnings.len() == 1 && s.warnings[0].contains("latitude (60 deg)"),
        "{:?}",
        s.warnings
    );
    assert_eq!(s.fixed.file.site.latitude_deg, rec.latitude_deg);
}

#[test]
fn heavy_tailed_samples_the_simulation_lacks_are_measured_and_put_in() {
    // Samples of a Student-t of 5 dof: their dwell means are Gaussian, their spread is not.
    let mut tailed = base();
    tailed.noise.student_t_dof = 5.0;
    let mut dofs = Vec::new();
    for seed in 1..=3 {
        tailed.seed = seed;
        let s = against(&recording(&tailed), &base());
        let l = s.before.line(sim_compare::Quantity::SampleKurtosis).unwrap();
        assert!(l.mismatch, "seed {seed}: {l:?}");
        let fixed = s.fixed.file.noise.student_t_dof;
        let after = s.fixed.after.line(sim_compare::Quantity::SampleKurtosis).unwrap();
        assert!(!after.mismatch, "seed {seed}: {after:?}");
        dofs.push(fixed);
    }
    println!("fixed dof {dofs:?}");
    assert!(dofs.iter().all(|d| (4.3..8.0).contains(d)), "{dofs:?}");
    // The other way: tails only the simulation has are taken out.
    let s = against(&recording(&base()), &tailed);
    assert!(s.before.line(sim_compare::Quantity::SampleKurtosis).unwrap().mismatch);
    assert_eq!(s.fixed.file.noise.student_t_dof, 0.0);
}

#[test]
fn a_scale_fitted_beside_a_nonlinearity_leaves_out_the_nonlinearity_s_own_gain() {
    // The twin squares the rate with its bias, so a nonlinearity k gains the first harmonic
    // by 1 + 2 k c: the fitted scale factor holds it, and the fix wrote both (an outside
    // audit's k of 3e-4 at a bias of 0.3 deg/h: scale 1.00023, 3.6 of its sigmas off 1).
    let mut both = 0;
    for seed in 1..=3 {
        let mut with = InstrumentFile::default();
        with.gyro.nonlinearity_per_dph = 3e-4;
        with.seed = seed;
        let s = against(&recording(&with), &InstrumentFile::default());
        let Some(scale) = s
            .physics
            .iter()
            .find(|p| p.kind == Kind::ScaleFactor && p.verdict.needs_change())
        else {
            continue;
        };
        both += 1;
        let sigma = scale.parameter.sigma.expect("a fitted scale has a sigma");
        let fixed = s.fixed.file.gyro.scale;
        eprintln!(
            "seed {seed}: fitted {} +- {sigma}, written {fixed}",
            scale.parameter.value
        );
        assert!(
            (fixed - 1.0).abs() < 2.5 * sigma,
            "seed {seed}: scale {fixed} +- {sigma}"
        );
    }
    assert!(both >= 1, "the scale factor was named in none");
}

#[test]
fn the_site_moves_only_by_the_recording_s_own_final() {
    // A Gauss-Markov bias the file lacks, judged under the file's white noise: that
    // diagnosis's final had a fifth of the printed final's sigma and moved the site 129" at
    // 1.4 of the printed sigmas (an outside audit, its seed 2).
    let mut judged = 0;
    for seed in 1..=3 {
        let mut with = InstrumentFile::default();
        (with.noise.gm_sigma_dph, with.noise.gm_tau_s) = (0.01, 30.0);
        with.seed = seed;
        let rec = recording(&with);
        let d = diagnose(&rec, &Options::default()).unwrap();
        let file = InstrumentFile::default();
        let opt = sim_compare::Options {
            replays: 10,
            ..sim_compare::Options::default()
        };
        let s = sim_compare::against(&rec, &d, &file, &opt).unwrap();
        let apart = nf_model::angle::wrap_180(d.final_.azimuth_deg - file.site.azimuth_deg) * 3600.0;
        let moved = s.fixed.file.site.azimuth_deg != file.site.azimuth_deg;
        eprintln!(
            "seed {seed}: final {apart:.1}\" +- {:.1}\", moved {moved}: {:?}",
            d.final_.sigma_arcsec, s.fixed.changes
        );
        assert_eq!(moved, apart.abs() > 3.0 * d.final_.sigma_arcsec, "seed {seed}");
        // The site was in question where the azimuth departed before the fix.
        judged += usize::from(s.before.line(Quantity::Azimuth).is_some_and(|l| l.mismatch));
    }
    assert!(judged >= 1, "no site judged");
}

#[test]
fn a_bias_moved_says_the_gyro_elevation_it_could_be() {
    // The gyro axis raised 0.29 deg: the Earth rate's vertical part adds a constant that one
    // run cannot tell from a bias (an outside audit: "misalignment is never named").
    let mut raised = InstrumentFile::default();
    raised.gyro.elevation_deg += 0.29;
    let s = against(&recording(&raised), &InstrumentFile::default());
    let note = s.fixed.changes.iter().find(|c| c.starts_with("bias: moved by"));
    let note = note.unwrap_or_else(|| panic!("{:?}", s.fixed.changes));
    let elevation: f64 = note
        .split("elevation moved by ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{note}"));
    assert!((elevation - 0.29).abs() < 0.02, "{note}");
}

#[test]
fn a_weak_wander_the_simulation_lacks_is_put_in_though_no_noise_term_is_named() {
    // An outside audit's Gauss-Markov bias and walk: the recording's noise test named no
    // term, so the fix kept the file's white noise and its replays stayed 3-16 sds from the
    // recording in the amplitude and the slow harmonics of the sweep.
    let mut put_in = 0;
    let mut told = Vec::new();
    for seed in 1..=6 {
        let mut wander = InstrumentFile::default();
        if seed % 2 == 0 {
            wander.noise.gm_sigma_dph = 0.01;
            wander.noise.gm_tau_s = 30.0;
        } else {
            wander.noise.rrw_dph_rth = 0.1;
        }
        wander.seed = seed;
        let s = against(&recording(&wander), &InstrumentFile::default());
        let n = &s.fixed.file.noise;
        let coloured = n.bias_instability_dph > 0.0 || n.rrw_dph_rth > 0.0 || n.gm_sigma_dph > 0.0;
        put_in += usize::from(coloured);
        told.push((seed, s.before.mismatches(), s.fixed.after.mismatches(), coloured));
        assert!(
            s.fixed.after.mismatches() <= s.before.mismatches(),
            "seed {seed}: {:?}",
            s.fixed.changes
        );
    }
    println!("(seed, mismatches before, after, wander put in): {told:?}");
    assert!(put_in >= 5, "{told:?}");
}
