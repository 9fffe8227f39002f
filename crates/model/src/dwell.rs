//! The dwell at one position: exact fixed-point sums of ADC counts.
//!
//! 24-bit samples are summed in `i64` and their squares in `i128`, so 2 s at 1 kHz (or days of
//! samples) lose nothing; the mean and standard deviation are formed once, at the end.

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

/// The statistics of a dwell, in ADC counts.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DwellStats {
    pub samples: u32,
    pub mean: f64,
    /// Sample standard deviation (NaN with fewer than two samples).
    pub sd: f64,
    /// Means of the four consecutive quarters (NaN for an empty quarter).
    pub quarters: [f64; 4],
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

    pub fn stats(&self) -> DwellStats {
        let n = self.n as f64;
        let var = if self.n > 1 {
            // Exact: n * sum(x^2) - sum(x)^2 in integers.
            let num = self.n as i128 * self.sumsq - (self.sum as i128) * (self.sum as i128);
            num as f64 / (n * (n - 1.0))
        } else {
            f64::NAN
        };
        let mut quarters = [f64::NAN; 4];
        for (q, m) in quarters.iter_mut().enumerate() {
            if self.quarter_n[q] > 0 {
                *m = self.quarter_sum[q] as f64 / self.quarter_n[q] as f64;
            }
        }
        DwellStats {
            samples: self.n,
            mean: if self.n > 0 { self.sum as f64 / n } else { f64::NAN },
            sd: num_traits::Float::sqrt(var),
            quarters,
        }
    }
}

/// Counts to deg/h: `rate = (counts - zero) * dph_per_count`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Calibration {
    pub zero_counts: f64,
    pub dph_per_count: f64,
}

impl Default for Calibration {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Calibration {
    /// A rebalance loop giving +-50 deg/h over the ADC's +-2^23 counts.
    pub const DEFAULT: Calibration = Calibration {
        zero_counts: 0.0,
        dph_per_count: 50.0 / 8_388_608.0,
    };

    pub fn rate_dph(&self, counts: f64) -> f64 {
        (counts - self.zero_counts) * self.dph_per_count
    }

    /// The nearest count for a rate (what an ideal ADC would read).
    pub fn counts(&self, rate_dph: f64) -> f64 {
        rate_dph / self.dph_per_count + self.zero_counts
    }

    pub fn sd_dph(&self, sd_counts: f64) -> f64 {
        sd_counts * num_traits::Float::abs(self.dph_per_count)
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
        let s = acc.stats();
        assert_eq!(s.mean, 0.0);
        // Alternating +-(2^23 - 1): sd = (2^23 - 1) sqrt(n / (n - 1)).
        let want = 8_388_607.0 * (2000.0f64 / 1999.0).sqrt();
        assert!((s.sd - want).abs() < 1e-6, "{} {}", s.sd, want);
        assert_eq!(s.quarters, [0.0; 4]);
    }

    #[test]
    fn f32_running_sum_would_lose_what_this_keeps() {
        // A mean of 5_000_000.25 counts: f32 cannot hold the sum's fraction, the integers can.
        let mut acc = DwellAccumulator::new(2000);
        let mut naive = 0.0f32;
        for i in 0..2000 {
            let x = 5_000_000 + (i % 4 == 0) as i32;
            acc.push(x);
            naive += x as f32;
        }
        assert_eq!(acc.stats().mean, 5_000_000.25);
        assert_ne!((naive / 2000.0) as f64, 5_000_000.25);
    }

    #[test]
    fn quarters_split_the_expected_samples() {
        let mut acc = DwellAccumulator::new(8);
        for x in [1, 1, 2, 2, 3, 3, 4, 4] {
            acc.push(x);
        }
        assert_eq!(acc.stats().quarters, [1.0, 2.0, 3.0, 4.0]);
        // A short dwell keeps what it has.
        let mut short = DwellAccumulator::new(8);
        for x in [5, 5, 6] {
            short.push(x);
        }
        let s = short.stats();
        assert_eq!(s.quarters[..2], [5.0, 6.0]);
        assert!(s.quarters[2].is_nan() && s.quarters[3].is_nan());
        assert!(DwellAccumulator::new(4).stats().mean.is_nan());
    }

    #[test]
    fn calibration_round_trip() {
        let c = Calibration {
            zero_counts: 1234.0,
            dph_per_count: 1e-5,
        };
        assert!((c.rate_dph(c.counts(10.856)) - 10.856).abs() < 1e-12);
    }
}
