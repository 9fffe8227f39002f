//! The inclinometer's lines and driver. On any bytes: `parse_line` does not panic and gives
//! finite readings only. A line formatted for a reading is the protocol's line (or empty when
//! that does not fit) and parses back to the reading to within the five written decimals, or
//! not at all; never to another reading. The driver, fed the input in
//! reads of any size over a fake UART, gives what a model of the protocol gives on the same
//! bytes (the first valid `$...\n` line, the count of bad lines, a timeout, a bus error), and
//! always returns.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf_fuzz::fake::{self, InstantClock, Uart, UartEnd, UartRead};
use nf_instrument::inclinometer::{self, Config, InclError, Inclinometer, MAX_LINE, format_line, parse_line};

/// What the driver must answer to `bytes`, before the UART's end.
enum Expect {
    Reading((f32, f32)),
    /// No valid line among the bytes; this many bad ones.
    None {
        bad_lines: u16,
    },
}

/// The protocol, line by line: a line starts at `$` and ends at `\n`; a `$` restarts it; a
/// line longer than `MAX_LINE` bytes is bad and skipped to the next `$`.
fn model(bytes: &[u8]) -> Expect {
    let mut bad: u16 = 0;
    let mut i = 0;
    while let Some(s) = bytes[i..].iter().position(|&b| b == b'$') {
        let start = i + s;
        let end = bytes[start + 1..].iter().position(|&b| b == b'$' || b == b'\n');
        let len = end.map_or(bytes.len() - start, |e| e + 1);
        let line = &bytes[start..start + len];
        let terminated_by_newline = end.is_some_and(|e| bytes[start + 1 + e] == b'\n');
        if line.len() > MAX_LINE {
            bad = bad.saturating_add(1);
        } else if terminated_by_newline {
            match parse_line(line) {
                Some(v) => return Expect::Reading(v),
                None => bad = bad.saturating_add(1),
            }
        }
        match end {
            Some(e) => i = start + 1 + e,
            None => break,
        }
    }
    Expect::None { bad_lines: bad }
}

fn close(got: f32, want: f32) -> bool {
    // `{:+.5}` rounds to five decimals; reading that back as f32 rounds once more.
    (got as f64 - want as f64).abs() <= 0.5e-5 + want.abs() as f64 * 2.0 * f32::EPSILON as f64
}

fn run(u: &mut Unstructured, data: &[u8]) -> Result<()> {
    // Formatted readings: the line is the protocol's when it fits; read back, it gives the
    // reading, or nothing when it is not finite or beyond 90 deg.
    let (x, y): (f32, f32) = (u.arbitrary()?, u.arbitrary()?);
    let body = format!("TLT,{x:+.5},{y:+.5}");
    let full = format!("${body}*{:02X}\r\n", body.bytes().fold(0, |a, b| a ^ b));
    let line = format_line(x, y);
    if full.len() <= MAX_LINE {
        assert_eq!(line.as_str(), full);
    } else {
        assert_eq!(line.as_str(), "", "too long for a line");
    }
    match parse_line(line.trim_end().as_bytes()) {
        Some((gx, gy)) => assert!(
            close(gx, x) && close(gy, y),
            "({x}, {y}) formatted as {line:?} reads ({gx}, {gy})"
        ),
        // Beyond a right angle is no reading: refused at the sensor.
        None => assert!(
            !x.is_finite() || !y.is_finite() || x.abs() > 90.0 || y.abs() > 90.0 || full.len() > MAX_LINE,
            "({x}, {y}): {line:?}"
        ),
    }

    // The driver.
    let fail_write = u.ratio(1, 32)?;
    let end: UartEnd = u.arbitrary()?;
    let error_at: Option<usize> = if u.ratio(1, 8)? {
        Some(u.int_in_range(0..=data.len())?)
    } else {
        None
    };
    let n = u.arbitrary_len::<u8>()?;
    let bytes = u.bytes(n)?;
    let bytes = &bytes[..error_at.unwrap_or(bytes.len()).min(bytes.len())];
    let mut reads: Vec<UartRead> = fake::chunks(u, bytes).into_iter().map(UartRead::Bytes).collect();
    if error_at.is_some() {
        reads.push(UartRead::Error);
    }
    let mut uart = Uart {
        reads: reads.into(),
        end: if error_at.is_some() { UartEnd::Error } else { end },
        fail_write,
        written: Vec::new(),
        calls: 0,
    };
    let mut clock = InstantClock::default();
    let mut drv = Inclinometer::new(&mut uart, Config::default());
    let got = embassy_futures::block_on(drv.read(&mut clock));
    if fail_write {
        assert_eq!(got, Err(InclError::Bus));
        return Ok(());
    }
    assert_eq!(uart.written, b"RD\r\n");
    match (model(bytes), got) {
        (Expect::Reading(v), got) => assert_eq!(got, Ok(v)),
        (Expect::None { bad_lines }, got) => {
            let want = match uart.end {
                _ if error_at.is_some() => Err(InclError::Bus),
                UartEnd::Error => Err(InclError::Bus),
                UartEnd::Eof => Err(InclError::Bus),
                UartEnd::Silent if bytes.is_empty() => Err(InclError::Timeout),
                UartEnd::Silent => Err(InclError::Garbage { bad_lines }),
            };
            assert_eq!(got, want);
        }
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    if let Some(v) = inclinometer::parse_line(data) {
        assert!(v.0.is_finite() && v.1.is_finite());
    }
    let _ = run(&mut Unstructured::new(data), data);
});
