//! Recording lines (`shared/recording-format.md`), written without float formatting code:
//! values go out as scaled integers, which keeps the firmware small and the digits exact.

use core::fmt::{self, Write};

/// Longest line this module writes.
pub const MAX_LINE: usize = 192;

/// The column header, in the order [`Record::write`] writes the values.
pub const HEADER: &str = "index,t_s,encoder_deg,rate_dph,rate_sd_dph,samples,temp_c,tilt_x_deg,tilt_y_deg,q1_dph,q2_dph,q3_dph,q4_dph,missed";

/// One position of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Record {
    pub index: u16,
    pub t_s: f64,
    pub encoder_deg: f64,
    pub rate_dph: f64,
    pub rate_sd_dph: f64,
    pub samples: u32,
    pub temp_c: f32,
    pub tilt_x_deg: f32,
    pub tilt_y_deg: f32,
    pub quarters_dph: [f64; 4],
    /// Samples of the dwell the gyro source lost (not in `samples`); readers that do not
    /// know the column ignore it.
    pub missed: u32,
}

/// Writes `x` with `decimals` digits after the point (`nan` for a value that is not finite, or
/// too large for the scaled integer: `|x| 10^decimals >= 2^64`).
pub fn write_fixed<W: Write>(w: &mut W, x: f64, decimals: u32) -> fmt::Result {
    let scale = 10u64.pow(decimals);
    let scaled = nf_model::Float::round(nf_model::Float::abs(x) * scale as f64);
    // `as u64` saturates there, which would write another number.
    if !x.is_finite() || scaled >= 18_446_744_073_709_551_616.0 {
        return w.write_str("nan");
    }
    let v = scaled as u64;
    let sign = if x < 0.0 && v != 0 { "-" } else { "" };
    if decimals == 0 {
        return write!(w, "{sign}{v}");
    }
    write!(
        w,
        "{sign}{}.{:0width$}",
        v / scale,
        v % scale,
        width = decimals as usize
    )
}

/// `deg` in [0, 360) as it reads at seven decimals: 359.99999996 would print as 360.0000000.
fn angle_7(deg: f64) -> f64 {
    let r = nf_model::Float::round(nf_model::angle::wrap_360(deg) * 1e7) / 1e7;
    if r >= 360.0 { 0.0 } else { r }
}

impl Record {
    /// The CSV line (without line end).
    pub fn write<W: Write>(&self, w: &mut W) -> fmt::Result {
        write!(w, "{},", self.index)?;
        write_fixed(w, self.t_s, 3)?;
        w.write_char(',')?;
        write_fixed(w, angle_7(self.encoder_deg), 7)?;
        w.write_char(',')?;
        write_fixed(w, self.rate_dph, 6)?;
        w.write_char(',')?;
        write_fixed(w, self.rate_sd_dph, 6)?;
        write!(w, ",{},", self.samples)?;
        write_fixed(w, self.temp_c as f64, 3)?;
        w.write_char(',')?;
        write_fixed(w, self.tilt_x_deg as f64, 5)?;
        w.write_char(',')?;
        write_fixed(w, self.tilt_y_deg as f64, 5)?;
        for q in self.quarters_dph {
            w.write_char(',')?;
            write_fixed(w, q, 6)?;
        }
        write!(w, ",{}", self.missed)
    }

    pub fn line(&self) -> heapless::String<MAX_LINE> {
        let mut s = heapless::String::new();
        // The widest record is shorter than MAX_LINE.
        let _ = self.write(&mut s);
        s
    }
}

/// A `# key = value` metadata line with a fixed-point value.
pub fn meta_fixed(key: &str, value: f64, decimals: u32) -> heapless::String<MAX_LINE> {
    let mut s = heapless::String::new();
    let _ = write!(s, "# {key} = ");
    let _ = write_fixed(&mut s, value, decimals);
    s
}

/// A `# key = value` metadata line.
pub fn meta(key: &str, value: impl fmt::Display) -> heapless::String<MAX_LINE> {
    let mut s = heapless::String::new();
    let _ = write!(s, "# {key} = {value}");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_point_formatting() {
        let f = |x: f64, d: u32| {
            let mut s = heapless::String::<32>::new();
            write_fixed(&mut s, x, d).unwrap();
            s
        };
        assert_eq!(f(10.8561234567, 6), "10.856123");
        assert_eq!(f(-0.0000004, 6), "0.000000");
        assert_eq!(f(-0.0000006, 6), "-0.000001");
        assert_eq!(f(359.99999999, 7), "360.0000000");
        assert_eq!(f(-12.5, 0), "-13");
        assert_eq!(f(f64::NAN, 3), "nan");
        assert_eq!(f(1e15, 5), "nan");
        // Past 2^64 scaled, the integer saturated: a tilt of 4.5e24 went out as
        // 18446744073709551.615 (found by the record_roundtrip fuzz target).
        assert_eq!(f(4.536673774803529e24, 3), "nan");
        assert_eq!(f(-1e30, 5), "nan");
        assert_eq!(f(1.8e16, 3), "18000000000000000.000");
    }

    #[test]
    fn angles_are_written_in_0_to_360() {
        for (deg, want) in [
            (359.99999999, ",0.0000000,"),
            (-0.00000001, ",0.0000000,"),
            (360.5, ",0.5000000,"),
        ] {
            let r = Record {
                index: 0,
                t_s: 0.0,
                encoder_deg: deg,
                rate_dph: 0.0,
                rate_sd_dph: 0.0,
                samples: 1,
                temp_c: 20.0,
                tilt_x_deg: 0.0,
                tilt_y_deg: 0.0,
                quarters_dph: [0.0; 4],
                missed: 0,
            };
            assert!(r.line().contains(want), "{deg}: {}", r.line());
        }
    }

    #[test]
    fn an_angle_that_rounds_to_360_is_written_as_0() {
        // A 29-bit encoder averaged to 0.05 counts below 0 gave 360.0000000, which the
        // recording reader refuses. Found by the record_roundtrip fuzz target.
        let mut r = Record {
            index: 0,
            t_s: 1.0,
            encoder_deg: 359.99999996,
            rate_dph: 0.0,
            rate_sd_dph: 0.0,
            samples: 1,
            temp_c: 0.0,
            tilt_x_deg: 0.0,
            tilt_y_deg: 0.0,
            quarters_dph: [0.0; 4],
            missed: 0,
        };
        assert!(r.line().starts_with("0,1.000,0.0000000,"), "{}", r.line());
        r.encoder_deg = 359.99999994;
        assert!(r.line().starts_with("0,1.000,359.9999999,"), "{}", r.line());
    }

    #[test]
    fn record_line_has_every_column_of_the_header() {
        let r = Record {
            index: 3,
            t_s: 7.1,
            encoder_deg: 15.0,
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
        assert!(l.ends_with(",4.000000,12"), "{l}");
        assert!(
            l.starts_with("3,7.100,15.0000000,-4.250000,0.100000,2000,35.500,0.00100,-0.00200,1.000000"),
            "{l}"
        );
        assert_eq!(
            meta("format", "northfinder-recording/1").as_str(),
            "# format = northfinder-recording/1"
        );
        assert_eq!(
            meta_fixed("latitude_deg", 43.8, 6).as_str(),
            "# latitude_deg = 43.800000"
        );
    }
}
