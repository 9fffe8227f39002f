use super::*;
use nf_model::rng::Rng;

fn parse_err(text: &str) -> Error {
    InstrumentFile::parse(text).expect_err(text)
}

const HEAD: &str = "format = \"northfinder-instrument/1\"\n";

#[test]
fn defaults_are_what_nf_simulate_uses_without_flags() {
    let f = InstrumentFile::parse(HEAD).unwrap();
    assert_eq!(f, InstrumentFile::default());
    let t = f.twin();
    assert_eq!(t.instrument.latitude_deg, 43.8);
    assert_eq!(t.noise, nf_model::noise::NoiseModel::white(0.005, 2.0));
    assert_eq!(f.run_config().positions, 72);
}

#[test]
fn every_section_reaches_the_twin() {
    let text = format!(
        "{HEAD}seed = 9
[site]
latitude_deg = -60
azimuth_deg = 200.5
[gyro]
bias_dph = -1.5
scale = 1.001
elevation_deg = 0.2
nonlinearity_per_dph = 1e-4
[noise]
arw_deg_rth = 0.001
bias_instability_dph = 0.002
[drift]
linear_dph_per_s = 2e-5
[jump]
time_s = 70
size_dph = 0.03
[temperature]
ramp_c_per_s = 0.01
bias_dph_per_c = 0.02
[settling]
size_dph = 0.1
tau_s = 0.4
[shaft]
tilt_deg = 1.5
[[encoder.error]]
harmonic = 2
amplitude_arcsec = 30
phase_deg = 45
[inclinometer]
offset_y_deg = 0.5
[[disturbance]]
from_s = 10
to_s = 12
size_dph = 0.5
[shocks]
per_hour = 120
size_dph = 0.2
duration_s = 0.5
[run]
positions = 36
order = \"forward-back\"
dwell_s = 4
"
    );
    let f = InstrumentFile::parse(&text).unwrap();
    let t = f.twin();
    assert_eq!(
        (t.seed, t.instrument.latitude_deg, t.instrument.psi_deg),
        (9, -60.0, 200.5)
    );
    assert_eq!(
        (t.instrument.bias_dph, t.instrument.scale, t.instrument.gyro_elev_deg),
        (-1.5, 1.001, 0.2)
    );
    assert_eq!(t.nonlinearity_per_dph, 1e-4);
    assert_eq!((t.noise.arw_deg_rth, t.noise.bias_instability_dph), (0.001, 0.002));
    assert_eq!(t.bias_drift_dph_per_s, 2e-5);
    assert_eq!(
        t.bias_jump,
        Some(nf_twin::BiasJump {
            time_s: 70.0,
            size_dph: 0.03
        })
    );
    assert_eq!((t.temp_ramp_c_per_s, t.bias_temp_dph_per_c), (0.01, 0.02));
    assert_eq!((t.settle_dph, t.settle_tau_s), (0.1, 0.4));
    assert_eq!(t.instrument.tilt_deg, 1.5);
    assert_eq!(
        t.encoder_error[0],
        nf_twin::EncoderHarmonic {
            harmonic: 2,
            amplitude_arcsec: 30.0,
            phase_deg: 45.0
        }
    );
    assert_eq!(t.encoder_error[1].amplitude_arcsec, 0.0);
    assert_eq!(t.incl_offset_deg, (0.01, 0.5));
    assert_eq!(
        t.disturbances,
        vec![nf_twin::Disturbance {
            from_s: 10.0,
            to_s: 12.0,
            size_dph: 0.5
        }]
    );
    assert_eq!(
        t.shocks,
        nf_twin::Shocks {
            per_hour: 120.0,
            size_dph: 0.2,
            duration_s: 0.5
        }
    );
    let r = f.run_config();
    assert_eq!((r.positions, r.order, r.dwell_ms), (36, Order::ForwardBack, 4000));
}

/// A file with every value drawn at random within its range.
fn random_file(rng: &mut Rng) -> InstrumentFile {
    let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng.unit();
    let mut f = InstrumentFile::default();
    f.site.latitude_deg = u(-89.0, 89.0);
    f.site.azimuth_deg = u(0.0, 360.0);
    f.gyro.bias_dph = u(-2.0, 2.0);
    f.gyro.scale = u(0.9, 1.1);
    f.gyro.nonlinearity_per_dph = u(-1e-3, 1e-3);
    f.noise.bias_instability_dph = u(0.0, 0.01);
    f.noise.gm_sigma_dph = u(0.0, 0.01);
    f.noise.gm_tau_s = u(1.0, 100.0);
    f.drift.linear_dph_per_s = u(-1e-4, 1e-4);
    f.jump = Some(Jump {
        time_s: u(0.0, 100.0),
        size_dph: u(-0.1, 0.1),
    });
    f.shaft.tilt_deg = u(0.0, 10.0);
    f.encoder.error = vec![EncoderError {
        harmonic: 3,
        amplitude_arcsec: u(0.0, 100.0),
        phase_deg: u(-180.0, 180.0),
    }];
    f.disturbance = vec![Disturbance {
        from_s: 1.0,
        to_s: u(2.0, 3.0),
        size_dph: u(-1.0, 1.0),
    }];
    f.shocks = Some(Shocks {
        per_hour: u(0.0, 1000.0),
        size_dph: u(0.0, 1.0),
        duration_s: u(0.01, 10.0),
    });
    f.run.target_arcsec = Some(u(1.0, 100.0));
    f
}

#[test]
fn write_then_read_gives_the_same_file_over_many_seeds() {
    let mut rng = Rng::new(4);
    for _ in 0..200 {
        let f = random_file(&mut rng);
        let text = f.write(&["a comment".into()]);
        assert_eq!(InstrumentFile::parse(&text).unwrap(), f, "{text}");
    }
}

#[test]
fn integers_are_accepted_where_reals_are_expected() {
    let f = InstrumentFile::parse(&format!("{HEAD}[site]\nlatitude_deg = 45\n")).unwrap();
    assert_eq!(f.site.latitude_deg, 45.0);
}

#[test]
fn bad_values_are_named_with_their_line() {
    let cases: [(&str, usize, &str); 14] = [
        ("[site]\nlatitude_deg = 95\n", 3, "outside [-89, 89]"),
        ("[site]\nlatitude_deg = nan\n", 3, "outside"),
        ("[gyro]\nbias_dph = \"1\"\n", 3, "invalid type"),
        ("[gyro]\nbais_dph = 1\n", 3, "unknown field `bais_dph`"),
        ("[shaft]\ntilt_deg = -1\n", 3, "outside [0, 10]"),
        ("[run]\npositions = 3\n", 3, "outside [4, 720]"),
        ("[run]\norder = \"spiral\"\n", 3, "spiral"),
        ("[run]\norder = \"opposite-pairs\"\npositions = 7\n", 3, "order"),
        (
            "[run]\npositions = 8\norder = \"0,4,0,4\"\n",
            4,
            "fewer than 3 different positions listed",
        ),
        (
            "[[disturbance]]\nfrom_s = 5\nto_s = 4\nsize_dph = 1\n",
            4,
            "ends before it begins",
        ),
        ("[site\n", 2, ""),
        (
            "[shocks]\nper_hour = -1\nsize_dph = 1\nduration_s = 1\n",
            3,
            "outside [0, 1000000] per hour",
        ),
        (
            "[shocks]\nper_hour = 10\nsize_dph = 1\n",
            2,
            "missing field `duration_s`",
        ),
        (
            "[shocks]\nper_hour = 1e6\nsize_dph = 1\nduration_s = 1\n",
            3,
            "278 under way at once",
        ),
    ];
    for (body, line, says) in cases {
        let e = parse_err(&format!("{HEAD}{body}"));
        assert_eq!(e.line, line, "{body}: {e}");
        assert!(e.what.contains(says), "{body}: {e}");
    }
}

#[test]
fn three_encoder_terms_and_a_wrong_format_are_refused() {
    let three = "[[encoder.error]]\nharmonic = 1\namplitude_arcsec = 1\n".repeat(3);
    assert!(parse_err(&format!("{HEAD}{three}")).what.contains("the twin has 2"));
    let e = parse_err("format = \"northfinder-recording/1\"\n");
    assert_eq!(e.line, 1);
    assert!(parse_err("seed = 2\n").what.contains("format is missing"));
    // After a table, `format` is that table's key.
    let late = parse_err("[site]\nlatitude_deg = 45\nformat = \"northfinder-instrument/1\"\n");
    assert_eq!(late.line, 3);
    assert!(late.what.contains("go before the first [table]"), "{late}");
}

#[test]
fn a_noise_model_the_twin_cannot_run_is_refused() {
    let e = parse_err(&format!("{HEAD}[noise]\ngm_sigma_dph = 0.01\n"));
    assert!(e.what.contains("[noise]"), "{e}");
    assert_eq!(e.line, 3);
    // The line of the term at fault, not the last of the terms that can be (an audit found
    // a Gauss-Markov sigma without its time reported at `student_t_dof`).
    let e = parse_err(&format!("{HEAD}[noise]\ngm_sigma_dph = 0.01\nstudent_t_dof = 4.0\n"));
    assert_eq!(e.line, 3, "{e}");
    let e = parse_err(&format!("{HEAD}[noise]\nstudent_t_dof = 1.5\ngm_tau_s = 3.0\n"));
    assert_eq!(e.line, 3, "{e}");
}
