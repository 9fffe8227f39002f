//! Reading recordings (`shared/recording-format.md`) written by any program: columns in any
//! order, extra columns and metadata ignored, optional columns may be missing. A malformed
//! line is an error that names the line and the problem; nothing is guessed.
//!
//! `index` is the visit number, so a repeated index is a duplicate: an error naming both lines,
//! unless the two lines are the same, when the copy is dropped with a warning. The same encoder
//! angle on two rows is fine: a run may visit a position twice (`order = forward-back`).

pub use crate::textfile::Error;
use crate::textfile::{
    self, Head, blank_cells, err, is_missing, number, optional as optional_cell, read_text, short, shown,
};
use std::collections::BTreeMap;

pub const FORMAT: &str = "northfinder-recording/1";

/// One position.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Line number in the file (from 1).
    pub line: usize,
    pub index: u32,
    pub t_s: f64,
    pub encoder_deg: f64,
    pub rate_dph: f64,
    pub rate_sd_dph: Option<f64>,
    pub samples: Option<u32>,
    pub temp_c: Option<f64>,
    pub tilt_x_deg: Option<f64>,
    pub tilt_y_deg: Option<f64>,
    pub quarters_dph: Option<[f64; 4]>,
}

/// A whole recording.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    pub latitude_deg: f64,
    /// Every metadata key, known or not, as written.
    pub meta: BTreeMap<String, String>,
    pub rows: Vec<Row>,
    /// What the reader accepted but the user should hear of (a dropped copy of a line).
    pub warnings: Vec<Error>,
}

const REQUIRED: [&str; 4] = ["index", "t_s", "encoder_deg", "rate_dph"];

/// The quarter means' columns, in order.
const QUARTERS: [&str; 4] = ["q1_dph", "q2_dph", "q3_dph", "q4_dph"];
/// Every column the reader uses: each may be given once only.
const COLUMNS: [&str; 13] = [
    "index",
    "t_s",
    "encoder_deg",
    "rate_dph",
    "rate_sd_dph",
    "samples",
    "temp_c",
    "tilt_x_deg",
    "tilt_y_deg",
    "q1_dph",
    "q2_dph",
    "q3_dph",
    "q4_dph",
];
/// The optional columns, as the fit uses them: the quarters are one.
const OPTIONAL_GROUPS: [(&str, &[&str]); 6] = [
    ("rate_sd_dph", &["rate_sd_dph"]),
    ("samples", &["samples"]),
    ("temp_c", &["temp_c"]),
    ("tilt_x_deg", &["tilt_x_deg"]),
    ("tilt_y_deg", &["tilt_y_deg"]),
    ("q1_dph .. q4_dph", &QUARTERS),
];

/// The lines on which an optional column has no value (empty, NaN, NA, null, ...): read as
/// not recorded there, and said once per column so that no value goes unremarked.
#[derive(Default)]
struct Blanks {
    lines: BTreeMap<&'static str, Vec<usize>>,
}

impl Blanks {
    fn add(&mut self, column: &'static str, line: usize) {
        self.lines.entry(column).or_default().push(line);
    }

    fn warnings(&self, rows: usize) -> Vec<Error> {
        self.lines
            .iter()
            .map(|(column, lines)| Error {
                line: lines[0],
                what: blank_cells(column, lines, rows, "positions"),
            })
            .collect()
    }
}

/// The metadata the readers of a recording use: each may be given once only.
const KEYS: [&str; 4] = ["format", "latitude_deg", "dwell_s", "sample_rate_hz"];
/// A rate no gyro gives (3e8 deg/s): a value this size is a fault, and its square would
/// leave no precision for the others.
const MAX_RATE_DPH: f64 = 1e12;
/// Encoder angles closer than this are one angle (the format writes 1e-7 deg).
const ANGLE_RESOLUTION_DEG: f64 = 1e-6;

impl Recording {
    pub fn parse(text: &str) -> Result<Recording, Error> {
        let head = Head::parse(text)?;
        head.require_format(text, FORMAT)?;
        head.known(&KEYS, &COLUMNS)?;
        let meta = head.meta.clone();
        let at = head.meta_line("latitude_deg");
        let latitude_deg: f64 = match meta.get("latitude_deg") {
            None => {
                return err(
                    0,
                    format!(
                        "required metadata 'latitude_deg' is missing{}",
                        head.misplaced(text, "latitude_deg")
                    ),
                );
            }
            Some(v) => match v.parse::<f64>() {
                Ok(l) if l.abs() < 90.0 => l,
                Ok(l) if l.abs() == 90.0 => {
                    return err(
                        at,
                        format!(
                            "latitude_deg {v} is a pole: the Earth rate has no horizontal component there, so there is no north to find"
                        ),
                    );
                }
                _ => {
                    return err(
                        at,
                        format!("latitude_deg '{}' is not a latitude in degrees (-90 to 90)", shown(v)),
                    );
                }
            },
        };
        let dwell_s = head.positive_meta("dwell_s", "seconds")?;
        head.positive_meta("sample_rate_hz", "Hz")?;
        head.require_columns(&REQUIRED)?;
        let col = |name: &str| head.col(name).expect("required column");
        let mut rows = Vec::new();
        let mut warnings = Vec::new();
        // Each index's first line and a hash of its cells (keeping the cells themselves would
        // take a gigabyte at a million rows).
        let mut seen: BTreeMap<u32, (usize, u64)> = BTreeMap::new();
        let mut blanks = Blanks::default();
        // Half the unit of the finest digit written in rate_dph and in each quarter column.
        let mut written = [f64::INFINITY; 5];
        for row in head.rows(text) {
            let (n, cells) = row?;
            let num = |name: &str| number(n, name, &cells[col(name)]);
            let optional = |name: &str| match head.col(name) {
                Some(i) => optional_cell(n, name, &cells[i]),
                None => Ok(None),
            };
            let index = num("index")?;
            if index < 0.0 || index.fract() != 0.0 || index > u32::MAX as f64 {
                return err(
                    n,
                    format!("index '{}' is not a whole number from 0", shown(&cells[col("index")])),
                );
            }
            let hash = cells_hash(&cells);
            match seen.get(&(index as u32)) {
                Some(&(first, h)) if h == hash => {
                    warnings.push(Error {
                        line: n,
                        what: format!("repeats line {first} exactly (index {index}): the copy is dropped"),
                    });
                    continue;
                }
                Some(&(first, _)) => {
                    return err(
                        n,
                        format!(
                            "index {index} appears on lines {first} and {n} with different values: each visit has its own index"
                        ),
                    );
                }
                None => {
                    seen.insert(index as u32, (n, hash));
                }
            }
            for (group, names) in OPTIONAL_GROUPS {
                if names.iter().any(|c| head.col(c).is_some_and(|i| is_missing(&cells[i]))) {
                    blanks.add(group, n);
                }
            }
            let encoder_deg = num("encoder_deg")?;
            if !(0.0..360.0).contains(&encoder_deg) {
                return err(n, format!("encoder_deg {encoder_deg} is outside 0 <= gamma < 360"));
            }
            let samples = match optional("samples")? {
                Some(s) if s < 0.0 || s.fract() != 0.0 || s > u32::MAX as f64 => {
                    return err(n, format!("samples {s} is not a count (0 to {})", u32::MAX));
                }
                s => s.map(|s| s as u32),
            };
            if samples == Some(0) {
                warnings.push(Error {
                    line: n,
                    what: "samples is 0: rate_dph is the mean of no samples; used as given".into(),
                });
            }
            let rate_sd_dph = optional("rate_sd_dph")?;
            if rate_sd_dph.is_some_and(|s| s < 0.0) {
                return err(n, "rate_sd_dph is negative");
            }
            let q = QUARTERS.map(&optional);
            let quarters = match q {
                [Ok(Some(a)), Ok(Some(b)), Ok(Some(c)), Ok(Some(d))] => Some([a, b, c, d]),
                _ => {
                    for r in q {
                        r?;
                    }
                    None
                }
            };
            let rate_dph = num("rate_dph")?;
            for (name, v) in
                std::iter::once(("rate_dph", rate_dph)).chain(QUARTERS.into_iter().zip(quarters.into_iter().flatten()))
            {
                if v.abs() >= MAX_RATE_DPH {
                    return err(
                        n,
                        format!("{name} {v:e} is beyond any gyro's range (|rate| below {MAX_RATE_DPH:e} deg/h)"),
                    );
                }
            }
            for (finest, name) in written.iter_mut().zip(std::iter::once("rate_dph").chain(QUARTERS)) {
                if let Some(h) = head.col(name).and_then(|i| half_unit(&cells[i])) {
                    *finest = finest.min(h);
                }
            }
            rows.push(Row {
                line: n,
                index: index as u32,
                t_s: num("t_s")?,
                encoder_deg,
                rate_dph,
                rate_sd_dph,
                samples,
                temp_c: optional("temp_c")?,
                tilt_x_deg: elevation(n, "tilt_x_deg", optional("tilt_x_deg")?, &mut warnings),
                tilt_y_deg: elevation(n, "tilt_y_deg", optional("tilt_y_deg")?, &mut warnings),
                quarters_dph: quarters,
            });
        }
        if rows.is_empty() {
            return err(0, "the recording has no positions");
        }
        warnings.extend(blanks.warnings(rows.len()));
        warnings.extend(textfile::unended(text, "position", || {
            rows.iter().map(|r| r.line).max()
        }));
        warnings.extend(head.free_text());
        let comments = head.comment_lines();
        if let Some(&first) = comments.first() {
            warnings.push(Error {
                line: first,
                what: format!(
                    "'#' lines among the positions (line{} {}) are comments: skipped, not read as positions",
                    if comments.len() > 1 { "s" } else { "" },
                    crate::noise_fit::lines_text(&comments)
                ),
            });
        }
        in_visiting_order(&mut rows, &mut warnings)?;
        // What rounding to the digits written can put between the quarters' mean and the
        // row's rate: each column's finest digit, as a writer that drops trailing zeros
        // writes a round value with fewer.
        let finest = written.map(|h| if h.is_finite() { h } else { 0.0 });
        let rounding = finest[0] + finest[1..].iter().sum::<f64>() / 4.0;
        quarters_of_their_dwells(&mut rows, rounding, &mut warnings);
        quarters_of_few_samples(&mut rows, &mut warnings);
        quarters_that_vary(&mut rows, &mut warnings);
        sample_spread_of_none(&rows, &mut warnings);
        some_quarter_columns(&head, &mut warnings);
        times_before_the_start(&rows, &mut warnings);
        time_leaps(&rows, &mut warnings);
        if let Some(d) = dwell_s {
            dwells_apart(&rows, d, head.meta_line("dwell_s"), &mut warnings);
        }
        fewer_than_planned(&meta, head.meta_line("positions"), rows.len(), &mut warnings);
        Ok(Recording {
            latitude_deg,
            meta,
            rows,
            warnings,
        })
    }

    /// The recording in the file `path`; an error gives its line (`Error::at` names the file).
    pub fn read(path: &str) -> Result<Recording, Error> {
        Recording::parse(&read_text(path)?)
    }

    /// At least `min` positions, which `what` needs: a clear reason rather than a fit without
    /// degrees of freedom.
    pub fn require_positions(&self, min: usize, what: &str) -> Result<(), String> {
        if self.rows.len() >= min {
            return Ok(());
        }
        Err(format!("{} positions: {what} needs at least {min}", self.rows.len()))
    }

    /// Three distinct encoder angles at least, as `A cos + B sin + C` needs: a shaft that did
    /// not turn (a stalled motor) gives a clear reason here rather than a singular fit.
    pub fn require_turning(&self) -> Result<(), String> {
        let mut angles: Vec<f64> = self.rows.iter().map(|r| r.encoder_deg).collect();
        angles.sort_by(f64::total_cmp);
        angles.dedup_by(|a, b| (*a - *b).abs() < ANGLE_RESOLUTION_DEG);
        if angles.len() >= 3 {
            return Ok(());
        }
        let seen: Vec<String> = angles.iter().map(|a| format!("{a}")).collect();
        Err(format!(
            "the encoder reads {} distinct angle(s) over {} positions ({} deg): the first harmonic A cos(gamma) + B sin(gamma) + C needs three at least; did the shaft turn (a stalled motor, an encoder that stopped answering)?",
            angles.len(),
            self.rows.len(),
            seen.join(", ")
        ))
    }

    /// Whether every row has an inclinometer X (and Y) reading.
    pub fn has_tilt_x(&self) -> bool {
        self.rows.iter().all(|r| r.tilt_x_deg.is_some())
    }

    pub fn has_tilt_xy(&self) -> bool {
        self.has_tilt_x() && self.rows.iter().all(|r| r.tilt_y_deg.is_some())
    }
}

/// An inclinometer reading is an elevation: beyond 90 deg it is a fill value or a fault, and
/// is read as no reading (the tilt path bridges those), with a warning naming the line.
fn elevation(line: usize, name: &str, v: Option<f64>, warnings: &mut Vec<Error>) -> Option<f64> {
    match v {
        Some(e) if e.abs() >= 90.0 => {
            warnings.push(Error {
                line,
                what: format!("{name} {e} is not an elevation in degrees (-90 to 90): read as no reading"),
            });
            None
        }
        v => v,
    }
}

/// Quarters that do not average to their row's rate are not of that dwell's samples (a cell
/// corrupted, or written from another dwell): they are dropped, with a warning naming the line,
/// as they would make the short-time noise they show any size. Allowed: a fifth of the
/// quarters' own spread, which covers quarters of unequal sample counts (40 samples or more),
/// and `rounding`, what the digits written allow (an outside audit's valid quarters of two
/// decimals were dropped in all of 40 files). Row by row, so that what was kept reads back the
/// same.
fn quarters_of_their_dwells(rows: &mut [Row], rounding: f64, warnings: &mut Vec<Error>) {
    for r in rows.iter_mut() {
        let Some(q) = r.quarters_dph else { continue };
        let mean = q.iter().sum::<f64>() / 4.0;
        let spread = q.iter().map(|v| (v - mean).abs()).fold(0.0, f64::max);
        let allowed = QUARTER_SLACK * spread + rounding + 1e-6 * (1.0 + r.rate_dph.abs());
        if (mean - r.rate_dph).abs() > allowed {
            warnings.push(Error {
                line: r.line,
                what: format!(
                    "q1_dph..q4_dph average {mean} deg/h where rate_dph is {} deg/h: not this dwell's quarters, not used",
                    r.rate_dph
                ),
            });
            r.quarters_dph = None;
        }
    }
}

/// Half the unit of the last digit written in `cell` (`-12.289` 0.0005, `1.5e-3` 0.00005,
/// `12` 0.5); `None` where it is no number.
fn half_unit(cell: &str) -> Option<f64> {
    cell.parse::<f64>().ok()?;
    let (mantissa, exponent) = match cell.find(['e', 'E']) {
        Some(at) => (&cell[..at], cell[at + 1..].parse::<i32>().ok()?),
        None => (cell, 0),
    };
    let decimals = mantissa.find('.').map_or(0, |dot| mantissa.len() - dot - 1) as i32;
    Some(0.5 * 10f64.powi(exponent - decimals))
}

/// Quarters equal to one another in every dwell are not the means of a gyro's samples (a
/// writer that copied the dwell mean into them): read as quarters they would say the gyro has
/// no short-time noise at all. They are dropped, with one warning.
fn quarters_that_vary(rows: &mut [Row], warnings: &mut Vec<Error>) {
    let with: Vec<usize> = (0..rows.len()).filter(|&i| rows[i].quarters_dph.is_some()).collect();
    let steady = |q: [f64; 4]| q.iter().all(|&v| v == q[0]);
    if with.len() < 2 || !with.iter().all(|&i| rows[i].quarters_dph.is_some_and(steady)) {
        return;
    }
    warnings.push(Error {
        line: rows[with[0]].line,
        what: format!(
            "q1_dph..q4_dph are equal to one another in all {} dwells that have them: not the means of a gyro's samples (copied from rate_dph?), not used",
            with.len()
        ),
    });
    for &i in &with {
        rows[i].quarters_dph = None;
    }
}

/// Quarters of a dwell of fewer than four samples are not the means of a quarter of its
/// samples each (one quarter at least holds none): read as quarters they would show a
/// short-time noise of any size. They are dropped, with one warning naming the first line.
fn quarters_of_few_samples(rows: &mut [Row], warnings: &mut Vec<Error>) {
    let few: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i].quarters_dph.is_some() && rows[i].samples.is_some_and(|s| s < 4))
        .collect();
    let Some(&first) = few.first() else { return };
    warnings.push(Error {
        line: rows[first].line,
        what: format!(
            "q1_dph..q4_dph given for {} dwell(s) of fewer than 4 samples (samples {}): a quarter of such a dwell holds no sample of its own, not used",
            few.len(),
            rows[first].samples.unwrap_or(0)
        ),
    });
    for &i in &few {
        rows[i].quarters_dph = None;
    }
}

/// A spread of exactly zero over more than one sample says the samples were all equal, which a
/// gyro's are not (or that the writer put 0 for a value it did not have): said once, the values
/// kept as written (a fit does not take them for the dwell's noise).
fn sample_spread_of_none(rows: &[Row], warnings: &mut Vec<Error>) {
    let zero: Vec<&Row> = rows
        .iter()
        .filter(|r| r.rate_sd_dph == Some(0.0) && r.samples.is_some_and(|s| s > 1))
        .collect();
    if let Some(first) = zero.first() {
        warnings.push(Error {
            line: first.line,
            what: format!(
                "rate_sd_dph is 0 in {} dwell(s) of more than one sample: their samples all equal, or no spread was written; kept, not taken for the dwells' noise",
                zero.len()
            ),
        });
    }
}

/// Some of the quarter columns without the others: a dwell's quarters are read only as all
/// four, so these are not used; said at the header.
fn some_quarter_columns(head: &Head<'_>, warnings: &mut Vec<Error>) {
    let present: Vec<&str> = QUARTERS.into_iter().filter(|c| head.col(c).is_some()).collect();
    if !present.is_empty() && present.len() < QUARTERS.len() {
        warnings.push(Error {
            line: head.line,
            what: format!(
                "{} without the other quarter columns: a dwell's quarters are read only as all four (q1_dph .. q4_dph), so these are not used",
                present.join(", ")
            ),
        });
    }
}

/// A `t_s` before the run's start, from which the format counts it: said once, at the first;
/// the times are used as given (only their differences enter a fit).
fn times_before_the_start(rows: &[Row], warnings: &mut Vec<Error>) {
    let early: Vec<&Row> = rows.iter().filter(|r| r.t_s < 0.0).collect();
    if let Some(first) = early.first() {
        warnings.push(Error {
            line: first.line,
            what: format!(
                "t_s {} is before the run's start, from which the format counts it ({} such dwell(s)); the times are used as given",
                short(first.t_s),
                early.len()
            ),
        });
    }
}

/// A step between visits this many times the median step is a leap: a pause, or a time
/// written wrong (a 1e300 was read without a word).
const LEAP: f64 = 100.0;

/// Steps of `t_s` of [`LEAP`] times the median step or more: said once, with the largest and
/// where; the times are used as given (the noise model reads them as time passed).
fn time_leaps(rows: &[Row], warnings: &mut Vec<Error>) {
    let mut steps: Vec<f64> = rows.windows(2).map(|w| w[1].t_s - w[0].t_s).collect();
    if steps.len() < 3 {
        return;
    }
    steps.sort_by(f64::total_cmp);
    let median = steps[steps.len() / 2];
    let leaps: Vec<&[Row]> = rows
        .windows(2)
        .filter(|w| w[1].t_s - w[0].t_s >= LEAP * median)
        .collect();
    if let Some(w) = leaps
        .iter()
        .max_by(|a, b| (a[1].t_s - a[0].t_s).total_cmp(&(b[1].t_s - b[0].t_s)))
    {
        warnings.push(Error {
            line: w[1].line,
            what: format!(
                "t_s leaps by {} s from line {} (the median step between visits is {} s; {} such leap(s)): a pause, or a time written wrong; the times are used as given",
                short(w[1].t_s - w[0].t_s),
                w[0].line,
                short(median),
                leaps.len()
            ),
        });
    }
}

/// A run that planned more positions (`positions`, the firmware's metadata) than it has rows
/// ended early: its target reached, an abort or a fault, or the file was cut. Said, as the
/// fit of the rows there are is not the run planned. A `positions` that is not a count (a
/// key of another writer's) is left alone.
fn fewer_than_planned(meta: &BTreeMap<String, String>, line: usize, rows: usize, warnings: &mut Vec<Error>) {
    if let Some(planned) = meta.get("positions").and_then(|v| v.trim().parse::<usize>().ok())
        && rows < planned
    {
        warnings.push(Error {
            line,
            what: format!(
                "positions = {planned} but {rows} rows: the run ended before its last position (the firmware's early stop at its target, an abort or a fault) or the file was cut; the rows written are fitted"
            ),
        });
    }
}

/// Dwells of `dwell_s` whose centres are closer than that overlap, which a stepped run cannot
/// do (it moves and settles between them): said once, at the metadata's line; the length is
/// taken as given.
fn dwells_apart(rows: &[Row], dwell_s: f64, line: usize, warnings: &mut Vec<Error>) {
    let closest = rows
        .windows(2)
        .min_by(|a, b| (a[1].t_s - a[0].t_s).total_cmp(&(b[1].t_s - b[0].t_s)));
    if let Some([a, b]) = closest
        && b.t_s - a.t_s < dwell_s * (1.0 - 1e-9)
    {
        warnings.push(Error {
            line,
            what: format!(
                "dwell_s {dwell_s} s is longer than the {} s between the centres of lines {} and {}: the dwells would overlap; taken as given",
                short(b.t_s - a.t_s),
                a.line,
                b.line
            ),
        });
    }
}

/// How far, in their spread, a row's quarters may average from its rate.
const QUARTER_SLACK: f64 = 0.2;

/// The rows in visiting order: by `index`, the visit number, when the file has them in
/// another order (with a warning), and `t_s` must then increase, since a later visit cannot
/// be earlier.
fn in_visiting_order(rows: &mut [Row], warnings: &mut Vec<Error>) -> Result<(), Error> {
    let first = rows.windows(2).find(|w| w[1].index < w[0].index);
    if let Some(((ai, al), (bi, bl))) = first.map(|w| ((w[0].index, w[0].line), (w[1].index, w[1].line))) {
        let what = format!(
            "the lines are not in the order of their index (index {bi} on line {bl} after index {ai} on line {al}): they are taken in index order, the visiting order"
        );
        rows.sort_by_key(|r| r.index);
        warnings.push(Error { line: bl, what });
    }
    missing_visits(rows, warnings);
    match rows.windows(2).find(|w| w[1].t_s <= w[0].t_s) {
        Some([a, b]) => err(
            b.line,
            format!(
                "t_s {} of index {} is not after t_s {} of index {} (line {}): the visits are in time order",
                short(b.t_s),
                b.index,
                short(a.t_s),
                a.index,
                a.line
            ),
        ),
        _ => Ok(()),
    }
}

/// A run of indices missing below the highest one: positions measured and lost from the file
/// (a `rec` line lost from a log). Missing ones after it are not seen: a file cut short, or a
/// run that ended early, just ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IndexGap {
    pub first: u32,
    pub last: u32,
    /// Lines of the positions on either side (none before index 0).
    pub after_line: Option<usize>,
    pub before_line: usize,
}

/// The runs of indices missing below the highest one, in any order of `rows`.
pub fn index_gaps(rows: &[Row]) -> Vec<IndexGap> {
    let mut by_index: Vec<&Row> = rows.iter().collect();
    by_index.sort_by_key(|r| r.index);
    let mut out = Vec::new();
    let mut prev: Option<&Row> = None;
    for r in by_index {
        let first = prev.map_or(0, |p| p.index + 1);
        if r.index > first {
            out.push(IndexGap {
                first,
                last: r.index - 1,
                after_line: prev.map(|p| p.line),
                before_line: r.line,
            });
        }
        prev = Some(r);
    }
    out
}

/// Visits the indices skip: the fit goes on with the rest.
fn missing_visits(rows: &[Row], warnings: &mut Vec<Error>) {
    for g in index_gaps(rows) {
        let what = if g.first == g.last {
            format!("index {}", g.first)
        } else {
            format!("indices {} to {}", g.first, g.last)
        };
        warnings.push(Error {
            line: g.before_line,
            what: format!(
                "{what} missing before this line's index {}: visits lost from the file",
                g.last + 1
            ),
        });
    }
}

/// A hash of a row's cells, fixed across runs: equal hashes are taken for an exact repeat
/// (two different rows collide with probability 2^-64).
fn cells_hash(cells: &csv::StringRecord) -> u64 {
    use std::hash::{DefaultHasher, Hash, Hasher};
    let mut h = DefaultHasher::new();
    for c in cells {
        c.hash(&mut h);
    }
    h.finish()
}
