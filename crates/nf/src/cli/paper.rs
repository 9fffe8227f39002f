//! `nf paper`: the paper's numbers recomputed, and where it is wrong.

use super::Fail;
use crate::plot::{Panel, Series, Style};
use crate::{paper, plot};
use nf_model::paper::{eq24_arcsec, eq30_arcsec};
use nf_model::uncertainty::tilt_arcsec;
use std::io::Write;

mod json;

#[derive(clap::Args)]
pub struct PaperArgs {
    #[arg(long)]
    json: bool,
    /// Plot Fig. 6 (Eq. 24) and Fig. 7 (Eq. 30 against the exact model), *.svg or *.png.
    #[arg(long, value_parser = super::plot_file)]
    plot: Option<String>,
}

pub fn cmd_paper(a: PaperArgs) -> Result<(), Fail> {
    super::folders_exist(&[&a.plot])?;
    let ns = [72u32, 90, 120, 180, 240];
    let sws = [0.001, 0.002, 0.003, 0.005, 0.01];
    let etas = [0.0, 0.001, 0.003, 0.01, 0.03, 0.1];
    let epss = [0.001, 0.01, 0.1];
    let tables: Vec<(&paper::Table, paper::Recomputed)> = paper::TABLES.iter().map(|t| (t, t.recompute())).collect();
    let findings = paper::findings();
    if let Some(p) = &a.plot {
        let fig6 = Panel {
            title: "Fig. 6: Eq. 24 at latitude 43.8 deg".into(),
            x_label: "gyro uncertainty sigma_w (deg/h)".into(),
            y_label: "sigma psi (arcsec)".into(),
            series: ns
                .iter()
                .map(|&n| Series {
                    name: format!("n = {n}"),
                    points: (1..=100)
                        .map(|k| k as f64 * 1e-4)
                        .map(|s| (s, eq24_arcsec(n, s, paper::LAT)))
                        .collect(),
                    style: Style::Line,
                })
                .collect(),
            log_x: false,
            log_y: false,
        };
        let mut fig7 = Panel {
            title:
                "Fig. 7: shaft misalignment (tilt) eta, Eq. 30 (eta = sigma_eta, n = 180, psi = 45) and the exact model"
                    .into(),
            x_label: "shaft misalignment (tilt) eta (deg)".into(),
            y_label: "sigma psi (arcsec)".into(),
            series: epss
                .iter()
                .map(|&e| Series {
                    name: format!("Eq. 30, eps = {e}"),
                    points: (0..=100)
                        .map(|k| k as f64 * 1e-3)
                        .map(|h| (h, eq30_arcsec(180, paper::LAT, 45.0, h, e, h)))
                        .collect(),
                    style: Style::Line,
                })
                .collect(),
            log_x: false,
            log_y: false,
        };
        fig7.series.push(Series {
            name: "exact: eta tan(lat)".into(),
            points: (0..=100)
                .map(|k| k as f64 * 1e-3)
                .map(|h| (h, tilt_arcsec(h, paper::LAT)))
                .collect(),
            style: Style::Line,
        });
        plot::write(p, &[fig6, fig7])?;
    }
    let mut out = std::io::stdout().lock();
    if a.json {
        let grids = json::Grids {
            ns: &ns,
            sws: &sws,
            etas: &etas,
            epss: &epss,
        };
        let j = json::paper_json(&grids, &tables, &findings);
        writeln!(out, "{}", serde_json::to_string_pretty(&j).unwrap_or_default())?;
        return Ok(());
    }
    writeln!(
        out,
        "Eq. 24 (Fig. 6): azimuth uncertainty in arcsec at latitude 43.8 deg"
    )?;
    write!(out, "{:>10}", "sigma_w")?;
    for n in ns {
        write!(out, "{:>9}", format!("n={n}"))?;
    }
    writeln!(out)?;
    for s in sws {
        write!(out, "{s:>10}")?;
        for n in ns {
            write!(out, "{:>9.2}", eq24_arcsec(n, s, paper::LAT))?;
        }
        writeln!(out)?;
    }
    writeln!(
        out,
        "\nFig. 7: shaft misalignment (arcsec), Eq. 30 as printed (sigma_eta = eta, n = 180, psi = 45) and exact"
    )?;
    writeln!(
        out,
        "{:>8} {:>12} {:>12} {:>12} {:>14}",
        "eta", "eps=0.001", "eps=0.01", "eps=0.1", "exact (max)"
    )?;
    for h in etas {
        let e: Vec<f64> = epss
            .iter()
            .map(|&e| eq30_arcsec(180, paper::LAT, 45.0, h, e, h))
            .collect();
        writeln!(
            out,
            "{h:>8} {:>12.3} {:>12.3} {:>12.3} {:>14.3}",
            e[0],
            e[1],
            e[2],
            tilt_arcsec(h, paper::LAT)
        )?;
    }
    writeln!(
        out,
        "\nTables 1-4, ten runs each: stated against recomputed from the rows"
    )?;
    writeln!(
        out,
        "{:>6} {:>5} {:>12} {:>12} {:>9} {:>9} {:>9} {:>9}",
        "table", "n", "mean stated", "recomputed", "sd stat.", "recomp.", "RSS<", "max"
    )?;
    for (t, r) in &tables {
        writeln!(
            out,
            "{:>6} {:>5} {:>12.4} {:>12.5} {:>8}\" {:>8.1}\" {:>9} {:>9}",
            t.number, t.n, t.stated_mean_deg, r.mean_deg, t.stated_sd_arcsec, r.sd_arcsec, t.stated_rss_max, r.rss_max
        )?;
    }
    writeln!(
        out,
        "\nEq. 31 (simulated uncertainty): stated, from the paper's own equations, and exact"
    )?;
    for (n, stated) in paper::STATED_EQ31 {
        writeln!(
            out,
            "  n = {n:>3}: stated {stated}\", Eq. 24+26+30 give {:.2}\", exact model {:.2}\"",
            paper::eq31_paper(n),
            paper::eq31_exact(n)
        )?;
    }
    writeln!(out, "\nWhere the paper disagrees with its tables or the physics:")?;
    for f in &findings {
        writeln!(out, "- {f}")?;
    }
    Ok(())
}
