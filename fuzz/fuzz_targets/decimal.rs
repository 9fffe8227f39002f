//! Fixed-point decimals (`nf_instrument::decimal`). On any bytes and any decimals: no panic; a
//! text taken is a plain decimal (sign, digits, at most one point, no exponent) whose value,
//! read by `f64`'s parser, is the count of units to within half a unit; a refused one is not
//! such a decimal, or its count overflows `i64`. Model: a count printed with its decimals,
//! with or without more digits after them, reads back to the count (rounded half away from
//! zero by the first extra digit).
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf_fuzz::link_print::fixed;
use nf_instrument::decimal::{DecimalError, MAX_DECIMALS, parse_fixed, pow10};

fn plain_decimal(t: &[u8]) -> bool {
    let d = t.strip_prefix(b"-").or_else(|| t.strip_prefix(b"+")).unwrap_or(t);
    d.iter().any(u8::is_ascii_digit)
        && d.iter().all(|&b| b.is_ascii_digit() || b == b'.')
        && d.iter().filter(|&&b| b == b'.').count() <= 1
}

fn any_text(text: &[u8], decimals: u32) {
    match parse_fixed(text, decimals) {
        Ok(v) => {
            assert!(plain_decimal(text), "{text:?} taken as {v}");
            let s = std::str::from_utf8(text).unwrap();
            let x: f64 = s.parse().unwrap();
            let units = v as f64 / pow10(decimals) as f64;
            let half = 0.5 / pow10(decimals) as f64;
            assert!(
                (units - x).abs() <= half * (1.0 + 1e-9) + x.abs() * 4.0 * f64::EPSILON,
                "{s:?} at {decimals} decimals: {v}"
            );
        }
        Err(DecimalError::Syntax) => assert!(!plain_decimal(text), "{text:?} refused"),
        Err(DecimalError::Overflow) => {
            assert!(plain_decimal(text), "{text:?}");
            let s = std::str::from_utf8(text).unwrap();
            let x: f64 = s.parse().unwrap();
            assert!(
                x.abs() * pow10(decimals) as f64 >= 9.2e18,
                "{s:?} at {decimals}: overflow"
            );
        }
    }
}

fn structured(u: &mut Unstructured) -> Result<()> {
    let decimals = u.int_in_range(0..=MAX_DECIMALS)?;
    let v: i64 = u.arbitrary()?;
    let mut s = fixed(v, decimals);
    assert_eq!(parse_fixed(s.as_bytes(), decimals), Ok(v), "{s}");
    let extra: u8 = u.int_in_range(0..=9)?;
    if decimals == 0 {
        s.push('.');
    }
    s.push((b'0' + extra) as char);
    s.extend(std::iter::repeat_n('7', u.int_in_range(0..=3)?));
    let up = extra >= 5;
    let want = if !up {
        Ok(v)
    } else if v < 0 {
        v.checked_sub(1).ok_or(DecimalError::Overflow)
    } else {
        v.checked_add(1).ok_or(DecimalError::Overflow)
    };
    assert_eq!(parse_fixed(s.as_bytes(), decimals), want, "{s}");
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    if let Some((&d, text)) = data.split_first() {
        any_text(text, (d as u32) % (MAX_DECIMALS + 1));
    }
    let _ = structured(&mut Unstructured::new(data));
});
