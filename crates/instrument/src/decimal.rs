//! Decimal numbers in text read as fixed point: `[+-]digits[.digits]` into an integer count of
//! `10^-decimals` units (micro-degrees, nano-units, ...). The firmware reads the host link's
//! settings and the inclinometer's lines with this instead of `core`'s float parser, which
//! brought some 17 KiB of tables and code to the MCU.
//!
//! Accepted: an optional sign, digits with at most one decimal point, and at least one digit
//! (`5`, `-0.25`, `+.5`, `7.`). Refused: anything else, including exponents (`1e3`), `inf`
//! and `nan`. Digits past `decimals` round the last unit half away from zero.

/// Why a text is not a number of the units asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DecimalError {
    /// Not a plain decimal number.
    Syntax,
    /// A number whose count of units does not fit an `i64`.
    Overflow,
}

/// The largest `decimals` the conversions take: `10^18` is the largest power of ten in `i64`.
pub const MAX_DECIMALS: u32 = 18;

/// `10^d`, `d <= MAX_DECIMALS`.
pub const fn pow10(d: u32) -> u64 {
    let mut p = 1u64;
    let mut i = 0;
    while i < d {
        p *= 10;
        i += 1;
    }
    p
}

/// Reads `text` as a count of `10^-decimals` units (`decimals <= MAX_DECIMALS`).
pub fn parse_fixed(text: &[u8], decimals: u32) -> Result<i64, DecimalError> {
    let (neg, digits) = match text {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, text),
    };
    let decimals = decimals.min(MAX_DECIMALS);
    // `None` once the count overflowed: the text is still read to its end, so that a text that
    // is no number says so whatever its length.
    let mut units = Some(0u64);
    let mut seen_digit = false;
    // Decimals taken after the point, or `None` before it.
    let mut frac: Option<u32> = None;
    // The first digit past `decimals`, for the rounding.
    let mut next: Option<u8> = None;
    for &b in digits {
        match b {
            b'.' if frac.is_none() => frac = Some(0),
            b'0'..=b'9' => {
                seen_digit = true;
                let d = b - b'0';
                match &mut frac {
                    Some(f) if *f >= decimals => {
                        next.get_or_insert(d);
                    }
                    f => {
                        units = units.and_then(|u| u.checked_mul(10)?.checked_add(d as u64));
                        if let Some(f) = f {
                            *f += 1;
                        }
                    }
                }
            }
            _ => return Err(DecimalError::Syntax),
        }
    }
    if !seen_digit {
        return Err(DecimalError::Syntax);
    }
    let scale = pow10(decimals - frac.unwrap_or(0));
    let round = next.is_some_and(|d| d >= 5) as u64;
    let units = units
        .and_then(|u| u.checked_mul(scale)?.checked_add(round))
        .ok_or(DecimalError::Overflow)?;
    if neg {
        0i64.checked_sub_unsigned(units).ok_or(DecimalError::Overflow)
    } else {
        i64::try_from(units).map_err(|_| DecimalError::Overflow)
    }
}

/// `units * 10^-decimals` as the nearest `f32` (ties to even), for every `units` and
/// `decimals` up to [`MAX_DECIMALS`]. No `f64` (the firmware has none) and no float rounding
/// but the last: the quotient's bits come from integer long division.
pub fn to_f32(units: i64, decimals: u32) -> f32 {
    const EXACT: u64 = 1 << 24;
    let scale = pow10(decimals.min(MAX_DECIMALS));
    let n = units.unsigned_abs();
    let sign = if units < 0 { -1.0 } else { 1.0 };
    if n <= EXACT && scale <= EXACT {
        // Both exact in f32: one rounding, in the division (one VDIV on the M4F).
        return sign * (n as f32 / scale as f32);
    }
    // m = floor(n / scale * 2^k) with at least 40 bits, its last bit set when a remainder is
    // left (a sticky bit far below the 24 kept).
    let (mut m, mut rem, mut k) = (n / scale, n % scale, 0i32);
    if m == 0 && rem == 0 {
        return 0.0;
    }
    while m < 1 << 40 {
        rem *= 2;
        m = 2 * m + (rem >= scale) as u64;
        if rem >= scale {
            rem -= scale;
        }
        k += 1;
    }
    m |= (rem != 0) as u64;
    // The top 24 bits, rounded to nearest, ties to even.
    let shift = 40 - m.leading_zeros() as i32;
    let mut mant = m >> shift;
    let rest = m & ((1 << shift) - 1);
    let half = 1u64 << (shift - 1);
    mant += (rest > half || (rest == half && mant & 1 == 1)) as u64;
    // mant <= 2^24 is exact in f32; the powers of two scale it exactly (normal range).
    sign * mant as f32 * pow2(shift - k)
}

/// `2^e` for `|e| <= 126`.
fn pow2(e: i32) -> f32 {
    f32::from_bits(((127 + e) as u32) << 23)
}

#[cfg(test)]
mod tests {
    use super::*;
    use DecimalError::{Overflow, Syntax};

    fn p(s: &str, d: u32) -> Result<i64, DecimalError> {
        parse_fixed(s.as_bytes(), d)
    }

    #[test]
    fn plain_decimals_in_units() {
        assert_eq!(p("43.8", 6), Ok(43_800_000));
        assert_eq!(p("-33.9", 6), Ok(-33_900_000));
        assert_eq!(p("+0.01234", 5), Ok(1234));
        assert_eq!(p("0", 9), Ok(0));
        assert_eq!(p("-0", 9), Ok(0));
        assert_eq!(p("7", 0), Ok(7));
        assert_eq!(p("7.", 2), Ok(700));
        assert_eq!(p(".5", 1), Ok(5));
        assert_eq!(p("-.5", 3), Ok(-500));
        assert_eq!(p("0000000000000000000000012.5", 1), Ok(125));
        assert_eq!(p("0.00000596", 15), Ok(5_960_000_000));
        assert_eq!(p("9223372036854775807", 0), Ok(i64::MAX));
        assert_eq!(p("-9223372036854775807", 0), Ok(-i64::MAX));
    }

    #[test]
    fn digits_past_the_units_round_half_away_from_zero() {
        assert_eq!(p("0.1234565", 6), Ok(123_457));
        assert_eq!(p("0.1234564999", 6), Ok(123_456));
        assert_eq!(p("-0.1234565", 6), Ok(-123_457));
        assert_eq!(p("-0.0000004", 6), Ok(0));
        assert_eq!(p("2.5", 0), Ok(3));
        assert_eq!(p("0.00000000000000000000000000009", 6), Ok(0));
        // Only the first digit past the units decides: 0.49999 is under a half.
        assert_eq!(p("0.49999", 0), Ok(0));
    }

    #[test]
    fn bad_text_is_refused_and_says_why() {
        for bad in [
            "", "+", "-", ".", "-.", "1e3", "1E-3", "nan", "NaN", "inf", "-inf", "infinity", "1.2.3", "--1", "+-1",
            " 1", "1 ", "1,5", "0x10", "1_000", "½", "١",
        ] {
            assert_eq!(p(bad, 6), Err(Syntax), "{bad:?}");
        }
        assert_eq!(parse_fixed(&[b'1', 0xff], 0), Err(Syntax));
        // No number, however long.
        assert_eq!(p("37203547758094775809x", 0), Err(Syntax));
        assert_eq!(p("9223372036854775808", 0), Err(Overflow));
        assert_eq!(p("-9223372036854775808", 0), Ok(i64::MIN));
        assert_eq!(p("-9223372036854775809", 0), Err(Overflow));
        assert_eq!(p("100000000000000000000", 0), Err(Overflow));
        assert_eq!(p("10000", 15), Err(Overflow));
        assert_eq!(p("9223372036854775807.5", 0), Err(Overflow));
        // Large but within the units: still a number, for the caller's range check.
        assert_eq!(p("9223.372036854775807", 15), Ok(i64::MAX));
    }

    #[test]
    fn the_decimals_ask_for_at_most_the_largest_power_of_ten() {
        assert_eq!(pow10(MAX_DECIMALS), 1_000_000_000_000_000_000);
        assert_eq!(p("1", 30), Ok(1_000_000_000_000_000_000));
        assert_eq!(to_f32(5, 30), 5e-18);
    }

    #[test]
    fn conversions_round_once() {
        for s in ["43.8", "-33.9", "0.01234", "-1.5", "89", "0.05", "10", "0"] {
            let want: f32 = s.parse().unwrap();
            assert_eq!(to_f32(p(s, 6).unwrap(), 6), want, "{s}");
        }
        for s in [
            "0.0012",
            "0.004",
            "0.3",
            "60",
            "0.0001178",
            "0.000000001",
            "0.016777216",
            "-100000",
            // Past 2^24 units too: the nearest f32, as Rust's parser reads the text.
            "123456.789123456",
            "0.016777217",
            "999999999.999999999",
            "-0.987654321",
            "0.069021955",
            "-33.912345678",
        ] {
            let want: f32 = s.parse().unwrap();
            assert_eq!(to_f32(p(s, 9).unwrap(), 9), want, "{s}");
        }
        assert_eq!(to_f32(i64::MAX, 0), 9.223372e18);
        assert_eq!(to_f32(i64::MIN, 0), -9.223372e18);
        assert_eq!(to_f32(1, 18), 1e-18);
        assert_eq!(to_f32(-i64::MAX, 18), -9.223372);
        assert_eq!(to_f32(0, 18), 0.0);
    }

    /// Random counts and decimals against Rust's own correctly rounded parse of the same text.
    #[test]
    fn every_count_is_read_as_the_nearest_f32() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..200_000 {
            let bits = next() % 64;
            let units = (next() >> (63 - bits.min(62))) as i64 * if next() % 2 == 0 { 1 } else { -1 };
            let d = (next() % (MAX_DECIMALS as u64 + 1)) as u32;
            let mut text = std::string::String::new();
            nf_model::text::write_units(&mut text, units, d).unwrap();
            let want: f32 = text.parse().unwrap();
            assert_eq!(to_f32(units, d), want, "{text}");
        }
    }
}
