//! One tilt path for `nf fit` and `nf diagnose`: on twin recordings tilted 0 to 10 deg at
//! latitudes up to 85 deg, with both inclinometer columns, with `tilt_x_deg` alone, and with a
//! reading missing, both reach the same azimuth, and it is the truth within its sigma.

use nf::analysis::{Options, analyse};
use nf::diagnose::{self, Kind, diagnose};
use nf::recording::Recording;
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_model::angle::wrap_180;
use nf_model::noise::NoiseModel;
use nf_twin::{Recorder, TwinConfig, simulate};

/// A recording from the twin with the given shaft tilt and latitude.
fn recording(tilt_deg: f64, lat: f64, seed: u64) -> (String, f64) {
    let mut twin = TwinConfig {
        seed,
        noise: NoiseModel::white(0.005, 1.0),
        ..TwinConfig::default()
    };
    twin.instrument.latitude_deg = lat;
    twin.instrument.tilt_deg = tilt_deg;
    twin.instrument.tilt_dir_deg = 30.0 + 17.0 * seed as f64;
    let cfg = RunConfig {
        positions: 24,
        dwell_ms: 1000,
        latitude_deg: lat as f32,
        tilt_policy: TiltPolicy::Warn,
        ..RunConfig::default()
    };
    let mut rec = Recorder::default();
    let (report, _) = simulate(&twin, &cfg, &mut rec);
    assert_eq!(report.result, Ok(()));
    (rec.text(), twin.instrument.psi_deg)
}

/// The recording with a column dropped, or one of its cells emptied.
fn edit(text: &str, drop_column: Option<&str>, blank_x_in_row: Option<usize>) -> String {
    let mut out = String::new();
    let mut cols: Vec<String> = Vec::new();
    let mut row = 0;
    for line in text.lines() {
        if line.starts_with('#') {
            out += line;
        } else if cols.is_empty() {
            cols = line.split(',').map(String::from).collect();
            let keep: Vec<&str> = cols
                .iter()
                .map(String::as_str)
                .filter(|c| Some(*c) != drop_column)
                .collect();
            out += &keep.join(",");
        } else {
            let cells: Vec<&str> = line
                .split(',')
                .zip(&cols)
                .filter(|(_, c)| Some(c.as_str()) != drop_column)
                .map(|(v, c)| {
                    if c == "tilt_x_deg" && blank_x_in_row == Some(row) {
                        ""
                    } else {
                        v
                    }
                })
                .collect();
            out += &cells.join(",");
            row += 1;
        }
        out.push('\n');
    }
    out
}

#[test]
fn fit_and_diagnose_agree_and_find_north_at_every_tilt_and_latitude() {
    let mut worst_z: f64 = 0.0;
    for (k, (tilt, lat)) in [
        (0.0, 43.8),
        (1.0, 43.8),
        (3.0, 60.0),
        (10.0, 43.8),
        (1.0, -85.0),
        (5.0, 85.0),
        (10.0, -85.0),
    ]
    .into_iter()
    .enumerate()
    {
        let (text, truth) = recording(tilt, lat, k as u64);
        for (case, variant) in [
            ("both columns", edit(&text, None, None)),
            ("tilt_x alone", edit(&text, Some("tilt_y_deg"), None)),
            ("tilt_y alone", edit(&text, Some("tilt_x_deg"), None)),
            ("one reading missing", edit(&text, None, Some(5))),
        ] {
            let rec = Recording::parse(&variant).unwrap_or_else(|e| panic!("{case}: {e}"));
            let at = format!("tilt {tilt} deg, lat {lat}: {case}");
            let fit = analyse(&rec, &Options::default()).unwrap_or_else(|e| panic!("{at}: {e}"));
            assert_eq!(fit.tilt_warning, None, "{at}");
            let diag = diagnose(&rec, &diagnose::Options::default()).unwrap_or_else(|e| panic!("{case}: {e}"));
            let at = format!("tilt {tilt} deg, lat {lat}: {case}");
            // Without findings diagnose's fit is nf fit's under the noise: the same tilt path.
            if diag
                .findings
                .iter()
                .all(|f| f.effect == Kind::ShaftTilt || f.effect.is_noise())
            {
                let d = wrap_180(diag.final_.azimuth_deg - fit.gls.psi_deg) * 3600.0;
                assert!(
                    d.abs() < 0.2 * fit.gls.sigma_psi_deg * 3600.0,
                    "{at}: diagnose {} vs fit {}",
                    diag.final_.azimuth_deg,
                    fit.gls.psi_deg
                );
            }
            let z = wrap_180(fit.fit.psi_deg - truth) * 3600.0 / (fit.fit.sigma_psi_deg * 3600.0);
            worst_z = worst_z.max(z.abs());
            assert!(z.abs() < 4.5, "{at}: error {z:.1} sigma");
        }
    }
    println!("worst |error| / sigma {worst_z:.2}");
}

/// The recording with each `tilt_y_deg` negated, or the two tilt columns' names swapped.
fn mirrored(text: &str, swap: bool) -> String {
    let mut y_at = None;
    let mut out = String::new();
    for line in text.lines() {
        if line.starts_with('#') {
            out += line;
        } else if y_at.is_none() {
            let cols: Vec<&str> = line.split(',').collect();
            y_at = cols.iter().position(|c| *c == "tilt_y_deg");
            if swap {
                out += &line
                    .replace("tilt_x_deg", "TMP")
                    .replace("tilt_y_deg", "tilt_x_deg")
                    .replace("TMP", "tilt_y_deg");
            } else {
                out += line;
            }
        } else {
            let cells: Vec<String> = line
                .split(',')
                .enumerate()
                .map(|(i, v)| match v.parse::<f64>() {
                    Ok(y) if Some(i) == y_at && !swap => format!("{}", -y),
                    _ => v.to_string(),
                })
                .collect();
            out += &cells.join(",");
        }
        out.push('\n');
    }
    out
}

/// Readings that turn round the tilt circle the mirror way (Y's sign flipped, X and Y
/// swapped) are said to, and the tilt comes from X alone: with Y flipped, the azimuth of the
/// recording without its Y column, near the truth.
#[test]
fn an_inclinometer_turning_the_wrong_way_is_named_and_x_alone_is_used() {
    for (k, (tilt, lat)) in [(1.0, 43.8), (3.0, 60.0), (0.05, 20.0)].into_iter().enumerate() {
        let (text, truth) = recording(tilt, lat, 10 + k as u64);
        let at = format!("tilt {tilt} deg, lat {lat}");
        let x_alone = analyse(
            &Recording::parse(&edit(&text, Some("tilt_y_deg"), None)).unwrap(),
            &Options::default(),
        )
        .unwrap();
        let flipped = analyse(&Recording::parse(&mirrored(&text, false)).unwrap(), &Options::default()).unwrap();
        let warning = flipped
            .tilt_warning
            .unwrap_or_else(|| panic!("{at}: flipped Y not named"));
        assert!(warning.contains("the wrong way"), "{at}: {warning}");
        assert!((flipped.gls.psi_deg - x_alone.gls.psi_deg).abs() < 1e-9, "{at}");
        let z = wrap_180(flipped.gls.psi_deg - truth) / flipped.gls.sigma_psi_deg;
        assert!(z.abs() < 4.5, "{at}: error {z:.1} sigma");
        let swapped = analyse(&Recording::parse(&mirrored(&text, true)).unwrap(), &Options::default()).unwrap();
        assert!(swapped.tilt_warning.is_some(), "{at}: swapped axes not named");
        let diag = diagnose(
            &Recording::parse(&mirrored(&text, false)).unwrap(),
            &diagnose::Options::default(),
        )
        .unwrap();
        assert!(
            diag.notes.iter().any(|n| n.contains("the wrong way")),
            "{at}: {:?}",
            diag.notes
        );
    }
}
