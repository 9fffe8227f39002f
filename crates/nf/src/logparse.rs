//! Turning the firmware's defmt log (as probe-rs or defmt-print print it) into a recording.
//!
//! The firmware logs every recording line as `rec <line>`. Printers put a time stamp, the
//! level and sometimes the location around the message, and may put the location on a
//! following `└─` line; all of that is dropped, and so are colour codes. Invalid UTF-8 (line
//! noise on the probe's link) is skipped with a warning; a `rec` line that had some is dropped,
//! since its values cannot be trusted, and shows as a missing index. The lines that end a run
//! (`result: ...`, `run ended: ...`, `target ... reached ...`) say how many positions the
//! firmware recorded, so that lines lost at the end of a run are seen too.

use crate::textfile::Error;
use std::borrow::Cow;

/// What a log holds.
#[derive(Debug, Clone, PartialEq)]
pub struct Log {
    /// The recording lines, each with its line in the log (from 1).
    pub rec: Vec<(usize, String)>,
    /// Invalid UTF-8 skipped and `rec` lines dropped for it.
    pub warnings: Vec<Error>,
    /// The lines that tell how a run ended, in the log's order.
    pub ends: Vec<End>,
}

/// A line of the firmware's log that tells how a run ended.
#[derive(Debug, Clone, PartialEq)]
pub struct End {
    /// Its line in the log (from 1).
    pub line: usize,
    /// The positions the firmware had recorded, where the line says (`result: ..., n 72`,
    /// `run ended: ...; 10 positions kept`).
    pub kept: Option<usize>,
    /// The message, as logged.
    pub text: String,
}

impl End {
    fn of(line: usize, l: &str) -> Option<End> {
        let (text, kept) = if let Some(m) = tagged(l, "result: ") {
            let m = trimmed(m);
            (m, m.rsplit_once(", n ").and_then(|(_, n)| n.trim().parse().ok()))
        } else if let Some(m) = tagged(l, "run ended: ") {
            let m = trimmed(m);
            let kept = m
                .rsplit_once("; ")
                .and_then(|(_, k)| k.strip_suffix(" positions kept")?.parse().ok());
            (m, kept)
        } else {
            let m = trimmed(tagged(l, "target ")?);
            (m, None)
        };
        if text.starts_with("target ") && !text.contains(" reached after ") {
            return None;
        }
        Some(End {
            line,
            kept,
            text: text.to_string(),
        })
    }

    /// Whether the run stopped before its last position: an abort, a fault or the target.
    pub fn early(&self) -> bool {
        !self.text.starts_with("result: ")
    }
}

impl Log {
    /// The recording as it is written out: its metadata and header, the position lines on
    /// the log's lines `rows` in that order (the reader's: visiting order, exact copies
    /// dropped), then any `#` lines that were among the positions.
    pub fn written(&self, rows: &[usize]) -> String {
        let header = self.rec.iter().position(|(_, l)| !l.starts_with('#'));
        let head = header.map_or(self.rec.len(), |h| h + 1);
        // The lines are in the log's order: found by halving, not by a scan per row.
        let body = &self.rec[head..];
        let line = |n: &usize| body.binary_search_by_key(n, |(at, _)| *at).ok().map(|i| &body[i].1);
        let comments = body.iter().filter(|(_, l)| l.starts_with('#')).map(|(_, l)| l);
        self.rec[..head]
            .iter()
            .map(|(_, l)| l)
            .chain(rows.iter().filter_map(line))
            .chain(comments)
            .map(|l| format!("{l}\n"))
            .collect()
    }

    /// The recording with each line on its line of the log (blank lines between), so that the
    /// reader's line numbers are the log's.
    pub fn on_log_lines(&self) -> String {
        let mut out = String::new();
        let mut at = 1;
        for (n, l) in &self.rec {
            out.extend(std::iter::repeat_n('\n', n - at));
            out += l;
            out.push('\n');
            at = n + 1;
        }
        out
    }
}

impl Log {
    /// The runs the log holds: a run begins where metadata (`# ...`) follows a position line
    /// or starts the log. Warnings go with the run whose lines they are among.
    pub fn runs(&self) -> Vec<Log> {
        let mut starts: Vec<usize> = Vec::new();
        let mut in_meta = false;
        for (i, (_, l)) in self.rec.iter().enumerate() {
            let meta = l.starts_with('#');
            if meta && !in_meta {
                starts.push(i);
            }
            in_meta = meta;
        }
        if starts.first() != Some(&0) {
            starts.insert(0, 0);
        }
        let bounds: Vec<(usize, usize)> = starts
            .iter()
            .zip(starts.iter().skip(1).chain(std::iter::once(&self.rec.len())))
            .map(|(&a, &b)| (a, b))
            .collect();
        bounds
            .iter()
            .enumerate()
            .map(|(k, &(a, b))| {
                let own = self.rec.get(a).map_or(0, |r| r.0);
                let first = if k == 0 { 0 } else { own };
                let next = bounds.get(k + 1).map_or(usize::MAX, |&(c, _)| self.rec[c].0);
                let within = |line: &usize| (first..next).contains(line);
                Log {
                    rec: self.rec[a..b].to_vec(),
                    warnings: self.warnings.iter().filter(|w| within(&w.line)).cloned().collect(),
                    // An end before the run's first line is a run that recorded nothing (one
                    // refused at levelling), not this one's.
                    ends: self
                        .ends
                        .iter()
                        .filter(|e| within(&e.line) && e.line > own)
                        .cloned()
                        .collect(),
                }
            })
            .collect()
    }

    /// The recording's metadata value of `key`, as written.
    pub fn meta(&self, key: &str) -> Option<&str> {
        self.rec.iter().find_map(|(_, l)| {
            let (k, v) = l.strip_prefix('#')?.split_once('=')?;
            (k.trim() == key).then(|| v.trim())
        })
    }

    /// The positions the firmware says it recorded, by the last line that tells, and that line.
    pub fn kept(&self) -> Option<(usize, &End)> {
        self.ends.iter().rev().find_map(|e| Some((e.kept?, e)))
    }

    /// Position lines (neither metadata nor the header).
    pub fn positions(&self) -> usize {
        self.rec
            .iter()
            .filter(|(_, l)| !l.starts_with('#') && !l.starts_with("index"))
            .count()
    }
}

/// The recording lines found in a log, in order.
pub fn extract(log: &[u8]) -> Log {
    let log = log.strip_prefix("\u{FEFF}".as_bytes()).unwrap_or(log);
    // A terminal that ends lines with a lone CR, in all the log or in part of it: a CR not
    // followed by LF is a line break (CRLF stays one).
    let lone = |i: usize| log[i] == b'\r' && log.get(i + 1) != Some(&b'\n');
    let crs: Vec<u8>;
    let log = if (0..log.len()).any(lone) {
        crs = (0..log.len()).map(|i| if lone(i) { b'\n' } else { log[i] }).collect();
        &crs[..]
    } else {
        log
    };
    let (mut rec, mut warnings, mut noisy, mut ends) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // A log cut off mid-line (the probe unplugged, a copy stopped) ends without a line break:
    // its last line may have lost fields or digits, 3.722 for 3.7222496.
    let unterminated = !log.is_empty() && !log.ends_with(b"\n");
    let last = log.split(|&b| b == b'\n').count();
    for (i, raw) in log.split(|&b| b == b'\n').enumerate() {
        let n = i + 1;
        let (text, bad) = valid_utf8(raw);
        let text = strip_colour(&text);
        let Some(msg) = rec_message(&text) else {
            if bad > 0 {
                noisy.push(n);
            }
            ends.extend(End::of(n, &text));
            continue;
        };
        if bad > 0 {
            warnings.push(Error {
                line: n,
                what: format!("a 'rec' line with {bad} invalid UTF-8 byte(s) is dropped: its values cannot be trusted"),
            });
        } else if unterminated && n == last {
            warnings.push(Error {
                line: n,
                what: "the log ends inside this 'rec' line (no line break after it): it is dropped, as its last value may be cut; end it with a line break if it is whole".into(),
            });
        } else {
            rec.push((n, msg));
        }
    }
    if let Some(&first) = noisy.first() {
        let list: Vec<String> = noisy.iter().take(8).map(usize::to_string).collect();
        let more = if noisy.len() > 8 {
            format!(" and {} more", noisy.len() - 8)
        } else {
            String::new()
        };
        warnings.insert(
            0,
            Error {
                line: first,
                what: format!("invalid UTF-8 skipped on line(s) {}{more}", list.join(", ")),
            },
        );
    }
    Log { rec, warnings, ends }
}

/// The text of a line with its invalid UTF-8 left out, and how many bytes that was.
fn valid_utf8(raw: &[u8]) -> (Cow<'_, str>, usize) {
    if let Ok(s) = std::str::from_utf8(raw) {
        return (Cow::Borrowed(s), 0);
    }
    let (mut s, mut bad) = (String::new(), 0);
    for c in raw.utf8_chunks() {
        s += c.valid();
        bad += c.invalid().len();
    }
    (Cow::Owned(s), bad)
}

/// The line without ANSI escape sequences (probe-rs colours the level and location).
fn strip_colour(l: &str) -> Cow<'_, str> {
    if !l.contains('\x1b') {
        return Cow::Borrowed(l);
    }
    let mut out = String::with_capacity(l.len());
    let mut chars = l.chars();
    while let Some(c) = chars.next() {
        if c != '\x1b' {
            out.push(c);
        } else if chars.next() == Some('[') {
            // Control sequence: parameters up to a final byte in '@'..='~'.
            for c in chars.by_ref() {
                if ('@'..='~').contains(&c) {
                    break;
                }
            }
        }
    }
    Cow::Owned(out)
}

/// The recording line a log line carries, if it is a `rec` message.
fn rec_message(l: &str) -> Option<String> {
    let msg = trimmed(&tagged(l, "rec ")?[4..]);
    if msg.starts_with('#') {
        Some(msg.to_string())
    } else {
        // Data and header lines have no spaces: anything after them is the printer's.
        msg.split_whitespace().next().map(str::to_string)
    }
}

/// A message without the location a printer may put after it on the same line.
fn trimmed(msg: &str) -> &str {
    let mut msg = msg.trim_end_matches('\r').trim();
    if let Some(i) = msg.find("└─") {
        msg = msg[..i].trim_end();
    }
    if let Some(i) = msg
        .rfind(" (")
        .filter(|&i| msg.ends_with(')') && msg[i..].contains(".rs:"))
    {
        msg = msg[..i].trim_end();
    }
    msg
}

/// The message from `tag` on, where it starts the line or follows the printer's prefix (a
/// level or a bracket after the time stamp).
fn tagged<'a>(l: &'a str, tag: &str) -> Option<&'a str> {
    if l.starts_with(tag) {
        return Some(l);
    }
    let spaced = format!(" {tag}");
    let mut from = 0;
    while let Some(i) = l[from..].find(&spaced) {
        let at = from + i + 1;
        let before = l[..at].trim_end();
        let ends_prefix = ["INFO", "DEBUG", "WARN", "ERROR", "TRACE", "]", ">"]
            .iter()
            .any(|p| before.ends_with(p));
        if ends_prefix {
            return Some(&l[at..]);
        }
        from = at;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_printers_formats() {
        let log = "\
INFO  north finder firmware 0.1.0
└─ north_finder::firmware::__main_task @ src/firmware.rs:250
0.000123 INFO  rec # format = northfinder-recording/1
└─ north_finder::firmware::{impl#1}::line @ src/firmware.rs:90
[INFO ] rec # latitude_deg = 43.80000 (north_finder src/firmware.rs:90)
INFO rec index,t_s,encoder_deg,rate_dph
12.5 INFO  position 0: gamma 0 deg, rate 4.49 deg/h
12.5 INFO  rec 0,1.25,0.0000000,4.495000 └─ north_finder::firmware @ src/firmware.rs:90
WARN  inclinometer: bad line dropped
";
        let lines: Vec<String> = extract(log.as_bytes()).rec.into_iter().map(|(_, l)| l).collect();
        assert_eq!(
            lines,
            vec![
                "# format = northfinder-recording/1",
                "# latitude_deg = 43.80000",
                "index,t_s,encoder_deg,rate_dph",
                "0,1.25,0.0000000,4.495000",
            ]
        );
    }

    #[test]
    fn a_log_of_two_runs_splits_where_the_metadata_starts_again() {
        let one = "rec # format = northfinder-recording/1\nrec # latitude_deg = 40\nrec index,t_s\nrec 0,1\nrec 1,2\n";
        let mut log = format!("INFO boot\n{one}INFO run ended\n").into_bytes();
        log.extend(b"\xff noise\n");
        log.extend(format!("{one}rec 2,3\n").bytes());
        let l = extract(&log);
        let runs = l.runs();
        assert_eq!(runs.len(), 2);
        assert_eq!((runs[0].positions(), runs[1].positions()), (2, 3));
        assert_eq!((runs[0].rec[0].0, runs[1].rec[0].0), (2, 9));
        assert_eq!(runs[1].meta("latitude_deg"), Some("40"));
        assert_eq!((runs[0].warnings.len(), runs[1].warnings.len()), (1, 0));
        assert_eq!(extract(b"rec 0,1\n").runs().len(), 1);
    }

    #[test]
    fn a_log_that_ends_inside_a_rec_line_drops_it_with_a_warning() {
        let whole = b"INFO  rec 0,1.5,0,3.7222496\nINFO  rec 1,2.5,90,3.722";
        let l = extract(whole);
        assert_eq!(l.rec, vec![(1, "0,1.5,0,3.7222496".to_string())]);
        assert_eq!(l.warnings.len(), 1);
        assert_eq!(l.warnings[0].line, 2);
        assert!(l.warnings[0].what.contains("ends inside"), "{:?}", l.warnings);
        // Ended by a line break (or by other text after it), the line is whole.
        assert_eq!(extract(b"INFO  rec 0,1.5,0,3.7\r\n").rec.len(), 1);
        assert_eq!(extract(b"INFO  rec 0,1.5,0,3.7\nINFO  done").rec.len(), 1);
    }

    #[test]
    fn the_lines_that_end_a_run_give_the_positions_recorded() {
        let log = "\
12.5 INFO  target 18 arcsec reached after 22 of 72 dwells: sigma 17.9 arcsec under the noise model
12.5 INFO  result: psi 65.5 deg +- 13.2 arcsec, amplitude 10.8 deg/h, rss 0.001 (deg/h)^2, n 22 └─ north_finder @ src/run.rs:676
[ERROR] run ended: RunError { stage: Position(9), fault: Aborted }; 10 positions kept (nf_instrument src/run.rs:684)
INFO  the target was moved
INFO  result: psi 65.5 deg, sigma undefined (0 dof), amplitude 10.8 deg/h, n 3
";
        let ends = extract(log.as_bytes()).ends;
        let kept: Vec<_> = ends.iter().map(|e| (e.line, e.kept, e.early())).collect();
        assert_eq!(
            kept,
            [
                (1, None, true),
                (2, Some(22), false),
                (3, Some(10), true),
                (5, Some(3), false)
            ]
        );
        assert_eq!(
            ends[2].text,
            "run ended: RunError { stage: Position(9), fault: Aborted }; 10 positions kept"
        );
    }

    #[test]
    fn lone_carriage_returns_end_lines() {
        let l = extract(b"INFO  rec # format = northfinder-recording/1\rINFO  rec index,t_s\rINFO  rec 0,1\r");
        assert_eq!(l.rec.iter().map(|(n, _)| *n).collect::<Vec<_>>(), [1, 2, 3]);
        // Mixed with CRLF and LF in one log.
        let l = extract(
            b"INFO  rec # format = northfinder-recording/1\rINFO  rec index,t_s\r\nINFO  rec 0,1\nINFO  rec 1,2\r",
        );
        let lines: Vec<&str> = l.rec.iter().map(|(_, s)| s.as_str()).collect();
        assert_eq!(lines, ["# format = northfinder-recording/1", "index,t_s", "0,1", "1,2"]);
    }

    #[test]
    fn a_message_that_mentions_rec_is_not_a_line() {
        assert!(extract(b"INFO  the rec button was pressed").rec.is_empty());
    }

    #[test]
    fn colours_invalid_utf8_and_the_log_s_line_numbers() {
        let mut log = b"\x1b[2m0.1\x1b[0m \x1b[32mINFO \x1b[0m rec # format = northfinder-recording/1\n".to_vec();
        log.extend_from_slice(b"noise \xff\xfe here\n");
        log.extend_from_slice(b"INFO  rec # latitude_deg = 4\xc3\n");
        log.extend_from_slice(b"INFO  rec index,t_s\r\n");
        let l = extract(&log);
        assert_eq!(
            l.rec,
            vec![
                (1, "# format = northfinder-recording/1".to_string()),
                (4, "index,t_s".to_string())
            ]
        );
        assert_eq!(l.warnings.iter().map(|w| w.line).collect::<Vec<_>>(), [2, 3]);
        assert!(l.warnings[0].what.contains("skipped on line(s) 2"), "{:?}", l.warnings);
        assert!(l.warnings[1].what.contains("dropped"), "{:?}", l.warnings);
        assert_eq!(l.on_log_lines(), "# format = northfinder-recording/1\n\n\nindex,t_s\n");
        assert_eq!(l.written(&[]), "# format = northfinder-recording/1\nindex,t_s\n");
    }

    #[test]
    fn the_recording_written_is_the_lines_the_reader_kept_in_its_order() {
        let log =
            b"rec # format = northfinder-recording/1\nrec index,t_s\nrec 0,1\nrec 2,3\nrec 1,2\nrec 1,2\nrec # note\n";
        let l = extract(log);
        assert_eq!(
            l.written(&[3, 5, 4]),
            "# format = northfinder-recording/1\nindex,t_s\n0,1\n1,2\n2,3\n# note\n"
        );
    }
}
