//! Checked ranges for the numeric options of the command lines (`nf` and the main run), as
//! clap value parsers: clap refuses a value outside with the option's name and exit code 2, so
//! no NaN, infinity or absurd size reaches the physics.

/// What clap takes as a `value_parser`.
pub trait Parser: Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {}
impl<F: Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static> Parser for F {}

/// A finite number from `lo` to `hi`, both included.
pub fn real(lo: f64, hi: f64) -> impl Parser {
    move |s| check(s, lo, hi, false)
}

/// A finite number above `lo` (excluded), up to `hi`.
pub fn above(lo: f64, hi: f64) -> impl Parser {
    move |s| check(s, lo, hi, true)
}

fn check(s: &str, lo: f64, hi: f64, lo_open: bool) -> Result<f64, String> {
    let v: f64 = s.trim().parse().map_err(|_| "not a number".to_string())?;
    let low_ok = if lo_open { v > lo } else { v >= lo };
    if v.is_finite() && low_ok && v <= hi {
        Ok(v)
    } else if lo_open {
        Err(format!("must be a finite number above {lo}, at most {hi}"))
    } else {
        Err(format!("must be a finite number from {lo} to {hi}"))
    }
}

/// Latitudes the firmware accepts (`SET lat`): away from the poles, where the Earth rate's
/// horizontal component, the signal, vanishes.
pub const MAX_LATITUDE_DEG: f64 = 89.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_nan_infinity_and_values_outside() {
        assert_eq!(real(0.0, 2.0)("1.5"), Ok(1.5));
        assert_eq!(real(0.0, 2.0)("0"), Ok(0.0));
        assert!(above(0.0, 2.0)("0").unwrap_err().contains("above 0"));
        for bad in ["nan", "NaN", "inf", "-inf", "2.5", "-1", "1e400"] {
            assert!(real(0.0, 2.0)(bad).unwrap_err().contains("finite number"), "{bad}");
        }
        assert_eq!(real(0.0, 2.0)("x").unwrap_err(), "not a number");
    }
}
