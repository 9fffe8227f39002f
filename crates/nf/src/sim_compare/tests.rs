use super::*;
use crate::instrument_file::InstrumentFile;

fn simulated(file: &InstrumentFile) -> Recording {
    let mut rec = nf_twin::Recorder::default();
    nf_twin::simulate(&file.twin(), &file.run_config(), &mut rec);
    Recording::parse(&rec.text()).unwrap()
}

#[test]
fn a_replay_keeps_the_plan_and_the_columns() {
    let file = InstrumentFile::default();
    let rec = simulated(&file);
    let r = replay(&file, &rec, 7, run_origin_s(&file));
    assert_eq!(r.rows.len(), rec.rows.len());
    for (a, b) in rec.rows.iter().zip(&r.rows) {
        assert_eq!((a.index, a.t_s), (b.index, b.t_s));
        assert!(
            (a.encoder_deg - b.encoder_deg).abs() < 1e-4,
            "{} {}",
            a.encoder_deg,
            b.encoder_deg
        );
        assert_eq!(a.tilt_y_deg.is_some(), b.tilt_y_deg.is_some());
        assert_eq!(a.quarters_dph.is_some(), b.quarters_dph.is_some());
        assert!((a.rate_dph - b.rate_dph).abs() < 0.05, "{} {}", a.rate_dph, b.rate_dph);
    }
}

#[test]
fn a_replay_takes_each_row_s_dwell_from_its_samples() {
    let file = InstrumentFile::default();
    let mut rec = simulated(&file);
    for r in rec.rows.iter_mut().step_by(2) {
        r.samples = r.samples.map(|s| s / 16);
    }
    let r = replay(&file, &rec, 7, run_origin_s(&file));
    for (a, b) in rec.rows.iter().zip(&r.rows) {
        assert_eq!(a.samples, b.samples, "line {}", a.line);
    }
    let against = warnings(&rec, &file);
    assert!(
        against.iter().any(|w| w.contains("dwells are 0.125-2.000 s")),
        "{against:?}"
    );
}

#[test]
fn the_plan_is_read_back_from_the_recording() {
    let mut file = InstrumentFile::default();
    assert_eq!(plan::infer(&simulated(&file)), Some((72, "sequential".to_string())));
    file.run.positions = 24;
    file.run.order = "forward-back".into();
    file.run.dwell_s = 0.5;
    let rec = simulated(&file);
    assert_eq!(plan::infer(&rec), Some((24, "forward-back".to_string())));
    assert!((crate::dwells::of(&rec).nominal_s - 0.5).abs() < 1e-9);
    file.run.positions = 8;
    file.run.order = "3,0,7,1,2,6,5,4".into();
    assert_eq!(plan::infer(&simulated(&file)), Some((8, "3,0,7,1,2,6,5,4".to_string())));
    let mut off = simulated(&file);
    off.rows[2].encoder_deg += 7.0;
    assert_eq!(plan::infer(&off), None);
}

#[test]
fn a_burst_within_one_dwell_is_not_the_quarters_white_level() {
    let quarter_sd = |rec: &Recording| {
        let p = profile(rec).unwrap();
        p.iter().find(|q| q.0 == Quantity::QuarterSd).unwrap().1
    };
    let mut rec = simulated(&InstrumentFile::default());
    let clean = quarter_sd(&rec);
    // A burst over three quarters of one dwell, 8 quarter sigmas: that dwell's quarters
    // scatter 4 times as far, and the pooled scatter of the 72 dwells would grow by 10 %.
    let q = rec.rows[30].quarters_dph.as_mut().unwrap();
    for v in &mut q[..3] {
        *v += 8.0 * clean;
    }
    let burst = quarter_sd(&rec);
    assert!((burst / clean - 1.0).abs() < 0.01, "{clean} -> {burst}");
    // A white level 10 % higher moves it as much.
    for r in &mut rec.rows {
        let q = r.quarters_dph.as_mut().unwrap();
        let m = q.iter().sum::<f64>() / 4.0;
        q.iter_mut().for_each(|v| *v = m + 1.1 * (*v - m));
    }
    assert!(
        (quarter_sd(&rec) / clean - 1.1).abs() < 0.01,
        "{}",
        quarter_sd(&rec) / clean
    );
}

#[test]
fn each_recording_gets_replays_of_its_own() {
    let file = InstrumentFile::default();
    let rec = simulated(&file);
    let mut other = file.clone();
    other.seed += 1;
    let rec2 = simulated(&other);
    assert_eq!(seed(&file, &rec, 3), seed(&file, &rec, 3));
    assert_ne!(seed(&file, &rec, 3), seed(&file, &rec2, 3));
    assert_ne!(seed(&file, &rec, 3), seed(&file, &rec, 4));
    // Away from the file's own noise, which simulated the recording.
    assert_ne!(seed(&file, &rec, 0), file.seed);
}

#[test]
fn a_scatter_is_judged_on_the_log_scale() {
    // Replays whose residual scatter spreads by a factor (one met a long burst): a recording
    // a quarter of their typical scatter stands out on the log scale, not on the linear one.
    let sims: Vec<profile::Profile> = [0.015, 0.017, 0.02, 0.019, 0.016, 0.035]
        .iter()
        .map(|&sd| vec![(Quantity::ResidualSd, sd), (Quantity::Bias, sd)])
        .collect();
    let rec = vec![(Quantity::ResidualSd, 0.0046), (Quantity::Bias, 0.0046)];
    let c = compare::compare(&rec, &sims, 0.05);
    let (scatter, bias) = (c.line(Quantity::ResidualSd).unwrap(), c.line(Quantity::Bias).unwrap());
    assert!(scatter.mismatch && scatter.z < -4.0, "{scatter:?}");
    assert!(!bias.mismatch, "{bias:?}");
    assert!(
        (scatter.simulated - 0.0203).abs() < 1e-4,
        "reported in deg/h: {scatter:?}"
    );
}
