//! The JSON of `nf paper --json`.
//!
//! The fields of each struct are in alphabetical order, the order the keys have always had.

use crate::paper::{self, Recomputed, Table};
use nf_model::paper::{eq24_arcsec, eq30_arcsec};
use nf_model::uncertainty::tilt_arcsec;
use serde::Serialize;

/// The paper's figures and tables recomputed, and where it is wrong.
#[derive(Serialize)]
pub(super) struct PaperJson<'a> {
    /// Eq. 24 (Fig. 6) at the paper's latitude, one entry per n.
    eq24_arcsec: Vec<Eq24>,
    /// Eq. 31, the simulated uncertainty: stated, from the paper's equations, and exact.
    eq31: Vec<Eq31>,
    /// Fig. 7, shaft misalignment: Eq. 30 as printed and the exact model, one entry per eta.
    fig7: Vec<Fig7>,
    /// Where the paper disagrees with its tables or the physics.
    findings: &'a [String],
    /// Tables 1-4: stated against recomputed from the rows.
    tables: Vec<TableJson>,
}

/// Eq. 24 for one n.
#[derive(Serialize)]
struct Eq24 {
    /// Positions.
    n: u32,
    /// One entry per gyro uncertainty.
    values: Vec<Eq24Value>,
}

/// Eq. 24 at one gyro uncertainty.
#[derive(Serialize)]
struct Eq24Value {
    /// Azimuth uncertainty, arcsec.
    arcsec: f64,
    /// Gyro uncertainty sigma_w, deg/h.
    sigma_w_dph: f64,
}

/// Eq. 31 for one n.
#[derive(Serialize)]
struct Eq31 {
    /// The exact model, arcsec.
    exact_arcsec: f64,
    /// Positions.
    n: u32,
    /// Eq. 24 + 26 + 30 as printed, arcsec.
    paper_equations_arcsec: f64,
    /// As stated in the paper, arcsec.
    stated_arcsec: f64,
}

/// Fig. 7 at one misalignment (sigma_eta = eta, n = 180, psi = 45).
#[derive(Serialize)]
struct Fig7 {
    /// Eq. 30 for each eps of the figure, arcsec.
    eq30_arcsec: Vec<f64>,
    /// Shaft misalignment eta, deg.
    eta_deg: f64,
    /// The exact model (eta tan(lat), its maximum), arcsec.
    exact_arcsec: f64,
}

/// One of the paper's tables.
#[derive(Serialize)]
struct TableJson {
    /// Positions per run.
    n: u32,
    /// Recomputed from the table's rows.
    recomputed: TableFigures,
    /// The factor the RSS column is printed in.
    rss_unit: f64,
    /// As stated in the paper.
    stated: TableFigures,
    /// The table's number.
    table: u8,
}

/// A table's summary figures.
#[derive(Serialize)]
struct TableFigures {
    /// Mean azimuth, deg.
    mean_deg: f64,
    /// Largest RSS, in the table's `rss_unit`.
    rss_max: f64,
    /// Standard deviation of the azimuths, arcsec.
    sd_arcsec: f64,
}

/// The grids of the figures: n and sigma_w of Fig. 6, eta and eps of Fig. 7.
pub(super) struct Grids<'a> {
    pub ns: &'a [u32],
    pub sws: &'a [f64],
    pub etas: &'a [f64],
    pub epss: &'a [f64],
}

pub(super) fn paper_json<'a>(g: &Grids, tables: &[(&Table, Recomputed)], findings: &'a [String]) -> PaperJson<'a> {
    PaperJson {
        eq24_arcsec: g
            .ns
            .iter()
            .map(|&n| Eq24 {
                n,
                values: g
                    .sws
                    .iter()
                    .map(|&s| Eq24Value {
                        arcsec: eq24_arcsec(n, s, paper::LAT),
                        sigma_w_dph: s,
                    })
                    .collect(),
            })
            .collect(),
        eq31: paper::STATED_EQ31
            .iter()
            .map(|&(n, s)| Eq31 {
                exact_arcsec: paper::eq31_exact(n),
                n,
                paper_equations_arcsec: paper::eq31_paper(n),
                stated_arcsec: s,
            })
            .collect(),
        fig7: g
            .etas
            .iter()
            .map(|&h| Fig7 {
                eq30_arcsec: g
                    .epss
                    .iter()
                    .map(|&e| eq30_arcsec(180, paper::LAT, 45.0, h, e, h))
                    .collect(),
                eta_deg: h,
                exact_arcsec: tilt_arcsec(h, paper::LAT),
            })
            .collect(),
        findings,
        tables: tables
            .iter()
            .map(|(t, r)| TableJson {
                n: t.n,
                recomputed: TableFigures {
                    mean_deg: r.mean_deg,
                    rss_max: r.rss_max,
                    sd_arcsec: r.sd_arcsec,
                },
                rss_unit: t.rss_unit,
                stated: TableFigures {
                    mean_deg: t.stated_mean_deg,
                    rss_max: t.stated_rss_max,
                    sd_arcsec: t.stated_sd_arcsec,
                },
                table: t.number,
            })
            .collect(),
    }
}
