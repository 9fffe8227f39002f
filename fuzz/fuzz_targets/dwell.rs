//! The dwell accumulator against exact arithmetic. Any `i32` samples (runs of a repeated value
//! reach long dwells), any expected count: the count, the sum and the four quarters' sums and
//! counts are exact; the variance agrees with sums formed in `i128` (as
//! `sum (n x_i - S)^2 / (n^2 (n - 1))`, another exact form than the accumulator's) to a few
//! units of f32 rounding; the mean rate of the default calibration lies within the samples; a
//! sample goes to quarter `min(3, 4 i / expected)`; a rate or variance without samples is NaN.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf_model::dwell::{Calibration, DwellAccumulator};

fn near(got: f64, want: f64, rel: f64) -> bool {
    (got - want).abs() <= rel * want.abs().max(f64::MIN_POSITIVE)
}

fn run(u: &mut Unstructured) -> Result<()> {
    let expected: u32 = if u.arbitrary()? {
        u.int_in_range(0..=64)?
    } else {
        u.arbitrary()?
    };
    let mut xs: Vec<i32> = Vec::new();
    while !u.is_empty() && xs.len() < 1 << 18 {
        let x: i32 = if u.arbitrary()? {
            u.arbitrary()?
        } else {
            u.int_in_range(-(1 << 23)..=(1 << 23) - 1)?
        };
        let times = if u.ratio(1, 32)? {
            u.int_in_range(1..=20_000usize)?
        } else {
            1
        };
        xs.extend(std::iter::repeat_n(x, times.min((1 << 18) - xs.len())));
    }
    let mut acc = DwellAccumulator::new(expected);
    xs.iter().for_each(|&x| acc.push(x));
    let n = xs.len();
    assert_eq!(acc.samples(), n as u32);
    let s: i128 = xs.iter().map(|&x| x as i128).sum();
    assert_eq!(acc.sum() as i128, s);

    let cal = Calibration::DEFAULT;
    let rate = cal.rate_dph(acc.sum(), acc.samples());
    if n == 0 {
        assert!(rate.is_nan() && acc.variance().is_nan());
    } else {
        // The mean, in counts, lies within the samples (to a few f32 roundings).
        let (lo, hi) = (*xs.iter().min().unwrap(), *xs.iter().max().unwrap());
        let mean = rate as f64 / cal.dph_per_count() as f64;
        let slack = 4.0 * f32::EPSILON as f64 * (lo as f64).abs().max((hi as f64).abs());
        assert!(
            mean >= lo as f64 - slack && mean <= hi as f64 + slack,
            "{mean} not in [{lo}, {hi}]"
        );
        assert!(near(mean, s as f64 / n as f64, 8.0 * f32::EPSILON as f64), "{mean}");
    }
    if n < 2 {
        assert!(acc.variance().is_nan());
    } else {
        let nn = n as i128;
        let ss: i128 = xs.iter().map(|&x| (nn * x as i128 - s).pow(2)).sum();
        let var = ss as f64 / ((n as f64) * (n as f64) * (n as f64 - 1.0));
        let got = acc.variance() as f64;
        assert!(
            got >= 0.0 && near(got, var, 8.0 * f32::EPSILON as f64),
            "variance {got} vs {var}"
        );
    }
    let e = expected.max(1) as u64;
    let mut qs = [(0i64, 0u32); 4];
    for (i, &x) in xs.iter().enumerate() {
        let q = ((4 * i as u64) / e).min(3) as usize;
        qs[q].0 += x as i64;
        qs[q].1 += 1;
    }
    for (k, &want) in qs.iter().enumerate() {
        assert_eq!(acc.quarter(k), want, "quarter {k}");
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
