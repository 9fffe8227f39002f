//! Reading static gyro logs (`shared/recording-format.md`, `northfinder-static/1`): one row per
//! sample, columns found by name, a malformed line named with its column. Where time jumps
//! the log is split into contiguous segments, since an Allan variance across a gap would mix
//! averaging times.

use crate::textfile::{self, Error, Head, err, number, optional, short};
use std::collections::BTreeMap;
use std::ops::Range;

pub const FORMAT: &str = "northfinder-static/1";

/// A step longer than this times the median step is a gap, unless the times jitter more.
pub const GAP_FACTOR: f64 = 1.5;
/// Robust sigmas of the steps' own scatter beyond the median that a gap must exceed: with
/// times jittered by a third of a step, a long step is the jitter, not a lost sample.
pub const JITTER_SIGMAS: f64 = 5.0;

/// Steps averaged at a time for the typical step.
const TYPICAL_SPAN: usize = 8;

/// A jump in time between two samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Gap {
    /// Line of the first sample after the gap (0 when not read from a file).
    pub line: usize,
    pub from_s: f64,
    pub to_s: f64,
}

/// How evenly a series is spaced: its step and the runs between gaps.
#[derive(Debug, Clone, PartialEq)]
pub struct Spacing {
    pub step_s: f64,
    /// The resolution the times were rounded to, where coarser than the step; else 0.
    pub resolution_s: f64,
    /// Robust scatter of the single steps about the typical one, s.
    pub jitter_s: f64,
    pub segments: Vec<Range<usize>>,
    pub gaps: Vec<Gap>,
}

impl Spacing {
    /// Splits increasing times `t_s` (at least two) where a step exceeds `GAP_FACTOR` times the
    /// typical step and the steps' own jitter; `lines` gives each sample's line for the report.
    /// The typical step is the median over [`TYPICAL_SPAN`] steps at a time, which jittered
    /// times (a host's time stamps, steps of 0.06 s and 0.14 s in turn at 10 Hz) average out
    /// of, where the median single step would be one of the jitter's values. The step is the
    /// mean within the segments: times rounded to the millisecond at 128 Hz step by 8 ms
    /// mostly, and by 7.8125 ms on average.
    pub fn of(t_s: &[f64], lines: &[usize]) -> Spacing {
        let in_order: Vec<f64> = t_s.windows(2).map(|w| w[1] - w[0]).collect();
        let mut steps = in_order.clone();
        steps.sort_by(f64::total_cmp);
        let median = steps[steps.len() / 2];
        // Short logs keep most of their windows apart from a gap.
        let k = TYPICAL_SPAN.min(in_order.len() / TYPICAL_SPAN).max(1);
        let mut spans: Vec<f64> = t_s.windows(k + 1).map(|w| (w[k] - w[0]) / k as f64).collect();
        spans.sort_by(f64::total_cmp);
        let typical = spans[spans.len() / 2];
        let resolution = rounding(&steps, &in_order, median);
        // Rounded times step by whole counts, most by the median's: their scatter about the
        // typical step is the rounding, which the resolution allows for.
        let centre = if resolution > 0.0 { median } else { typical };
        let jitter = crate::stats::robust_sigma(steps.iter().map(|s| s - centre));
        let gap = typical
            + ((GAP_FACTOR - 1.0) * typical)
                .max(JITTER_SIGMAS * jitter)
                .max(GAP_FACTOR * resolution);
        let (mut segments, mut gaps, mut start) = (Vec::new(), Vec::new(), 0);
        for i in 1..t_s.len() {
            if t_s[i] - t_s[i - 1] > gap {
                segments.push(start..i);
                gaps.push(Gap {
                    line: lines.get(i).copied().unwrap_or(0),
                    from_s: t_s[i - 1],
                    to_s: t_s[i],
                });
                start = i;
            }
        }
        segments.push(start..t_s.len());
        let (span, count) = segments
            .iter()
            .filter(|r| r.len() > 1)
            .fold((0.0, 0usize), |(s, c), r| {
                (s + t_s[r.end - 1] - t_s[r.start], c + r.len() - 1)
            });
        let step_s = if count > 0 { span / count as f64 } else { median };
        Spacing {
            step_s,
            resolution_s: resolution,
            jitter_s: jitter,
            segments,
            gaps,
        }
    }
}

/// The resolution the times were written to, where it is coarser than the step: they then
/// step by whole counts of it (800 Hz written to the millisecond steps by 1 ms and 2 ms), the
/// count next to the median's holds many steps (a twentieth, and three), and the times stay
/// within a count or two of an even grid between gaps; a lost sample is one step, and
/// samples lost often put the times ever later than the grid (a 100 Hz log missing 6 % of
/// its samples steps by 10 ms and 20 ms too). 0 when there is no such resolution.
fn rounding(sorted_steps: &[f64], in_order: &[f64], median: f64) -> f64 {
    let Some(&next) = sorted_steps.iter().find(|&&s| s > median * (1.0 + 1e-6)) else {
        return 0.0;
    };
    // Every step is at least one count, so a count is at most the median step.
    let q = next - median;
    let near = sorted_steps.iter().filter(|&&s| (s - next).abs() < q / 2.0).count();
    if q > median * (1.0 + 1e-6) || near < 3 || near * 20 < sorted_steps.len() {
        return 0.0;
    }
    let counted = |s: f64| s < next + q / 2.0;
    let (sum, count) = in_order
        .iter()
        .filter(|s| counted(**s))
        .fold((0.0, 0usize), |(a, c), s| (a + s, c + 1));
    let mean = sum / count as f64;
    // The distance from the grid, started afresh after each gap.
    let mut off: f64 = 0.0;
    let mut worst: f64 = 0.0;
    for &s in in_order {
        off = if counted(s) { off + s - mean } else { 0.0 };
        worst = worst.max(off.abs());
    }
    if worst <= 2.0 * q { q } else { 0.0 }
}

/// Where the sampling rate changes: the median step of one twentieth of the log against the
/// first twentieth's, beyond a tenth, the times' resolution and the spread of the steps inside
/// a twentieth (times rounded to 1 ms at 133 Hz step by 7 and 8 ms in turn). Lost samples
/// do not move a median; a rate that changes does.
fn rate_change(t_s: &[f64], lines: &[usize], resolution: f64) -> Result<(), Error> {
    const BLOCKS: usize = 20;
    let steps: Vec<f64> = t_s.windows(2).map(|w| w[1] - w[0]).collect();
    let len = steps.len() / BLOCKS;
    if len < 10 {
        return Ok(());
    }
    // Each twentieth's median and interquartile range.
    let blocks: Vec<(f64, f64)> = (0..BLOCKS)
        .map(|k| {
            let mut b = steps[k * len..(k + 1) * len].to_vec();
            b.sort_by(f64::total_cmp);
            (b[len / 2], b[3 * len / 4] - b[len / 4])
        })
        .collect();
    let spread = blocks.iter().map(|b| b.1).fold(f64::MAX, f64::min);
    let first = blocks[0].0;
    let tolerance = (0.1 * first).max(1.5 * resolution).max(1.5 * spread);
    let Some(k) = (1..BLOCKS).find(|&k| (blocks[k].0 - first).abs() > tolerance) else {
        return Ok(());
    };
    let m = blocks[k].0;
    // The first step of the twentieth that is nearer its median than the first one's.
    let at = (k * len..(k + 1) * len)
        .find(|&i| (steps[i] - m).abs() < (steps[i] - first).abs())
        .unwrap_or(k * len);
    err(
        lines.get(at + 1).copied().unwrap_or(0),
        format!(
            "the samples are {} s apart at the start and {} s apart from here (t_s {}): the sampling rate changes, and an Allan deviation needs one; split the log here",
            short(first),
            short(m),
            t_s[at + 1]
        ),
    )
}

/// A whole static log.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticLog {
    /// Every metadata key, known or not, as written.
    pub meta: BTreeMap<String, String>,
    pub t_s: Vec<f64>,
    pub rate_dph: Vec<f64>,
    /// Each sample's line in the file.
    pub lines: Vec<usize>,
    /// Lowest and highest `temp_c`, when the log has that column.
    pub temp_span_c: Option<(f64, f64)>,
    /// The lines whose `temp_c` has no value, when the log has that column.
    pub temp_blank: Vec<usize>,
    pub spacing: Spacing,
    /// The lines of `#` comments among the samples, skipped.
    pub comments: Vec<usize>,
    /// What the reader read with a doubt: free text before the header, a last line cut.
    pub warnings: Vec<Error>,
}

impl StaticLog {
    pub fn parse(text: &str) -> Result<StaticLog, Error> {
        let head = Head::parse(text)?;
        head.require_format(text, FORMAT)?;
        head.known(
            &["format", "sample_rate_hz", "latitude_deg"],
            &["t_s", "rate_dph", "temp_c"],
        )?;
        head.positive_meta("sample_rate_hz", "Hz")?;
        // Not used by the Allan fit, but a value the format defines is checked all the same.
        if let Some(v) = head.meta.get("latitude_deg")
            && !v.parse::<f64>().is_ok_and(|x| x.abs() <= 90.0)
        {
            return err(
                head.meta_line("latitude_deg"),
                format!("latitude_deg '{v}' is not a latitude in degrees (-90 to 90)"),
            );
        }
        head.require_columns(&["t_s", "rate_dph"])?;
        let required = |name: &str| head.col(name).expect("required column");
        let (ct, cr, ctemp) = (required("t_s"), required("rate_dph"), head.col("temp_c"));
        let (mut t_s, mut rate_dph, mut lines) = (Vec::new(), Vec::new(), Vec::new());
        let mut temp_span_c: Option<(f64, f64)> = None;
        let mut temp_blank = Vec::new();
        for row in head.rows(text) {
            let (n, cells) = row?;
            let t = number(n, "t_s", &cells[ct])?;
            let r = number(n, "rate_dph", &cells[cr])?;
            if let Some(&prev) = t_s.last()
                && t <= prev
            {
                return err(
                    n,
                    format!(
                        "t_s {t} is not after the previous sample's {prev} (line {}): samples must be in increasing time",
                        lines.last().copied().unwrap_or(0)
                    ),
                );
            }
            if let Some(c) = ctemp {
                match optional(n, "temp_c", &cells[c])? {
                    Some(v) => temp_span_c = Some(temp_span_c.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v)))),
                    None => temp_blank.push(n),
                }
            }
            t_s.push(t);
            rate_dph.push(r);
            lines.push(n);
        }
        if t_s.len() < 2 {
            let s = if t_s.len() == 1 { "" } else { "s" };
            return err(0, format!("the log has {} sample{s}: no time step to read", t_s.len()));
        }
        let spacing = Spacing::of(&t_s, &lines);
        rate_change(&t_s, &lines, spacing.resolution_s)?;
        let warnings = head
            .free_text()
            .into_iter()
            .chain(textfile::unended(text, "sample", || lines.last().copied()))
            .collect();
        Ok(StaticLog {
            comments: head.comment_lines(),
            warnings,
            meta: head.meta,
            t_s,
            rate_dph,
            lines,
            temp_span_c,
            temp_blank,
            spacing,
        })
    }

    /// The rates of each contiguous segment.
    pub fn segments(&self) -> Vec<&[f64]> {
        self.spacing
            .segments
            .iter()
            .map(|r| &self.rate_dph[r.clone()])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "# format = northfinder-static/1\n# sample_rate_hz = 10\n";

    #[test]
    fn reads_columns_in_any_order_and_splits_at_gaps() {
        let text =
            format!("{HEAD}rate_dph,temp_c,t_s\n1.0,40.1,0.0\n2.0,,0.1\n3.0,40.3,0.2\n4.0,40.2,0.5\n5.0,40.2,0.6\n");
        let log = StaticLog::parse(&text).unwrap();
        assert_eq!(log.rate_dph, vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(log.temp_span_c, Some((40.1, 40.3)));
        assert_eq!(log.temp_blank, vec![5]);
        assert!((log.spacing.step_s - 0.1).abs() < 1e-12);
        assert_eq!(log.spacing.segments, vec![0..3, 3..5]);
        assert_eq!(log.spacing.gaps[0].line, 7);
        assert_eq!(log.segments()[1], &[4.0, 5.0]);
        assert_eq!(log.meta["sample_rate_hz"], "10");
        assert!(log.warnings.is_empty());
        let cut = StaticLog::parse(&format!("# rig 4\n{}", text.trim_end())).unwrap();
        let said: Vec<String> = cut.warnings.iter().map(Error::to_string).collect();
        assert_eq!(said.len(), 2, "{said:?}");
        assert!(said[0].starts_with("line 1: free text before the header"), "{said:?}");
        assert!(
            said[1].starts_with("line 9: the last sample has no line end"),
            "{said:?}"
        );
    }

    /// A static log's text of `t` and a constant rate.
    fn log_of(t: impl Iterator<Item = f64>) -> StaticLog {
        let rows: String = t.map(|t| format!("{t},1\n")).collect();
        StaticLog::parse(&format!("{HEAD}t_s,rate_dph\n{rows}")).unwrap()
    }

    #[test]
    fn rounded_and_jittered_times_give_the_mean_step_and_a_lost_sample_is_still_a_gap() {
        // 128 Hz written to the millisecond: steps of 7 and 8 ms, 7.8125 ms on average.
        let rounded = log_of((0..4000).map(|i| (i as f64 / 128.0 * 1000.0).round() / 1000.0));
        assert!(
            (rounded.spacing.step_s - 1.0 / 128.0).abs() < 1e-6,
            "{}",
            rounded.spacing.step_s
        );
        assert!(rounded.spacing.gaps.is_empty());
        // 100 Hz with +-3 ms of jitter: no gaps.
        let mut rng = nf_model::rng::Rng::new(3);
        let jittered = log_of((0..4000).map(|i| i as f64 * 0.01 + rng.uniform(-0.003, 0.003)));
        assert!(jittered.spacing.gaps.is_empty(), "{:?}", jittered.spacing.gaps.first());
        assert!((jittered.spacing.step_s - 0.01).abs() < 1e-5);
        // 800 Hz written to the millisecond: steps of 1 and 2 ms, and a lost sample there a
        // step of 3 ms (2.5 ms).
        let ms = |i: usize| (i as f64 / 800.0 * 1000.0).round() / 1000.0;
        let coarse = log_of((0..4000).map(ms));
        assert!(coarse.spacing.gaps.is_empty(), "{:?}", coarse.spacing.gaps.first());
        assert!((coarse.spacing.step_s - 1.0 / 800.0).abs() < 1e-6);
        let coarse_lost = log_of((0..4000).filter(|&i| i != 1001).map(ms));
        assert_eq!(coarse_lost.spacing.segments, vec![0..1001, 1001..3999]);
        // 10 Hz stamped 0.04 s late every other sample: steps of 0.06 s and 0.14 s in turn.
        let alternate = log_of((0..4000).map(|i| i as f64 * 0.1 + if i % 2 == 0 { 0.04 } else { 0.0 }));
        assert!(
            alternate.spacing.gaps.is_empty(),
            "{:?}",
            alternate.spacing.gaps.first()
        );
        assert!(
            (alternate.spacing.step_s - 0.1).abs() < 1e-4,
            "{}",
            alternate.spacing.step_s
        );
        assert!((alternate.spacing.jitter_s - 0.04 * 1.4826).abs() < 1e-3);
        // A pause of a minute among them is still a gap.
        let paused = log_of(
            (0..4000)
                .map(|i| i as f64 * 0.1 + if i % 2 == 0 { 0.04 } else { 0.0 } + if i >= 2500 { 60.0 } else { 0.0 }),
        );
        assert_eq!(paused.spacing.segments, vec![0..2500, 2500..4000]);
        // A sample lost from a clean log.
        let lost = log_of((0..4000).filter(|&i| i != 2000).map(|i| i as f64 * 0.01));
        assert_eq!(lost.spacing.segments, vec![0..2000, 2000..3999]);
        assert!((lost.spacing.step_s - 0.01).abs() < 1e-12);
    }

    #[test]
    fn samples_lost_often_are_each_a_gap_and_not_a_rounding() {
        // 100 Hz, one sample in 16 lost at random, times to 10 us: steps of 10 ms and 20 ms,
        // as a log rounded to 10 ms would have, but the times walk off any even grid.
        let mut rng = nf_model::rng::Rng::new(8);
        let kept: Vec<usize> = (0..20_000).filter(|_| rng.unit() >= 1.0 / 16.0).collect();
        let lost = log_of(kept.iter().map(|&i| (i as f64 * 0.01 * 1e5).round() / 1e5));
        let singles = kept.windows(2).filter(|w| w[1] - w[0] > 1).count();
        assert_eq!(lost.spacing.resolution_s, 0.0);
        assert_eq!(lost.spacing.gaps.len(), singles);
        assert!((lost.spacing.step_s - 0.01).abs() < 1e-9, "{}", lost.spacing.step_s);
    }

    #[test]
    fn a_rate_that_changes_is_refused_where_it_changes() {
        // 100 Hz for 30 s, then 50 Hz.
        let t = (0..3000)
            .map(|i| i as f64 * 0.01)
            .chain((0..1500).map(|i| 30.0 + i as f64 * 0.02));
        let text: String = t.map(|t| format!("{t:.5},1\n")).collect();
        let e = StaticLog::parse(&format!("{HEAD}t_s,rate_dph\n{text}")).unwrap_err();
        // Line 4 holds t = 0; the first step of 20 ms ends at t = 30.02, line 3005.
        assert_eq!(e.line, 3005, "{e}");
        assert!(
            e.to_string().contains("0.01 s apart at the start and 0.02 s apart"),
            "{e}"
        );
        // Times rounded to the millisecond at 133.3 Hz step by 7 and 8 ms in turn: one rate.
        let text: String = (0..4000)
            .map(|i| format!("{:.3},1\n", (i as f64 * 7.5).round() / 1000.0))
            .collect();
        let even = StaticLog::parse(&format!("{HEAD}t_s,rate_dph\n{text}"));
        assert!(even.is_ok(), "{:?}", even.err());
    }

    #[test]
    fn every_bad_log_names_the_line_and_the_column() {
        let cases: &[(&str, usize, &str)] = &[
            ("t_s,rate_dph\n0,1\n", 0, "'format' is missing"),
            (
                "# format = northfinder-recording/1\nt_s,rate_dph\n0,1\n",
                1,
                "not supported",
            ),
            (
                "# format = northfinder-static/1\nt_s,rate\n0,1\n",
                2,
                "'rate_dph' is missing",
            ),
            (
                "# format = northfinder-static/1\nt_s,rate_dph\n0,1\n1,x\n",
                4,
                "rate_dph 'x'",
            ),
            (
                "# format = northfinder-static/1\n# sample_rate_hz = -5\nt_s,rate_dph\n0,1\n",
                2,
                "sample_rate_hz '-5' is not a positive number of Hz",
            ),
            (
                "# format = northfinder-static/1\nt_s,rate_dph\n0,1\n1,inf\n",
                4,
                "rate_dph 'inf'",
            ),
            (
                "# format = northfinder-static/1\nt_s,rate_dph\n0,1\n1,2\n1,3\n",
                5,
                "not after",
            ),
            ("# format = northfinder-static/1\nt_s,rate_dph\n0,1\n1\n", 4, "1 fields"),
            (
                "# format = northfinder-static/1\nt_s,rate_dph\n0,1\n",
                0,
                "has 1 sample:",
            ),
            (
                "# format = northfinder-static/1\n# latitude_deg = 95\nt_s,rate_dph\n0,1\n1,2\n",
                2,
                "latitude_deg '95' is not a latitude",
            ),
            (
                "# format = northfinder-static/1\nt_s,rate_dph,temp_c\n0,1,x\n",
                3,
                "temp_c 'x'",
            ),
        ];
        for (text, line, what) in cases {
            let e = StaticLog::parse(text).unwrap_err();
            assert_eq!(e.line, *line, "{text}: {e}");
            assert!(e.to_string().contains(what), "{text}: {e}");
        }
    }
}
