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

use crate::decimal;
pub use crate::link_key::{
    ANGLE_DECIMALS, CAL_SCALE_DECIMALS, CAL_ZERO_DECIMALS, Key, NOISE_DECIMALS, NoiseTerm, TARGET_DECIMALS,
};
use crate::run::{RunConfig, TiltPolicy};
use nf_model::order::{Order, OrderError, VisitList};

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
    /// The value is not of the key's kind.
    BadValue(Key),
    /// The value is outside the key's range.
    OutOfRange(Key),
    /// Words after the command's last.
    ExtraWords,
    Order(OrderError),
    /// `SET order+` when the order is not a list.
    NoListToExtend,
}

impl LinkError {
    /// The message, through `write_str` alone (no `core::fmt` on the MCU).
    pub fn write_message<W: core::fmt::Write>(&self, w: &mut W) -> core::fmt::Result {
        let text = match self {
            LinkError::Empty => "empty line",
            LinkError::UnknownCommand => "unknown command (SET, START, ABORT, STATUS, CONFIG, SAVE, DEFAULTS)",
            // The keys from their one table.
            LinkError::UnknownKey => {
                w.write_str("unknown key (")?;
                for (i, (name, _)) in crate::link_key::KEYS.iter().enumerate() {
                    w.write_str(if i == 0 { "" } else { " " })?;
                    w.write_str(name)?;
                }
                ")"
            }
            LinkError::MissingValue => "SET needs a key and a value",
            LinkError::BadValue(k) => return k.write_refusal(w, false),
            LinkError::OutOfRange(k) => return k.write_refusal(w, true),
            LinkError::ExtraWords => "too many words: SET takes a key and one value, the other commands none",
            LinkError::Order(e) => {
                w.write_str("order: ")?;
                return e.write_message(w);
            }
            LinkError::NoListToExtend => "SET order+ continues a listed order; set one first",
        };
        w.write_str(text)
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

/// A blank between words: ASCII white space and the vertical tab.
pub fn blank(b: u8) -> bool {
    b.is_ascii_whitespace() || b == 0x0b
}

/// The first word of `s` and what follows it, both without the blanks around them.
fn word(s: &str) -> (&str, &str) {
    let is_blank = |c: char| c.is_ascii() && blank(c as u8);
    let s = s.trim_start_matches(is_blank);
    // An ASCII byte is never inside a longer character: the split is on a boundary.
    let end = s.bytes().position(blank).unwrap_or(s.len());
    let (w, rest) = s.split_at(end);
    (w, rest.trim_matches(is_blank))
}

/// Parses one command line.
pub fn parse(line: &str) -> Result<Command, LinkError> {
    let (cmd, rest) = word(line);
    let is = |name: &str| cmd.eq_ignore_ascii_case(name);
    let c = if cmd.is_empty() {
        return Err(LinkError::Empty);
    } else if is("SET") {
        let (key, value) = word(rest);
        if value.is_empty() {
            return Err(LinkError::MissingValue);
        }
        let key = Key::find(key).ok_or(LinkError::UnknownKey)?;
        // A list may have blanks after its commas; other values are one word.
        let value = match key {
            Key::Order | Key::OrderMore => value,
            _ => match word(value) {
                (v, "") => v,
                _ => return Err(LinkError::ExtraWords),
            },
        };
        Command::Set(key.read(value)?)
    } else if is("START") {
        Command::Start
    } else if is("ABORT") {
        Command::Abort
    } else if is("STATUS") {
        Command::Status
    } else if is("CONFIG") {
        Command::Config
    } else if is("SAVE") {
        Command::Save
    } else if is("DEFAULTS") {
        Command::Defaults
    } else {
        return Err(LinkError::UnknownCommand);
    };
    if !rest.is_empty() && !is("SET") {
        return Err(LinkError::ExtraWords);
    }
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link_key::KEYS;

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
        assert_eq!(parse("SET n seventy"), Err(LinkError::BadValue(Key::Positions)));
        assert_eq!(parse("SET n 3"), Err(LinkError::OutOfRange(Key::Positions)));
        assert_eq!(parse("SET n 70000"), Err(LinkError::OutOfRange(Key::Positions)));
        assert_eq!(parse("SET n -8"), Err(LinkError::OutOfRange(Key::Positions)));
        assert_eq!(parse("SET n 72.0"), Err(LinkError::BadValue(Key::Positions)));
        assert_eq!(parse("SET n +72"), Ok(Command::Set(Setting::Positions(72))));
        assert_eq!(
            parse("SET dwell_ms 99999999999999999999"),
            Err(LinkError::OutOfRange(Key::DwellMs))
        );
        assert_eq!(parse("SET settle_ms 1e3"), Err(LinkError::BadValue(Key::SettleMs)));
        assert_eq!(parse("SET lat 91"), Err(LinkError::OutOfRange(Key::Latitude)));
        assert_eq!(parse("SET lat 89.0000005"), Err(LinkError::OutOfRange(Key::Latitude)));
        assert_eq!(parse("SET lat 1e1"), Err(LinkError::BadValue(Key::Latitude)));
        assert_eq!(parse("SET lat 4x"), Err(LinkError::BadValue(Key::Latitude)));
        assert_eq!(parse("SET lat inf"), Err(LinkError::BadValue(Key::Latitude)));
        assert_eq!(
            parse("SET lat 99999999999999999999"),
            Err(LinkError::OutOfRange(Key::Latitude))
        );
        assert_eq!(parse("SET tilt_limit -0.1"), Err(LinkError::OutOfRange(Key::TiltLimit)));
        assert_eq!(parse("SET cal_zero 8388609"), Err(LinkError::OutOfRange(Key::CalZero)));
        assert_eq!(parse("SET cal_scale 0"), Err(LinkError::OutOfRange(Key::CalScale)));
        assert_eq!(
            parse("SET cal_scale 0.0000000000000004"),
            Err(LinkError::OutOfRange(Key::CalScale))
        );
        assert_eq!(parse("SET cal_scale -1.5"), Err(LinkError::OutOfRange(Key::CalScale)));
        assert_eq!(
            parse("SET target_arcsec 36000.1"),
            Err(LinkError::OutOfRange(Key::Target))
        );
        assert_eq!(
            parse("SET tilt_policy maybe"),
            Err(LinkError::BadValue(Key::TiltPolicy))
        );
        assert_eq!(parse("START now"), Err(LinkError::ExtraWords));
        assert_eq!(parse("STATUS now"), Err(LinkError::ExtraWords));
        assert_eq!(parse("SET n 8 9"), Err(LinkError::ExtraWords));
        assert_eq!(parse("SET order zigzag"), Err(LinkError::Order(OrderError::Unknown)));
        assert_eq!(
            parse("SET order 0,1,two"),
            Err(LinkError::Order(OrderError::BadEntry { at: 2 }))
        );
    }

    fn says(line: &str) -> std::string::String {
        let mut m = std::string::String::new();
        parse(line).unwrap_err().write_message(&mut m).unwrap();
        m
    }

    #[test]
    fn a_refusal_names_the_key_and_its_range() {
        assert_eq!(
            says("SET colour blue"),
            "unknown key (n dwell_ms settle_ms lat tilt_limit tilt_policy order order+ target_arcsec arw bias_instability rrw gm_sigma gm_tau cal_zero cal_scale)"
        );
        assert_eq!(says("SET n 3"), "n: out of range, 4 to 720");
        assert_eq!(says("set LAT 91"), "lat: out of range, -89 to 89 deg");
        assert_eq!(says("SET arw -1"), "arw: out of range, 0 to 1000000 deg/sqrt(h)");
        assert_eq!(says("SET gm_tau 1e3"), "gm_tau: not a plain decimal number");
        assert_eq!(says("SET dwell_ms 2.5"), "dwell_ms: not a whole number");
        assert_eq!(says("SET tilt_policy maybe"), "tilt_policy: refuse or warn");
        assert_eq!(
            says("SET cal_scale 0"),
            "cal_scale: out of range, -1 to 1 deg/h per count, not 0"
        );
        assert_eq!(
            says("SET target_arcsec 36000.1"),
            "target_arcsec: out of range, 0 to 36000"
        );
        // Every numeric key: its ends are taken, one unit past either is refused with the range.
        let text = |units: i64, decimals: u32| {
            let mut t = std::string::String::new();
            nf_model::text::write_units_trimmed(&mut t, units, decimals).unwrap();
            t
        };
        for (name, key) in KEYS {
            let Some(r) = key.range() else { continue };
            let (lo, hi) = (text(r.lo, r.decimals), text(r.hi, r.decimals));
            let refusal = std::format!("{name}: out of range, {lo} to {hi}{}", r.unit);
            for past in [r.lo - 1, r.hi + 1] {
                assert_eq!(says(&std::format!("SET {name} {}", text(past, r.decimals))), refusal);
            }
            for end in [lo, hi] {
                assert_eq!(
                    parse(&std::format!("SET {name} {end}")).map(|_| ()),
                    Ok(()),
                    "{name} {end}"
                );
            }
        }
    }

    #[test]
    fn words_are_parted_by_any_blank_and_lists_may_have_blanks() {
        assert_eq!(parse("\x0bSET\x0cn\t72\x0b"), parse("SET n 72"));
        assert_eq!(parse("\x0c\x0b"), Err(LinkError::Empty));
        assert_eq!(parse("SET order 0, 2, 1"), parse("SET order 0,2,1"));
        assert_eq!(parse("SET order+ 3 ,4"), parse("SET order+ 3,4"));
        assert_eq!(
            parse("SET order 0 2 1"),
            Err(LinkError::Order(OrderError::BadEntry { at: 0 }))
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
        assert_eq!(
            parse("SET rrw -1"),
            Err(LinkError::OutOfRange(Key::Noise(NoiseTerm::Rrw)))
        );
        assert_eq!(
            parse("SET arw nan"),
            Err(LinkError::BadValue(Key::Noise(NoiseTerm::Arw)))
        );
        assert_eq!(
            parse("SET arw 1000000.000000001"),
            Err(LinkError::OutOfRange(Key::Noise(NoiseTerm::Arw)))
        );
        assert_eq!(parse("SET target_arcsec x"), Err(LinkError::BadValue(Key::Target)));
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
