//! The keys of `SET`: their names, the kind and range of their values, and how a value is
//! read. One table, so that a refusal can name the key and its range.

use crate::decimal::{self, DecimalError};
use crate::link::{LinkError, Setting};
use nf_model::dwell::Calibration;
use nf_model::order::{Order, VisitList};
use nf_model::text;

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

/// A key of `SET`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Key {
    Positions,
    DwellMs,
    SettleMs,
    Latitude,
    TiltLimit,
    TiltPolicy,
    Order,
    /// More entries of a listed order.
    OrderMore,
    Target,
    Noise(NoiseTerm),
    CalZero,
    CalScale,
}

/// The keys by name, as the link spells them.
pub const KEYS: [(&str, Key); 16] = [
    ("n", Key::Positions),
    ("dwell_ms", Key::DwellMs),
    ("settle_ms", Key::SettleMs),
    ("lat", Key::Latitude),
    ("tilt_limit", Key::TiltLimit),
    ("tilt_policy", Key::TiltPolicy),
    ("order", Key::Order),
    ("order+", Key::OrderMore),
    ("target_arcsec", Key::Target),
    ("arw", Key::Noise(NoiseTerm::Arw)),
    ("bias_instability", Key::Noise(NoiseTerm::BiasInstability)),
    ("rrw", Key::Noise(NoiseTerm::Rrw)),
    ("gm_sigma", Key::Noise(NoiseTerm::GmSigma)),
    ("gm_tau", Key::Noise(NoiseTerm::GmTau)),
    ("cal_zero", Key::CalZero),
    ("cal_scale", Key::CalScale),
];

/// The values a numeric key takes: `lo..=hi` in units of `10^-decimals`, and their unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Range {
    pub lo: i64,
    pub hi: i64,
    pub decimals: u32,
    pub unit: &'static str,
}

const fn range(lo: i64, hi: i64, decimals: u32, unit: &'static str) -> Option<Range> {
    Some(Range { lo, hi, decimals, unit })
}

impl Key {
    /// The key named `name` (case-insensitive).
    pub fn find(name: &str) -> Option<Key> {
        KEYS.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)).map(|&(_, k)| k)
    }

    pub fn name(self) -> &'static str {
        KEYS.iter().find(|&&(_, k)| k == self).map_or("", |&(n, _)| n)
    }

    /// The range of a numeric key; `None` for `tilt_policy` and the orders.
    pub fn range(self) -> Option<Range> {
        const NOISE_MAX: i64 = 1_000_000 * decimal::pow10(NOISE_DECIMALS) as i64;
        const ZERO_MAX: i64 = Calibration::MAX_ZERO_MICRO_COUNTS;
        const SCALE_MAX: i64 = Calibration::MAX_FEMTO_DPH_PER_COUNT;
        match self {
            Key::Positions => range(4, 720, 0, ""),
            Key::DwellMs => range(10, 600_000, 0, ""),
            Key::SettleMs => range(0, 60_000, 0, ""),
            Key::Latitude => range(-89_000_000, 89_000_000, ANGLE_DECIMALS, " deg"),
            Key::TiltLimit => range(0, 10_000_000, ANGLE_DECIMALS, " deg"),
            Key::Target => range(0, 36_000_000_000, TARGET_DECIMALS, ""),
            Key::Noise(t) => range(
                0,
                NOISE_MAX,
                NOISE_DECIMALS,
                match t {
                    NoiseTerm::Arw => " deg/sqrt(h)",
                    NoiseTerm::BiasInstability | NoiseTerm::GmSigma => " deg/h",
                    NoiseTerm::Rrw => " deg/h/sqrt(h)",
                    NoiseTerm::GmTau => " s",
                },
            ),
            Key::CalZero => range(-ZERO_MAX, ZERO_MAX, CAL_ZERO_DECIMALS, " counts"),
            // Not zero (`Key::read`): 1e-15 deg/h per count and more, either way.
            Key::CalScale => range(-SCALE_MAX, SCALE_MAX, CAL_SCALE_DECIMALS, " deg/h per count, not 0"),
            Key::TiltPolicy | Key::Order | Key::OrderMore => None,
        }
    }

    /// Reads the value of `SET <key> <value>`.
    pub fn read(self, value: &str) -> Result<Setting, LinkError> {
        let num = || self.number(value);
        // The whole-number keys' ranges fit their types.
        Ok(match self {
            Key::Positions => Setting::Positions(num()? as u16),
            Key::DwellMs => Setting::DwellMs(num()? as u32),
            Key::SettleMs => Setting::SettleMs(num()? as u32),
            Key::Latitude => Setting::LatitudeUdeg(num()?),
            Key::TiltLimit => Setting::TiltLimitUdeg(num()?),
            Key::Target => Setting::TargetUarcsec(num()?),
            Key::Noise(t) => Setting::Noise(t, num()?),
            Key::CalZero => Setting::CalZero(num()?),
            Key::CalScale => Setting::CalScale(num()?),
            Key::TiltPolicy if value.eq_ignore_ascii_case("refuse") => Setting::TiltRefuse(true),
            Key::TiltPolicy if value.eq_ignore_ascii_case("warn") => Setting::TiltRefuse(false),
            Key::TiltPolicy => return Err(LinkError::BadValue(self)),
            Key::Order => Setting::Order(Order::parse(value).map_err(LinkError::Order)?),
            Key::OrderMore => {
                let mut more = VisitList::EMPTY;
                more.extend(value).map_err(LinkError::Order)?;
                Setting::OrderMore(more)
            }
        })
    }

    /// A numeric key's value in units of its decimals, within its range.
    fn number(self, value: &str) -> Result<i64, LinkError> {
        let r = self.range().ok_or(LinkError::BadValue(self))?;
        if r.decimals == 0 && value.contains('.') {
            return Err(LinkError::BadValue(self));
        }
        let v = decimal::parse_fixed(value.as_bytes(), r.decimals).map_err(|e| match e {
            DecimalError::Syntax => LinkError::BadValue(self),
            DecimalError::Overflow => LinkError::OutOfRange(self),
        })?;
        if v < r.lo || v > r.hi || (self == Key::CalScale && v == 0) {
            return Err(LinkError::OutOfRange(self));
        }
        Ok(v)
    }

    /// `x`, a value this key set, as the shortest text that `SET` reads back to the same `f32`.
    pub fn write_f32<W: core::fmt::Write>(self, w: &mut W, x: f32) -> core::fmt::Result {
        let most = self.range().map_or(0, |r| r.decimals);
        for d in 0..=most.min(text::MAX_F32_DECIMALS) {
            let Some(units) = text::f32_units(x, d).and_then(|u| i64::try_from(u).ok()) else {
                break;
            };
            let units = if x < 0.0 { -units } else { units };
            let full = units.checked_mul(decimal::pow10(most - d) as i64);
            if full.is_some_and(|f| decimal::to_f32(f, most) == x) {
                return text::write_units(w, units, d);
            }
        }
        text::write_f32(w, x, most)
    }

    /// Why a value was refused, after the key's name.
    pub fn write_refusal<W: core::fmt::Write>(self, w: &mut W, out_of_range: bool) -> core::fmt::Result {
        w.write_str(self.name())?;
        w.write_str(": ")?;
        match self.range() {
            None => w.write_str("refuse or warn"),
            Some(r) if out_of_range => {
                w.write_str("out of range, ")?;
                text::write_units_trimmed(w, r.lo, r.decimals)?;
                w.write_str(" to ")?;
                text::write_units_trimmed(w, r.hi, r.decimals)?;
                w.write_str(r.unit)
            }
            Some(r) if r.decimals == 0 => w.write_str("not a whole number"),
            Some(_) => w.write_str("not a plain decimal number"),
        }
    }
}
