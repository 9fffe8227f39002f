//! What the project's CSV files share (recordings, static logs): errors that name the line,
//! leading `# key = value` metadata, and a header whose columns are found by name.

use std::collections::BTreeMap;
use std::fmt;

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

impl Error {
    /// `file:line: what`, the form compilers use, for messages about a named file.
    pub fn at(&self, path: &str) -> String {
        if self.line == 0 {
            format!("{path}: {}", self.what)
        } else {
            format!("{path}:{}: {}", self.line, self.what)
        }
    }
}

pub fn err<T>(line: usize, what: impl Into<String>) -> Result<T, Error> {
    Err(Error {
        line,
        what: what.into(),
    })
}

/// The metadata and the header line of a CSV file.
#[derive(Debug, Clone)]
pub struct Head<'a> {
    /// Every metadata key, known or not, as written.
    pub meta: BTreeMap<String, String>,
    /// The line of each metadata key.
    meta_at: BTreeMap<String, usize>,
    /// Line number of the header (from 1).
    pub line: usize,
    pub header: &'a str,
    pub names: Vec<String>,
    col: BTreeMap<String, usize>,
    /// Metadata keys given again with another value (the key, the first line and the
    /// repeat's), and column names given again: harmless unless the reader uses them
    /// ([`Head::known`]). A key repeated with its value says nothing new.
    repeated_meta: Vec<(String, usize, usize)>,
    repeated_cols: Vec<String>,
    /// The `#` lines after the header (comments to the reader), with the key of those that
    /// read as `# key = value`.
    comments: Vec<(usize, Option<String>)>,
    /// The `#` lines before the header that are not `# key = value` (free text other writers
    /// keep there), with their text.
    free: Vec<(usize, String)>,
}

impl<'a> Head<'a> {
    pub fn parse(text: &'a str) -> Result<Head<'a>, Error> {
        let mut meta = BTreeMap::new();
        let mut meta_at: BTreeMap<String, usize> = BTreeMap::new();
        let mut repeated = Vec::new();
        let mut free = Vec::new();
        for (i, l) in text.lines().enumerate() {
            // A byte-order mark, as spreadsheet programs write UTF-8, is not part of the text
            // (nor a second one, as a program that adds its own to a file that has one writes).
            let l = if i == 0 { l.trim_start_matches('\u{FEFF}') } else { l };
            let (n, t) = (i + 1, l.trim());
            if t.is_empty() {
                continue;
            }
            let Some(m) = t.strip_prefix('#') else {
                let head = Head::header(meta, meta_at, repeated, n, t, comments_after(text, n));
                return head.map(|h| Head { free, ..h });
            };
            // A bare `#` sets the metadata apart; it says nothing.
            if m.trim().is_empty() {
                continue;
            }
            // Free text is a comment; a reader refuses it where it names a key it uses
            // (`Head::known`).
            let Some((k, v)) = m.split_once('=') else {
                free.push((n, t.to_string()));
                continue;
            };
            let (k, v) = (k.trim().to_string(), v.trim().to_string());
            if k.is_empty() {
                return err(n, "metadata line with an empty key");
            }
            match meta_at.get(&k) {
                // The first stands; whether a repeat matters is the reader's to say.
                Some(&first) if meta.get(&k) != Some(&v) => repeated.push((k, first, n)),
                Some(_) => {}
                None => {
                    meta.insert(k.clone(), v);
                    meta_at.insert(k, n);
                }
            }
        }
        err(0, "no header line: the file ends before the column names")
    }

    fn header(
        meta: BTreeMap<String, String>,
        meta_at: BTreeMap<String, usize>,
        repeated_meta: Vec<(String, usize, usize)>,
        line: usize,
        header: &'a str,
        comments: Vec<(usize, Option<String>)>,
    ) -> Result<Head<'a>, Error> {
        let names: Vec<String> = match reader(header.as_bytes()).records().next() {
            Some(Ok(r)) => r.iter().map(String::from).collect(),
            Some(Err(e)) => return err(line, format!("the header is not CSV: {e}")),
            None => Vec::new(),
        };
        let mut col = BTreeMap::new();
        let mut repeated_cols = Vec::new();
        for (i, name) in names.iter().enumerate().filter(|(_, n)| !n.is_empty()) {
            if col.contains_key(name) {
                repeated_cols.push(name.clone());
            } else {
                col.insert(name.clone(), i);
            }
        }
        Ok(Head {
            meta,
            meta_at,
            line,
            header,
            names,
            col,
            repeated_meta,
            repeated_cols,
            comments,
            free: Vec::new(),
        })
    }

    /// The `#` lines of free text before the header, skipped, said as a warning.
    pub fn free_text(&self) -> Option<Error> {
        let lines: Vec<usize> = self.free.iter().map(|f| f.0).collect();
        let (first, text) = self.free.first()?;
        Some(Error {
            line: *first,
            what: format!(
                "free text before the header ('{text}'{} on line{} {}): a '#' line there that is not '# key = value' is a comment, skipped",
                if lines.len() > 1 { " and more" } else { "" },
                if lines.len() > 1 { "s" } else { "" },
                crate::noise_fit::lines_text(&lines),
            ),
        })
    }

    /// The lines of the `#` comments among the rows, which the reader skips.
    pub fn comment_lines(&self) -> Vec<usize> {
        self.comments.iter().map(|c| c.0).collect()
    }

    /// A metadata key or a column the reader uses may be given once only; the others it
    /// ignores, repeated or not.
    pub fn known(&self, keys: &[&str], columns: &[&str]) -> Result<(), Error> {
        if let Some((n, t)) = self.free.iter().find(|(_, t)| keys.iter().any(|k| names_key(t, k))) {
            return err(
                *n,
                format!("metadata line without '=': '{t}' (expected '# key = value')"),
            );
        }
        if let Some((k, first, n)) = self.repeated_meta.iter().find(|r| keys.contains(&r.0.as_str())) {
            return err(
                *n,
                format!("metadata key '{k}' given twice with different values (first on line {first})"),
            );
        }
        // Read as a comment it would be ignored, and the value before the header used in its
        // place without a word.
        if let Some((n, Some(k))) = self
            .comments
            .iter()
            .find(|c| c.1.as_deref().is_some_and(|k| keys.contains(&k)))
        {
            return err(
                *n,
                format!(
                    "metadata '{k}' after the header, where '#' lines are comments: metadata goes before the header"
                ),
            );
        }
        match self.repeated_cols.iter().find(|c| columns.contains(&c.as_str())) {
            Some(c) => err(self.line, format!("column '{c}' appears twice")),
            None => Ok(()),
        }
    }

    /// Where a missing metadata key is written all the same: in another case before the
    /// header, or after the header, where a `#` line is a comment. Empty when nowhere.
    pub fn misplaced(&self, text: &str, key: &str) -> String {
        if let Some((n, t)) = self.free.iter().find(|(_, t)| names_key(t, key)) {
            return format!("; line {n} '{t}' has no '=' (expected '# {key} = value')");
        }
        let found = text.lines().enumerate().find_map(|(i, l)| {
            let (k, _) = l.trim().strip_prefix('#')?.split_once('=')?;
            let k = k.trim().trim_start_matches('#').trim();
            k.eq_ignore_ascii_case(key).then_some((i + 1, k))
        });
        match found {
            Some((n, k)) if n > self.line => {
                format!("; line {n} has '{k}' after the header, where '#' lines are comments")
            }
            Some((n, k)) if k == key => {
                format!("; line {n} has it after more than one '#' (expected '# {key} = value')")
            }
            Some((n, k)) => format!("; line {n} has '{k}' (keys are case-sensitive)"),
            None => String::new(),
        }
    }

    /// The line of a metadata key (0 when it is missing).
    pub fn meta_line(&self, key: &str) -> usize {
        self.meta_at.get(key).copied().unwrap_or(0)
    }

    /// Optional metadata a reader uses as a quantity: a positive number, or an error at its
    /// line (never ignored).
    pub fn positive_meta(&self, key: &str, unit: &str) -> Result<Option<f64>, Error> {
        match self.meta.get(key) {
            None => Ok(None),
            Some(v) => match v.parse::<f64>() {
                Ok(x) if x.is_finite() && x > 0.0 => Ok(Some(x)),
                _ => err(
                    self.meta_line(key),
                    format!("{key} '{}' is not a positive number of {unit}", shown(v)),
                ),
            },
        }
    }

    /// The `format` metadata must be `want`.
    pub fn require_format(&self, text: &str, want: &str) -> Result<(), Error> {
        match self.meta.get("format").map(String::as_str) {
            None => err(
                0,
                format!(
                    "required metadata 'format' is missing (expected 'format = {want}'){}",
                    self.misplaced(text, "format")
                ),
            ),
            Some(f) if f == want => Ok(()),
            Some(f) => err(
                self.meta_line("format"),
                format!("format '{f}' is not supported (this reader knows {want})"),
            ),
        }
    }

    pub fn require_columns(&self, names: &[&str]) -> Result<(), Error> {
        match names.iter().find(|c| !self.col.contains_key(**c)) {
            Some(c) => {
                // A whole header in one cell: the writer used another separator.
                let other = [('\t', "tabs"), (';', "semicolons")]
                    .into_iter()
                    .find(|(sep, _)| self.names.len() == 1 && self.header.contains(*sep))
                    .map_or(String::new(), |(_, name)| {
                        format!("; the header is split by {name}, where the format separates columns by commas")
                    });
                err(
                    self.line,
                    format!("required column '{c}' is missing (header: '{}'){other}", self.header),
                )
            }
            None => Ok(()),
        }
    }

    /// Index of a column.
    pub fn col(&self, name: &str) -> Option<usize> {
        self.col.get(name).copied()
    }

    /// The data records after the header as `(line number, cells)`, by the `csv` crate
    /// (quoted fields, fields trimmed); blank and `#` lines skipped.
    pub fn rows(&self, text: &'a str) -> impl Iterator<Item = Result<(usize, csv::StringRecord), Error>> {
        let (width, names, header) = (self.names.len(), self.names.clone(), self.line);
        // The byte where the line after the header starts.
        let start = text
            .match_indices('\n')
            .nth(self.line - 1)
            .map_or(text.len(), |(i, _)| i + 1);
        let data = &text[start..];
        // Lines from the byte offsets (the crate's own line count skips comment lines).
        let (mut at, mut line) = (0usize, self.line + 1);
        let mut line_of = move |byte: u64| {
            // A record's position is where the reader began, before the comment and blank
            // lines it skipped.
            let mut b = (byte as usize).min(data.len());
            while let Some(end) = data[b..].find('\n') {
                let l = data[b..b + end].trim();
                if !(l.is_empty() || l.starts_with('#')) {
                    break;
                }
                b += end + 1;
            }
            if b >= at {
                line += data.as_bytes()[at..b].iter().filter(|&&c| c == b'\n').count();
                at = b;
            }
            line
        };
        let blank =
            |r: &Result<csv::StringRecord, csv::Error>| r.as_ref().is_ok_and(|r| r.len() == 1 && r[0].is_empty());
        reader(data.as_bytes())
            .into_records()
            .filter(move |r| !blank(r))
            .map(move |r| {
                let r = r.map_err(|e| Error {
                    line: e.position().map_or(0, |p| line_of(p.byte())),
                    what: format!("not a CSV record: {}", e.kind_text()),
                })?;
                let n = r.position().map_or(0, |p| line_of(p.byte()));
                if r.iter().eq(names.iter().map(String::as_str)) {
                    return err(
                        n,
                        format!("the header of line {header} again: two files joined? Each file holds one run"),
                    );
                }
                if r.len() == width {
                    Ok((n, r))
                } else {
                    err(n, format!("{} fields, the header has {width}", r.len()))
                }
            })
    }
}

/// Whether the free text of a `#` line starts with `key` as a word, as `# key value` or
/// `# key: value` would: metadata written without its `=`.
fn names_key(text: &str, key: &str) -> bool {
    let word = text
        .trim_start_matches('#')
        .split([' ', '\t', ':'])
        .find(|w| !w.is_empty());
    word.is_some_and(|w| w.eq_ignore_ascii_case(key))
}

/// The warning for a text whose last line, a row (`row` names it), has no line end: a file cut
/// while it was written ends so, its last value perhaps cut short. The lines are counted only
/// then: a million-row file is not read again to no end.
pub fn unended(text: &str, row: &str, last_row_line: impl FnOnce() -> Option<usize>) -> Option<Error> {
    if text.is_empty() || text.ends_with('\n') {
        return None;
    }
    let line = text.lines().count();
    if last_row_line()? != line {
        return None;
    }
    let last = text.lines().last()?.rsplit(',').next()?.trim();
    Some(Error {
        line,
        what: format!(
            "the last {row} has no line end: a file cut short while it was written ends so, its last value ('{last}') perhaps cut too; read as it stands"
        ),
    })
}

/// The `#` lines after the header on line `header`, with the key of each that reads as
/// `# key = value`.
fn comments_after(text: &str, header: usize) -> Vec<(usize, Option<String>)> {
    text.lines()
        .enumerate()
        .skip(header)
        .filter_map(|(i, l)| {
            let c = l.trim().strip_prefix('#')?;
            let key = c
                .split_once('=')
                .map(|(k, _)| k.trim())
                .filter(|k| !k.is_empty() && !k.contains(','))
                .map(str::to_string);
            Some((i + 1, key))
        })
        .collect()
}

/// The project's CSV dialect: commas, `"` quotes, `#` comment lines, fields trimmed, any
/// number of fields per line (checked by the caller, who can say which line). Lines end at
/// `\n` (a `\r` before it is trimmed, so `\r\n` lines and their blank lines read as blank),
/// as `str::lines` has them for the metadata.
fn reader(bytes: &[u8]) -> csv::Reader<&[u8]> {
    csv::ReaderBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(bytes)
}

/// What went wrong in a CSV record, without the crate's own position (the caller gives the
/// file's line).
trait KindText {
    fn kind_text(&self) -> String;
}

impl KindText for csv::Error {
    fn kind_text(&self) -> String {
        match self.kind() {
            csv::ErrorKind::Utf8 { err, .. } => format!("invalid UTF-8 in field {}", err.field() + 1),
            csv::ErrorKind::Io(e) => e.to_string(),
            _ => self.to_string(),
        }
    }
}

/// A file's text. Bytes that are not UTF-8 (a name in Latin-1 in a column no reader uses)
/// become U+FFFD, so that a cell the reader needs fails with its line and column. Lines ended
/// by a carriage return alone (classic Mac OS) are read as lines.
pub fn read_text(path: &str) -> Result<String, Error> {
    // `-`: standard input, so that a run's recording can be piped in.
    let bytes = if path == "-" {
        let mut b = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin().lock(), &mut b).map(|_| b)
    } else {
        std::fs::read(path)
    };
    match bytes {
        Ok(bytes) if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) => err(
            1,
            "the file is UTF-16 text (it starts with that encoding's byte-order mark); the format is UTF-8: save it as UTF-8",
        ),
        Ok(bytes) => {
            let text = String::from_utf8_lossy(&bytes).into_owned();
            Ok(if text.contains('\r') && !text.contains('\n') {
                text.replace('\r', "\n")
            } else {
                text
            })
        }
        // The caller names the file (`Error::at`).
        Err(e) => err(0, format!("cannot read it: {e}")),
    }
}

/// An optional column without a value on some `lines` of `total` rows (named `rows`), said
/// once with the first few lines, so that no value goes unremarked.
pub fn blank_cells(column: &str, lines: &[usize], total: usize, rows: &str) -> String {
    const LISTED: usize = 5;
    let mut list: Vec<String> = lines.iter().take(LISTED).map(|l| l.to_string()).collect();
    if lines.len() > LISTED {
        list.push("...".into());
    }
    let plural = if lines.len() > 1 { "s" } else { "" };
    format!(
        "{column}: no value on {} of {total} {rows} (line{plural} {}): read as not recorded there",
        lines.len(),
        list.join(", ")
    )
}

/// A number as a message gives it: six decimals at most, no trailing zeros (a difference of
/// two times is 3.4, not 3.3999999999999915); from 1e9 on in exponent form (1e308 is not 309
/// digits).
pub fn short(x: f64) -> String {
    if x.abs() >= 1e9 {
        return format!("{x:.4e}");
    }
    let s = format!("{x:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A cell as an error message shows it: control characters escaped, not sent to the
/// terminal, and a long one cut (a binary block would fill the screen).
pub fn shown(v: &str) -> String {
    const MOST: usize = 40;
    let escaped: String = v.escape_debug().collect();
    match escaped.char_indices().nth(MOST) {
        Some((at, _)) => format!("{}... ({} bytes)", &escaped[..at], v.len()),
        None => escaped,
    }
}

/// A required cell as a finite number; the error names the line and the column.
pub fn number(line: usize, name: &str, v: &str) -> Result<f64, Error> {
    match v.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ if v.is_empty() => err(line, format!("{name} is empty")),
        _ => err(line, format!("{name} '{}' is not a finite number", shown(v))),
    }
}

/// What spreadsheets, pandas, R and databases write for no value, in any case.
const MISSING: [&str; 8] = ["nan", "-nan", "na", "n/a", "#n/a", "null", "none", "-"];

/// Whether a cell holds no value: empty or one of [`MISSING`].
pub fn is_missing(v: &str) -> bool {
    v.is_empty() || MISSING.iter().any(|m| v.eq_ignore_ascii_case(m))
}

/// An optional cell: empty or one of [`MISSING`] is a missing value.
pub fn optional(line: usize, name: &str, v: &str) -> Result<Option<f64>, Error> {
    if is_missing(v) {
        return Ok(None);
    }
    match v.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(Some(x)),
        // An infinity is no "no value": the writer measured something off the scale.
        Ok(_) => err(line, format!("{name} '{v}' is not a finite number")),
        // A corrupt cell may hold control characters: shown escaped, not sent to the terminal.
        _ => err(line, format!("{name} '{}' is not a number", shown(v))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn head_reads_metadata_and_finds_columns() {
        let text = "# format = x/1\n\n# a = b = c\n\"t_s\",rate_dph\n1,2\n# note\n3,4,5\n";
        let h = Head::parse(text).unwrap();
        assert_eq!((h.line, h.meta["a"].as_str()), (4, "b = c"));
        assert_eq!((h.col("rate_dph"), h.col("temp_c")), (Some(1), None));
        assert!(h.require_format(text, "x/1").is_ok());
        assert_eq!(
            h.require_format(text, "y/1").unwrap_err().to_string(),
            "line 1: format 'x/1' is not supported (this reader knows y/1)"
        );
        let bare = Head::parse("#\n# format = x/1\n#   \nt_s\n").unwrap();
        assert_eq!((bare.line, bare.meta_line("format")), (4, 2));
        // Free text before the header is a comment, unless it names a key the reader uses.
        let free = Head::parse("# recorded by rig 4\n# latitude_deg: 43.8\nt_s\n").unwrap();
        assert_eq!(
            free.free_text().unwrap().to_string(),
            "line 1: free text before the header ('# recorded by rig 4' and more on lines 1, 2): a '#' line there that is not '# key = value' is a comment, skipped"
        );
        assert!(free.known(&["format"], &[]).is_ok());
        assert_eq!(
            free.known(&["latitude_deg"], &[]).unwrap_err().to_string(),
            "line 2: metadata line without '=': '# latitude_deg: 43.8' (expected '# key = value')"
        );
        assert_eq!(
            free.misplaced("", "latitude_deg"),
            "; line 2 '# latitude_deg: 43.8' has no '=' (expected '# latitude_deg = value')"
        );
        let hashes = "## format = x/1\nt_s\n";
        assert_eq!(
            Head::parse(hashes).unwrap().misplaced(hashes, "format"),
            "; line 1 has it after more than one '#' (expected '# format = value')"
        );
        assert_eq!(Head::parse("t_s\n").unwrap().free_text(), None);
        let tabs = Head::parse("# format = x/1\nt_s\trate_dph\n").unwrap();
        assert!(
            tabs.require_columns(&["t_s"])
                .unwrap_err()
                .to_string()
                .ends_with("; the header is split by tabs, where the format separates columns by commas")
        );
        let rows: Vec<_> = h.rows(text).collect();
        let (n, r) = rows[0].as_ref().unwrap();
        assert_eq!((*n, r.iter().collect::<Vec<_>>()), (5, vec!["1", "2"]));
        assert_eq!(rows[1].as_ref().unwrap_err().line, 7);
        assert_eq!(h.require_columns(&["t_s", "q"]).unwrap_err().line, 4);
        let cased = "# Format = x/1\nt_s\n";
        assert_eq!(
            Head::parse(cased)
                .unwrap()
                .require_format(cased, "x/1")
                .unwrap_err()
                .to_string(),
            "required metadata 'format' is missing (expected 'format = x/1'); line 1 has 'Format' (keys are case-sensitive)"
        );
        let late = "t_s\n# format = x/1\n1\n";
        assert!(
            Head::parse(late)
                .unwrap()
                .require_format(late, "x/1")
                .unwrap_err()
                .to_string()
                .ends_with("; line 2 has 'format' after the header, where '#' lines are comments")
        );
        let twice = Head::parse("# a = 1\n# b = 0\n# a = 2\nx,y,x\n").unwrap();
        assert_eq!((twice.meta["a"].as_str(), twice.col("x")), ("1", Some(0)));
        assert!(twice.known(&["b"], &["y"]).is_ok(), "repeats the reader ignores");
        assert_eq!(
            twice.known(&["a"], &[]).unwrap_err().to_string(),
            "line 3: metadata key 'a' given twice with different values (first on line 1)"
        );
        let again = Head::parse("# a = 1\n# a = 1\nx\n").unwrap();
        assert!(again.known(&["a"], &["x"]).is_ok(), "a key repeated with its value");
        let text = "# a = 1\nx,y\n1,2\n# a = 2\n# 3,4\n5,6\n#\n";
        let late = Head::parse(text).unwrap();
        assert_eq!(late.comment_lines(), [4, 5, 7]);
        assert!(
            late.known(&["b"], &["x"]).is_ok(),
            "a comment with a key the reader ignores"
        );
        assert_eq!(
            late.known(&["a"], &[]).unwrap_err().to_string(),
            "line 4: metadata 'a' after the header, where '#' lines are comments: metadata goes before the header"
        );
        assert_eq!(
            twice.known(&[], &["x"]).unwrap_err().to_string(),
            "line 4: column 'x' appears twice"
        );
        assert_eq!(h.meta_line("a"), 3);
        let twice = Head::parse("\u{FEFF}\u{FEFF}# format = x/1\nt_s\n").unwrap();
        assert_eq!(twice.meta["format"], "x/1");
        let bom = Head::parse("\u{FEFF}# format = x/1\nt_s\n").unwrap();
        assert!(bom.require_format("", "x/1").is_ok());
        assert_eq!(Head::parse("\u{FEFF}t_s,x\n").unwrap().col("t_s"), Some(0));
        assert_eq!(
            number(3, "t_s", "inf").unwrap_err().to_string(),
            "line 3: t_s 'inf' is not a finite number"
        );
        for none in ["NaN", "-nan", "NA", "N/A", "#N/A", "null", "None", "-"] {
            assert_eq!(optional(3, "temp_c", none), Ok(None), "{none}");
        }
        assert!(optional(3, "temp_c", "--").is_err());
        assert_eq!(
            optional(4, "temp_c", "-inf").unwrap_err().to_string(),
            "line 4: temp_c '-inf' is not a finite number"
        );
        // A corrupt cell's control characters are shown escaped, not sent to the terminal.
        assert_eq!(
            number(5, "rate_dph", "1\u{0}\u{1b}[31m").unwrap_err().to_string(),
            "line 5: rate_dph '1\\0\\u{1b}[31m' is not a finite number"
        );
        assert_eq!(
            optional(6, "temp_c", "\u{7}").unwrap_err().to_string(),
            "line 6: temp_c '\\u{7}' is not a number"
        );
        assert_eq!(
            Error {
                line: 2,
                what: "bad".into()
            }
            .at("f.csv"),
            "f.csv:2: bad"
        );
    }

    #[test]
    fn quoted_fields_keep_their_commas_and_lines_count_past_comments() {
        let text = "# format = x/1\n\"t_s\",\"note, free\",rate_dph\n1,\"a, b\",2\n\n# c\n\n3,\"say \"\"hi\"\"\",4\n";
        let h = Head::parse(text).unwrap();
        assert_eq!(h.names, ["t_s", "note, free", "rate_dph"]);
        let rows: Vec<_> = h.rows(text).map(Result::unwrap).collect();
        assert_eq!((rows[0].0, &rows[0].1[1]), (3, "a, b"));
        assert_eq!((rows[1].0, &rows[1].1[1]), (7, "say \"hi\""));
    }

    #[test]
    fn a_number_is_short_in_a_message_however_large() {
        assert_eq!(
            (short(3.3999999999999915), short(-0.5), short(1.0)),
            ("3.4".into(), "-0.5".into(), "1".into())
        );
        assert_eq!((short(1e308), short(-2.5e9)), ("1.0000e308".into(), "-2.5000e9".into()));
    }

    #[test]
    fn lines_ended_by_a_carriage_return_alone_are_lines() {
        let path = std::env::temp_dir().join(format!("nf-cr-{}.csv", std::process::id()));
        std::fs::write(&path, "# format = x/1\rt_s,rate_dph\r1,2\r").unwrap();
        let text = read_text(path.to_str().unwrap()).unwrap();
        std::fs::remove_file(&path).unwrap();
        let h = Head::parse(&text).unwrap();
        assert_eq!(h.names, ["t_s", "rate_dph"]);
        assert_eq!(h.rows(&text).map(Result::unwrap).map(|r| r.0).collect::<Vec<_>>(), [3]);
    }

    #[test]
    fn a_last_row_without_its_line_end_is_said_with_its_value() {
        let cut = "t_s,rate_dph\n0,1.5\n0.1,-2";
        assert_eq!(
            unended(cut, "sample", || Some(3)).unwrap().to_string(),
            "line 3: the last sample has no line end: a file cut short while it was written ends so, its last value ('-2') perhaps cut too; read as it stands"
        );
        assert_eq!(unended(&format!("{cut}\n"), "sample", || Some(3)), None);
        // A last line that is no row (a comment) cuts no value.
        assert_eq!(unended("t_s\n0\n# end", "sample", || Some(2)), None);
    }
}
