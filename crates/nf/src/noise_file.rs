//! Noise-model files: `key = value` lines whose keys are the `NoiseModel` field names (IEEE
//! Std 952 units), `#` comments; or the JSON that `nf allan --json` writes (or any JSON with
//! those keys, at the top or under `noise_model` as `nf fit --json` has them). N, B and K are
//! given in every file (0 for a term the gyro lacks); the others are 0 where left out. What
//! is wrong is named with its line.

use crate::textfile::{Error, err};
use nf_model::noise::{NoiseError, NoiseModel};
use serde_json::Value;

/// The keys, in the order written.
pub const KEYS: [&str; 7] = [
    "arw_deg_rth",
    "bias_instability_dph",
    "rrw_dph_rth",
    "gm_sigma_dph",
    "gm_tau_s",
    "quantization_arcsec",
    "student_t_dof",
];

/// The terms every file gives: a file cut short, or a term forgotten, would otherwise drop
/// a term without a word and the sigmas under the model would be too small.
pub const REQUIRED: [&str; 3] = ["arw_deg_rth", "bias_instability_dph", "rrw_dph_rth"];

/// An error naming the required terms that `given` lacks, if any.
fn lacking(given: impl Fn(&str) -> bool) -> Result<(), Error> {
    let missing: Vec<&str> = REQUIRED.iter().copied().filter(|k| !given(k)).collect();
    if missing.is_empty() {
        return Ok(());
    }
    err(
        0,
        format!(
            "no {}: a noise file gives N, B and K, 0 for a term the gyro lacks (a file cut short would drop them without a word)",
            missing.join(", ")
        ),
    )
}

fn field<'a>(m: &'a mut NoiseModel, key: &str) -> Option<&'a mut f64> {
    Some(match key {
        "arw_deg_rth" => &mut m.arw_deg_rth,
        "bias_instability_dph" => &mut m.bias_instability_dph,
        "rrw_dph_rth" => &mut m.rrw_dph_rth,
        "gm_sigma_dph" => &mut m.gm_sigma_dph,
        "gm_tau_s" => &mut m.gm_tau_s,
        "quantization_arcsec" => &mut m.quantization_arcsec,
        "student_t_dof" => &mut m.student_t_dof,
        _ => return None,
    })
}

/// The file for `model`, with `comments` (a line each) at the top.
pub fn write(model: &NoiseModel, comments: &[String]) -> String {
    let mut m = *model;
    let mut out =
        String::from("# gyro noise model, IEEE Std 952 units (deg/sqrt(h), deg/h, deg/h/sqrt(h), s, arcsec)\n");
    for c in comments {
        // A line break would end the comment and start a line the reader parses.
        out += &format!("# {}\n", c.replace(['\n', '\r'], " "));
    }
    for key in KEYS {
        // `{}` is the shortest text that reads back to the same f64.
        let v = field(&mut m, key).map_or(0.0, |v| *v);
        out += &format!("{key} = {v}\n");
    }
    out
}

/// A value that a noise term may take: finite and not negative.
fn check(line: usize, key: &str, v: f64) -> Result<f64, Error> {
    if !v.is_finite() {
        return err(line, format!("{key} = {v} is not a finite number"));
    }
    if v < 0.0 {
        return err(line, format!("{key} = {v} is negative: noise terms are sizes, >= 0"));
    }
    Ok(v)
}

/// `validate` on the finished model, the error put on the line of the key it is about.
fn validated(m: NoiseModel, line_of: impl Fn(&str) -> usize) -> Result<NoiseModel, Error> {
    match m.validate() {
        Ok(()) => Ok(m),
        Err(e) => {
            let key = match e {
                NoiseError::Invalid(k) => k,
                NoiseError::GmWithoutTau => "gm_sigma_dph",
                NoiseError::DofTooSmall => "student_t_dof",
            };
            err(line_of(key), e.to_string())
        }
    }
}

pub fn parse(text: &str) -> Result<NoiseModel, Error> {
    if text.trim_start().starts_with('{') {
        return parse_json(text);
    }
    let mut m = NoiseModel::WHITE_NONE;
    let mut seen: Vec<(&str, usize)> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let n = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let Some((k, v)) = line.split_once('=') else {
            return err(n, format!("'{line}' is not 'key = value'"));
        };
        let (k, v) = (k.trim(), v.trim());
        if let Some((_, first)) = seen.iter().find(|(s, _)| *s == k) {
            return err(n, format!("{k} given twice (first on line {first})"));
        }
        let Some(slot) = field(&mut m, k) else {
            return err(n, format!("unknown key '{k}' (known: {})", KEYS.join(", ")));
        };
        let x = v.parse::<f64>().map_err(|_| Error {
            line: n,
            what: format!("{k} = '{v}' is not a number"),
        })?;
        *slot = check(n, k, x)?;
        seen.push((k, n));
    }
    if seen.is_empty() {
        return err(
            0,
            format!(
                "no noise terms: expected lines like 'arw_deg_rth = 0.002' with the keys {}",
                KEYS.join(", ")
            ),
        );
    }
    lacking(|k| seen.iter().any(|(s, _)| *s == k))?;
    validated(m, |key| seen.iter().find(|(s, _)| *s == key).map_or(0, |(_, l)| *l))
}

/// Line of the first `"key"` in the text, for JSON errors.
fn json_line(text: &str, key: &str) -> usize {
    text.find(&format!("\"{key}\""))
        .map_or(0, |at| text[..at].matches('\n').count() + 1)
}

fn parse_json(text: &str) -> Result<NoiseModel, Error> {
    let v: Value = serde_json::from_str(text).map_err(|e| Error {
        line: e.line(),
        what: format!("not valid JSON: {e}"),
    })?;
    let obj = v.get("noise_model").filter(|o| o.is_object()).unwrap_or(&v);
    let Some(obj) = obj.as_object() else {
        return err(1, "the JSON is not an object of noise terms");
    };
    let mut m = NoiseModel::WHITE_NONE;
    let mut any = false;
    for key in KEYS {
        let line = json_line(text, key);
        let x = match obj.get(key) {
            None | Some(Value::Null) => continue,
            Some(Value::Number(x)) => x.as_f64().unwrap_or(f64::NAN),
            Some(other) => return err(line, format!("{key} = {other} is not a number")),
        };
        if let Some(slot) = field(&mut m, key) {
            *slot = check(line, key, x)?;
        }
        any = true;
    }
    if !any {
        return err(0, format!("no noise terms in the JSON (keys: {})", KEYS.join(", ")));
    }
    lacking(|k| obj.get(k).is_some_and(Value::is_number))?;
    validated(m, |key| json_line(text, key))
}

/// Reads a noise file; the error reads `file:line: what`.
pub fn read(path: &str) -> Result<NoiseModel, String> {
    let text = crate::textfile::read_text(path).map_err(|e| e.at(path))?;
    parse(&text).map_err(|e| e.at(path))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> NoiseModel {
        NoiseModel {
            arw_deg_rth: 0.0020134567891234,
            bias_instability_dph: 0.019,
            rrw_dph_rth: 1.0 / 3.0,
            gm_sigma_dph: 0.01,
            gm_tau_s: 42.5,
            quantization_arcsec: 0.0,
            student_t_dof: 5.0,
        }
    }

    #[test]
    fn write_then_read_is_the_same_model() {
        let text = write(&model(), &["from a test".into(), "two\nlines\rarw_deg_rth = 9".into()]);
        assert!(text.contains("# from a test\n# two lines arw_deg_rth = 9\n"));
        assert_eq!(parse(&text), Ok(model()));
        assert!(text.contains("rrw_dph_rth = 0.3333333333333333\n"));
        // Keys in any order, comments, the terms beyond N, B and K zero where left out.
        let m = parse("# mine\n\nrrw_dph_rth = 0.1  # K\narw_deg_rth=2e-3\nbias_instability_dph = 0\n").unwrap();
        assert_eq!((m.arw_deg_rth, m.rrw_dph_rth, m.gm_tau_s), (0.002, 0.1, 0.0));
    }

    #[test]
    fn reads_the_json_of_nf_allan_and_nf_fit() {
        let allan = r#"{"arw_deg_rth": 0.002, "arw_deg_rth_sigma": 1e-5, "bias_instability_dph": 0.02,
            "rrw_dph_rth": 0.05, "gm_sigma_dph": null, "curve": [{"tau_s": 0.1}]}"#;
        let m = parse(allan).unwrap();
        assert_eq!((m.arw_deg_rth, m.rrw_dph_rth, m.gm_sigma_dph), (0.002, 0.05, 0.0));
        let fit = r#"{"azimuth_deg": 12.0, "noise_model": {"arw_deg_rth": 0.001, "bias_instability_dph": 0,
            "rrw_dph_rth": 0, "gm_tau_s": 3}}"#;
        assert_eq!(parse(fit).unwrap().gm_tau_s, 3.0);
    }

    #[test]
    fn every_bad_file_names_the_line() {
        let cases: &[(&str, usize, &str)] = &[
            ("arw_deg_rth = 0.1\nbogus = 1\n", 2, "unknown key 'bogus'"),
            (
                "arw_deg_rth = 0.1\nbias_instability_dph = 0.01\n",
                0,
                "no rrw_dph_rth: a noise file gives N, B and K",
            ),
            ("rrw_dph_rth = 0.1\n", 0, "no arw_deg_rth, bias_instability_dph:"),
            (
                "{\"arw_deg_rth\": 1, \"bias_instability_dph\": null, \"rrw_dph_rth\": 0}",
                0,
                "no bias_instability_dph:",
            ),
            ("arw_deg_rth = 0.1\n\narw_deg_rth = 0.2\n", 3, "twice (first on line 1)"),
            ("# c\nrrw_dph_rth = -0.1\n", 2, "negative"),
            ("rrw_dph_rth = inf\n", 1, "not a finite number"),
            ("rrw_dph_rth = NaN\n", 1, "not a finite number"),
            ("rrw_dph_rth = abc\n", 1, "'abc' is not a number"),
            ("rrw_dph_rth 0.1\n", 1, "not 'key = value'"),
            (
                "arw_deg_rth = 0.1\ngm_sigma_dph = 0.1\nbias_instability_dph = 0\nrrw_dph_rth = 0\n",
                2,
                "needs gm_tau_s > 0",
            ),
            ("# nothing\n", 0, "no noise terms"),
            ("{\n  \"arw_deg_rth\": 1,\n  \"rrw_dph_rth\": -2\n}", 3, "negative"),
            (
                "{\n  \"arw_deg_rth\": 1,\n  \"bias_instability_dph\": 0,\n  \"rrw_dph_rth\": 0,\n  \"gm_sigma_dph\": 1\n}",
                5,
                "needs gm_tau_s",
            ),
            ("{\n  \"rrw_dph_rth\": \"x\"\n}", 2, "not a number"),
            ("{\n  \"arw_deg_rth\": 1,\n", 3, "not valid JSON"),
            ("{\"azimuth_deg\": 1}", 0, "no noise terms"),
        ];
        for (text, line, what) in cases {
            let e = parse(text).unwrap_err();
            assert_eq!(e.line, *line, "{text}: {e}");
            assert!(e.to_string().contains(what), "{text}: {e}");
        }
    }
}
