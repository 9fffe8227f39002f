//! `nf diagnose` on twin recordings with concealed effects, and on clean ones.

use nf::diagnose::{Diagnosis, Finding, Kind, Options, diagnose};
use nf::diagnose_eval::{EvalOptions, Outcome, evaluate, outcome_of};
use nf::recording::Recording;
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_twin::{Recorder, TwinConfig, simulate};

fn outcome(rec: &Recording) -> Option<Outcome> {
    diagnose(rec, &Options::default()).ok().map(|d| outcome_of(&d))
}

#[test]
fn clear_effects_are_named_first_and_clean_recordings_stay_clean() {
    let opts = EvalOptions {
        seeds: 4,
        clean: 60,
        category: Some("white".into()),
    };
    let ev = evaluate(&opts, &outcome, &mut |_| {});
    let white = &ev.categories[0];
    let clear: Vec<_> = white.rows.iter().filter(|r| r.label.ends_with(" clear")).collect();
    assert_eq!(clear.len(), Kind::CATALOGUE.len());
    let (mut first, mut recalled) = (0, 0);
    for r in &clear {
        let t = &r.tally;
        println!("{:<28}: named first {}/{}", r.label, t.named_first, t.runs);
        assert_eq!(t.runs, 4);
        // Judged under the noise the recording allows, a clear effect can still go unnamed
        // where a random walk or flicker would explain it as well.
        assert!(t.recalled >= 1, "{}: named {} of 4", r.label, t.recalled);
        first += t.named_first;
        recalled += t.recalled;
    }
    assert!(
        recalled as f64 >= 0.8 * (4 * Kind::CATALOGUE.len()) as f64,
        "named {recalled}"
    );
    assert!(
        first as f64 >= 0.7 * (4 * Kind::CATALOGUE.len()) as f64,
        "named first {first}"
    );
    let clean = &white.rows[0].tally;
    println!("false alarms {} of {}", clean.false_alarms, clean.clean);
    assert_eq!(clean.clean, 60);
    // alpha = 0.05: more than 7 of 60 would have probability below 1.5%.
    assert!(clean.false_alarms <= 7, "{}", clean.false_alarms);
    // Modelling the clear effects brings the azimuth back: a jump and an encoder error bias it.
    // (A drift does not: the baseline is fitted under the recording's noise, whose random walk
    // already takes the drift out of the first harmonic.)
    for r in &clear {
        if [Kind::BiasJump, Kind::EncoderError]
            .iter()
            .any(|e| r.label.starts_with(e.name()))
        {
            let (before, after) = (r.tally.rms_baseline().unwrap(), r.tally.rms_final().unwrap());
            assert!(after < 0.5 * before, "{}: {before} -> {after}", r.label);
        }
    }
}

/// The recording, and the twin time at which the recording's `t_s = 0` lies (levelling comes first).
fn recording_t0(twin: &TwinConfig) -> (Recording, f64) {
    let run = RunConfig {
        positions: 48,
        dwell_ms: 1000,
        settle_ms: 100,
        tilt_policy: TiltPolicy::Warn,
        ..RunConfig::default()
    };
    let mut rec = Recorder::default();
    let (_, world) = simulate(twin, &run, &mut rec);
    let r = Recording::parse(&rec.text()).unwrap();
    // The run ends half a dwell after the last dwell's middle.
    let t0 = world.t_s() - r.rows.last().unwrap().t_s - 0.5;
    (r, t0)
}

/// The first finding of the catalogue (noise terms come first in the list).
fn first_effect(d: &Diagnosis) -> &Finding {
    d.findings
        .iter()
        .find(|f| !f.effect.is_noise())
        .expect("an effect is named")
}

fn recording(twin: &TwinConfig) -> Recording {
    recording_t0(twin).0
}

fn quiet_twin(seed: u64) -> TwinConfig {
    let mut t = TwinConfig {
        seed,
        ..TwinConfig::default()
    };
    t.instrument.tilt_deg = 0.0;
    t.settle_dph = 0.0;
    t.noise.rrw_dph_rth = 0.0;
    t
}

#[test]
fn a_bias_jump_is_found_with_its_time_and_size() {
    let mut twin = quiet_twin(3);
    twin.bias_jump = Some(nf_twin::BiasJump {
        time_s: 30.0,
        size_dph: 0.08,
    });
    let (rec, t0) = recording_t0(&twin);
    let d = diagnose(&rec, &Options::default()).unwrap();
    let f = first_effect(&d);
    assert_eq!(f.effect, Kind::BiasJump);
    let size = f.parameters.iter().find(|p| p.name == "size_dph").unwrap();
    assert!((size.value - 0.08).abs() < 3.0 * size.sigma.unwrap(), "{size:?}");
    let time = f.parameters.iter().find(|p| p.name == "time_s").unwrap().value;
    // Positions are 1.4 s apart: the step is placed between two of them.
    assert!((time - (30.0 - t0)).abs() < 1.0, "{time} vs {}", 30.0 - t0);
    assert!(f.after.rss < d.baseline.rss);
    let err = |a: f64| nf_model::angle::wrap_180(a - twin.instrument.psi_deg).abs() * 3600.0;
    assert!(err(d.final_.azimuth_deg) < err(d.baseline.azimuth_deg));
    // The plot's fitted step lies on Eq. 7's residuals (their share of C, A and B taken out):
    // the residuals, which hold the true step, regress on it with the slope true / fitted.
    let dot = |a: &dyn Fn(&nf::diagnose::Point) -> f64| d.points.iter().map(|p| a(p) * p.fitted).sum::<f64>();
    let slope = dot(&|p| p.before) / dot(&|p| p.fitted);
    assert!((slope - 0.08 / size.value).abs() < 0.2, "{slope} {size:?}");
    // Drawn by least squares, before and after are centred and the step is what they differ by.
    let mean = |a: &dyn Fn(&nf::diagnose::Point) -> f64| d.points.iter().map(a).sum::<f64>() / d.points.len() as f64;
    assert!(mean(&|p| p.before).abs() < 1e-9 && mean(&|p| p.after).abs() < 1e-9);
    assert!(mean(&|p| p.after.powi(2)) < 0.5 * mean(&|p| p.before.powi(2)));
}

#[test]
fn a_jump_inside_a_dwell_is_sized_and_placed_inside_it() {
    // A step three quarters of the way through dwell 20 of 48 (1 s dwells): that dwell holds a
    // quarter of it. Placed at a boundary, the step was sized short under the whitening the
    // jump's own noise estimate gives (0.83 of the truth on the audit's runs).
    let (plain, t0) = recording_t0(&quiet_twin(1));
    let at = t0 + plain.rows[20].t_s + 0.25;
    let (mut sizes, mut inside) = (Vec::new(), 0);
    for seed in 1..=10 {
        let mut twin = quiet_twin(seed);
        twin.bias_jump = Some(nf_twin::BiasJump {
            time_s: at,
            size_dph: 0.05,
        });
        let d = diagnose(&recording(&twin), &Options::default()).unwrap();
        let Some(f) = d.findings.iter().find(|f| f.effect == Kind::BiasJump) else {
            continue;
        };
        let value = |name: &str| f.parameters.iter().find(|p| p.name == name).unwrap().value;
        sizes.push(value("size_dph"));
        inside += usize::from((value("time_s") - (at - t0)).abs() < 0.3);
    }
    let mean = sizes.iter().sum::<f64>() / sizes.len() as f64;
    println!(
        "{} named, mean size {mean:.4} (truth 0.05), {inside} placed in the dwell",
        sizes.len()
    );
    assert!(sizes.len() >= 8, "{sizes:?}");
    assert!((mean / 0.05 - 1.0).abs() < 0.1, "{sizes:?}");
    assert!(inside * 2 >= sizes.len(), "{inside} of {}", sizes.len());
}

#[test]
fn beside_a_jump_named_no_walk_or_tail_is_named_for_it() {
    // Estimated before any effect is known, the noise takes a jump for a walk (and its
    // whitening makes the step one large innovation, a tail); estimated again with the jump in
    // the design, it is white, as the twin's is.
    let (mut jumps, mut with_noise) = (0, 0);
    for seed in 0..10 {
        let mut twin = quiet_twin(40 + seed);
        twin.bias_jump = Some(nf_twin::BiasJump {
            time_s: 40.0,
            size_dph: 0.05,
        });
        let d = diagnose(&recording(&twin), &Options::default()).unwrap();
        if d.findings.iter().any(|f| f.effect == Kind::BiasJump) {
            jumps += 1;
            let noise: Vec<&str> = d
                .findings
                .iter()
                .filter(|f| f.effect.is_noise())
                .map(|f| f.effect.name())
                .collect();
            if !noise.is_empty() {
                println!("seed {seed}: {noise:?}, with the jump {:?}", d.noise_with_effects);
                with_noise += 1;
            }
        }
    }
    println!("{with_noise} of {jumps} jumps named with a noise term beside");
    assert!(jumps >= 8, "{jumps} jumps named");
    assert!(with_noise <= 1, "{with_noise} of {jumps}");
}

#[test]
fn of_rival_explanations_the_one_the_averaging_weighs_most_is_named() {
    // An encoder error and a jump together: at the first step both are significant, and the
    // one named must be the one whose model the averaging weighs most, where it weighs.
    let mut contested = 0;
    for seed in 1..=40 {
        let mut twin = quiet_twin(seed);
        twin.encoder_error[0] = nf_twin::EncoderHarmonic {
            harmonic: 2,
            amplitude_arcsec: 500.0,
            phase_deg: 10.0 * seed as f64,
        };
        twin.bias_jump = Some(nf_twin::BiasJump {
            time_s: 40.0,
            size_dph: 0.05,
        });
        let d = diagnose(&recording(&twin), &Options::default()).unwrap();
        let Some(first) = d.findings.iter().find(|f| !f.effect.is_noise()) else {
            continue;
        };
        // The models in the order met: Eq. 7, the first step's alternatives, its choice, ...
        // The tilt is corrected before the tests: it adds no model of its own; nor does
        // `unexplained`, said where neither is named (in 1 of the 40 the jump's step the draws
        // of the null read as the wander its unmodelled encoder error gives it).
        if matches!(first.effect, Kind::ShaftTilt | Kind::Unexplained) {
            continue;
        }
        let chosen = d.models.iter().position(|m| m.label == first.effect.name()).unwrap();
        for m in &d.models[1..chosen] {
            contested += 1;
            let named = d.models[chosen].weight;
            // The naming ranks by BIC under the tests' noise, the result by the evidence under
            // each model's own: where both weigh nothing in the result (a later step's model
            // carries it) the two may differ without consequence.
            assert!(
                named >= m.weight || named.max(m.weight) < 1e-3,
                "seed {seed}: {} {named} against {} {}",
                first.effect.name(),
                m.label,
                m.weight
            );
        }
    }
    assert!(contested >= 4, "{contested} contested steps");
}

#[test]
fn a_second_harmonic_encoder_error_shows_in_the_third_harmonic_and_is_removed() {
    let mut twin = quiet_twin(4);
    // 600": the third harmonic it makes is about ten times its standard error here.
    twin.encoder_error[0] = nf_twin::EncoderHarmonic {
        harmonic: 2,
        amplitude_arcsec: 600.0,
        phase_deg: 30.0,
    };
    let d = diagnose(&recording(&twin), &Options::default()).unwrap();
    let f = first_effect(&d);
    assert_eq!(f.effect, Kind::EncoderError);
    assert_eq!(f.parameters[0].value, 2.0);
    let amp = &f.parameters[1];
    assert!((amp.value - 600.0).abs() < 3.0 * amp.sigma.unwrap(), "{amp:?}");
    // The phase of the reading's error, as the twin (and the instrument file) adds it.
    let phase = f.parameters[2].value;
    assert!(nf_model::angle::wrap_180(phase - 30.0).abs() < 10.0, "phase {phase}");
    let err = |a: f64| nf_model::angle::wrap_180(a - twin.instrument.psi_deg).abs() * 3600.0;
    assert!(
        err(d.final_.azimuth_deg) < 3.0 * d.final_.sigma_arcsec,
        "{}",
        err(d.final_.azimuth_deg)
    );
}

#[test]
fn too_few_positions_are_refused() {
    let text = "# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n1,2,90,0\n2,3,180,-1\n";
    let rec = Recording::parse(text).unwrap();
    assert!(diagnose(&rec, &Options::default()).unwrap_err().contains("at least 8"));
}

#[test]
fn structure_the_catalogue_lacks_is_unexplained() {
    // A square wave in time, three dwells up and three down (a disturbance no effect of the
    // catalogue has), about three times a dwell mean's noise.
    let named = (0..5)
        .filter(|&seed| {
            let mut rec = recording(&quiet_twin(40 + seed));
            for (i, row) in rec.rows.iter_mut().enumerate() {
                let d = if (i / 3) % 2 == 0 { 0.02 } else { -0.02 };
                row.rate_dph += d;
                if let Some(q) = row.quarters_dph.as_mut() {
                    q.iter_mut().for_each(|v| *v += d);
                }
            }
            let d = diagnose(&rec, &Options::default()).unwrap();
            let hit = d.findings.iter().find(|f| f.effect == Kind::Unexplained);
            println!("seed {seed}: {:?}", hit.map(|f| &f.location));
            hit.is_some()
        })
        .count();
    assert!(named >= 4, "unexplained in {named} of 5");
}

#[test]
fn dwells_that_scatter_beyond_their_quarters_are_not_unexplained() {
    // Whole dwells shifted (shocks between stops: the quarters do not show it), heavy-tailed,
    // about twice a dwell mean's noise: the estimate takes the excess for flicker, and its
    // whitening anti-correlates neighbouring residuals; white noise explains them.
    let mut rng = nf_twin::Rng::new(9);
    let unexplained = (0..20)
        .filter(|&seed| {
            let mut rec = recording(&quiet_twin(60 + seed));
            for row in rec.rows.iter_mut() {
                let chi2: f64 = (0..3).map(|_| rng.gauss().powi(2)).sum();
                row.rate_dph += 0.01 * rng.gauss() / (chi2 / 3.0).sqrt();
            }
            let d = diagnose(&rec, &Options::default()).unwrap();
            d.findings.iter().any(|f| f.effect == Kind::Unexplained)
        })
        .count();
    println!("unexplained in {unexplained} of 20");
    assert!(unexplained <= 2, "unexplained in {unexplained} of 20");
}

/// A quiet twin whose temperature swings 2 C over `cycles` periods of a 67 s run, moving the
/// bias by `level` white sds of a 1 s dwell mean at its peak.
fn temperature_cycle(seed: u64, cycles: f64, level: f64) -> TwinConfig {
    let mut twin = quiet_twin(seed);
    let s = twin.noise.white_mean_sd_dph(1.0);
    twin.temp_swing = nf_twin::TempSwing {
        amplitude_c: 2.0,
        period_s: 67.0 / cycles,
        phase_deg: 0.0,
    };
    twin.bias_temp_dph_per_c = level * s / 2.0;
    twin
}

#[test]
fn a_temperature_cycle_is_named_as_a_thermal_drift_rather_than_a_drift() {
    // In a sweep 1.5 to 3 temperature cycles per run (48 positions 1.4 s apart) are a slow
    // wander of the bias with time; judged under the same noise model as its rivals, drift
    // and jump, the recorded temperature explains it best.
    let (mut first, runs) = (0, 12);
    for seed in 0..runs {
        let twin = temperature_cycle(100 + seed, 1.5 + 0.125 * seed as f64, 2.5);
        let d = diagnose(&recording(&twin), &Options::default()).unwrap();
        let named = d.findings.iter().find(|f| !f.effect.is_noise()).map(|f| f.effect);
        first += usize::from(named == Some(Kind::ThermalDrift));
        let err = nf_model::angle::wrap_180(d.final_.azimuth_deg - twin.instrument.psi_deg).abs() * 3600.0;
        assert!(
            err < 3.0 * d.final_.sigma_arcsec,
            "seed {seed}: {err} vs {}",
            d.final_.sigma_arcsec
        );
    }
    assert!(first >= 10, "thermal drift named first in {first} of {runs}");
}

#[test]
fn a_few_missing_temperatures_are_bridged_and_the_thermal_drift_still_named() {
    // Three blank temp_c cells switched the thermal test off (an outside audit: a clear
    // thermal drift then named as an encoder error and a walk in 13 and 12 of 15).
    let (mut first, runs) = (0, 8);
    for seed in 0..runs {
        let mut rec = recording(&temperature_cycle(300 + seed, 1.5 + 0.2 * seed as f64, 8.0));
        for i in [5, 20, 40] {
            rec.rows[i].temp_c = None;
        }
        let d = diagnose(&rec, &Options::default()).unwrap();
        first += usize::from(first_effect(&d).effect == Kind::ThermalDrift);
        assert!(
            d.notes
                .iter()
                .any(|n| n.starts_with("temp_c: 3 of the 48 dwells have no reading: each bridged")),
            "{:?}",
            d.notes
        );
    }
    assert!(first >= 7, "thermal drift named first in {first} of {runs}");
}

#[test]
fn a_temperature_cycle_without_its_temperature_is_named_a_thermal_drift_s_cycle() {
    // No temp_c column: an encoder error, a curved drift and a scale factor together took a
    // heater's cycle in a sweep, the final 5-9 sigma off (two outside audits). Cycles a
    // run at least 0.3 from a whole number: nearer, the encoder harmonic of that number holds
    // 95 % of the cycle and takes it (docs/diagnose.md).
    let cycles_per_run = [2.3, 2.5, 2.7, 3.3, 3.5, 3.7, 4.3, 4.5];
    let (mut first, mut z2, runs) = (0, 0.0, cycles_per_run.len());
    for (seed, cycles) in (0..).zip(cycles_per_run) {
        let twin = temperature_cycle(400 + seed, cycles, 8.0);
        let mut rec = recording(&twin);
        for r in &mut rec.rows {
            r.temp_c = None;
        }
        let d = diagnose(&rec, &Options::default()).unwrap();
        let f = first_effect(&d);
        if f.effect == Kind::ThermalDrift {
            first += 1;
            let period = f.parameters.iter().find(|p| p.name == "cycle_period_s").unwrap().value;
            assert!(
                (period * cycles / 67.0 - 1.0).abs() < 0.1,
                "seed {seed}: period {period}"
            );
        }
        let err = nf_model::angle::wrap_180(d.final_.azimuth_deg - twin.instrument.psi_deg) * 3600.0;
        z2 += (err / d.final_.sigma_arcsec).powi(2);
    }
    let rms = (z2 / runs as f64).sqrt();
    println!("named first {first} of {runs}, RMS error/sigma {rms:.2}");
    assert!(first >= 7, "thermal drift named first in {first} of {runs}");
    assert!(rms < 1.5, "RMS error/sigma {rms}");
}

/// 48 dwells of 1 s at 24 angles, each angle dwelt at twice running (no move between), white
/// noise of 0.01 deg/h per quarter; the first quarter of the dwells `excess` picks is 0.03
/// deg/h high.
fn dwelt_twice(excess: impl Fn(usize) -> bool) -> Recording {
    let mut rng = nf_twin::Rng::new(5);
    let (lat, psi) = (40.0f64, 30.0f64);
    let amplitude = nf_model::EARTH_RATE_DPH * lat.to_radians().cos();
    let mut rec = nf_twin::QuarteredRecording::new(lat, 1.0, 1000.0);
    for i in 0..48 {
        let gamma = 15.0 * (i / 2) as f64;
        let signal = amplitude * (gamma + psi).to_radians().cos() + 0.5;
        let mut q: [f64; 4] = core::array::from_fn(|_| signal + 0.01 * rng.gauss());
        if excess(i) {
            q[0] += 0.03;
        }
        rec.position(1.35 * i as f64, gamma, q);
    }
    Recording::parse(rec.text()).unwrap()
}

#[test]
fn a_settling_transient_follows_a_move_only() {
    let named = |rec: &Recording| {
        let d = diagnose(rec, &Options::default()).unwrap();
        d.findings.iter().any(|f| f.effect == Kind::SettlingTransient)
    };
    // The same first-quarter excess, after each move or on each dwell after none.
    assert!(named(&dwelt_twice(|i| i % 2 == 0)));
    assert!(!named(&dwelt_twice(|i| i % 2 == 1)));
}

#[test]
fn a_wild_dwell_mean_is_an_outlier_and_moves_neither_the_tilt_nor_the_azimuth() {
    // A logger's fill value or a glitch of 10^6 deg/h on one dwell, with both tilt columns:
    // the exact tilt correction scales with the fitted amplitude, which the glitch must not
    // set (it did: 70.2 deg for 65.5).
    let mut twin = quiet_twin(21);
    twin.instrument.tilt_deg = 0.02;
    let (clean, wild) = {
        let r = recording(&twin);
        let mut w = r.clone();
        w.rows[5].rate_dph = 1e6;
        (r, w)
    };
    assert!(clean.has_tilt_xy());
    let base = diagnose(&clean, &Options::default()).unwrap();
    let d = diagnose(&wild, &Options::default()).unwrap();
    let out = d
        .findings
        .iter()
        .find(|f| f.effect == Kind::Outliers)
        .expect("the outlier is named");
    assert!(out.location.contains("position 5"), "{}", out.location);
    let off = nf_model::angle::wrap_180(d.final_.azimuth_deg - base.final_.azimuth_deg) * 3600.0;
    assert!(
        off.abs() < base.final_.sigma_arcsec,
        "{off}\" against {}\"",
        base.final_.sigma_arcsec
    );
}

#[test]
fn the_noise_estimate_takes_the_quarters_of_the_dwells_that_have_them() {
    // A writer that leaves some dwells' quarter cells empty: the rest still show the noise
    // inside a dwell (without them the sigma came out 50 % larger).
    let full = recording(&quiet_twin(8));
    let mut part = full.clone();
    for row in part.rows.iter_mut().step_by(4) {
        row.quarters_dph = None;
    }
    let (a, b) = (
        diagnose(&full, &Options::default()).unwrap(),
        diagnose(&part, &Options::default()).unwrap(),
    );
    assert!(
        b.noise_source.contains("quarter means of 36 dwells"),
        "{}",
        b.noise_source
    );
    let ratio = b.final_.sigma_arcsec / a.final_.sigma_arcsec;
    assert!((0.9..1.1).contains(&ratio), "{ratio}");
}

#[test]
fn a_run_over_four_angles_again_and_again_is_diagnosed() {
    // The classic four-position finder: harmonics 2-4 of four angles alias or vanish, and the
    // noise estimate keeps only the columns they leave.
    let mut rng = nf_model::rng::Rng::new(6);
    let mut text = "# format = northfinder-recording/1\n# latitude_deg = 43.8\n# dwell_s = 2\n\
                    index,t_s,encoder_deg,rate_dph\n"
        .to_string();
    let amp = 15.041 * 43.8f64.to_radians().cos();
    for i in 0..36 {
        let g = [0.0, 90.0, 180.0, 270.0][i % 4];
        let rate = amp * (g + 30.0f64).to_radians().cos() + 0.3 + 0.005 * rng.gauss();
        text += &format!("{i},{},{g},{rate}\n", 2.0 + 3.0 * i as f64);
    }
    let d = diagnose(&Recording::parse(&text).unwrap(), &Options::default()).unwrap();
    let err = (d.final_.azimuth_deg - 30.0) * 3600.0;
    assert!(
        err.abs() < 3.0 * d.final_.sigma_arcsec,
        "{err}\" off, sigma {}",
        d.final_.sigma_arcsec
    );
}

#[test]
fn a_curved_drift_named_as_a_line_leaves_its_curve_in_the_sigma() {
    // A curve of about 4 dwell-mean sigmas over a 48-position sweep: in a sweep it is mostly
    // the first harmonic of the angle. With the line alone the finals were beyond 3 of their
    // sigmas in 15 of 20 runs, 200" off at 40-100"; with the curve averaged in, in none.
    let mut beyond = 0;
    for seed in 0..20 {
        let mut twin = quiet_twin(40 + seed);
        twin.bias_drift2_dph_per_s2 = 3e-5;
        let rec = recording(&twin);
        let d = diagnose(&rec, &Options::default()).unwrap();
        let err = nf_model::angle::wrap_180(d.final_.azimuth_deg - twin.instrument.psi_deg) * 3600.0;
        println!("seed {seed}: {err:.1}\" +- {:.1}\"", d.final_.sigma_arcsec);
        beyond += usize::from(err.abs() > 3.0 * d.final_.sigma_arcsec);
    }
    assert!(beyond <= 2, "{beyond} of 20 beyond 3 sigma");
}

#[test]
fn with_nothing_named_the_baseline_has_the_final_sigma() {
    // Both come from the noise estimated with Eq. 7's columns, over the models the recording
    // allows, calibrated by replicates (before, the baseline's was the plain GLS sigma under
    // the tests' noise: up to 5 times smaller on Gauss-Markov recordings).
    let mut compared = 0;
    for seed in 1..=6 {
        let mut twin = quiet_twin(seed);
        twin.noise.bias_instability_dph = 0.004;
        let d = diagnose(&recording(&twin), &Options::default()).unwrap();
        if d.findings.iter().any(|f| !f.effect.is_noise()) {
            continue;
        }
        compared += 1;
        let ratio = d.baseline.sigma_arcsec / d.final_.sigma_arcsec;
        println!(
            "seed {seed}: baseline {:.1}\" final {:.1}\"",
            d.baseline.sigma_arcsec, d.final_.sigma_arcsec
        );
        assert!((ratio - 1.0).abs() < 0.1, "seed {seed}: ratio {ratio}");
    }
    assert!(compared >= 4, "{compared}");
}
