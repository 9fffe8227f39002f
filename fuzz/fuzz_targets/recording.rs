//! The recording reader on any text: no panic; what it accepts keeps the format's rules (rows
//! in visiting order, tilts elevations); and printing what it read back in the format and
//! reading that again gives the same recording.
#![no_main]

use libfuzzer_sys::fuzz_target;
use nf::recording::{Recording, Row};
use std::fmt::Write;

fn cell(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x}"))
}

/// The recording in the format, every column, values in the shortest text that reads back.
fn print(rec: &Recording) -> String {
    let mut s = String::new();
    for (k, v) in &rec.meta {
        let _ = writeln!(s, "# {k} = {v}");
    }
    s +=
        "index,t_s,encoder_deg,rate_dph,rate_sd_dph,samples,temp_c,tilt_x_deg,tilt_y_deg,q1_dph,q2_dph,q3_dph,q4_dph\n";
    for r in &rec.rows {
        let q = r.quarters_dph.map_or([None; 4], |q| q.map(Some));
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.index,
            r.t_s,
            r.encoder_deg,
            r.rate_dph,
            cell(r.rate_sd_dph),
            r.samples.map_or(String::new(), |n| n.to_string()),
            cell(r.temp_c),
            cell(r.tilt_x_deg),
            cell(r.tilt_y_deg),
            cell(q[0]),
            cell(q[1]),
            cell(q[2]),
            cell(q[3]),
        );
    }
    s
}

fn finite(v: Option<f64>) -> bool {
    v.is_none_or(f64::is_finite)
}

fn check(r: &Row) {
    assert!(r.t_s.is_finite() && r.rate_dph.is_finite(), "{r:?}");
    assert!((0.0..360.0).contains(&r.encoder_deg), "{r:?}");
    assert!(r.rate_sd_dph.is_none_or(|s| s >= 0.0) && finite(r.rate_sd_dph), "{r:?}");
    assert!(
        finite(r.temp_c) && finite(r.tilt_x_deg) && finite(r.tilt_y_deg),
        "{r:?}"
    );
    let elevation = |v: Option<f64>| v.is_none_or(|e| e.abs() < 90.0);
    assert!(elevation(r.tilt_x_deg) && elevation(r.tilt_y_deg), "{r:?}");
    assert!(r.quarters_dph.is_none_or(|q| q.iter().all(|x| x.is_finite())), "{r:?}");
}

fuzz_target!(|data: &[u8]| {
    let text = nf_fuzz::text(data);
    let Ok(rec) = Recording::parse(&text) else {
        return;
    };
    assert!(!rec.rows.is_empty());
    assert!((-90.0..=90.0).contains(&rec.latitude_deg));
    assert_eq!(rec.meta.get("format").map(String::as_str), Some(nf::recording::FORMAT));
    for w in rec.rows.windows(2) {
        assert!(w[1].index > w[0].index && w[1].t_s > w[0].t_s, "visiting order: {w:?}");
    }
    for r in &rec.rows {
        check(r);
    }
    let printed = print(&rec);
    let again = Recording::parse(&printed).unwrap_or_else(|e| panic!("{e}\n{printed}"));
    assert_eq!(again.latitude_deg, rec.latitude_deg);
    assert_eq!(again.meta, rec.meta);
    assert_eq!(again.rows.len(), rec.rows.len());
    for (a, b) in again.rows.iter().zip(&rec.rows) {
        assert_eq!(
            Row {
                line: b.line,
                ..a.clone()
            },
            *b,
            "{printed}"
        );
    }
});
