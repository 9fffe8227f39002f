//! `nf plan`: budgets, the fastest run for a target and a Monte Carlo check.

use super::Fail;
use super::noise_args::NoiseArgs;
use crate::plan_noise::{self, Candidate, Space};
use crate::plot::{Panel, Series, Style};
use crate::range::{MAX_LATITUDE_DEG, above, real};
use crate::schedule::{Schedule, Timing};
use crate::twin_check::{self, RunSpec, TwinCheck};
use crate::{plan, plot};
use json::{AllowanceJson, CandidateJson, MonteCarloJson, NoiseBudgetJson, PlanJson, TwinCheckJson};
use nf_instrument::stepper;
use nf_model::noise::NoiseModel;
use nf_model::order::Order;
use nf_model::uncertainty::{Budget, Sigmas, allocate};
use std::io::Write;

mod json;
mod text;

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
    /// Shaft-tilt uncertainty the azimuth is left with, deg: a levelling residue the fit does
    /// not correct (`nf fit --tilt none`). The firmware and `nf fit` correct the tilt from the
    /// inclinometer at each position, which leaves a few hundredths of this default: plan
    /// such runs with `--tilt 0` or the inclinometer's own uncertainty.
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
    #[arg(long, allow_hyphen_values = true, default_value_t = stepper::Config::default().steps_per_rev, value_parser = clap::value_parser!(u32).range(4..=10_000_000))]
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
fn unreachable(p: &plan_noise::Plan, space: &Space) -> String {
    let max_time_s = space.max_time_s;
    let Some(floor) = &p.floor else {
        return match p.shortest_s {
            Some(t) if t > max_time_s => {
                format!("in runs up to {max_time_s:.0} s (--max-time): the shortest run searched takes {t:.1} s")
            }
            _ => "in any run searched".into(),
        };
    };
    let most = space.positions.iter().copied().max().unwrap_or(0);
    // A longer dwell goes on gaining where the time allows it: the time limit binds first.
    if floor.time_s > 0.9 * max_time_s {
        let also = if floor.n >= most {
            format!(" at {most} positions, the most a plan takes")
        } else {
            String::new()
        };
        format!(
            "in runs up to {max_time_s:.0} s (--max-time){also}: the best is {}",
            describe(floor)
        )
    } else if floor.n >= most {
        format!(
            "in runs of up to {most} positions, the most a plan takes: the best is {}",
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
    super::folders_exist(&[&a.plot])?;
    let p = Planned::new(&a)?;
    if let Some(path) = &a.plot {
        plot::write(path, &[p.panel(&a)])?;
    }
    let mut out = std::io::stdout().lock();
    if a.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&p.json(&a)).unwrap_or_default())?;
    } else {
        text::write(&mut out, &a, &p)?;
    }
    Ok(())
}

/// The planned run's budgets, and what was asked beside them: the search for a target, the
/// twin's check, the Monte Carlo.
struct Planned {
    model: NoiseModel,
    timing: Timing,
    order: Order,
    /// The planned run's time to north, levelling and moves included, s.
    time_s: f64,
    budget: plan_noise::Budget,
    /// Visits of each position (forward-back dwells twice at each).
    visits_per_position: f64,
    /// The gyro's term and the total under the noise model (GLS), arcsec.
    noise_gyro: Option<f64>,
    noise_total: Option<f64>,
    inp: plan::Inputs,
    sigmas: Sigmas<f64>,
    paper: Budget<f64>,
    exact: Budget<f64>,
    numerical: Budget<f64>,
    search: Option<plan_noise::Plan>,
    twin: Option<(Candidate, f64, TwinCheck)>,
    allowance: Option<Sigmas<f64>>,
    paper_n: Option<u32>,
    /// The Monte Carlo's sd and the formula's, arcsec.
    mc: Option<(f64, f64)>,
}

impl Planned {
    fn new(a: &PlanArgs) -> Result<Planned, Fail> {
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
        if a.n > a.steps_per_rev {
            return Err(Fail(
                format!(
                    "--n {}: more positions than the motor's {} steps a turn (--steps-per-rev): two would share an angle",
                    a.n, a.steps_per_rev
                ),
                2,
            ));
        }
        let n = a.n as usize;
        // Levelling: two half turns, settling and an inclinometer reading at each.
        let levelling_s = 2.0 * (timing.move_s(a.steps_per_rev / 2) + a.settle + timing.per_position_s);
        let schedule = Schedule::new(&order, n, n / 2, &timing);
        let budget = plan_noise::Budget {
            latitude_deg: a.lat,
            encoder_deg: a.encoder,
            tilt_deg: a.tilt,
        };
        // The white-noise budgets are per position: forward-back dwells twice at each.
        let visits_per_position = order.visits(a.n as u16) as f64 / a.n as f64;
        let inp = plan::Inputs {
            latitude_deg: a.lat,
            // A sensor's short filter tail is noise each position has on its own, as white.
            gyro_dph: model.own_mean_sd_dph(a.ref_dwell),
            ref_dwell_s: a.ref_dwell,
            encoder_deg: a.encoder,
            tilt_deg: a.tilt,
            n: a.n,
            dwell_s: a.dwell * visits_per_position,
            gyro_elev_deg: 0.01,
        };
        let sigmas = inp.sigmas(inp.dwell_s);
        let search = a.target.map(|t| search(a, &model, &budget, &timing, t, levelling_s));
        let twin = twin_check(a, &model, &timing, search.as_ref().and_then(|p| p.fastest.as_ref()))?;
        Ok(Planned {
            time_s: levelling_s + schedule.duration_s,
            noise_gyro: plan_noise::gyro_arcsec(&model, &schedule, a.lat),
            noise_total: plan_noise::total_arcsec(&model, &schedule, &budget),
            paper: Budget::paper(a.n, &sigmas, a.lat, 45.0, inp.gyro_elev_deg),
            exact: Budget::closed_form(a.n, &sigmas, a.lat),
            numerical: plan::numerical(&inp),
            allowance: a.target.map(|t| allocate(t, a.n, a.lat)),
            paper_n: a.target.and_then(|t| plan::paper_n(&inp, t)),
            mc: monte_carlo(a, &inp),
            model,
            timing,
            order,
            budget,
            visits_per_position,
            inp,
            sigmas,
            search,
            twin,
        })
    }

    /// The uncertainty against n: the paper's, the exact white-noise one and the noise
    /// model's in the planned order.
    fn panel(&self, a: &PlanArgs) -> Panel {
        let ns: Vec<u32> = (2..=72).map(|k| k * 5).collect();
        let curve = |f: &dyn Fn(u32) -> f64| ns.iter().map(|&n| (n as f64, f(n))).collect::<Vec<_>>();
        let under_noise = ns
            .iter()
            // A listed order is a run of its own n only.
            .filter(|&&m| !matches!(self.order, Order::List(_)) || m == a.n)
            .filter_map(|&m| {
                self.order.check(m as u16).ok()?;
                let sc = Schedule::new(&self.order, m as usize, m as usize / 2, &self.timing);
                Some((m as f64, plan_noise::total_arcsec(&self.model, &sc, &self.budget)?))
            })
            .collect();
        let s = &self.sigmas;
        Panel {
            title: format!("azimuth uncertainty, lat {} deg, dwell {} s", a.lat, a.dwell),
            x_label: "positions n".into(),
            y_label: "sigma psi (arcsec)".into(),
            series: vec![
                Series {
                    name: "Eq. 31 (paper)".into(),
                    points: curve(&|n| Budget::paper(n, s, a.lat, 45.0, 0.01).total_arcsec),
                    style: Style::Line,
                },
                Series {
                    name: "exact model, white noise".into(),
                    points: curve(&|n| Budget::closed_form(n, s, a.lat).total_arcsec),
                    style: Style::Line,
                },
                Series {
                    name: format!("noise model, {} order (GLS)", self.order.name()),
                    points: under_noise,
                    style: Style::Line,
                },
            ]
            .into_iter()
            .chain(self.noise_total.map(|v| Series {
                name: format!("n = {} asked", a.n),
                points: vec![(a.n as f64, v)],
                style: Style::Points,
            }))
            .chain(a.target.map(|t| Series {
                name: format!("target {t} arcsec"),
                points: curve(&|_| t),
                style: Style::Line,
            }))
            // The search's answer, of its own order and dwell: where the curves above are
            // the run asked.
            .chain(self.search.as_ref().and_then(|p| p.fastest.as_ref()).map(|c| Series {
                name: format!("fastest: {}, {:.1} s dwells, {:.0} s", c.order, c.dwell_s, c.time_s),
                points: vec![(c.n as f64, c.sigma_arcsec)],
                style: Style::Points,
            }))
            .collect(),
            log_x: false,
            log_y: false,
        }
    }

    fn json(&self, a: &PlanArgs) -> PlanJson {
        let search = self.search.as_ref();
        PlanJson {
            allowance_for_target: self.allowance.map(AllowanceJson::from),
            budget_eq31_paper: (&self.paper).into(),
            budget_exact: (&self.exact).into(),
            budget_noise_model: NoiseBudgetJson {
                gyro_arcsec: self.noise_gyro,
                total_arcsec: self.noise_total,
            },
            budget_numerical: (&self.numerical).into(),
            dwell_s: a.dwell,
            fastest: search.and_then(|p| p.fastest.as_ref()).map(CandidateJson::from),
            fastest_per_order: search.map(|p| p.per_order.iter().map(CandidateJson::from).collect()),
            floor: search.and_then(|p| p.floor.as_ref()).map(CandidateJson::from),
            floor_per_order_short_of_target: search.map(|p| p.short_of.iter().map(CandidateJson::from).collect()),
            gyro_dph_per_position: self.sigmas.gyro_dph,
            monte_carlo: self.mc.map(|(sd_arcsec, formula_arcsec)| MonteCarloJson {
                formula_arcsec,
                runs: a.mc_runs,
                sd_arcsec,
            }),
            n: a.n,
            noise_model: (&self.model).into(),
            order: self.order.name(),
            paper_n_for_target: self.paper_n,
            target_arcsec: a.target,
            time_s: self.time_s,
            twin_check: self
                .twin
                .as_ref()
                .map(|(c, stated, k)| TwinCheckJson::new(c, *stated, k)),
        }
    }
}

/// The runs the search considers: no more positions than the motor has steps a turn (two
/// would share an angle), none longer than `--max-time`.
fn space(a: &PlanArgs) -> Space {
    let all = Space::default();
    Space {
        positions: all
            .positions
            .into_iter()
            .filter(|&n| n <= a.steps_per_rev as usize)
            .collect(),
        max_time_s: a.max_time,
        ..all
    }
}

/// The fastest run reaching `target` arcsec, with a spinner while it is searched.
fn search(
    a: &PlanArgs,
    model: &NoiseModel,
    budget: &plan_noise::Budget,
    timing: &Timing,
    target: f64,
    levelling_s: f64,
) -> plan_noise::Plan {
    let bar = indicatif::ProgressBar::new_spinner();
    bar.set_message("searching orders, n and dwells");
    let space = space(a);
    let p = plan_noise::search(
        model,
        budget,
        timing,
        &plan_noise::named_orders(),
        &space,
        target,
        levelling_s,
    );
    bar.finish_and_clear();
    p
}

/// The Monte Carlo check of the white-noise formula, when asked: its sd and the formula's.
fn monte_carlo(a: &PlanArgs, inp: &plan::Inputs) -> Option<(f64, f64)> {
    (a.mc_runs > 0).then(|| {
        let bar = indicatif::ProgressBar::new(a.mc_runs as u64);
        bar.set_message("Monte Carlo");
        let r = plan::monte_carlo(inp, a.mc_runs, a.seed, || bar.inc(1));
        bar.finish_and_clear();
        r
    })
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
