//! Two-axis inclinometer on a UART, ASCII line protocol.
//!
//! The driver sends `RD\r\n`; the inclinometer answers `$TLT,<x>,<y>*HH\r\n` with both
//! elevations in degrees and `HH` the XOR of the bytes between `$` and `*` in upper-case hex
//! (NMEA style). The driver skips anything up to the next `$`, drops lines that are too long
//! or fail the checksum, and gives up after a timeout.

use crate::clock::{Clock, with_timeout};
use crate::decimal;
use core::fmt::Write as _;
use embedded_io_async::{Read, Write};

/// Longest line accepted.
pub const MAX_LINE: usize = 64;

/// Why no reading came.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum InclError {
    /// The UART reported an error, or the end of its stream.
    Bus,
    /// Nothing at all arrived before the timeout.
    Timeout,
    /// Bytes arrived but no valid line among them: `bad_lines` failed the checksum or the
    /// format.
    Garbage { bad_lines: u16 },
}

/// Driver settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// How long to wait for an answer.
    pub timeout_ms: u32,
}

impl Default for Config {
    fn default() -> Self {
        Config { timeout_ms: 250 }
    }
}

fn checksum(body: &[u8]) -> u8 {
    body.iter().fold(0, |a, b| a ^ b)
}

/// Formats an answer line (what the inclinometer sends); empty for a reading too long for a
/// line (magnitudes near `f32::MAX`), rather than a line cut short that could read as another.
pub fn format_line(x_deg: f32, y_deg: f32) -> heapless::String<MAX_LINE> {
    let mut body = heapless::String::<MAX_LINE>::new();
    let mut line = heapless::String::new();
    if write!(body, "TLT,{x_deg:+.5},{y_deg:+.5}").is_err()
        || write!(line, "${}*{:02X}\r\n", body, checksum(body.as_bytes())).is_err()
    {
        line.clear();
    }
    line
}

/// Parses one line (without the line end); `None` if it is not a valid answer.
///
/// The elevations are plain decimals (`+0.01234`; no exponent), read in fixed point to
/// micro-degrees ([`crate::decimal`]): the firmware carries no float parser.
pub fn parse_line(line: &[u8]) -> Option<(f32, f32)> {
    let line = line.strip_prefix(b"$")?;
    let star = line.iter().position(|&b| b == b'*')?;
    let (body, sum) = (&line[..star], &line[star + 1..]);
    let sum = sum.trim_ascii_end();
    if hex_byte(sum)? != checksum(body) {
        return None;
    }
    let mut fields = body.split(|&b| b == b',');
    if fields.next()? != b"TLT" {
        return None;
    }
    let x = elevation_udeg(fields.next()?)?;
    let y = elevation_udeg(fields.next()?)?;
    fields.next().is_none().then_some((to_deg(x), to_deg(y)))
}

/// Two hex digits (either case) as a byte.
fn hex_byte(digits: &[u8]) -> Option<u8> {
    let [hi, lo] = digits else { return None };
    let value = |d: u8| (d as char).to_digit(16);
    Some((value(*hi)? * 16 + value(*lo)?) as u8)
}

/// An elevation in micro-degrees, `None` if it is no number or beyond a right angle.
fn elevation_udeg(field: &[u8]) -> Option<i64> {
    let v = decimal::parse_fixed(field, 6).ok()?;
    (v.unsigned_abs() <= MAX_ELEVATION_UDEG).then_some(v)
}

fn to_deg(udeg: i64) -> f32 {
    decimal::to_f32(udeg, 6)
}

/// An axis elevation beyond a right angle is no reading: refused at the sensor, never written.
pub const MAX_ELEVATION_DEG: f32 = 90.0;
const MAX_ELEVATION_UDEG: u64 = 90_000_000;

/// The inclinometer driver.
pub struct Inclinometer<U> {
    uart: U,
    cfg: Config,
}

impl<U: Read + Write> Inclinometer<U> {
    pub fn new(uart: U, cfg: Config) -> Self {
        Inclinometer { uart, cfg }
    }

    /// Asks for a reading and waits for a valid answer: `(x, y)` in degrees.
    pub async fn read<C: Clock>(&mut self, clock: &mut C) -> Result<(f32, f32), InclError> {
        self.uart.write_all(b"RD\r\n").await.map_err(|_| InclError::Bus)?;
        let (mut got_bytes, mut bad_lines) = (false, 0u16);
        let timeout = self.cfg.timeout_ms as u64 * 1000;
        let r = with_timeout(clock, timeout, self.receive(&mut got_bytes, &mut bad_lines)).await;
        match r {
            Some(r) => r,
            None if got_bytes => Err(InclError::Garbage { bad_lines }),
            None => Err(InclError::Timeout),
        }
    }

    async fn receive(&mut self, got_bytes: &mut bool, bad_lines: &mut u16) -> Result<(f32, f32), InclError> {
        let mut line = heapless::Vec::<u8, MAX_LINE>::new();
        let mut in_line = false;
        loop {
            let mut buf = [0u8; 16];
            let n = self.uart.read(&mut buf).await.map_err(|_| InclError::Bus)?;
            if n == 0 {
                // End of file: nothing more will come, and reading again would spin without
                // ever letting the timeout run.
                return Err(InclError::Bus);
            }
            *got_bytes = true;
            for &b in &buf[..n] {
                if b == b'$' {
                    line.clear();
                    let _ = line.push(b);
                    in_line = true;
                } else if !in_line {
                    // Skipping to the next start of line.
                } else if b == b'\n' {
                    in_line = false;
                    match parse_line(&line) {
                        Some(v) => return Ok(v),
                        None => {
                            *bad_lines = bad_lines.saturating_add(1);
                            warn!("inclinometer: bad line dropped");
                        }
                    }
                } else if line.push(b).is_err() {
                    in_line = false;
                    *bad_lines = bad_lines.saturating_add(1);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_round_trip() {
        let l = format_line(0.01234, -1.5);
        assert!(l.starts_with("$TLT,+0.01234,-1.50000*"));
        let body = l.trim_end();
        assert_eq!(parse_line(body.as_bytes()), Some((0.01234, -1.5)));
        assert_eq!(parse_line(b"$TLT,-90,90.0000004*7B"), Some((-90.0, 90.0)));
        assert_eq!(parse_line(b"$TLT,43.8,.5*46\r"), Some((43.8, 0.5)));
        // Too long for a line: the line was cut after "+1097727." with a checksum of what was
        // left, and read as y = 1097727. Found by the inclinometer fuzz target.
        assert_eq!(format_line(-2.3939604e38, 1097727.8), "");
        // A long line that fits is written whole; beyond 90 deg it is no reading.
        let l = format_line(1e30, 0.0);
        assert!(l.starts_with("$TLT,+1000000015047466219876688855040.00000,"), "{l}");
        assert_eq!(parse_line(l.trim_end().as_bytes()), None);
    }

    /// A UART at the end of its stream: every read gives `Ok(0)`.
    struct Ended;

    impl embedded_io_async::ErrorType for Ended {
        type Error = core::convert::Infallible;
    }

    impl Read for Ended {
        async fn read(&mut self, _: &mut [u8]) -> Result<usize, Self::Error> {
            Ok(0)
        }
    }

    impl Write for Ended {
        async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
            Ok(buf.len())
        }

        async fn flush(&mut self) -> Result<(), Self::Error> {
            Ok(())
        }
    }

    struct Instant;

    impl Clock for Instant {
        fn now_us(&self) -> u64 {
            0
        }
        async fn delay_us(&mut self, _: u64) {}
    }

    #[test]
    fn a_uart_at_its_end_is_a_bus_error_not_a_hang() {
        // `Ok(0)` (end of file, which embedded-io allows) was read again for ever: the
        // receive loop never returned to the timeout. Found by the inclinometer fuzz target.
        let mut incl = Inclinometer::new(Ended, Config::default());
        assert_eq!(embassy_futures::block_on(incl.read(&mut Instant)), Err(InclError::Bus));
    }

    #[test]
    fn bad_lines_are_refused() {
        let good = format_line(0.5, 0.25);
        let good = good.trim_end();
        let mut flipped = std::string::String::from(good);
        flipped.replace_range(7..8, "9");
        for bad in [
            &flipped[..],
            "$TLT,+0.5,+0.25",
            "TLT,+0.5,+0.25*00",
            "$XYZ,+0.5,+0.25*5B",
            "$TLT,nan,1*00",
            "$TLT,1,2,3*00",
        ] {
            assert_eq!(parse_line(bad.as_bytes()), None, "{bad}");
        }
        // Fields that are no plain decimal, or beyond a right angle, with the checksum right.
        for body in [
            "TLT,1e-3,0",
            "TLT,nan,0",
            "TLT,inf,0",
            "TLT,0,",
            "TLT,,0",
            "TLT,0.5.1,0",
            "TLT,0x1,0",
            "TLT, 0.5,0",
            "TLT,90.0000005,0",
            "TLT,0,-90.000001",
            "TLT,99999999999999999999999,0",
        ] {
            let bad = std::format!("${body}*{:02X}", checksum(body.as_bytes()));
            assert_eq!(parse_line(bad.as_bytes()), None, "{bad}");
        }
        // Well-formed but beyond a right angle: no reading.
        let absurd = format_line(1.8e14, 0.0);
        assert_eq!(parse_line(absurd.trim_end().as_bytes()), None, "{absurd}");
    }

    #[test]
    fn the_checksum_is_two_hex_digits_of_either_case() {
        for b in 0..=255u8 {
            for text in [std::format!("{b:02X}"), std::format!("{b:02x}")] {
                assert_eq!(hex_byte(text.as_bytes()), Some(b), "{text}");
            }
        }
        for bad in ["", "0", "000", "+F", "-1", "0g", "g0", " 1", "1 ", "\u{e9}"] {
            assert_eq!(hex_byte(bad.as_bytes()), None, "{bad:?}");
        }
        let body = "TLT,+0.50000,+0.25000";
        let sum = checksum(body.as_bytes());
        assert_eq!(
            parse_line(std::format!("${body}*{sum:02x}").as_bytes()),
            Some((0.5, 0.25))
        );
    }
}
