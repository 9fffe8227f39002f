//! `nf plan`: budgets, the fastest run for a target and a Monte Carlo check.

use super::Fail;
use super::noise_args::NoiseArgs;
use crate::plan_noise::{self, Candidate, Space};
use crate::plot::{Panel, Series, Style};
use crate::range::{MAX_LATITUDE_DEG, above, real};
use crate::schedule::{Schedule, Timing};
use crate::textfile::short;
use crate::twin_check::{self, RunSpec, TwinCheck};
use crate::{plan, plot};
use json::{AllowanceJson, CandidateJson, MonteCarloJson, NoiseBudgetJson, PlanJson, TwinCheckJson};
use nf_instrument::stepper;
use nf_model::noise::NoiseModel;
use nf_model::order::Order;
use nf_model::uncertainty::{Budget, allocate, tilt_arcsec};
use std::io::Write;

mod json;

#[derive(clap::Args)]
pub struct PlanArgs {
    #[arg(long, default_value_t = 43.8, allow_hyphen_values = true, value_parser = real(-MAX_LATITUDE_DEG, MAX_LATITUDE_DEG))]
    lat: f64,
    /// White gyro noise of one position's mean, deg/h, for a dwell of --ref-dwell (sets the
    /// ARW unless --arw is given).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.005, value_parser = real(0.0, 10.0))]
    gyro_noise: f64,
    #[arg(long, allow_hyphen_values = true, default_value_t = 2.0, value_parser = real(0.01, 3600.0))]
    ref_dwell: f64,
    /// Encoder uncertainty per position, deg.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.001, value_parser = real(0.0, 10.0))]
    encoder: f64,
    /// Shaft-tilt uncertainty left after levelling, deg.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.003, value_parser = real(0.0, 10.0))]
    tilt: f64,
    /// Positions of the planned run.
    #[arg(long, allow_hyphen_values = true, default_value_t = 72, value_parser = clap::value_parser!(u32).range(4..=720))]
    n: u32,
    /// Dwell of the planned run, s.
    #[arg(long, allow_hyphen_values = true, default_value_t = 2.0, value_parser = real(0.01, 600.0))]
    dwell: f64,
    /// Visiting order of the planned run.
    #[arg(long, default_value = "sequential")]
    order: String,
    /// Settling time after each move, s.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.3, value_parser = real(0.0, 60.0))]
    settle: f64,
    /// Stepper cruise speed, steps/s.
    #[arg(long, allow_hyphen_values = true, default_value_t = stepper::Config::default().max_sps as f64, value_parser = real(stepper::Config::default().start_sps as f64, 1e6))]
    max_sps: f64,
    /// Stepper acceleration, steps/s^2.
    #[arg(long, allow_hyphen_values = true, default_value_t = stepper::Config::default().accel_sps2 as f64, value_parser = above(0.0, 1e8))]
    accel: f64,
    /// Motor steps per shaft turn.
    #[arg(long, allow_hyphen_values = true, default_value_t = stepper::Config::default().steps_per_rev, value_parser = clap::value_parser!(u32).range(2..=10_000_000))]
    steps_per_rev: u32,
    /// Coloured noise terms (bias instability, random walk, Gauss-Markov) of the gyro.
    #[command(flatten)]
    noise: NoiseArgs,
    /// Target uncertainty, arcsec.
    #[arg(long, allow_hyphen_values = true, value_parser = above(0.0, 36_000.0))]
    target: Option<f64>,
    /// Longest run the search considers, s.
    #[arg(long, allow_hyphen_values = true, default_value_t = Space::default().max_time_s, value_parser = above(0.0, 1e6))]
    max_time: f64,
    /// Twin runs checking the stated sigma of the fastest run (or of the planned run without a
    /// target): the firmware's logic, this gyro and motor, fitted with this noise model.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=10_000))]
    twin_runs: u32,
    /// Monte Carlo runs checking the formula (0: none).
    #[arg(long, allow_hyphen_values = true, default_value_t = 2000, value_parser = clap::value_parser!(u32).range(0..=1_000_000))]
    mc_runs: u32,
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    seed: u64,
    #[arg(long)]
    json: bool,
    /// Plot the uncertainty against n (*.svg or *.png).
    #[arg(long, value_parser = super::plot_file)]
    plot: Option<String>,
}

fn describe(c: &Candidate) -> String {
    format!(
        "{} order, n = {}, dwell {} s: {:.1}\" in {:.0} s",
        c.order, c.n, c.dwell_s, c.sigma_arcsec, c.time_s
    )
}

/// The white-noise budgets take every position visited equally often: a list that leaves
/// some out, or visits some more, is refused rather than planned as if it did.
fn even_visits(order: &Order, n: u16) -> Result<(), Fail> {
    let Some(u) = order.uneven(n) else { return Ok(()) };
    Err(Fail(
        format!(
            "--order: the list visits {} of the {n} positions, {}; a plan takes every position visited equally often (a list over all {n}, or --n for the positions it visits)",
            u.visited,
            if u.first_missed.is_some() {
                "leaving the rest out"
            } else {
                "some more often than others"
            }
        ),
        2,
    ))
}

/// Why no run reaches the target: the limit its best run stands at, or the noise's floor.
fn unreachable(p: &plan_noise::Plan, max_time_s: f64) -> String {
    let Some(floor) = &p.floor else {
        return "in any run searched".into();
    };
    let most = Space::default().positions.into_iter().max().unwrap_or(0);
    if floor.n >= most {
        format!(
            "in runs of up to {most} positions, the most a plan takes: the best is {}",
            describe(floor)
        )
    } else if floor.time_s > 0.9 * max_time_s {
        format!(
            "in runs up to {max_time_s:.0} s (--max-time): the best is {}",
            describe(floor)
        )
    } else {
        format!(
            "at any n, dwell and order: the noise sets a floor, the best being {}",
            describe(floor)
        )
    }
}

pub fn cmd_plan(a: PlanArgs) -> Result<(), Fail> {
    let model = a.noise.apply(NoiseModel::white(a.gyro_noise, a.ref_dwell))?;
    let timing = Timing {
        motor: stepper::Config {
            steps_per_rev: a.steps_per_rev,
            max_sps: a.max_sps as f32,
            accel_sps2: a.accel as f32,
            ..Default::default()
        },
        settle_s: a.settle,
        dwell_s: a.dwell,
        ..Timing::default()
    };
    let order = Order::parse(&a.order)
        .and_then(|o| o.check(a.n as u16).map(|()| o))
        .map_err(|e| Fail(format!("--order: {e}"), 2))?;
    even_visits(&order, a.n as u16)?;
    let n = a.n as usize;
    // Levelling: two half turns, settling and an inclinometer reading at each.
    let levelling_s = 2.0 * (timing.move_s(a.steps_per_rev / 2) + a.settle + timing.per_position_s);
    let schedule = Schedule::new(&order, n, n / 2, &timing);
    let time_s = levelling_s + schedule.duration_s;
    let budget = plan_noise::Budget {
        latitude_deg: a.lat,
        encoder_deg: a.encoder,
        tilt_deg: a.tilt,
    };
    // The white-noise budgets are per position: forward-back dwells twice at each.
    let visits_per_position = order.visits(a.n as u16) as f64 / a.n as f64;
    let noise_gyro = plan_noise::gyro_arcsec(&model, &schedule, a.lat);
    let noise_total = plan_noise::total_arcsec(&model, &schedule, &budget);
    let inp = plan::Inputs {
        latitude_deg: a.lat,
        gyro_dph: model.white_mean_sd_dph(a.ref_dwell),
        ref_dwell_s: a.ref_dwell,
        encoder_deg: a.encoder,
        tilt_deg: a.tilt,
        n: a.n,
        dwell_s: a.dwell * visits_per_position,
        gyro_elev_deg: 0.01,
    };
    let s = inp.sigmas(inp.dwell_s);
    let paper_b = Budget::paper(a.n, &s, a.lat, 45.0, inp.gyro_elev_deg);
    let exact_b = Budget::closed_form(a.n, &s, a.lat);
    let num_b = plan::numerical(&inp);
    let search = a.target.map(|t| {
        let bar = indicatif::ProgressBar::new_spinner();
        bar.set_message("searching orders, n and dwells");
        let space = Space {
            max_time_s: a.max_time,
            ..Space::default()
        };
        let p = plan_noise::search(
            &model,
            &budget,
            &timing,
            &plan_noise::named_orders(),
            &space,
            t,
            levelling_s,
        );
        bar.finish_and_clear();
        p
    });
    let twin = twin_check(&a, &model, &timing, search.as_ref().and_then(|p| p.fastest.as_ref()))?;
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
        let under_noise = ns
            .iter()
            // A listed order is a run of its own n only.
            .filter(|&&m| !matches!(order, Order::List(_)) || m == a.n)
            .filter_map(|&m| {
                order.check(m as u16).ok()?;
                let sc = Schedule::new(&order, m as usize, m as usize / 2, &timing);
                Some((m as f64, plan_noise::total_arcsec(&model, &sc, &budget)?))
            })
            .collect();
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
                    name: "exact model, white noise".into(),
                    points: curve(&|n| Budget::closed_form(n, &s, a.lat).total_arcsec),
                    style: Style::Line,
                },
                Series {
                    name: format!("noise model, {} order (GLS)", order.name()),
                    points: under_noise,
                    style: Style::Line,
                },
            ],
            log_x: false,
            log_y: false,
        };
        plot::write(p, &[panel])?;
    }
    let mut out = std::io::stdout().lock();
    if a.json {
        let j = PlanJson {
            allowance_for_target: allowance.map(AllowanceJson::from),
            budget_eq31_paper: (&paper_b).into(),
            budget_exact: (&exact_b).into(),
            budget_noise_model: NoiseBudgetJson {
                gyro_arcsec: noise_gyro,
                total_arcsec: noise_total,
            },
            budget_numerical: (&num_b).into(),
            dwell_s: a.dwell,
            fastest: search
                .as_ref()
                .and_then(|p| p.fastest.as_ref())
                .map(CandidateJson::from),
            fastest_per_order: search
                .as_ref()
                .map(|p| p.per_order.iter().map(CandidateJson::from).collect()),
            floor: search.as_ref().and_then(|p| p.floor.as_ref()).map(CandidateJson::from),
            floor_per_order_short_of_target: search
                .as_ref()
                .map(|p| p.short_of.iter().map(CandidateJson::from).collect()),
            gyro_dph_per_position: s.gyro_dph,
            monte_carlo: mc.map(|(sd_arcsec, formula_arcsec)| MonteCarloJson {
                formula_arcsec,
                runs: a.mc_runs,
                sd_arcsec,
            }),
            n: a.n,
            noise_model: (&model).into(),
            order: order.name(),
            paper_n_for_target: paper_n,
            target_arcsec: a.target,
            time_s,
            twin_check: twin.as_ref().map(|(c, stated, k)| TwinCheckJson::new(c, *stated, k)),
        };
        writeln!(out, "{}", serde_json::to_string_pretty(&j).unwrap_or_default())?;
        return Ok(());
    }
    let visits = if visits_per_position == 1.0 {
        String::new()
    } else {
        format!(
            ", {} visits and {} s of dwell per position",
            short(visits_per_position),
            short(inp.dwell_s)
        )
    };
    writeln!(
        out,
        "planned run: n = {}, dwell {} s, {} order (gyro {:.5} deg/h per position{visits}), {:.0} s to north with levelling and moves",
        a.n,
        a.dwell,
        order.name(),
        s.gyro_dph,
        time_s
    )?;
    writeln!(
        out,
        "{:<22} {:>9} {:>9} {:>9} {:>9}",
        "budget (arcsec)", "gyro", "encoder", "tilt", "total"
    )?;
    for (name, b) in [
        ("Eq. 31 (paper)", paper_b),
        ("exact, white noise", exact_b),
        ("exact, numerical", num_b),
    ] {
        writeln!(
            out,
            "{name:<22} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
            b.gyro_arcsec, b.encoder_arcsec, b.tilt_arcsec, b.total_arcsec
        )?;
    }
    if let (Some(g), Some(t)) = (noise_gyro, noise_total) {
        writeln!(
            out,
            "{:<22} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
            "noise model (GLS)", g, exact_b.encoder_arcsec, exact_b.tilt_arcsec, t
        )?;
    }
    if let (Some(t), Some(p)) = (a.target, &search) {
        match &p.fastest {
            Some(c) => writeln!(out, "target {t}\": fastest run under the noise model: {}", describe(c))?,
            None if tilt_arcsec(a.tilt, a.lat) >= t => writeln!(
                out,
                "target {t}\": not reachable: the levelling residue alone (tilt {} deg) gives {:.2}\"",
                a.tilt,
                tilt_arcsec(a.tilt, a.lat)
            )?,
            None => writeln!(
                out,
                "target {t}\": not reachable with this gyro and motor {}",
                unreachable(p, a.max_time)
            )?,
        }
        for c in &p.per_order {
            writeln!(out, "  fastest {}", describe(c))?;
        }
        if p.fastest.is_some() {
            for c in &p.short_of {
                writeln!(out, "  never reaches it: {} (its best)", describe(c))?;
            }
        }
        if let Some(s) = allowance {
            writeln!(
                out,
                "target {t}\" at n = {}: allowances of a third of the variance each (the gyro's as white noise of a position's mean): gyro {:.5} deg/h per position, encoder {:.5} deg, levelling {:.5} deg",
                a.n, s.gyro_dph, s.encoder_deg, s.tilt_deg
            )?;
        }
        match paper_n {
            Some(n) => writeln!(
                out,
                "target {t}\": the paper's Eq. 31 (white noise) asks for n = {n} at {} s of dwell per position",
                short(inp.dwell_s)
            )?,
            None => writeln!(
                out,
                "target {t}\": the paper's Eq. 31 (white noise, {} s of dwell per position) reaches it with no n",
                short(inp.dwell_s)
            )?,
        }
    }
    if let Some((c, stated, k)) = &twin {
        writeln!(
            out,
            "twin check, {} runs of the {}: RMS error {:.2}\" against the stated gyro term {stated:.2}\" ({:+.1}%), RMS error/sigma {:.2}",
            k.runs,
            describe(c),
            k.rms_error_arcsec,
            (k.rms_error_arcsec / stated - 1.0) * 100.0,
            k.rms_z
        )?;
    }
    if let Some((m, f)) = mc {
        writeln!(
            out,
            "Monte Carlo (white noise), {} runs: sd {m:.2}\" against the formula {f:.2}\" ({:+.1}%)",
            a.mc_runs,
            (m / f - 1.0) * 100.0
        )?;
    }
    Ok(())
}

/// The twin's check of the fastest run, else of the planned run: the run, its stated gyro
/// term and what the twin gave.
fn twin_check(
    a: &PlanArgs,
    model: &NoiseModel,
    timing: &Timing,
    fastest: Option<&Candidate>,
) -> Result<Option<(Candidate, f64, TwinCheck)>, Fail> {
    if a.twin_runs == 0 {
        return Ok(None);
    }
    let (order, n, dwell_s) = match fastest {
        Some(c) => (Order::parse(c.order).map_err(|e| e.to_string())?, c.n, c.dwell_s),
        None => (
            Order::parse(&a.order).map_err(|e| e.to_string())?,
            a.n as usize,
            a.dwell,
        ),
    };
    let tm = Timing { dwell_s, ..*timing };
    let schedule = Schedule::new(&order, n, n / 2, &tm);
    let stated = plan_noise::gyro_arcsec(model, &schedule, a.lat)
        .ok_or_else(|| "the GLS covariance of the run is singular".to_string())?;
    let spec = RunSpec {
        order,
        n: n as u16,
        dwell_s,
        settle_s: a.settle,
        motor: timing.motor,
        latitude_deg: a.lat,
    };
    let bar = indicatif::ProgressBar::new(a.twin_runs as u64);
    bar.set_message("twin runs");
    let k = twin_check::check(model, &spec, a.twin_runs, a.seed, || bar.inc(1))?;
    bar.finish_and_clear();
    let c = Candidate {
        order: order.name(),
        n,
        dwell_s,
        time_s: k.mean_time_s,
        sigma_arcsec: stated,
    };
    Ok(Some((c, stated, k)))
}
