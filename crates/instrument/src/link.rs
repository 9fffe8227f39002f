//! The host link: line commands in, recording lines and replies out.
//!
//! Commands (case-insensitive, one per line):
//! `SET <key> <value>` with key `n`, `dwell_ms`, `settle_ms`, `lat`, `tilt_limit` (deg),
//! `tilt_policy` (`refuse` | `warn`) or `order` (a name of [`nf_model::order::NAMES`] or a
//! comma-separated list of position numbers; `SET order+ <list>` continues a long list),
//! `target_arcsec` (end the run at that running sigma; 0: off) or a gyro noise term in IEEE
//! Std 952 units: `arw` (deg/sqrt(h)), `bias_instability` (deg/h), `rrw` (deg/h/sqrt(h)),
//! `gm_sigma` (deg/h), `gm_tau` (s);
//! `cal_zero` (ADC counts at zero rate) or `cal_scale` (deg/h per count);
//! `START`; `ABORT`; `STATUS`; `CONFIG`; `SAVE` (to flash, loaded at boot); `DEFAULTS`.
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
    TargetArcsec(f32),
    Noise(NoiseTerm, f64),
    /// The ADC counts at zero rate.
    CalZero(f64),
    /// Degrees per hour per ADC count.
    CalScale(f64),
}

/// A term of the gyro's noise model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NoiseTerm {
    Arw,
    BiasInstability,
    Rrw,
    GmSigma,
    GmTau,
}

const NOISE_KEYS: [(&str, NoiseTerm); 5] = [
    ("arw", NoiseTerm::Arw),
    ("bias_instability", NoiseTerm::BiasInstability),
    ("rrw", NoiseTerm::Rrw),
    ("gm_sigma", NoiseTerm::GmSigma),
    ("gm_tau", NoiseTerm::GmTau),
];

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
    /// Store the settings in flash (loaded at the next boot).
    Save,
    /// Back to the firmware's defaults (SAVE stores them).
    Defaults,
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
            LinkError::UnknownCommand => "unknown command (SET, START, ABORT, STATUS, CONFIG, SAVE, DEFAULTS)",
            LinkError::UnknownKey => {
                "unknown key (n, dwell_ms, settle_ms, lat, tilt_limit, tilt_policy, order, target_arcsec, arw, bias_instability, rrw, gm_sigma, gm_tau, cal_zero, cal_scale)"
            }
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
        Setting::TargetArcsec(v) => cfg.target_arcsec = v,
        Setting::CalZero(v) => cfg.calibration.zero_counts = v,
        Setting::CalScale(v) => cfg.calibration.dph_per_count = v,
        Setting::Noise(term, v) => {
            let m = &mut cfg.noise;
            *match term {
                NoiseTerm::Arw => &mut m.arw_deg_rth,
                NoiseTerm::BiasInstability => &mut m.bias_instability_dph,
                NoiseTerm::Rrw => &mut m.rrw_dph_rth,
                NoiseTerm::GmSigma => &mut m.gm_sigma_dph,
                NoiseTerm::GmTau => &mut m.gm_tau_s,
            } = v;
        }
        Setting::OrderMore(more) => match &mut cfg.order {
            Order::List(l) => {
                // All or nothing: a refused line leaves the list as it was.
                let mut longer = *l;
                for &p in more.as_slice() {
                    longer.push(p).map_err(LinkError::Order)?;
                }
                *l = longer;
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
        } else if k("cal_zero") {
            Setting::CalZero(check(num::<f32>(val)?, -8_388_608.0, 8_388_608.0)? as f64)
        } else if k("cal_scale") {
            let v: f32 = num(val)?;
            if !(v.is_finite() && v != 0.0 && v.abs() <= 1.0) {
                return Err(LinkError::OutOfRange);
            }
            Setting::CalScale(v as f64)
        } else if k("target_arcsec") {
            Setting::TargetArcsec(check(num(val)?, 0.0, 36_000.0)?)
        } else if let Some(&(_, term)) = NOISE_KEYS.iter().find(|(name, _)| k(name)) {
            // Parsed as f32: the firmware carries no f64 parser for seven significant digits.
            let v: f32 = num(val)?;
            Setting::Noise(term, check(v, 0.0, 1.0e6)? as f64)
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
    } else if cmd.eq_ignore_ascii_case("SAVE") {
        Command::Save
    } else if cmd.eq_ignore_ascii_case("DEFAULTS") {
        Command::Defaults
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
    fn the_noise_model_and_the_target_are_set_in_ieee_units() {
        let mut cfg = RunConfig::DEFAULT;
        for line in [
            "SET arw 0.0012",
            "SET bias_instability 0.004",
            "SET rrw 0.3",
            "SET gm_sigma 0.01",
            "SET gm_tau 60",
            "SET target_arcsec 18",
        ] {
            match parse(line) {
                Ok(Command::Set(s)) => apply(&mut cfg, s).unwrap(),
                other => panic!("{line}: {other:?}"),
            }
        }
        let m = cfg.noise;
        assert_eq!(
            (
                m.arw_deg_rth,
                m.bias_instability_dph,
                m.rrw_dph_rth,
                m.gm_sigma_dph,
                m.gm_tau_s
            ),
            // To f32's seven digits.
            (0.0012f32 as f64, 0.004f32 as f64, 0.3f32 as f64, 0.01f32 as f64, 60.0)
        );
        assert_eq!(cfg.target_arcsec, 18.0);
        assert_eq!(parse("SET rrw -1"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET arw nan"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET target_arcsec x"), Err(LinkError::BadValue));
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

    #[test]
    fn a_refused_order_continuation_changes_nothing() {
        // `SET order+` past 256 visits answered ERR but kept the entries that fitted (and the
        // firmware stores the configuration either way). Found by the link fuzz target.
        let mut cfg = RunConfig::DEFAULT;
        let Ok(Command::Set(first)) = parse("SET order 0") else {
            panic!()
        };
        apply(&mut cfg, first).unwrap();
        let more = std::vec![1u16; 200]
            .iter()
            .map(|p| std::format!("{p}"))
            .collect::<std::vec::Vec<_>>()
            .join(",");
        let Ok(Command::Set(more)) = parse(&std::format!("SET order+ {more}")) else {
            panic!()
        };
        apply(&mut cfg, more).unwrap();
        let before = cfg;
        assert_eq!(apply(&mut cfg, more), Err(LinkError::Order(OrderError::TooLong)));
        assert_eq!(cfg, before);
        assert_eq!(cfg.order.visits(72), 201);
    }
}
