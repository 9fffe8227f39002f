//! The dwell accumulator against exact arithmetic. Any `i32` samples (runs of a repeated value
//! reach long dwells), any expected count: the count is right; the mean, the sample standard
//! deviation and the four quarter means agree with sums formed in `i128` (the variance as
//! `sum (n x_i - S)^2 / (n^2 (n - 1))`, another exact form than the accumulator's) to a few
//! units of f64 rounding; the mean lies within the samples; a sample goes to quarter
//! `min(3, 4 i / expected)`; a quarter or statistic without samples is NaN.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf_model::dwell::DwellAccumulator;

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
    let st = acc.stats();
    let n = xs.len();
    assert_eq!((acc.samples(), st.samples), (n as u32, n as u32));

    let s: i128 = xs.iter().map(|&x| x as i128).sum();
    if n == 0 {
        assert!(st.mean.is_nan() && st.sd.is_nan() && st.quarters.iter().all(|q| q.is_nan()));
        return Ok(());
    }
    let (lo, hi) = (*xs.iter().min().unwrap(), *xs.iter().max().unwrap());
    let slack = 4.0 * f64::EPSILON * (lo as f64).abs().max((hi as f64).abs());
    assert!(
        st.mean >= lo as f64 - slack && st.mean <= hi as f64 + slack,
        "{} not in [{lo}, {hi}]",
        st.mean
    );
    assert!(
        near(st.mean, s as f64 / n as f64, 4.0 * f64::EPSILON),
        "{} {}",
        st.mean,
        s as f64 / n as f64
    );
    if n < 2 {
        assert!(st.sd.is_nan());
    } else {
        let nn = n as i128;
        let ss: i128 = xs.iter().map(|&x| (nn * x as i128 - s).pow(2)).sum();
        let var = ss as f64 / ((n as f64) * (n as f64) * (n as f64 - 1.0));
        assert!(
            st.sd >= 0.0 && near(st.sd * st.sd, var, 1e-12),
            "sd {} var {var}",
            st.sd
        );
    }
    let e = expected.max(1) as u64;
    let mut qs = [(0i128, 0u64); 4];
    for (i, &x) in xs.iter().enumerate() {
        let q = ((4 * i as u64) / e).min(3) as usize;
        qs[q].0 += x as i128;
        qs[q].1 += 1;
    }
    for (k, &(sum, len)) in qs.iter().enumerate() {
        let got = st.quarters[k];
        if len == 0 {
            assert!(got.is_nan(), "quarter {k}: {got}");
        } else {
            assert!(
                near(got, sum as f64 / len as f64, 4.0 * f64::EPSILON),
                "quarter {k}: {got}"
            );
        }
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
