//! JSON pieces shared by several commands' `--json` output.
//!
//! The fields of each struct are in alphabetical order, the order the keys have always had.

use nf_model::uncertainty::Budget;
use serde::Serialize;

/// An uncertainty budget of the azimuth: each part and their root sum of squares.
#[derive(Serialize)]
pub(super) struct BudgetJson {
    /// The encoder's part, arcsec.
    encoder_arcsec: f64,
    /// The gyro noise's part, arcsec.
    gyro_arcsec: f64,
    /// The shaft tilt's part (worst case over its direction), arcsec.
    tilt_arcsec: f64,
    /// The root sum of squares of the parts, arcsec.
    total_arcsec: f64,
}

impl From<&Budget<f64>> for BudgetJson {
    fn from(b: &Budget<f64>) -> BudgetJson {
        BudgetJson {
            encoder_arcsec: b.encoder_arcsec,
            gyro_arcsec: b.gyro_arcsec,
            tilt_arcsec: b.tilt_arcsec,
            total_arcsec: b.total_arcsec,
        }
    }
}
