//! The firmware's recording writer against the host's reader: records as the run makes them
//! (and tilt and temperature readings of any size, since those come from devices) are written
//! with the run's metadata and header, and read back. Every value comes back to within half a
//! unit of its last written digit, or as missing (`nan`) when it has no fixed-point text or
//! is a tilt beyond 90 deg, or quarters of fewer than 4 samples or equal in every dwell; never
//! as another number. No line is cut short.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf_fuzz::close;
use nf_instrument::encoder_angle::EncoderAngle;
use nf_instrument::record::{self, HEADER, MAX_LINE, Record};
use nf_model::dwell::Calibration;
use nf_model::text;
use std::fmt::Write;

/// A reading from a device: usually in range, sometimes anything an f32 holds.
fn reading(u: &mut Unstructured, range: f32) -> Result<f32> {
    Ok(match u.int_in_range(0..=3u8)? {
        0 => f32::NAN,
        1 => u.arbitrary()?,
        _ => (u.int_in_range(-1_000_000i32..=1_000_000)? as f32 / 1e6) * range,
    })
}

/// A record at `t_us` and the exact angle (deg) of the counts it came from.
fn record(u: &mut Unstructured, index: u16, t_us: u64) -> Result<(Record, f64)> {
    let cal = Calibration::DEFAULT;
    // The run's angle: the commanded count plus the mean encoder error, over 2^bits a turn.
    let bits: u32 = u.int_in_range(8..=32)?;
    let per_turn = 1u64 << bits;
    let target = u.int_in_range(0..=per_turn - 1)? as i64;
    let enc_n: i64 = u.int_in_range(1..=20)?;
    let enc_sum: i64 = u.int_in_range(-3 * enc_n..=3 * enc_n)?;
    let num = target * enc_n + enc_sum;
    let angle = num as f64 / enc_n as f64 / per_turn as f64 * 360.0;
    // The dwell's samples in four consecutive quarters, as the run sums them: the rate and
    // the quarters come from the same sums (the reader drops quarters that do not average to
    // the rate; with 40 samples or more unequal quarters stay within what it allows).
    let n: u32 = u.int_in_range(40..=4000)?;
    let counts = [0, 1, 2, 3].map(|k| n * (k + 1) / 4 - n * k / 4);
    let mut sums = [0i64; 4];
    for (s, c) in sums.iter_mut().zip(counts) {
        *s = u.int_in_range(-(1i64 << 23) * c as i64..=((1i64 << 23) - 1) * c as i64)?;
    }
    let mut quarters = [0f32; 4];
    for k in 0..4 {
        quarters[k] = if u.ratio(1, 8)? {
            f32::NAN
        } else {
            cal.rate_dph(sums[k], counts[k])
        };
    }
    let r = Record {
        index,
        t_us,
        encoder: EncoderAngle::from_counts(num, enc_n as u32, per_turn).expect("in range"),
        rate_dph: cal.rate_dph(sums.iter().sum(), n),
        rate_sd_dph: if u.ratio(1, 8)? {
            f32::NAN
        } else {
            cal.sd_dph(u.int_in_range(0..=1u32 << 24)? as f32 / 16.0)
        },
        samples: u.arbitrary()?,
        temp_c: reading(u, 150.0)?,
        tilt_x_deg: reading(u, 10.0)?,
        tilt_y_deg: reading(u, 10.0)?,
        quarters_dph: quarters,
        missed: u.arbitrary()?,
    };
    Ok((r, angle))
}

/// What a value written with `decimals` digits reads back as: itself to within the last
/// digit, or missing; `required` columns must come back.
fn same(got: Option<f64>, want: f64, decimals: u32, what: &str, line: &str) {
    same_below(got, want, decimals, f64::INFINITY, what, line);
}

/// The same for a value the reader takes only below `limit` in size (an elevation).
fn same_below(got: Option<f64>, want: f64, decimals: u32, limit: f64, what: &str, line: &str) {
    match got {
        Some(g) => assert!(
            want.is_finite() && want.abs() < limit && close(g, want, decimals),
            "{what}: wrote {want:e}, read {g:e}\n{line}"
        ),
        None => assert!(
            !want.is_finite()
                || want.abs() >= limit
                || (want.abs() * 10f64.powi(decimals as i32)).round() >= 2f64.powi(64),
            "{what}: wrote {want:e}, read nothing\n{line}"
        ),
    }
}

fn run(u: &mut Unstructured) -> Result<()> {
    let lat = u.int_in_range(-8_900_000i32..=8_900_000)? as f32 / 1e5;
    let mut text = String::new();
    for l in [
        record::meta("format", |l| l.write_str("northfinder-recording/1")),
        record::meta("latitude_deg", |l| text::write_f32(l, lat, 5)),
        record::meta("dwell_s", |l| text::write_units(l, 2000, 3)),
        record::meta("sample_rate_hz", |l| text::write_u64(l, 1000)),
        record::meta("positions", |l| text::write_u64(l, 72)),
        record::meta("order", |l| l.write_str("sequential")),
    ] {
        text += &l;
        text.push('\n');
    }
    text += HEADER;
    text.push('\n');
    let n = u.int_in_range(1..=8u16)?;
    let mut recs = Vec::new();
    // Visits in time order, a millisecond apart at least as t_s has it, within the 142 years
    // (2^52 us) where an f64 of seconds still tells milliseconds apart.
    let mut t_us: u64 = u.int_in_range(0..=1u64 << 52)?;
    for i in 0..n {
        t_us += 1000 + u.int_in_range(0..=1u64 << 40)?;
        let (r, angle) = record(u, i, t_us)?;
        let line = r.line();
        let mut full = String::new();
        r.write(&mut full).unwrap();
        assert_eq!(line.as_str(), full, "the line is cut at {MAX_LINE} bytes");
        text += &line;
        text.push('\n');
        recs.push((r, angle));
    }
    // Quarters of fewer than 4 samples are not quarter means: the reader drops them. Then
    // quarters equal to one another in every dwell that has them (two or more) are not a
    // gyro's: it drops them all. Judged on the text as written.
    let few = |r: &Record| r.samples < 4;
    let q1 = HEADER.split(',').position(|c| c == "q1_dph").expect("quarter columns");
    let written: Vec<[f64; 4]> = recs
        .iter()
        .filter(|(r, _)| !few(r))
        .filter_map(|(r, _)| {
            let line = r.line();
            let cells: Vec<&str> = line.as_str().split(',').collect();
            let q = [0, 1, 2, 3].map(|k| cells[q1 + k].trim().parse::<f64>().unwrap_or(f64::NAN));
            q.iter().all(|v| v.is_finite()).then_some(q)
        })
        .collect();
    let steady = written.len() >= 2 && written.iter().all(|q| q.iter().all(|&v| v == q[0]));
    let rec = nf::recording::Recording::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert!(close(rec.latitude_deg, lat as f64, 5));
    assert_eq!(rec.rows.len(), recs.len());
    for (row, (r, angle)) in rec.rows.iter().zip(&recs) {
        let line = r.line();
        let line = line.as_str();
        assert_eq!(row.index, r.index as u32);
        same(Some(row.t_s), r.t_us as f64 * 1e-6, 3, "t_s", line);
        // An angle comes back as the same direction: 359.99999996 is written as 0.
        let d = (row.encoder_deg - angle).rem_euclid(360.0);
        let d = if d > 180.0 { d - 360.0 } else { d };
        same(Some(angle + d), *angle, 7, "encoder_deg", line);
        same(Some(row.rate_dph), r.rate_dph as f64, 6, "rate_dph", line);
        same(row.rate_sd_dph, r.rate_sd_dph as f64, 6, "rate_sd_dph", line);
        assert_eq!(row.samples, Some(r.samples));
        same(row.temp_c, r.temp_c as f64, 3, "temp_c", line);
        same_below(row.tilt_x_deg, r.tilt_x_deg as f64, 5, 90.0, "tilt_x_deg", line);
        same_below(row.tilt_y_deg, r.tilt_y_deg as f64, 5, 90.0, "tilt_y_deg", line);
        match row.quarters_dph {
            Some(q) => {
                assert!(!steady && !few(r), "{line}");
                for (got, want) in q.iter().zip(r.quarters_dph) {
                    same(Some(*got), want as f64, 6, "quarter", line);
                }
            }
            None => assert!(steady || few(r) || r.quarters_dph.iter().any(|q| q.is_nan()), "{line}"),
        }
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
