//! What `nf allan` reads, as one rate series: a static log's samples, or a recording's dwell
//! means in time order with the Earth-rate harmonic and the bias removed. Either way it comes
//! with its sampling (step and averaging window), its contiguous segments, and notes on what
//! was assumed.

use crate::allan::{MIN_CLUSTERS, MIN_POINTS, octaves};
use crate::allan_model::Sampling;
use crate::allan_removed::Removed;
use crate::dwells;
use crate::gap_bridge;
use crate::linfit;
use crate::recording::{self, Recording};
use crate::spikes;
use crate::static_log::{self, GAP_FACTOR, Spacing, StaticLog};
use crate::textfile::{Error, Head, blank_cells, err, short};

/// A number for a note: six decimals at most, no trailing zeros.

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    StaticLog,
    Recording,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::StaticLog => "static_log",
            Kind::Recording => "recording",
        }
    }
}

#[derive(Debug, Clone)]
pub struct Source {
    pub kind: Kind,
    pub rates: Vec<f64>,
    pub spacing: Spacing,
    pub sampling: Sampling,
    /// What was fitted out of a recording's dwell means before (its columns in time order).
    pub removed: Option<Removed>,
    pub notes: Vec<String>,
}

impl Source {
    /// Reads either format, told apart by its `format` metadata; `sample_rate_hz` overrides
    /// the step the time column gives. A static log's spikes are left out unless
    /// `keep_spikes`.
    pub fn parse(text: &str, sample_rate_hz: Option<f64>, keep_spikes: bool) -> Result<Source, Error> {
        let head = Head::parse(text)?;
        let src = match head.meta.get("format").map(String::as_str) {
            Some(static_log::FORMAT) => from_static(StaticLog::parse(text)?, sample_rate_hz, keep_spikes),
            Some(recording::FORMAT) => from_recording(&Recording::parse(text)?, sample_rate_hz)?,
            other => {
                let what = other.map_or_else(
                    || format!("no 'format' metadata{}", head.misplaced(text, "format")),
                    |f| format!("format '{f}'"),
                );
                return err(
                    0,
                    format!(
                        "{what}: nf allan reads '# format = {}' (a static log) or '# format = {}'",
                        static_log::FORMAT,
                        recording::FORMAT
                    ),
                );
            }
        };
        src.long_enough()?;
        Ok(src)
    }

    pub fn segments(&self) -> Vec<&[f64]> {
        self.spacing.segments.iter().map(|r| &self.rates[r.clone()]).collect()
    }

    fn long_enough(&self) -> Result<(), Error> {
        let longest = self.spacing.segments.iter().map(|r| r.len()).max().unwrap_or(0);
        let points = octaves(longest).len();
        if points >= MIN_POINTS {
            return Ok(());
        }
        let need = MIN_CLUSTERS << (MIN_POINTS - 1);
        err(
            0,
            format!(
                "too short for an Allan fit: the longest contiguous run has {longest} values, which give {points} averaging times with {MIN_CLUSTERS} clusters each; the fit needs {MIN_POINTS} (at least {need} contiguous values)"
            ),
        )
    }
}

/// The step: the override, else the time column's median step (with a note where the
/// metadata's rate disagrees).
fn step_of(spacing: &Spacing, meta_rate: Option<f64>, override_hz: Option<f64>, notes: &mut Vec<String>) -> f64 {
    let off = |rate: f64| (rate * spacing.step_s - 1.0).abs() > 0.01;
    if let Some(hz) = override_hz {
        if off(hz) {
            notes.push(format!(
                "--sample-rate {hz} Hz sets the step to {} s; the time column steps by {} s (gaps are still found from it)",
                short(1.0 / hz),
                short(spacing.step_s)
            ));
        }
        return 1.0 / hz;
    }
    // Times rounded to a coarse resolution scatter by it, which `rounding` already says.
    if spacing.resolution_s == 0.0 && spacing.jitter_s > JITTER_NOTED * spacing.step_s {
        notes.push(format!(
            "t_s steps scatter by {} s (robust sd) about {} s: jittered time stamps, the samples read as evenly spaced between gaps",
            short(spacing.jitter_s),
            short(spacing.step_s)
        ));
    }
    if let Some(hz) = meta_rate.filter(|hz| off(*hz)) {
        notes.push(format!(
            "metadata sample_rate_hz = {hz}, but t_s steps by {} s: the time column is used (--sample-rate overrides)",
            short(spacing.step_s)
        ));
    }
    spacing.step_s
}

/// Steps that scatter by more than this share of the step are noted as jittered times.
const JITTER_NOTED: f64 = 0.01;

/// Gaps listed one by one up to this many; a log with more (jittered times) gets a count.
const GAPS_LISTED: usize = 10;

fn gap_notes(spacing: &Spacing, notes: &mut Vec<String>) {
    for g in spacing.gaps.iter().take(GAPS_LISTED) {
        notes.push(format!(
            "gap at line {}: time jumps from {} s to {} s",
            g.line,
            short(g.from_s),
            short(g.to_s)
        ));
    }
    if spacing.gaps.len() > GAPS_LISTED {
        notes.push(format!(
            "and {} more gaps (steps over {GAP_FACTOR} times the median step and beyond the times' jitter)",
            spacing.gaps.len() - GAPS_LISTED
        ));
    }
    if spacing.segments.len() > 1 {
        notes.push(format!(
            "the log is split into {} contiguous segments: the Allan variance pools their second differences, none spans a gap",
            spacing.segments.len()
        ));
    }
}

fn from_static(log: StaticLog, override_hz: Option<f64>, keep_spikes: bool) -> Source {
    let mut notes = Vec::new();
    let meta_rate = log.meta.get("sample_rate_hz").and_then(|v| v.parse().ok());
    let step = step_of(&log.spacing, meta_rate, override_hz, &mut notes);
    if let Some((lo, hi)) = log.temp_span_c {
        notes.push(format!("temp_c from {lo} to {hi} C"));
    }
    if !log.temp_blank.is_empty() {
        notes.push(blank_cells("temp_c", &log.temp_blank, log.t_s.len(), "samples"));
    }
    notes.extend(log.warnings.iter().map(Error::to_string));
    if !log.comments.is_empty() {
        notes.push(format!(
            "'#' lines among the samples (lines {}) are comments: skipped",
            crate::noise_fit::lines_text(&log.comments)
        ));
    }
    let found = spikes::find(&log.rate_dph, &log.spacing.segments);
    spike_notes(&found, &log, keep_spikes, &mut notes);
    let mut spacing = log.spacing;
    if !keep_spikes {
        spacing.segments = spikes::split(&spacing.segments, &found);
    }
    let bridged = gap_bridge::bridge(&log.rate_dph, &log.t_s, &spacing.segments, spacing.step_s);
    if bridged.gaps > 0 {
        notes.push(format!(
            "{} gaps of at most {} lost samples (or spikes left out) bridged: {} samples ({:.3} % of the log) filled with the mean of the samples around each, so the averaging times run as long as the whole log allows",
            bridged.gaps,
            gap_bridge::MAX_LOST,
            bridged.filled,
            100.0 * bridged.filled as f64 / bridged.rates.len() as f64
        ));
    }
    spacing.segments = bridged.segments;
    gap_notes(&spacing, &mut notes);
    Source {
        kind: Kind::StaticLog,
        rates: bridged.rates,
        spacing,
        sampling: Sampling::contiguous(step),
        removed: None,
        notes,
    }
}

/// Spikes listed one by one up to this many.
const SPIKES_LISTED: usize = 10;

fn spike_notes(found: &[spikes::Spike], log: &StaticLog, kept: bool, notes: &mut Vec<String>) {
    for s in found.iter().take(SPIKES_LISTED) {
        notes.push(format!(
            "spike at line {}: rate_dph {} is {} robust sigmas off its neighbours or the log",
            log.lines[s.index],
            short(log.rate_dph[s.index]),
            short(s.sigmas.round())
        ));
    }
    if found.len() > SPIKES_LISTED {
        notes.push(format!("and {} more spikes", found.len() - SPIKES_LISTED));
    }
    if !found.is_empty() {
        notes.push(if kept {
            format!("the {} spikes are kept (--keep-spikes)", found.len())
        } else {
            format!(
                "the {} spikes (beyond {} robust sigmas: no gyro noise) are left out as lost samples are; --keep-spikes keeps them",
                found.len(),
                spikes::SIGMAS
            )
        });
    }
}

fn from_recording(rec: &Recording, override_hz: Option<f64>) -> Result<Source, Error> {
    let mut rows: Vec<&recording::Row> = rec.rows.iter().collect();
    rows.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    if let Some(w) = rows.windows(2).find(|w| w[1].t_s <= w[0].t_s) {
        return err(
            w[1].line,
            format!("t_s {} repeats line {}'s: dwell times must differ", w[1].t_s, w[0].line),
        );
    }
    if rows.len() < 2 {
        return err(0, "one position: no time step to read");
    }
    let y: Vec<f64> = rows.iter().map(|r| r.rate_dph).collect();
    let ones = vec![1.0; y.len()];
    let cos: Vec<f64> = rows.iter().map(|r| r.encoder_deg.to_radians().cos()).collect();
    let sin: Vec<f64> = rows.iter().map(|r| r.encoder_deg.to_radians().sin()).collect();
    let mut notes = vec![
        "a recording: its dwell means in time order, so only averaging times of a dwell cycle and longer are visible"
            .to_string(),
    ];
    notes.extend(rec.warnings.iter().map(Error::to_string));
    let harmonic = vec![ones.clone(), cos, sin];
    let (rates, removed) = match linfit::fit(&harmonic, &y) {
        Some(ls) => {
            notes.push("the Earth-rate harmonic and the bias (A cos + B sin + C, least squares) are removed first: the slowest noise is partly absorbed".into());
            (ls.resid, Removed::new(harmonic))
        }
        None => {
            notes.push("the positions do not determine a harmonic: only the mean is removed".into());
            let rates = linfit::fit(std::slice::from_ref(&ones), &y).map_or(y, |ls| ls.resid);
            (rates, Removed::new(vec![ones]))
        }
    };
    let t: Vec<f64> = rows.iter().map(|r| r.t_s).collect();
    let lines: Vec<usize> = rows.iter().map(|r| r.line).collect();
    let spacing = Spacing::of(&t, &lines);
    // The loss is reckoned over one contiguous series; across gaps it is left out.
    let removed = removed.filter(|_| spacing.segments.len() == 1);
    notes.push(match removed {
        Some(_) => "the fit allows for what the removed columns took from each averaging time".into(),
        None => "the fit does not allow for what the removal took: the log has gaps".into(),
    });
    let step = step_of(&spacing, None, override_hz, &mut notes);
    let dw = dwells::of(rec);
    let (dwell, from) = (dw.nominal_s, dw.from);
    let window = dwell.min(step);
    notes.push(format!(
        "one mean every {} s, each over {} s ({from}): the fit allows for the dead time between them",
        short(step),
        short(window)
    ));
    gap_notes(&spacing, &mut notes);
    Ok(Source {
        kind: Kind::Recording,
        rates,
        spacing,
        sampling: Sampling {
            step_s: step,
            window_s: window,
        },
        removed,
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tells_the_formats_apart_and_says_what_it_assumed() {
        let mut s = String::from("# format = northfinder-static/1\n# sample_rate_hz = 5\nt_s,rate_dph\n");
        for i in 0..100 {
            s += &format!("{},{}\n", i as f64 * 0.1, (i % 3) as f64);
        }
        let src = Source::parse(&s, None, false).unwrap();
        assert_eq!((src.kind, src.rates.len()), (Kind::StaticLog, 100));
        assert!(src.sampling.is_contiguous() && (src.sampling.step_s - 0.1).abs() < 1e-12);
        assert!(src.notes[0].contains("sample_rate_hz = 5"), "{:?}", src.notes);
        let over = Source::parse(&s, Some(5.0), false).unwrap();
        assert!((over.sampling.step_s - 0.2).abs() < 1e-12);
        let e = Source::parse("# format = other/1\nt_s,rate_dph\n0,1\n", None, false).unwrap_err();
        assert!(e.what.contains("format 'other/1'"), "{e}");
    }

    #[test]
    fn a_blank_temperature_is_said_with_its_lines() {
        let mut s = String::from("# format = northfinder-static/1\nt_s,rate_dph,temp_c\n");
        for i in 0..2000 {
            let temp = if i % 300 == 7 { String::new() } else { "40.0".into() };
            s += &format!("{},{},{temp}\n", i as f64 * 0.1, (i % 3) as f64);
        }
        let src = Source::parse(&s, None, false).unwrap();
        let note = src.notes.iter().find(|n| n.starts_with("temp_c: no value"));
        assert_eq!(
            note.map(String::as_str),
            Some(
                "temp_c: no value on 7 of 2000 samples (lines 10, 310, 610, 910, 1210, ...): read as not recorded there"
            ),
            "{:?}",
            src.notes
        );
    }

    #[test]
    fn a_recording_loses_its_harmonic_and_keeps_its_dead_time() {
        // 80 dwells, from the 71st on `gap_s` later.
        let text = |gap_s: f64| {
            let mut s = String::from(
                "# format = northfinder-recording/1\n# latitude_deg = 40\n# dwell_s = 2\nindex,t_s,encoder_deg,rate_dph\n",
            );
            for i in 0..80 {
                let g = (i * 45 % 360) as f64;
                let noise = if i % 2 == 0 { 0.01 } else { -0.01 };
                let t = 3.0 * i as f64 + 1.0 + if i >= 70 { gap_s } else { 0.0 };
                s += &format!("{i},{t},{g},{}\n", 11.5 * g.to_radians().cos() + 0.3 + noise);
            }
            s
        };
        let s = text(0.0);
        let src = Source::parse(&s, None, false).unwrap();
        assert_eq!(src.kind, Kind::Recording);
        assert!(src.rates.iter().all(|r| r.abs() < 0.02), "{:?}", &src.rates[..4]);
        assert_eq!((src.sampling.step_s, src.sampling.window_s), (3.0, 2.0));
        // The columns removed go with it, for the fit to allow for, unless the log has a gap.
        assert_eq!(src.removed.as_ref().map(Removed::values), Some(80));
        assert!(
            src.notes
                .iter()
                .any(|n| n.contains("allows for what the removed columns took"))
        );
        let src = Source::parse(&text(40.0), None, false).unwrap();
        assert!(src.removed.is_none() && src.notes.iter().any(|n| n.contains("the log has gaps")));
        // 40 means are too few: four octaves need 64.
        let short: String = s.lines().take(4 + 40).map(|l| format!("{l}\n")).collect();
        assert!(
            Source::parse(&short, None, false)
                .unwrap_err()
                .what
                .contains("too short")
        );
    }
}
