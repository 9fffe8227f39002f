//! Numbers as text without `core::fmt`'s formatting machinery (`write!` and the integer and
//! float `Display` impls, some 3 KiB on the MCU): integers, fixed-point integers, and `f32`
//! values rounded exactly to a number of decimals. Everything goes out through
//! [`Write::write_str`], so a `heapless::String` and a `Formatter` both take it.
//!
//! Rounding is half away from zero, as the firmware's fixed-point reader rounds.

use core::fmt::{Result, Write};

/// Most decimals [`write_f32`] writes: a 24-bit mantissa times `10^9` stays within `u64`.
pub const MAX_F32_DECIMALS: u32 = 9;

/// `10^d` for `d <= 19`.
const fn pow10(d: u32) -> u64 {
    let mut p = 1u64;
    let mut i = 0;
    while i < d {
        p *= 10;
        i += 1;
    }
    p
}

/// `v` in decimal, at least `width` digits (zeros in front).
fn write_digits<W: Write>(w: &mut W, mut v: u64, width: usize) -> Result {
    let mut buf = [b'0'; 20];
    let mut at = buf.len();
    while v > 0 {
        at -= 1;
        buf[at] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    at = at.min(buf.len() - width.clamp(1, buf.len()));
    // Char by char: a str from the bytes would link a UTF-8 decoder into the firmware.
    buf[at..].iter().try_for_each(|&d| w.write_char(char::from(d)))
}

pub fn write_u64<W: Write>(w: &mut W, v: u64) -> Result {
    write_digits(w, v, 1)
}

pub fn write_i64<W: Write>(w: &mut W, v: i64) -> Result {
    if v < 0 {
        w.write_char('-')?;
    }
    write_digits(w, v.unsigned_abs(), 1)
}

/// A magnitude of `10^-decimals` units with all its decimals (`decimals <= 19`).
fn write_unsigned_units<W: Write>(w: &mut W, units: u64, decimals: u32) -> Result {
    if decimals == 0 {
        return write_digits(w, units, 1);
    }
    let scale = pow10(decimals);
    write_digits(w, units / scale, 1)?;
    w.write_char('.')?;
    write_digits(w, units % scale, decimals as usize)
}

/// `units * 10^-decimals` with all its decimals: `write_units(w, -1_234_500, 3)` writes
/// `-1234.500` (`decimals <= 19`).
pub fn write_units<W: Write>(w: &mut W, units: i64, decimals: u32) -> Result {
    if units < 0 {
        w.write_char('-')?;
    }
    write_unsigned_units(w, units.unsigned_abs(), decimals)
}

/// `units * 10^-decimals` without trailing zeros after the point:
/// `write_units_trimmed(w, -1_234_500, 3)` writes `-1234.5`, and `(w, 7_000, 3)` writes `7`.
pub fn write_units_trimmed<W: Write>(w: &mut W, mut units: i64, mut decimals: u32) -> Result {
    while decimals > 0 && units % 10 == 0 {
        units /= 10;
        decimals -= 1;
    }
    write_units(w, units, decimals)
}

/// A count of `10^-from` units as a count of `10^-to` units (`to <= from <= 19`), rounded.
pub fn round_units(units: i64, from: u32, to: u32) -> i64 {
    let div = pow10(from.saturating_sub(to)) as i128;
    let u = units as i128;
    let half = div / 2;
    let q = if u < 0 { (u - half) / div } else { (u + half) / div };
    q as i64
}

/// `|x| * 10^decimals` rounded to the nearest integer (halves away from zero) from the exact
/// binary value of `x`, or `None` when `x` is not finite or the result is `2^64` or more.
pub fn f32_units(x: f32, decimals: u32) -> Option<u64> {
    if !x.is_finite() {
        return None;
    }
    let bits = x.to_bits();
    let exp = ((bits >> 23) & 0xff) as i32;
    let frac = (bits & 0x7f_ffff) as u64;
    // |x| = mant * 2^e exactly.
    let (mant, e) = if exp == 0 {
        (frac, -149)
    } else {
        (frac | 0x80_0000, exp - 150)
    };
    let v = mant * pow10(decimals.min(MAX_F32_DECIMALS));
    if v == 0 {
        return Some(0);
    }
    if e >= 0 {
        // Shifted within 64 bits, or too large.
        return ((e as u32) <= v.leading_zeros()).then(|| v << e);
    }
    let s = e.unsigned_abs();
    if s >= 64 {
        // v < 2^54: under a half.
        return Some(0);
    }
    let rem = v & ((1u64 << s) - 1);
    Some((v >> s) + (rem >= 1u64 << (s - 1)) as u64)
}

/// `x` with `decimals` digits after the point (at most [`MAX_F32_DECIMALS`]), rounded half
/// away from zero from its exact value; `nan` when it is not finite or `|x| 10^decimals` is
/// `2^64` or more (a fixed-point text with those digits would be another number). A value
/// that rounds to zero has no sign.
pub fn write_f32<W: Write>(w: &mut W, x: f32, decimals: u32) -> Result {
    let decimals = decimals.min(MAX_F32_DECIMALS);
    match f32_units(x, decimals) {
        None => w.write_str("nan"),
        Some(units) => {
            if x < 0.0 && units != 0 {
                w.write_char('-')?;
            }
            write_unsigned_units(w, units, decimals)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::format;
    use std::string::String;

    fn text(f: impl FnOnce(&mut String) -> Result) -> String {
        let mut s = String::new();
        f(&mut s).unwrap();
        s
    }

    /// The reference: Rust's exact decimal expansion of the value (as `f64`, which holds every
    /// `f32`), rounded half away from zero by hand on the digits.
    fn reference(x: f32, decimals: u32) -> String {
        let full = format!("{:.200}", (x as f64).abs());
        let (int, frac) = full.split_once('.').unwrap();
        let d = decimals as usize;
        let mut digits: std::vec::Vec<u8> = int.bytes().chain(frac[..d].bytes()).map(|b| b - b'0').collect();
        if frac.as_bytes()[d] >= b'5' {
            let mut i = digits.len();
            loop {
                if i == 0 {
                    digits.insert(0, 1);
                    break;
                }
                i -= 1;
                if digits[i] == 9 {
                    digits[i] = 0;
                } else {
                    digits[i] += 1;
                    break;
                }
            }
        }
        let s: String = digits.iter().map(|&b| (b + b'0') as char).collect();
        let (i, f) = s.split_at(s.len() - d);
        let i = i.trim_start_matches('0');
        let i = if i.is_empty() { "0" } else { i };
        let body = if d == 0 { i.into() } else { format!("{i}.{f}") };
        let zero = body.bytes().all(|b| b == b'0' || b == b'.');
        if x < 0.0 && !zero { format!("-{body}") } else { body }
    }

    #[test]
    fn integers() {
        assert_eq!(text(|s| write_u64(s, 0)), "0");
        assert_eq!(text(|s| write_u64(s, u64::MAX)), "18446744073709551615");
        assert_eq!(text(|s| write_i64(s, i64::MIN)), "-9223372036854775808");
        assert_eq!(text(|s| write_i64(s, -7)), "-7");
        assert_eq!(text(|s| write_i64(s, 42)), "42");
    }

    #[test]
    fn fixed_point_integers() {
        assert_eq!(text(|s| write_units(s, -1_234_500, 3)), "-1234.500");
        assert_eq!(text(|s| write_units(s, 5, 3)), "0.005");
        assert_eq!(text(|s| write_units(s, -5, 0)), "-5");
        assert_eq!(text(|s| write_units(s, 0, 2)), "0.00");
        assert_eq!(text(|s| write_units(s, i64::MIN, 18)), "-9.223372036854775808");
        assert_eq!(text(|s| write_units(s, 5_960_464_478, 15)), "0.000005960464478");
        assert_eq!(text(|s| write_units_trimmed(s, -1_234_500, 3)), "-1234.5");
        assert_eq!(text(|s| write_units_trimmed(s, 7_000, 3)), "7");
        assert_eq!(text(|s| write_units_trimmed(s, 0, 9)), "0");
        assert_eq!(text(|s| write_units_trimmed(s, 5_960_000_000, 15)), "0.00000596");
        assert_eq!(text(|s| write_units_trimmed(s, 120, 0)), "120");
        assert_eq!(round_units(5_960_464_478, 15, 12), 5_960_464);
        assert_eq!(round_units(-1_200_050_000, 6, 1), -12_001);
        assert_eq!(round_units(-1_200_049_999, 6, 1), -12_000);
        assert_eq!(round_units(250, 2, 0), 3);
        assert_eq!(round_units(-250, 2, 0), -3);
        assert_eq!(round_units(i64::MAX, 18, 18), i64::MAX);
        assert_eq!(round_units(i64::MIN, 1, 0), -922_337_203_685_477_581);
    }

    #[test]
    fn f32_rounds_its_exact_value_half_away_from_zero() {
        let cases: [(f32, u32, &str); 12] = [
            (10.856_123, 6, "10.856123"),
            (-0.000_000_4, 6, "0.000000"),
            (-0.000_000_6, 6, "-0.000001"),
            (-12.5, 0, "-13"),
            (0.5, 0, "1"),
            (2.5, 0, "3"),
            (-0.0, 3, "0.000"),
            // 0.125 is exact in binary: a true half.
            (0.125, 2, "0.13"),
            // As f32, 0.145 is 0.1449999958...: below the half.
            (0.145, 2, "0.14"),
            (359.999_97, 7, "359.9999695"),
            (1.0e-45, 9, "0.000000000"),
            (16_777_216.0, 3, "16777216.000"),
        ];
        for (x, d, want) in cases {
            assert_eq!(text(|s| write_f32(s, x, d)), want, "{x} to {d}");
            assert_eq!(reference(x, d), want, "reference of {x} to {d}");
        }
    }

    #[test]
    fn f32_matches_the_exact_decimal_expansion_everywhere() {
        let mut rng = crate::rng::Rng::new(5);
        for _ in 0..200_000 {
            // Every exponent, both signs, every mantissa bit pattern.
            let bits = (rng.next_u64() >> 32) as u32;
            let x = f32::from_bits(bits);
            let d = (rng.next_u64() % (MAX_F32_DECIMALS as u64 + 1)) as u32;
            let got = text(|s| write_f32(s, x, d));
            // Exact but within a few units of 2^64, where the f64 product rounds.
            let scaled = (x.abs() as f64) * 10f64.powi(d as i32);
            if !x.is_finite() || scaled > 1.844_674_407_370_955_2e19 {
                assert_eq!(got, "nan", "{x:e} to {d}");
                continue;
            }
            if scaled > 1.844_674_407_370_955e19 {
                continue;
            }
            assert_eq!(got, reference(x, d), "{x:e} ({bits:#x}) to {d}");
        }
    }

    #[test]
    fn f32_too_large_or_not_finite_is_nan() {
        for (x, d) in [
            (f32::NAN, 3),
            (f32::INFINITY, 0),
            (f32::NEG_INFINITY, 5),
            (f32::MAX, 0),
            (1.9e19, 0),
            (1.9e10, 9),
            (-4.5e24, 3),
        ] {
            assert_eq!(text(|s| write_f32(s, x, d)), "nan", "{x} to {d}");
        }
        // Just below 2^64: the largest f32 under it is written in full.
        let below = f32::from_bits(((64 + 127) << 23) - 1);
        assert_eq!(text(|s| write_f32(s, below, 0)), "18446742974197923840");
        assert_eq!(text(|s| write_f32(s, 1.8e9, 9)), "1800000000.000000000");
    }
}
