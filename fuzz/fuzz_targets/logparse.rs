//! Extraction of the recording from a defmt log. On any text: no panic, and every extracted
//! line is non-empty, one line, and a piece of the input. Model: recording lines (metadata and
//! data) printed the way probe-rs and defmt-print print the firmware's `rec <line>`, among
//! other log lines and location lines, come back exactly and in order; the runs it splits
//! them into hold every line once, in order.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf::logparse::extract;

fn word(u: &mut Unstructured, alphabet: &[u8], max: usize) -> Result<String> {
    let n = u.int_in_range(1..=max)?;
    let mut s = String::new();
    for _ in 0..n {
        s.push(*u.choose(alphabet)? as char);
    }
    Ok(s)
}

const KEY: &[u8] = b"abcdefghijklmnopqrstuvwxyz_0123456789";
const VALUE: &[u8] = b"abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789./+-_=:,[]<>";
const DATA: &[u8] = b"0123456789.,-+enaNAabcdefghijklmnopqrstuvwxyz_";
const LEVELS: [&str; 5] = ["INFO", "DEBUG", "WARN", "ERROR", "TRACE"];
const OTHER: [&str; 6] = [
    "position 0: gamma 0 deg, rate 4.49 deg/h",
    "inclinometer: bad line dropped",
    "north finder firmware 0.1.0",
    "the rec button was pressed",
    "running: psi 12.3 deg, sigma 40 arcsec after 3 of 72",
    "encoder: CRC error, retry 1",
];

/// A recording line: metadata (`# key = value`, the value words separated by single spaces)
/// or a data or header line (no spaces).
fn rec_line(u: &mut Unstructured) -> Result<String> {
    if u.ratio(1, 3)? {
        let mut v = word(u, VALUE, 12)?;
        for _ in 0..u.int_in_range(0..=3)? {
            v.push(' ');
            v += &word(u, VALUE, 8)?;
        }
        Ok(format!("# {} = {v}", word(u, KEY, 16)?))
    } else {
        word(u, DATA, 60)
    }
}

fn stamp(u: &mut Unstructured) -> Result<String> {
    Ok(format!(
        "{}.{:06}",
        u.int_in_range(0..=99_999u32)?,
        u.int_in_range(0..=999_999u32)?
    ))
}

/// One message as a printer shows it, and whether it is followed by a location line.
fn printed(u: &mut Unstructured, msg: &str) -> Result<String> {
    let level = *u.choose(&LEVELS)?;
    let pad = if level.len() == 4 { "  " } else { " " };
    Ok(match u.int_in_range(0..=5u8)? {
        0 => format!("{} {level}{pad}{msg}", stamp(u)?),
        1 => format!(
            "[{level:<5}] {msg} (north_finder src/firmware.rs:{})",
            u.int_in_range(1..=999u16)?
        ),
        2 => format!("{level} {msg}"),
        3 => format!(
            "{} {level}{pad}{msg} └─ north_finder::firmware @ src/firmware.rs:90",
            stamp(u)?
        ),
        4 => format!("{level}{pad}{msg}\r"),
        _ => format!(
            "{} {level}{pad}{msg}\n└─ north_finder::firmware::{{impl#1}}::line @ src/firmware.rs:90",
            stamp(u)?
        ),
    })
}

fn model(u: &mut Unstructured) -> Result<()> {
    let (mut log, mut want) = (String::new(), Vec::new());
    for _ in 0..u.int_in_range(0..=24)? {
        if u.ratio(1, 3)? {
            let other = *u.choose(&OTHER)?;
            log += &printed(u, other)?;
        } else {
            let l = rec_line(u)?;
            let first = log.is_empty() && u.arbitrary()?;
            log += &if first {
                format!("rec {l}")
            } else {
                printed(u, &format!("rec {l}"))?
            };
            want.push(l);
        }
        log.push('\n');
    }
    let got: Vec<String> = extract(log.as_bytes()).rec.into_iter().map(|(_, l)| l).collect();
    assert_eq!(got, want, "{log}");
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    // Lines end at LF or at a CR not followed by LF, as the reader takes them.
    let breaks = (0..data.len())
        .filter(|&i| data[i] == b'\n' || (data[i] == b'\r' && data.get(i + 1) != Some(&b'\n')))
        .count();
    let log = extract(data);
    for (at, l) in &log.rec {
        assert!(!l.is_empty() && !l.contains('\n'), "{l:?}");
        assert!((1..=breaks + 1).contains(at), "{l:?} at line {at} of {}", breaks + 1);
    }
    // The runs partition the lines, each after the first starting with metadata.
    let runs = log.runs();
    let joined: Vec<_> = runs.iter().flat_map(|r| r.rec.clone()).collect();
    assert_eq!(joined, log.rec);
    assert!(runs.iter().skip(1).all(|r| r.rec[0].1.starts_with('#')));
    let _ = model(&mut Unstructured::new(data));
});
