//! The shaft angle of a dwell in fixed point: whole units of 1e-7 deg (the recording's
//! resolution) in `[0, 360)`, from encoder counts in integer arithmetic. An `f32` near 360 deg
//! resolves only 3e-5 deg, and the firmware has no `f64`.

/// An angle in `[0, 360)` deg, in units of `10^-DECIMALS` deg.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct EncoderAngle {
    units: u32,
}

/// Units in a turn.
const TURN: u64 = 3_600_000_000;
/// `TURN = SPLIT^2`: the angle is formed in two steps, each within `u64`.
const SPLIT: u64 = 60_000;
/// Largest `counts_per_turn * den` the two steps take: `SPLIT` times it stays in `u64`.
const MAX_DIVISOR: u64 = 1 << 48;

impl EncoderAngle {
    /// Decimals of a degree the units resolve.
    pub const DECIMALS: u32 = 7;

    /// The angle of `num / den` counts of an encoder with `per_turn` counts a turn, rounded
    /// to the nearest unit (halves up) and wrapped into `[0, 360)`; `None` unless
    /// `per_turn * den` is 1 to 2^48.
    pub fn from_counts(num: i64, den: u32, per_turn: u64) -> Option<Self> {
        let d = per_turn
            .checked_mul(den as u64)
            .filter(|d| (1..=MAX_DIVISOR).contains(d))?;
        // Within the turn: 0 <= x < d.
        let x = num.rem_euclid(d as i64) as u64;
        // x / d turns = (q + r / d) / SPLIT turns, and r / d / SPLIT turns is
        // r SPLIT / d units.
        let (q, r) = ((x * SPLIT) / d, (x * SPLIT) % d);
        let units = q * SPLIT + (r * SPLIT + d / 2) / d;
        // Rounded up to a whole turn: the same direction as 0.
        Some(EncoderAngle {
            units: (units % TURN) as u32,
        })
    }

    /// The angle in units of `10^-DECIMALS` deg, below `360 * 10^DECIMALS`.
    pub fn units(&self) -> u32 {
        self.units
    }

    /// The angle in degrees, to `f32`'s resolution (two roundings): within 2e-5 deg of 360, that
    /// is 360.0, the same direction as 0.
    pub fn deg(&self) -> f32 {
        let per_deg = 10u32.pow(Self::DECIMALS);
        (self.units / per_deg) as f32 + (self.units % per_deg) as f32 / per_deg as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn units(num: i64, den: u32, per_turn: u64) -> u32 {
        EncoderAngle::from_counts(num, den, per_turn).unwrap().units()
    }

    /// The reference: exact rational arithmetic in `i128`, rounded half up, wrapped.
    fn exact(num: i64, den: u32, per_turn: u64) -> u32 {
        let d = per_turn as i128 * den as i128;
        let x = (num as i128).rem_euclid(d);
        let u = (2 * x * TURN as i128 + d) / (2 * d);
        (u % TURN as i128) as u32
    }

    #[test]
    fn angles_of_whole_and_fractional_counts() {
        assert_eq!(units(0, 1, 1 << 23), 0);
        assert_eq!(units(1 << 21, 1, 1 << 23), 900_000_000);
        assert_eq!(units(-(1 << 21), 1, 1 << 23), 2_700_000_000);
        // A third of a turn: 120 deg, rounded to 1e-7 deg.
        assert_eq!(units(1, 3, 1), 1_200_000_000);
        assert_eq!(units(2, 3, 1), 2_400_000_000);
        // Turns beyond the first wrap.
        assert_eq!(units(5 << 23, 1, 1 << 23), 0);
        assert_eq!(EncoderAngle::from_counts(3, 1, 12).unwrap().deg(), 90.0);
    }

    #[test]
    fn just_below_a_turn_is_written_as_zero() {
        // A 29-bit encoder averaged to 0.05 counts below 0: 359.99999997 deg, which reads
        // 360.0000000 at seven decimals; the direction is 0.
        let per_turn = 1u64 << 29;
        assert_eq!(units(-1, 20, per_turn), 0);
        // 0.2 counts below: 359.9999999 deg.
        assert_eq!(units(-4, 20, per_turn), 3_599_999_999);
    }

    #[test]
    fn matches_exact_rational_arithmetic() {
        let mut rng = nf_model::rng::Rng::new(9);
        for _ in 0..200_000 {
            let bits = 1 + rng.next_u64() % 32;
            let per_turn = 1u64 << bits;
            let den = 1 + (rng.next_u64() % 20) as u32;
            let num = rng.next_u64() as i64 >> (rng.next_u64() % 64);
            assert_eq!(
                units(num, den, per_turn),
                exact(num, den, per_turn),
                "{num}/{den} of {per_turn}"
            );
        }
        assert_eq!(units(i64::MIN, 1, 1 << 32), exact(i64::MIN, 1, 1 << 32));
        assert_eq!(units(i64::MAX, 7, 1 << 45), exact(i64::MAX, 7, 1 << 45));
    }

    #[test]
    fn degrees_are_within_f32_resolution() {
        for u in [0u32, 1, 9_999_999, 10_000_000, 1_234_567_891, 3_599_999_999] {
            let a = EncoderAngle { units: u };
            let want = u as f64 * 1e-7;
            let ulp = (want as f32).abs().max(1e-30) * f32::EPSILON;
            assert!((a.deg() as f64 - want).abs() <= ulp as f64 + 1e-14, "{u}: {}", a.deg());
            assert!(a.deg() <= 360.0);
        }
    }

    #[test]
    fn a_divisor_out_of_range_is_refused() {
        assert_eq!(EncoderAngle::from_counts(1, 0, 1 << 23), None);
        assert_eq!(EncoderAngle::from_counts(1, 1, 0), None);
        assert_eq!(EncoderAngle::from_counts(1, 2, 1 << 48), None);
        assert_eq!(EncoderAngle::from_counts(1, 1, u64::MAX), None);
        assert!(EncoderAngle::from_counts(1, 1, 1 << 48).is_some());
    }
}
