//! The firmware's recording writer (`nf_instrument::record`, fixed-point text from integers
//! and `f32`) against the host's reader, over many seeds: every value reads back within half
//! a unit of its last written digit of its exact value, angles in `[0, 360)` and in the
//! direction of the counts they came from, and a value with no fixed-point text (NaN,
//! infinite, too large) reads as missing, never as another number.

use core::fmt::Write;
use nf::recording::Recording;
use nf_instrument::encoder_angle::EncoderAngle;
use nf_instrument::record::{HEADER, Record, meta};
use nf_model::rng::Rng;
use nf_model::text;

fn within_half_unit(got: f64, want: f64, decimals: u32) -> bool {
    let half = 0.5 * 10f64.powi(-(decimals as i32));
    (got - want).abs() <= half * (1.0 + 1e-9) + want.abs() * 4.0 * f64::EPSILON
}

/// An `f32` as a device or a computation could give it: usually in range, at times NaN,
/// infinite, huge or tiny.
fn value(rng: &mut Rng, range: f64) -> f32 {
    match rng.next_u64() % 10 {
        0 => f32::NAN,
        1 => f32::INFINITY * if rng.unit() < 0.5 { -1.0 } else { 1.0 },
        2 => f32::from_bits(rng.next_u64() as u32),
        3 => rng.uniform(-1e-6, 1e-6) as f32,
        _ => rng.uniform(-range, range) as f32,
    }
}

/// What the reader must give for an optional `f32` written with `decimals`.
fn check_optional(got: Option<f64>, want: f32, decimals: u32, what: &str, line: &str) {
    check_in(got, want, decimals, f64::INFINITY, what, line);
}

/// The same for a value the reader takes only below `limit` in size (an elevation).
fn check_in(got: Option<f64>, want: f32, decimals: u32, limit: f64, what: &str, line: &str) {
    let scaled = (want.abs() as f64) * 10f64.powi(decimals as i32);
    // Within rounding of 2^64 the f64 product cannot tell: either outcome is right there.
    if (1.84e19..1.85e19).contains(&scaled) {
        return;
    }
    let fits = want.is_finite() && scaled < 1.84e19 && (want.abs() as f64) < limit;
    match got {
        Some(g) => assert!(
            fits && within_half_unit(g, want as f64, decimals),
            "{what}: wrote {want:e}, read {g:e}\n{line}"
        ),
        None => assert!(!fits, "{what}: wrote {want:e}, read nothing\n{line}"),
    }
}

#[test]
fn what_the_firmware_writes_the_host_reads_back() {
    for seed in 0..200 {
        let mut rng = Rng::new(seed);
        let lat = rng.uniform(-89.0, 89.0) as f32;
        let mut text = String::new();
        for l in [
            meta("format", |l| l.write_str("northfinder-recording/1")),
            meta("latitude_deg", |l| text::write_f32(l, lat, 5)),
            meta("dwell_s", |l| text::write_units(l, 2000, 3)),
        ] {
            text += &l;
            text.push('\n');
        }
        text += HEADER;
        text.push('\n');
        let mut written = Vec::new();
        // Times in visiting order, a millisecond apart at least as t_s has it (the reader
        // refuses a visit no later than the one before), within the 2^52 us where an f64 of
        // seconds still tells milliseconds apart.
        let mut t_us = rng.next_u64() >> (12 + rng.next_u64() % 52);
        for index in 0..20u16 {
            t_us += 1000 + (rng.next_u64() >> (24 + rng.next_u64() % 40));
            let bits = 8 + rng.next_u64() % 25;
            let per_turn = 1u64 << bits;
            let den = 1 + (rng.next_u64() % 20) as u32;
            // Near a whole turn now and then: the angles that round to 360.
            let num = if rng.unit() < 0.2 {
                -((rng.next_u64() % 3) as i64)
            } else {
                (rng.next_u64() % (per_turn * den as u64)) as i64
            };
            // The required rate always has a value: counts times a scale. Its quarters
            // average to it (the reader drops quarters that do not).
            let rate = rng.uniform(-100.0, 100.0);
            let d = [0; 4].map(|_| rng.uniform(-1.0, 1.0));
            let m = d.iter().sum::<f64>() / 4.0;
            let r = Record {
                index,
                t_us,
                encoder: EncoderAngle::from_counts(num, den, per_turn).unwrap(),
                rate_dph: rate as f32,
                // A spread is never negative (NaN for a dwell of one sample).
                rate_sd_dph: value(&mut rng, 1.0).abs(),
                samples: rng.next_u64() as u32,
                temp_c: value(&mut rng, 125.0),
                tilt_x_deg: value(&mut rng, 10.0),
                tilt_y_deg: value(&mut rng, 10.0),
                quarters_dph: d.map(|d| (rate + d - m) as f32),
                missed: rng.next_u64() as u32,
            };
            text += &r.line();
            text.push('\n');
            written.push((r, num as f64 / den as f64 / per_turn as f64 * 360.0));
        }
        let rec = Recording::parse(&text).unwrap_or_else(|e| panic!("seed {seed}: {e}\n{text}"));
        assert!(within_half_unit(rec.latitude_deg, lat as f64, 5));
        assert_eq!(rec.rows.len(), written.len());
        for (row, (r, angle)) in rec.rows.iter().zip(&written) {
            let line = r.line();
            let line = line.as_str();
            assert_eq!(row.index, r.index as u32);
            assert!(within_half_unit(row.t_s, r.t_us as f64 * 1e-6, 3), "{line}");
            // In [0, 360) (the reader refuses anything else) and the counts' direction.
            let d = (row.encoder_deg - angle).rem_euclid(360.0);
            assert!(
                d.min(360.0 - d) <= 0.5e-7 * (1.0 + 1e-6),
                "{angle} read {}\n{line}",
                row.encoder_deg
            );
            assert!(within_half_unit(row.rate_dph, r.rate_dph as f64, 6), "{line}");
            check_optional(row.rate_sd_dph, r.rate_sd_dph, 6, "rate_sd_dph", line);
            assert_eq!(row.samples, Some(r.samples));
            check_optional(row.temp_c, r.temp_c, 3, "temp_c", line);
            check_in(row.tilt_x_deg, r.tilt_x_deg, 5, 90.0, "tilt_x_deg", line);
            check_in(row.tilt_y_deg, r.tilt_y_deg, 5, 90.0, "tilt_y_deg", line);
            let q = row.quarters_dph.unwrap();
            for (got, want) in q.iter().zip(r.quarters_dph) {
                assert!(within_half_unit(*got, want as f64, 6), "{line}");
            }
        }
    }
}
