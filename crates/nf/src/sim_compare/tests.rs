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
