//! `nf plan`: budgets, the fastest run for a target and a Monte Carlo check.

use super::{Fail, positive};
use crate::plot::{Panel, Series, Style};
use crate::{plan, plot};
use nf_model::uncertainty::{Budget, allocate, tilt_arcsec};
use serde_json::json;

#[derive(clap::Args)]
pub struct PlanArgs {
    #[arg(long, default_value_t = 43.8, allow_hyphen_values = true)]
    lat: f64,
    /// Gyro noise of one position's mean, deg/h, for a dwell of --ref-dwell.
    #[arg(long, default_value_t = 0.005)]
    gyro_noise: f64,
    #[arg(long, default_value_t = 2.0)]
    ref_dwell: f64,
    /// Encoder uncertainty per position, deg.
    #[arg(long, default_value_t = 0.001)]
    encoder: f64,
    /// Shaft-tilt uncertainty left after levelling, deg.
    #[arg(long, default_value_t = 0.003)]
    tilt: f64,
    /// Positions of the planned run.
    #[arg(long, default_value_t = 72)]
    n: u32,
    /// Dwell of the planned run, s.
    #[arg(long, default_value_t = 2.0)]
    dwell: f64,
    /// Move and settle time per position, s.
    #[arg(long, default_value_t = 0.2)]
    overhead: f64,
    /// Target uncertainty, arcsec.
    #[arg(long)]
    target: Option<f64>,
    /// Monte Carlo runs checking the formula (0: none).
    #[arg(long, default_value_t = 2000)]
    mc_runs: u32,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[arg(long)]
    json: bool,
    /// Plot the uncertainty against n (*.svg or *.png).
    #[arg(long)]
    plot: Option<String>,
}

pub fn cmd_plan(a: PlanArgs) -> Result<(), Fail> {
    if a.n < 4 || !positive(a.dwell) || !positive(a.ref_dwell) || !(-89.0..=89.0).contains(&a.lat) {
        return Err(Fail("need n >= 4, positive dwells and |lat| <= 89 deg".into(), 2));
    }
    let inp = plan::Inputs {
        latitude_deg: a.lat,
        gyro_dph: a.gyro_noise,
        ref_dwell_s: a.ref_dwell,
        encoder_deg: a.encoder,
        tilt_deg: a.tilt,
        n: a.n,
        dwell_s: a.dwell,
        overhead_s: a.overhead,
        gyro_elev_deg: 0.01,
    };
    let s = inp.sigmas(a.dwell);
    let paper_b = Budget::paper(a.n, &s, a.lat, 45.0, inp.gyro_elev_deg);
    let exact_b = Budget::closed_form(a.n, &s, a.lat);
    let num_b = plan::numerical(&inp);
    let fastest = a.target.and_then(|t| plan::fastest(&inp, t));
    let allowance = a.target.map(|t| allocate(t, a.n, a.lat));
    let paper_n = a.target.and_then(|t| plan::paper_n(&inp, t));
    let mc = (a.mc_runs > 0).then(|| {
        let bar = indicatif::ProgressBar::new(a.mc_runs as u64);
        bar.set_message("Monte Carlo");
        let r = plan::monte_carlo(&inp, a.mc_runs, a.seed, || bar.inc(1));
        bar.finish_and_clear();
        r
    });
    if let Some(p) = &a.plot {
        let ns: Vec<u32> = (2..=72).map(|k| k * 5).collect();
        let curve = |f: &dyn Fn(u32) -> f64| ns.iter().map(|&n| (n as f64, f(n))).collect::<Vec<_>>();
        let panel = Panel {
            title: format!("azimuth uncertainty, lat {} deg, dwell {} s", a.lat, a.dwell),
            x_label: "positions n".into(),
            y_label: "sigma psi (arcsec)".into(),
            series: vec![
                Series {
                    name: "Eq. 31 (paper)".into(),
                    points: curve(&|n| Budget::paper(n, &s, a.lat, 45.0, 0.01).total_arcsec),
                    style: Style::Line,
                },
                Series {
                    name: "exact model".into(),
                    points: curve(&|n| Budget::closed_form(n, &s, a.lat).total_arcsec),
                    style: Style::Line,
                },
            ],
            log_x: false,
            log_y: false,
        };
        plot::write(p, &[panel])?;
    }
    let bj = |b: &Budget<f64>| json!({"gyro_arcsec": b.gyro_arcsec, "encoder_arcsec": b.encoder_arcsec, "tilt_arcsec": b.tilt_arcsec, "total_arcsec": b.total_arcsec});
    if a.json {
        let j = json!({
            "n": a.n, "dwell_s": a.dwell, "time_s": inp.time_s(a.n, a.dwell),
            "gyro_dph_per_position": s.gyro_dph,
            "budget_eq31_paper": bj(&paper_b), "budget_exact": bj(&exact_b), "budget_numerical": bj(&num_b),
            "target_arcsec": a.target,
            "fastest": fastest.map(|(n, d, t)| json!({"n": n, "dwell_s": d, "time_s": t})),
            "paper_n_for_target": paper_n,
            "allowance_for_target": allowance.map(|s| json!({"gyro_dph": s.gyro_dph, "encoder_deg": s.encoder_deg, "tilt_deg": s.tilt_deg})),
            "monte_carlo": mc.map(|(m, f)| json!({"runs": a.mc_runs, "sd_arcsec": m, "formula_arcsec": f})),
        });
        println!("{}", serde_json::to_string_pretty(&j).unwrap_or_default());
        return Ok(());
    }
    println!(
        "planned run: n = {}, dwell {} s (gyro {:.5} deg/h per position), {:.0} s to north",
        a.n,
        a.dwell,
        s.gyro_dph,
        inp.time_s(a.n, a.dwell)
    );
    println!(
        "{:<22} {:>9} {:>9} {:>9} {:>9}",
        "budget (arcsec)", "gyro", "encoder", "tilt", "total"
    );
    for (name, b) in [
        ("Eq. 31 (paper)", paper_b),
        ("exact, closed form", exact_b),
        ("exact, numerical", num_b),
    ] {
        println!(
            "{name:<22} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
            b.gyro_arcsec, b.encoder_arcsec, b.tilt_arcsec, b.total_arcsec
        );
    }
    if let Some(t) = a.target {
        match fastest {
            Some((n, d, time)) => {
                println!("target {t}\": fastest is n = {n} at {d} s dwell, {time:.0} s to north (exact model)")
            }
            None => println!(
                "target {t}\": not reachable: the tilt term alone is {:.2}\"",
                tilt_arcsec(a.tilt, a.lat)
            ),
        }
        if let Some(s) = allowance {
            println!(
                "target {t}\" at n = {}: allowances of a third of the variance each: gyro {:.5} deg/h per position, encoder {:.5} deg, levelling {:.5} deg",
                a.n, s.gyro_dph, s.encoder_deg, s.tilt_deg
            );
        }
        match paper_n {
            Some(n) => println!(
                "target {t}\": the paper's Eq. 31 asks for n = {n} at {} s dwell",
                a.dwell
            ),
            None => println!("target {t}\": not reachable by the paper's Eq. 31"),
        }
    }
    if let Some((m, f)) = mc {
        println!(
            "Monte Carlo, {} runs: sd {m:.2}\" against the formula {f:.2}\" ({:+.1}%)",
            a.mc_runs,
            (m / f - 1.0) * 100.0
        );
    }
    Ok(())
}
