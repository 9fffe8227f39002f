//! Reading recordings (`shared/recording-format.md`) written by any program: columns in any
//! order, extra columns and metadata ignored, optional columns may be missing. A malformed
//! line is an error that names the line and the problem; nothing is guessed.

use std::collections::BTreeMap;
use std::fmt;

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
}

/// What is wrong, and on which line (0 when it is about the whole file).
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    pub line: usize,
    pub what: String,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}", self.what)
        } else {
            write!(f, "line {}: {}", self.line, self.what)
        }
    }
}

impl std::error::Error for Error {}

fn err<T>(line: usize, what: impl Into<String>) -> Result<T, Error> {
    Err(Error {
        line,
        what: what.into(),
    })
}

const REQUIRED: [&str; 4] = ["index", "t_s", "encoder_deg", "rate_dph"];

fn unquote(s: &str) -> &str {
    let s = s.trim();
    s.strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(s)
        .trim()
}

impl Recording {
    pub fn parse(text: &str) -> Result<Recording, Error> {
        let mut meta = BTreeMap::new();
        let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim_end_matches('\r')));
        // Metadata, then the header.
        let (header_line, header) = loop {
            let Some((n, l)) = lines.next() else {
                return err(0, "no header line: the file ends before the column names");
            };
            let t = l.trim();
            if t.is_empty() {
                continue;
            }
            if let Some(m) = t.strip_prefix('#') {
                let Some((k, v)) = m.split_once('=') else {
                    return err(
                        n,
                        format!("metadata line without '=': '{t}' (expected '# key = value')"),
                    );
                };
                let (k, v) = (k.trim().to_string(), v.trim().to_string());
                if k.is_empty() {
                    return err(n, "metadata line with an empty key");
                }
                if meta.insert(k.clone(), v).is_some() {
                    return err(n, format!("metadata key '{k}' given twice"));
                }
                continue;
            }
            break (n, t);
        };
        match meta.get("format").map(String::as_str) {
            None => {
                return err(
                    0,
                    "required metadata 'format' is missing (expected 'format = northfinder-recording/1')",
                );
            }
            Some(FORMAT) => {}
            Some(f) => return err(0, format!("format '{f}' is not supported (this reader knows {FORMAT})")),
        }
        let latitude_deg: f64 = match meta.get("latitude_deg") {
            None => return err(0, "required metadata 'latitude_deg' is missing"),
            Some(v) => match v.parse::<f64>() {
                Ok(l) if (-90.0..=90.0).contains(&l) => l,
                _ => {
                    return err(
                        0,
                        format!("latitude_deg '{v}' is not a latitude in degrees (-90 to 90)"),
                    );
                }
            },
        };
        let names: Vec<&str> = header.split(',').map(unquote).collect();
        let mut col = BTreeMap::new();
        for (i, name) in names.iter().enumerate() {
            if name.is_empty() {
                continue;
            }
            if col.insert(*name, i).is_some() {
                return err(header_line, format!("column '{name}' appears twice"));
            }
        }
        for r in REQUIRED {
            if !col.contains_key(r) {
                return err(
                    header_line,
                    format!("required column '{r}' is missing (header: '{header}')"),
                );
            }
        }
        let opt = |name: &str| col.get(name).copied();
        let mut rows = Vec::new();
        for (n, l) in lines {
            let t = l.trim();
            if t.is_empty() || t.starts_with('#') {
                continue;
            }
            let cells: Vec<&str> = t.split(',').map(unquote).collect();
            if cells.len() != names.len() {
                return err(n, format!("{} fields, the header has {}", cells.len(), names.len()));
            }
            let num = |name: &str| -> Result<f64, Error> {
                let v = cells[col[name]];
                match v.parse::<f64>() {
                    Ok(x) if x.is_finite() => Ok(x),
                    _ if v.is_empty() => err(n, format!("{name} is empty")),
                    _ => err(n, format!("{name} '{v}' is not a finite number")),
                }
            };
            let optional = |name: &str| -> Result<Option<f64>, Error> {
                let Some(i) = opt(name) else { return Ok(None) };
                let v = cells[i];
                if v.is_empty() || v.eq_ignore_ascii_case("nan") || v.eq_ignore_ascii_case("na") {
                    return Ok(None);
                }
                match v.parse::<f64>() {
                    Ok(x) if x.is_finite() => Ok(Some(x)),
                    _ => err(n, format!("{name} '{v}' is not a number")),
                }
            };
            let index = num("index")?;
            if index < 0.0 || index.fract() != 0.0 || index > u32::MAX as f64 {
                return err(
                    n,
                    format!("index '{}' is not a whole number from 0", cells[col["index"]]),
                );
            }
            let encoder_deg = num("encoder_deg")?;
            if !(0.0..360.0).contains(&encoder_deg) {
                return err(n, format!("encoder_deg {encoder_deg} is outside 0 <= gamma < 360"));
            }
            let samples = match optional("samples")? {
                Some(s) if s < 0.0 || s.fract() != 0.0 => return err(n, format!("samples {s} is not a count")),
                s => s.map(|s| s as u32),
            };
            let rate_sd_dph = optional("rate_sd_dph")?;
            if rate_sd_dph.is_some_and(|s| s < 0.0) {
                return err(n, "rate_sd_dph is negative");
            }
            let q = ["q1_dph", "q2_dph", "q3_dph", "q4_dph"].map(&optional);
            let quarters = match q {
                [Ok(Some(a)), Ok(Some(b)), Ok(Some(c)), Ok(Some(d))] => Some([a, b, c, d]),
                _ => {
                    for r in q {
                        r?;
                    }
                    None
                }
            };
            rows.push(Row {
                line: n,
                index: index as u32,
                t_s: num("t_s")?,
                encoder_deg,
                rate_dph: num("rate_dph")?,
                rate_sd_dph,
                samples,
                temp_c: optional("temp_c")?,
                tilt_x_deg: optional("tilt_x_deg")?,
                tilt_y_deg: optional("tilt_y_deg")?,
                quarters_dph: quarters,
            });
        }
        if rows.is_empty() {
            return err(0, "the recording has no positions");
        }
        Ok(Recording {
            latitude_deg,
            meta,
            rows,
        })
    }

    pub fn read(path: &str) -> Result<Recording, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| Error {
            line: 0,
            what: format!("cannot read {path}: {e}"),
        })?;
        Recording::parse(&text).map_err(|e| Error {
            line: e.line,
            what: format!("{path}: {}", e.what),
        })
    }

    /// Whether every row has an inclinometer X (and Y) reading.
    pub fn has_tilt_x(&self) -> bool {
        self.rows.iter().all(|r| r.tilt_x_deg.is_some())
    }

    pub fn has_tilt_xy(&self) -> bool {
        self.has_tilt_x() && self.rows.iter().all(|r| r.tilt_y_deg.is_some())
    }
}
