//! The host link: line commands in, recording lines and replies out.
//!
//! Commands (case-insensitive, one per line):
//! `SET <key> <value>` with key `n`, `dwell_ms`, `settle_ms`, `lat`, `tilt_limit` (deg),
//! `tilt_policy` (`refuse` | `warn`) or `order` (a name of [`nf_model::order::NAMES`] or a
//! comma-separated list of position numbers; `SET order+ <list>` continues a long list);
//! `START`; `ABORT`; `STATUS`; `CONFIG`.
//! Replies: `OK`, `ERR <what>`, and the lines of the recording while a run goes.

use crate::run::{RunConfig, TiltPolicy};
use nf_model::order::{Order, OrderError, VisitList};

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
    Order(Order),
    /// More entries of a listed order.
    OrderMore(VisitList),
}

// A listed order travels inline (no allocator); the link holds one command at a time.
#[allow(clippy::large_enum_variant)]
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
    Order(OrderError),
    /// `SET order+` when the order is not a list.
    NoListToExtend,
}

impl LinkError {
    pub fn message(&self) -> &'static str {
        match self {
            LinkError::Empty => "empty line",
            LinkError::UnknownCommand => "unknown command (SET, START, ABORT, STATUS, CONFIG)",
            LinkError::UnknownKey => "unknown key (n, dwell_ms, settle_ms, lat, tilt_limit, tilt_policy, order)",
            LinkError::MissingValue => "SET needs a key and a value",
            LinkError::BadValue => "value is not a number of the right kind",
            LinkError::OutOfRange => "value out of range",
            LinkError::Order(_) => "order: not a named order or a valid list of positions",
            LinkError::NoListToExtend => "SET order+ continues a listed order; set one first",
        }
    }
}

impl core::fmt::Display for LinkError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            LinkError::Order(e) => write!(f, "order: {e}"),
            e => f.write_str(e.message()),
        }
    }
}

/// Applies a setting to the run's configuration.
pub fn apply(cfg: &mut RunConfig, s: Setting) -> Result<(), LinkError> {
    match s {
        Setting::Positions(n) => cfg.positions = n,
        Setting::DwellMs(v) => cfg.dwell_ms = v,
        Setting::SettleMs(v) => cfg.settle_ms = v,
        Setting::LatitudeDeg(v) => cfg.latitude_deg = v,
        Setting::TiltLimitDeg(v) => cfg.tilt_limit_deg = v,
        Setting::TiltRefuse(r) => cfg.tilt_policy = if r { TiltPolicy::Refuse } else { TiltPolicy::Warn },
        Setting::Order(o) => cfg.order = o,
        Setting::OrderMore(more) => match &mut cfg.order {
            Order::List(l) => {
                for &p in more.as_slice() {
                    l.push(p).map_err(LinkError::Order)?;
                }
            }
            _ => return Err(LinkError::NoListToExtend),
        },
    }
    Ok(())
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
        } else if k("order") {
            Setting::Order(Order::parse(val).map_err(LinkError::Order)?)
        } else if k("order+") {
            let mut more = VisitList::EMPTY;
            more.extend(val).map_err(LinkError::Order)?;
            Setting::OrderMore(more)
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
        assert_eq!(parse("SET order zigzag"), Err(LinkError::Order(OrderError::Unknown)));
        assert_eq!(
            parse("SET order 0,1,two"),
            Err(LinkError::Order(OrderError::BadEntry { at: 2 }))
        );
    }

    #[test]
    fn orders_are_set_by_name_or_by_a_list_over_several_lines() {
        let mut cfg = RunConfig::DEFAULT;
        let set = |cfg: &mut RunConfig, line: &str| match parse(line) {
            Ok(Command::Set(s)) => apply(cfg, s),
            other => panic!("{line}: {other:?}"),
        };
        set(&mut cfg, "SET order opposite-pairs").unwrap();
        assert_eq!(cfg.order, Order::OppositePairs);
        assert_eq!(set(&mut cfg, "SET order+ 4,5"), Err(LinkError::NoListToExtend));
        set(&mut cfg, "SET n 6").unwrap();
        set(&mut cfg, "SET order 0,3,4").unwrap();
        set(&mut cfg, "set ORDER+ 1,2,5").unwrap();
        assert_eq!(cfg.order.positions(6).collect::<std::vec::Vec<_>>(), [0, 3, 4, 1, 2, 5]);
        assert_eq!(cfg.order.check(6), Ok(()));
    }
}
