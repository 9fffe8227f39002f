//! Recording lines (`shared/recording-format.md`), written without float formatting code:
//! values go out as scaled integers ([`nf_model::text`]), which keeps the firmware small and
//! the digits exact.

use crate::encoder_angle::EncoderAngle;
use core::fmt::{self, Write};
use nf_model::text;

/// Longest line this module writes.
pub const MAX_LINE: usize = 192;

/// One line of the recording.
pub type Line = heapless::String<MAX_LINE>;

/// The column header, in the order [`Record::write`] writes the values.
pub const HEADER: &str = "index,t_s,encoder_deg,rate_dph,rate_sd_dph,samples,temp_c,tilt_x_deg,tilt_y_deg,q1_dph,q2_dph,q3_dph,q4_dph,missed";

/// One position of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Record {
    pub index: u16,
    /// The dwell's centre from the start of the first dwell, microseconds (written to the ms).
    pub t_us: u64,
    pub encoder: EncoderAngle,
    pub rate_dph: f32,
    pub rate_sd_dph: f32,
    pub samples: u32,
    pub temp_c: f32,
    pub tilt_x_deg: f32,
    pub tilt_y_deg: f32,
    pub quarters_dph: [f32; 4],
    /// Samples of the dwell the gyro source lost (not in `samples`); readers that do not
    /// know the column ignore it.
    pub missed: u32,
}

impl Record {
    /// The CSV line (without line end). A value that is not finite, or too large for its
    /// digits, is written `nan` ([`text::write_f32`]).
    pub fn write<W: Write>(&self, w: &mut W) -> fmt::Result {
        text::write_u64(w, self.index as u64)?;
        w.write_char(',')?;
        let ms = self.t_us / 1000 + (self.t_us % 1000 >= 500) as u64;
        text::write_units(w, ms as i64, 3)?;
        w.write_char(',')?;
        text::write_units(w, self.encoder.units() as i64, EncoderAngle::DECIMALS)?;
        for (x, decimals) in [(self.rate_dph, 6), (self.rate_sd_dph, 6)] {
            w.write_char(',')?;
            text::write_f32(w, x, decimals)?;
        }
        w.write_char(',')?;
        text::write_u64(w, self.samples as u64)?;
        for (x, decimals) in [(self.temp_c, 3), (self.tilt_x_deg, 5), (self.tilt_y_deg, 5)] {
            w.write_char(',')?;
            text::write_f32(w, x, decimals)?;
        }
        for q in self.quarters_dph {
            w.write_char(',')?;
            text::write_f32(w, q, 6)?;
        }
        w.write_char(',')?;
        text::write_u64(w, self.missed as u64)
    }

    pub fn line(&self) -> Line {
        let mut s = Line::new();
        // The widest record is shorter than MAX_LINE.
        let _ = self.write(&mut s);
        s
    }
}

/// A `# key = value` metadata line, the value written by `value`.
pub fn meta(key: &str, value: impl FnOnce(&mut Line) -> fmt::Result) -> Line {
    let mut s = Line::new();
    let _ = s.push_str("# ");
    let _ = s.push_str(key);
    let _ = s.push_str(" = ");
    let _ = value(&mut s);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(encoder: EncoderAngle) -> Record {
        Record {
            index: 0,
            t_us: 1_000_000,
            encoder,
            rate_dph: 0.0,
            rate_sd_dph: 0.0,
            samples: 1,
            temp_c: 0.0,
            tilt_x_deg: 0.0,
            tilt_y_deg: 0.0,
            quarters_dph: [0.0; 4],
            missed: 0,
        }
    }

    #[test]
    fn an_angle_that_rounds_to_360_is_written_as_0() {
        // A 29-bit encoder averaged to 0.05 counts below 0 gave 360.0000000, which the
        // recording reader refuses. Found by the record_roundtrip fuzz target.
        let per_turn = 1 << 29;
        let r = record(EncoderAngle::from_counts(-1, 20, per_turn).unwrap());
        assert!(r.line().starts_with("0,1.000,0.0000000,"), "{}", r.line());
        let r = record(EncoderAngle::from_counts(-4, 20, per_turn).unwrap());
        assert!(r.line().starts_with("0,1.000,359.9999999,"), "{}", r.line());
        let r = record(EncoderAngle::from_counts(1, 2, 1 << 23).unwrap());
        assert!(r.line().starts_with("0,1.000,0.0000215,"), "{}", r.line());
    }

    #[test]
    fn times_round_to_the_millisecond() {
        for (t_us, want) in [(0, "0.000"), (1_499, "0.001"), (1_500, "0.002"), (7_100_000, "7.100")] {
            let r = Record {
                t_us,
                ..record(EncoderAngle::from_counts(0, 1, 1).unwrap())
            };
            assert_eq!(r.line().split(',').nth(1), Some(want), "{t_us}");
        }
        let r = Record {
            t_us: u64::MAX,
            ..record(EncoderAngle::from_counts(0, 1, 1).unwrap())
        };
        assert_eq!(r.line().split(',').nth(1), Some("18446744073709.552"));
    }

    #[test]
    fn record_line_has_every_column_of_the_header() {
        let r = Record {
            index: 3,
            t_us: 7_100_000,
            encoder: EncoderAngle::from_counts(1 << 19, 3, 1 << 23).unwrap(),
            rate_dph: -4.25,
            rate_sd_dph: 0.1,
            samples: 2000,
            temp_c: 35.5,
            tilt_x_deg: 0.001,
            tilt_y_deg: -0.002,
            quarters_dph: [1.0, 2.0, 3.0, 4.0],
            missed: 12,
        };
        let l = r.line();
        assert_eq!(l.split(',').count(), HEADER.split(',').count());
        assert_eq!(
            l.as_str(),
            "3,7.100,7.5000000,-4.250000,0.100000,2000,35.500,0.00100,-0.00200,1.000000,2.000000,3.000000,4.000000,12"
        );
        let bad = Record {
            rate_sd_dph: f32::NAN,
            temp_c: f32::INFINITY,
            tilt_x_deg: 4.5e24,
            ..r
        };
        assert!(bad.line().contains(",nan,2000,nan,nan,-0.00200,"), "{}", bad.line());
        assert_eq!(
            meta("format", |l| l.write_str("northfinder-recording/1")).as_str(),
            "# format = northfinder-recording/1"
        );
        assert_eq!(
            meta("latitude_deg", |l| text::write_f32(l, 43.8, 6)).as_str(),
            "# latitude_deg = 43.799999"
        );
    }
}
