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
//!
//! Numbers are plain decimals (`-33.9`, `0.0001178`; no exponent), read as fixed point
//! ([`crate::decimal`]) to the decimals of their setting: angles to micro-degrees, the target
//! to micro-arcseconds, noise terms to 1e-9 of their units, `cal_zero` to micro-counts and
//! `cal_scale` to 1e-15 deg/h per count; further digits round.

use crate::decimal::{self, DecimalError};
use crate::run::{RunConfig, TiltPolicy};
use nf_model::dwell::Calibration;
use nf_model::order::{Order, OrderError, VisitList};

/// Decimals of the latitude and the tilt limit: micro-degrees.
pub const ANGLE_DECIMALS: u32 = 6;
/// Decimals of the target: micro-arcseconds.
pub const TARGET_DECIMALS: u32 = 6;
/// Decimals of the noise terms: 1e-9 of their units.
pub const NOISE_DECIMALS: u32 = 9;
/// Decimals of `cal_zero`: micro-counts.
pub const CAL_ZERO_DECIMALS: u32 = Calibration::ZERO_DECIMALS;
/// Decimals of `cal_scale`: 1e-15 deg/h per count.
pub const CAL_SCALE_DECIMALS: u32 = Calibration::SCALE_DECIMALS;

/// A setting the host can change; values as the line gives them, in fixed point (the
/// `*_DECIMALS` constants); [`apply`] converts them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Setting {
    Positions(u16),
    DwellMs(u32),
    SettleMs(u32),
    /// Micro-degrees.
    LatitudeUdeg(i64),
    /// Micro-degrees.
    TiltLimitUdeg(i64),
    TiltRefuse(bool),
    Order(Order),
    /// More entries of a listed order.
    OrderMore(VisitList),
    /// Micro-arcseconds.
    TargetUarcsec(i64),
    /// 1e-9 of the term's unit.
    Noise(NoiseTerm, i64),
    /// The ADC counts at zero rate, in micro-counts.
    CalZero(i64),
    /// Degrees per hour per ADC count, in units of 1e-15.
    CalScale(i64),
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
                "unknown key (n dwell_ms settle_ms lat tilt_limit tilt_policy order target_arcsec arw bias_instability rrw gm_sigma gm_tau cal_zero cal_scale)"
            }
            LinkError::MissingValue => "SET needs a key and a value",
            LinkError::BadValue => "value is not a number of the right kind",
            LinkError::OutOfRange => "value out of range",
            // `write_message` goes on with the order's own.
            LinkError::Order(_) => "order: ",
            LinkError::NoListToExtend => "SET order+ continues a listed order; set one first",
        }
    }

    /// The message with an order's details, through `write_str` alone (no `core::fmt` on the
    /// MCU).
    pub fn write_message<W: core::fmt::Write>(&self, w: &mut W) -> core::fmt::Result {
        match self {
            LinkError::Order(e) => {
                w.write_str(self.message())?;
                e.write_message(w)
            }
            e => w.write_str(e.message()),
        }
    }
}

impl core::fmt::Display for LinkError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        self.write_message(f)
    }
}

/// Applies a setting to the run's configuration.
pub fn apply(cfg: &mut RunConfig, s: Setting) -> Result<(), LinkError> {
    match s {
        Setting::Positions(n) => cfg.positions = n,
        Setting::DwellMs(v) => cfg.dwell_ms = v,
        Setting::SettleMs(v) => cfg.settle_ms = v,
        Setting::LatitudeUdeg(v) => cfg.latitude_deg = decimal::to_f32(v, ANGLE_DECIMALS),
        Setting::TiltLimitUdeg(v) => cfg.tilt_limit_deg = decimal::to_f32(v, ANGLE_DECIMALS),
        Setting::TiltRefuse(r) => cfg.tilt_policy = if r { TiltPolicy::Refuse } else { TiltPolicy::Warn },
        Setting::Order(o) => cfg.order = o,
        Setting::TargetUarcsec(v) => cfg.target_arcsec = decimal::to_f32(v, TARGET_DECIMALS),
        Setting::CalZero(v) => cfg.calibration.zero_micro_counts = v,
        Setting::CalScale(v) => cfg.calibration.femto_dph_per_count = v,
        Setting::Noise(term, v) => {
            let m = &mut cfg.noise;
            *match term {
                NoiseTerm::Arw => &mut m.arw_deg_rth,
                NoiseTerm::BiasInstability => &mut m.bias_instability_dph,
                NoiseTerm::Rrw => &mut m.rrw_dph_rth,
                NoiseTerm::GmSigma => &mut m.gm_sigma_dph,
                NoiseTerm::GmTau => &mut m.gm_tau_s,
            } = decimal::to_f32(v, NOISE_DECIMALS);
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

/// A whole number (`[+-]digits`) within `lo..=hi`.
fn whole<T: TryFrom<i64>>(v: &str, lo: i64, hi: i64) -> Result<T, LinkError> {
    if v.contains('.') {
        return Err(LinkError::BadValue);
    }
    T::try_from(fixed(v, 0, lo, hi)?).map_err(|_| LinkError::OutOfRange)
}

/// A decimal in units of `10^-decimals`, within `lo..=hi` units.
fn fixed(v: &str, decimals: u32, lo: i64, hi: i64) -> Result<i64, LinkError> {
    let units = decimal::parse_fixed(v.as_bytes(), decimals).map_err(|e| match e {
        DecimalError::Syntax => LinkError::BadValue,
        DecimalError::Overflow => LinkError::OutOfRange,
    })?;
    check(units, lo, hi)
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
            Setting::Positions(whole(val, 4, 720)?)
        } else if k("dwell_ms") {
            Setting::DwellMs(whole(val, 10, 600_000)?)
        } else if k("settle_ms") {
            Setting::SettleMs(whole(val, 0, 60_000)?)
        } else if k("lat") {
            Setting::LatitudeUdeg(fixed(val, ANGLE_DECIMALS, -89_000_000, 89_000_000)?)
        } else if k("tilt_limit") {
            Setting::TiltLimitUdeg(fixed(val, ANGLE_DECIMALS, 0, 10_000_000)?)
        } else if k("tilt_policy") {
            match val {
                v if v.eq_ignore_ascii_case("refuse") => Setting::TiltRefuse(true),
                v if v.eq_ignore_ascii_case("warn") => Setting::TiltRefuse(false),
                _ => return Err(LinkError::BadValue),
            }
        } else if k("cal_zero") {
            const MAX: i64 = Calibration::MAX_ZERO_MICRO_COUNTS;
            Setting::CalZero(fixed(val, CAL_ZERO_DECIMALS, -MAX, MAX)?)
        } else if k("cal_scale") {
            // Not zero: 1e-15 deg/h per count and more, up to 1 deg/h per count either way.
            const MAX: i64 = Calibration::MAX_FEMTO_DPH_PER_COUNT;
            match fixed(val, CAL_SCALE_DECIMALS, -MAX, MAX)? {
                0 => return Err(LinkError::OutOfRange),
                v => Setting::CalScale(v),
            }
        } else if k("target_arcsec") {
            Setting::TargetUarcsec(fixed(val, TARGET_DECIMALS, 0, 36_000_000_000)?)
        } else if let Some(&(_, term)) = NOISE_KEYS.iter().find(|(name, _)| k(name)) {
            Setting::Noise(term, fixed(val, NOISE_DECIMALS, 0, 1_000_000_000_000_000)?)
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
        assert_eq!(
            parse("SET lat -33.9\r"),
            Ok(Command::Set(Setting::LatitudeUdeg(-33_900_000)))
        );
        assert_eq!(
            parse("SET cal_scale 0.00000596"),
            Ok(Command::Set(Setting::CalScale(5_960_000_000)))
        );
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
        assert_eq!(parse("SET n 70000"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET n -8"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET n 72.0"), Err(LinkError::BadValue));
        assert_eq!(parse("SET n +72"), Ok(Command::Set(Setting::Positions(72))));
        assert_eq!(parse("SET dwell_ms 99999999999999999999"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET settle_ms 1e3"), Err(LinkError::BadValue));
        assert_eq!(parse("SET lat 91"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET lat 89.0000005"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET lat 1e1"), Err(LinkError::BadValue));
        assert_eq!(parse("SET lat 4x"), Err(LinkError::BadValue));
        assert_eq!(parse("SET lat inf"), Err(LinkError::BadValue));
        assert_eq!(parse("SET lat 99999999999999999999"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET tilt_limit -0.1"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET cal_zero 8388609"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET cal_scale 0"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET cal_scale 0.0000000000000004"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET cal_scale -1.5"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET target_arcsec 36000.1"), Err(LinkError::OutOfRange));
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
            // Read in fixed point: the nearest f32 to each.
            (0.0012, 0.004, 0.3, 0.01, 60.0)
        );
        assert_eq!(cfg.target_arcsec, 18.0);
        assert_eq!(parse("SET rrw -1"), Err(LinkError::OutOfRange));
        assert_eq!(parse("SET arw nan"), Err(LinkError::BadValue));
        assert_eq!(parse("SET arw 1000000.000000001"), Err(LinkError::OutOfRange));
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
