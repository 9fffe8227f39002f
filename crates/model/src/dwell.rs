//! The dwell at one position: exact fixed-point sums of ADC counts.
//!
//! 24-bit samples are summed in `i64` and their squares in `i128`, so 2 s at 1 kHz (or days of
//! samples) lose nothing; the rates and the variance are formed once, at the end, in `f32` from
//! the exact sums.

/// Running sums of one dwell, split into four consecutive quarters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DwellAccumulator {
    expected: u32,
    n: u32,
    sum: i64,
    sumsq: i128,
    quarter_sum: [i64; 4],
    quarter_n: [u32; 4],
}

impl DwellAccumulator {
    /// A dwell that expects `expected` samples (what splits it into quarters).
    pub fn new(expected: u32) -> Self {
        DwellAccumulator {
            expected: expected.max(1),
            ..Default::default()
        }
    }

    pub fn push(&mut self, sample: i32) {
        let q = ((self.n as u64 * 4) / self.expected as u64).min(3) as usize;
        let s = sample as i64;
        self.n += 1;
        self.sum += s;
        self.sumsq += (s * s) as i128;
        self.quarter_sum[q] += s;
        self.quarter_n[q] += 1;
    }

    pub fn samples(&self) -> u32 {
        self.n
    }

    /// The sum of the samples, counts.
    pub fn sum(&self) -> i64 {
        self.sum
    }

    /// The sum and the number of the samples of quarter `q` (0 to 3).
    pub fn quarter(&self, q: usize) -> (i64, u32) {
        (self.quarter_sum[q], self.quarter_n[q])
    }

    /// The sample variance, counts^2 (NaN with fewer than two samples): from the exact
    /// `n sum(x^2) - sum(x)^2`, rounded to `f32` and divided.
    pub fn variance(&self) -> f32 {
        if self.n < 2 {
            return f32::NAN;
        }
        let num = (self.n as i128 * self.sumsq - (self.sum as i128) * (self.sum as i128)) as u128;
        // Not negative; through two u64 halves: the MCU then needs no 128-bit float conversion.
        let num = (num >> 64) as u64 as f32 * 18_446_744_073_709_551_616.0 + num as u64 as f32;
        num / (self.n as f32 * (self.n - 1) as f32)
    }
}

/// Counts to deg/h: `rate = (counts - zero) * scale`, both in fixed point as the host link
/// sets them, so that the firmware computes a rate without `f64`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Calibration {
    /// ADC counts at zero rate, in units of `10^-ZERO_DECIMALS` count.
    pub zero_micro_counts: i64,
    /// deg/h per count, in units of `10^-SCALE_DECIMALS`.
    pub femto_dph_per_count: i64,
}

impl Default for Calibration {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Calibration {
    /// Decimals of [`Calibration::zero_micro_counts`].
    pub const ZERO_DECIMALS: u32 = 6;
    /// Decimals of [`Calibration::femto_dph_per_count`].
    pub const SCALE_DECIMALS: u32 = 15;

    /// Largest zero either way: the ADC's full scale, 2^23 counts.
    pub const MAX_ZERO_MICRO_COUNTS: i64 = 8_388_608_000_000;
    /// Largest scale either way: 1 deg/h per count.
    pub const MAX_FEMTO_DPH_PER_COUNT: i64 = 1_000_000_000_000_000;

    /// A rebalance loop giving +-50 deg/h over the ADC's +-2^23 counts (50 / 2^23 deg/h per
    /// count, to 1e-15).
    pub const DEFAULT: Calibration = Calibration {
        zero_micro_counts: 0,
        femto_dph_per_count: 5_960_464_478,
    };

    /// Within the ranges above, and a scale that is not zero.
    pub fn is_valid(&self) -> bool {
        self.zero_micro_counts.unsigned_abs() <= Self::MAX_ZERO_MICRO_COUNTS as u64
            && self.femto_dph_per_count != 0
            && self.femto_dph_per_count.unsigned_abs() <= Self::MAX_FEMTO_DPH_PER_COUNT as u64
    }

    /// deg/h per count.
    pub fn dph_per_count(&self) -> f32 {
        self.femto_dph_per_count as f32 * 1e-15
    }

    /// The rate of the mean of `n` samples that sum to `sum` counts (NaN for none). The
    /// whole counts of the zero come off the integer sum, so a large zero costs no precision.
    pub fn rate_dph(&self, sum: i64, n: u32) -> f32 {
        if n == 0 {
            return f32::NAN;
        }
        let unit = 10i64.pow(Self::ZERO_DECIMALS);
        let (whole, frac) = (
            self.zero_micro_counts.div_euclid(unit),
            self.zero_micro_counts.rem_euclid(unit),
        );
        let above = sum - whole * n as i64;
        let counts = above as f32 / n as f32 - frac as f32 / unit as f32;
        counts * self.dph_per_count()
    }

    /// A spread of `sd_counts` counts in deg/h.
    pub fn sd_dph(&self, sd_counts: f32) -> f32 {
        sd_counts * self.dph_per_count().abs()
    }

    /// The count an ideal ADC reads at `rate_dph`, unrounded (the twin's ADC, on the host).
    pub fn counts(&self, rate_dph: f64) -> f64 {
        rate_dph / self.scale_f64() + self.zero_f64()
    }

    /// The rate a reading of `counts` stands for, in `f64` (the host's replays).
    pub fn rate_of_counts(&self, counts: f64) -> f64 {
        (counts - self.zero_f64()) * self.scale_f64()
    }

    fn scale_f64(&self) -> f64 {
        self.femto_dph_per_count as f64 / 10i64.pow(Self::SCALE_DECIMALS) as f64
    }

    fn zero_f64(&self) -> f64 {
        self.zero_micro_counts as f64 / 10i64.pow(Self::ZERO_DECIMALS) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_scale_for_two_seconds_at_1khz_is_exact() {
        let mut acc = DwellAccumulator::new(2000);
        for i in 0..2000 {
            acc.push(if i % 2 == 0 { 8_388_607 } else { -8_388_608 + 1 });
        }
        assert_eq!((acc.sum(), acc.samples()), (0, 2000));
        // Alternating +-(2^23 - 1): variance (2^23 - 1)^2 n / (n - 1).
        let want = 8_388_607.0f64.powi(2) * 2000.0 / 1999.0;
        assert!((acc.variance() as f64 / want - 1.0).abs() < 2e-7, "{}", acc.variance());
        assert_eq!(
            (0..4).map(|q| acc.quarter(q)).collect::<std::vec::Vec<_>>(),
            [(0, 500); 4]
        );
    }

    #[test]
    fn the_rate_keeps_what_an_f32_mean_would_lose() {
        // A mean of 5_000_000.25 counts against a zero of 4_999_990.5: f32 cannot hold the
        // mean's fraction, the integer sum can.
        let mut acc = DwellAccumulator::new(2000);
        for i in 0..2000 {
            acc.push(5_000_000 + (i % 4 == 0) as i32);
        }
        let cal = Calibration {
            zero_micro_counts: 4_999_990_500_000,
            femto_dph_per_count: 1_000_000_000_000_000,
        };
        let rate = cal.rate_dph(acc.sum(), acc.samples());
        assert_eq!(rate, 9.75);
        let naive = (acc.sum() as f32 / 2000.0 - 4_999_990.5) * cal.dph_per_count();
        assert_ne!(naive, 9.75);
    }

    #[test]
    fn rates_are_within_a_few_f32_roundings_of_exact() {
        let mut rng = crate::rng::Rng::new(3);
        for _ in 0..10_000 {
            let n = 1 + (rng.next_u64() % 20_000) as u32;
            let mean = rng.uniform(-8_388_608.0, 8_388_607.0);
            let sum = (mean * n as f64).round() as i64;
            let cal = Calibration {
                zero_micro_counts: (rng.uniform(-8.4e12, 8.4e12)).round() as i64,
                femto_dph_per_count: (rng.uniform(1e3, 1e15)).round() as i64 * if rng.unit() < 0.5 { -1 } else { 1 },
            };
            let scale = cal.femto_dph_per_count as f64 * 1e-15;
            let exact = (sum as f64 / n as f64 - cal.zero_micro_counts as f64 * 1e-6) * scale;
            let got = cal.rate_dph(sum, n) as f64;
            // Four roundings of the counts off the zero, two of the scale; and one of the
            // fractional zero (1e-6 count at most 0.06 ulp of one count).
            let counts = sum as f64 / n as f64 - cal.zero_micro_counts as f64 * 1e-6;
            let tol = (counts.abs() * 5.0 * f32::EPSILON as f64 + 1e-7) * scale.abs();
            assert!((got - exact).abs() <= tol, "{got} vs {exact} ({n} samples, {cal:?})");
        }
    }

    #[test]
    fn quarters_split_the_expected_samples() {
        let mut acc = DwellAccumulator::new(8);
        for x in [1, 1, 2, 2, 3, 3, 4, 4] {
            acc.push(x);
        }
        assert_eq!([0, 1, 2, 3].map(|q| acc.quarter(q)), [(2, 2), (4, 2), (6, 2), (8, 2)]);
        // A short dwell keeps what it has.
        let mut short = DwellAccumulator::new(8);
        for x in [5, 5, 6] {
            short.push(x);
        }
        assert_eq!(
            [0, 1, 2, 3].map(|q| short.quarter(q)),
            [(10, 2), (6, 1), (0, 0), (0, 0)]
        );
        let empty = DwellAccumulator::new(4);
        assert!(empty.variance().is_nan() && Calibration::DEFAULT.rate_dph(empty.sum(), 0).is_nan());
        let mut one = DwellAccumulator::new(4);
        one.push(7);
        assert!(one.variance().is_nan());
    }

    #[test]
    fn calibration_round_trip() {
        let c = Calibration {
            zero_micro_counts: 1_234_000_000,
            femto_dph_per_count: 10_000_000_000,
        };
        let counts = c.counts(10.856);
        assert!((counts - (1_085_600.0 + 1234.0)).abs() < 1e-6, "{counts}");
        assert!((c.rate_of_counts(counts) - 10.856).abs() < 1e-12);
        // The default is 50 / 2^23 deg/h per count to 1e-15.
        let d = Calibration::DEFAULT;
        assert!((d.counts(50.0) - 8_388_608.0).abs() < 1e-3);
        assert_eq!(d.dph_per_count(), (50.0f64 / 8_388_608.0) as f32);
        assert_eq!(c.sd_dph(2.0), 2.0e-5);
        assert!(c.is_valid() && d.is_valid());
        for bad in [
            Calibration {
                femto_dph_per_count: 0,
                ..d
            },
            Calibration {
                zero_micro_counts: -Calibration::MAX_ZERO_MICRO_COUNTS - 1,
                ..d
            },
            Calibration {
                femto_dph_per_count: i64::MIN,
                ..d
            },
        ] {
            assert!(!bad.is_valid(), "{bad:?}");
        }
    }
}
