//! Turning the firmware's defmt log (as probe-rs or defmt-print print it) into a recording.
//!
//! The firmware logs every recording line as `rec <line>`. Printers put a time stamp, the
//! level and sometimes the location around the message, and may put the location on a
//! following `└─` line; all of that is dropped.

/// The recording lines found in a log, in order.
pub fn extract(log: &str) -> Vec<String> {
    let mut out = Vec::new();
    for raw in log.lines() {
        let l = raw.trim_end_matches('\r');
        let Some(pos) = find_tag(l) else { continue };
        let mut msg = l[pos + 4..].trim();
        // A location printed on the same line.
        if let Some(i) = msg.find("└─") {
            msg = msg[..i].trim_end();
        }
        if let Some(i) = msg
            .rfind(" (")
            .filter(|&i| msg.ends_with(')') && msg[i..].contains(".rs:"))
        {
            msg = msg[..i].trim_end();
        }
        if msg.starts_with('#') {
            out.push(msg.to_string());
        } else if let Some(tok) = msg.split_whitespace().next() {
            // Data and header lines have no spaces: anything after them is the printer's.
            out.push(tok.to_string());
        }
    }
    out
}

/// Byte offset of the `rec ` tag: at the start of the message, after level and time stamp.
fn find_tag(l: &str) -> Option<usize> {
    if l.starts_with("rec ") {
        return Some(0);
    }
    let mut from = 0;
    while let Some(i) = l[from..].find(" rec ") {
        let at = from + i + 1;
        let before = l[..at].trim_end();
        // Only when what precedes is the printer's prefix: ends with a level or a bracket.
        let ends_prefix = ["INFO", "DEBUG", "WARN", "ERROR", "TRACE", "]", ">"]
            .iter()
            .any(|p| before.ends_with(p));
        if ends_prefix {
            return Some(at);
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
        let lines = extract(log);
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
    fn a_message_that_mentions_rec_is_not_a_line() {
        assert!(extract("INFO  the rec button was pressed").is_empty());
    }
}
