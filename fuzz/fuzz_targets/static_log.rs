//! The static-log reader on any text: no panic; times strictly increase; the segments cover
//! the samples in order, split exactly where a step exceeds the typical step (the median of
//! the mean steps over eight at a time, fewer in a short log) by `GAP_FACTOR` times it, by
//! `JITTER_SIGMAS` robust sigmas of the steps and, for times written coarser than the step,
//! by `GAP_FACTOR` counts of their resolution; the step is the mean within the segments; and
//! printing the log back in the format and reading it again gives the same log.
#![no_main]

use libfuzzer_sys::fuzz_target;
use nf::static_log::{GAP_FACTOR, JITTER_SIGMAS, StaticLog};
use std::fmt::Write;

fn print(log: &StaticLog) -> String {
    let mut s = String::new();
    for (k, v) in &log.meta {
        let _ = writeln!(s, "# {k} = {v}");
    }
    s += "t_s,rate_dph\n";
    for (t, r) in log.t_s.iter().zip(&log.rate_dph) {
        let _ = writeln!(s, "{t},{r}");
    }
    s
}

fuzz_target!(|data: &[u8]| {
    let text = nf_fuzz::text(data);
    let Ok(log) = StaticLog::parse(&text) else {
        return;
    };
    let n = log.t_s.len();
    assert!(n >= 2 && log.rate_dph.len() == n);
    assert!(log.t_s.windows(2).all(|w| w[0] < w[1]), "times increase");
    assert!(log.t_s.iter().chain(&log.rate_dph).all(|x| x.is_finite()));
    if let Some((lo, hi)) = log.temp_span_c {
        assert!(lo <= hi && lo.is_finite() && hi.is_finite());
    }
    // The gap threshold from the median step and the steps' median distance from it.
    let sp = &log.spacing;
    let steps: Vec<f64> = log.t_s.windows(2).map(|w| w[1] - w[0]).collect();
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let m = median(steps.clone());
    let k = (steps.len() / 8).clamp(1, 8);
    let typical = median(log.t_s.windows(k + 1).map(|w| (w[k] - w[0]) / k as f64).collect());
    // Times written coarser than the step step by whole counts: the smallest step above the
    // median, when it is one count above it (at most the median) and at least three steps and a
    // twentieth of them lie within half a count of it, allows GAP_FACTOR counts more.
    let above = steps
        .iter()
        .copied()
        .filter(|&s| s > m * (1.0 + 1e-6))
        .fold(f64::INFINITY, f64::min);
    let count = above - m;
    let near = steps.iter().filter(|&&s| (s - above).abs() < count / 2.0).count();
    let coarse = above.is_finite() && count <= m * (1.0 + 1e-6) && near >= 3 && near * 20 >= steps.len();
    let resolution = if coarse { count } else { 0.0 };
    // Rounded times scatter about the median step by whole counts; jittered ones about the
    // typical step.
    let centre = if coarse { m } else { typical };
    let jitter = 1.4826 * median(steps.iter().map(|s| (s - centre).abs()).collect());
    let threshold = typical
        + ((GAP_FACTOR - 1.0) * typical)
            .max(JITTER_SIGMAS * jitter)
            .max(GAP_FACTOR * resolution);
    // The step: the mean step within the segments of two samples or more.
    let (span, count) = sp.segments.iter().filter(|r| r.len() > 1).fold((0.0, 0), |(s, c), r| {
        (s + log.t_s[r.end - 1] - log.t_s[r.start], c + r.len() - 1)
    });
    let mean = if count > 0 { span / count as f64 } else { m };
    assert!(
        sp.step_s > 0.0 && (sp.step_s - mean).abs() <= 1e-9 * mean,
        "{} vs {mean}",
        sp.step_s
    );
    // Segments: contiguous, covering, split at the gaps only.
    assert_eq!(sp.segments.first().map(|r| r.start), Some(0));
    assert_eq!(sp.segments.last().map(|r| r.end), Some(n));
    assert_eq!(sp.gaps.len() + 1, sp.segments.len());
    for (w, gap) in sp.segments.windows(2).zip(&sp.gaps) {
        let i = w[0].end;
        assert_eq!(w[1].start, i);
        assert!(log.t_s[i] - log.t_s[i - 1] > threshold);
        assert_eq!((gap.from_s, gap.to_s), (log.t_s[i - 1], log.t_s[i]));
        assert!(gap.line > 0);
    }
    for seg in &sp.segments {
        assert!(!seg.is_empty());
        for i in seg.start + 1..seg.end {
            assert!(log.t_s[i] - log.t_s[i - 1] <= threshold);
        }
    }
    assert_eq!(log.segments().iter().map(|s| s.len()).sum::<usize>(), n);
    // Printed and read again.
    let printed = print(&log);
    let again = StaticLog::parse(&printed).unwrap_or_else(|e| panic!("{e}\n{printed}"));
    assert_eq!(
        (&again.t_s, &again.rate_dph, &again.meta),
        (&log.t_s, &log.rate_dph, &log.meta)
    );
    assert_eq!(
        (again.spacing.step_s, &again.spacing.segments),
        (sp.step_s, &sp.segments)
    );
});
