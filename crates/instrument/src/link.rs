//! The host link: line commands in, recording lines and replies out.
//!
//! Commands (case-insensitive, one per line):
//! `SET <key> <value>` with key `n`, `dwell_ms`, `settle_ms`, `lat`, `tilt_limit` (deg) or
//! `tilt_policy` (`refuse` | `warn`); `START`; `ABORT`; `STATUS`; `CONFIG`.
//! Replies: `OK`, `ERR <what>`, and the lines of the recording while a run goes.

/// A setting the host can change.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Setting {
    Positions(u16),
    DwellMs(u32),
    SettleMs(u32),
    LatitudeDeg(f32),
    TiltLimitDeg(f32),
    TiltRefuse(bool),
}

#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Command {
    Set(Setting),
    Start,
    Abort,
    Status,
    Config,
}

/// Why a command line was refused; the reply is `ERR <message>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinkError {
    Empty,
    UnknownCommand,
    UnknownKey,
    MissingValue,
    BadValue,
    OutOfRange,
}

impl LinkError {
    pub fn message(&self) -> &'static str {
        match self {
            LinkError::Empty => "empty line",
            LinkError::UnknownCommand => "unknown command (SET, START, ABORT, STATUS, CONFIG)",
            LinkError::UnknownKey => "unknown key (n, dwell_ms, settle_ms, lat, tilt_limit, tilt_policy)",
            LinkError::MissingValue => "SET needs a key and a value",
            LinkError::BadValue => "value is not a number of the right kind",
            LinkError::OutOfRange => "value out of range",
        }
    }
}

fn num<T: core::str::FromStr>(v: &str) -> Result<T, LinkError> {
    v.parse().map_err(|_| LinkError::BadValue)
}

fn check<T: PartialOrd>(v: T, lo: T, hi: T) -> Result<T, LinkError> {
    if v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(LinkError::OutOfRange)
    }
}

/// Parses one command line.
pub fn parse(line: &str) -> Result<Command, LinkError> {
    let mut words = line.split_ascii_whitespace();
    let cmd = words.next().ok_or(LinkError::Empty)?;
    let c = if cmd.eq_ignore_ascii_case("SET") {
        let key = words.next().ok_or(LinkError::MissingValue)?;
        let val = words.next().ok_or(LinkError::MissingValue)?;
        let k = |s: &str| key.eq_ignore_ascii_case(s);
        let s = if k("n") {
            Setting::Positions(check(num(val)?, 4, 720)?)
        } else if k("dwell_ms") {
            Setting::DwellMs(check(num(val)?, 10, 600_000)?)
        } else if k("settle_ms") {
            Setting::SettleMs(check(num(val)?, 0, 60_000)?)
        } else if k("lat") {
            Setting::LatitudeDeg(check(num(val)?, -89.0, 89.0)?)
        } else if k("tilt_limit") {
            Setting::TiltLimitDeg(check(num(val)?, 0.0, 10.0)?)
        } else if k("tilt_policy") {
            match val {
                v if v.eq_ignore_ascii_case("refuse") => Setting::TiltRefuse(true),
                v if v.eq_ignore_ascii_case("warn") => Setting::TiltRefuse(false),
                _ => return Err(LinkError::BadValue),
            }
        } else {
            return Err(LinkError::UnknownKey);
        };
        Command::Set(s)
    } else if cmd.eq_ignore_ascii_case("START") {
        Command::Start
    } else if cmd.eq_ignore_ascii_case("ABORT") {
        Command::Abort
    } else if cmd.eq_ignore_ascii_case("STATUS") {
        Command::Status
    } else if cmd.eq_ignore_ascii_case("CONFIG") {
        Command::Config
    } else {
        return Err(LinkError::UnknownCommand);
    };
    if words.next().is_some() {
        return Err(LinkError::BadValue);
    }
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands() {
        assert_eq!(parse("set n 72"), Ok(Command::Set(Setting::Positions(72))));
        assert_eq!(parse("SET lat -33.9\r"), Ok(Command::Set(Setting::LatitudeDeg(-33.9))));
        assert_eq!(
            parse("SET tilt_policy WARN"),
            Ok(Command::Set(Setting::TiltRefuse(false)))
        );
        assert_eq!(parse("  start "), Ok(Command::Start));
        assert_eq!(parse("abort"), Ok(Command::Abort));
        assert_eq!(parse("STATUS"), Ok(Command::Status));
    }

    #[test]
    fn every_bad_line_says_why() {
        assert_eq!(parse(""), Err(LinkError::Empty));
        assert_eq!(parse("GO"), Err(LinkError::UnknownCommand));
        assert_eq!(parse("SET n"), Err(LinkError::MissingValue));
        assert_eq!(parse("SET x 1"), Err(LinkError::UnknownKey));
        assert_eq!(parse("SET n seventy"), Err(LinkError::BadValue));
        assert_eq!(parse("SET n 3"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET lat 91"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET tilt_policy maybe"), Err(LinkError::BadValue));
        assert_eq!(parse("START now"), Err(LinkError::BadValue));
        assert!(LinkError::OutOfRange.message().contains("range"));
    }
}
