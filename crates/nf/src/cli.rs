//! The command line: `nf simulate | fit | plan | paper | log`.

use crate::analysis::{Analysis, Options, TiltMethod, analyse};
use crate::diagnose::diagnose;
use crate::plot::{Panel, Series, Style};
use crate::recording::Recording;
use crate::{diagnose, diagnose_eval, logparse, paper, plan, plot};
use clap::{Parser, Subcommand, ValueEnum};
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_model::angle::surveying_azimuth_deg;
use nf_model::fit::Drift;
use nf_model::paper::{eq24_arcsec, eq30_arcsec};
use nf_model::uncertainty::{Budget, allocate, tilt_arcsec};
use nf_twin::{Recorder, TwinConfig, simulate};
use serde_json::{Value, json};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "nf",
    version,
    about = "North finder host tool: simulate, fit, plan, reproduce the paper, read firmware logs"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Write a recording from the digital twin (the firmware's run logic on a simulated instrument).
    Simulate(SimArgs),
    /// Fit a recording: azimuth, amplitude, bias, residuals and uncertainty.
    Fit(FitArgs),
    /// Plan a run: uncertainty budget, n and dwell for a target, time to north, Monte Carlo check.
    Plan(PlanArgs),
    /// Reproduce the paper's numbers and list where it disagrees with itself or the physics.
    Paper(PaperArgs),
    /// Turn a firmware defmt log (probe-rs or defmt-print output) into a recording.
    Log(LogArgs),
    /// Find the physics a recording has and the simulation left out; `--evaluate` runs the test suite.
    Diagnose(DiagnoseArgs),
}

#[derive(clap::Args)]
struct DiagnoseArgs {
    /// The recording (not needed with --evaluate).
    recording: Option<String>,
    /// Family-wise false-alarm rate of each selection step.
    #[arg(long, default_value_t = 0.05)]
    alpha: f64,
    #[arg(long)]
    json: bool,
    /// Plot the residuals before and after (*.svg or *.png).
    #[arg(long)]
    plot: Option<String>,
    /// Run the suite of twin recordings with concealed effects and print the rates.
    #[arg(long)]
    evaluate: bool,
    /// Recordings per effect and magnitude in the suite.
    #[arg(long, default_value_t = 20)]
    seeds: u32,
    /// Clean recordings in the suite.
    #[arg(long, default_value_t = 200)]
    clean: u32,
}

#[derive(clap::Args)]
struct SimArgs {
    /// Latitude, deg.
    #[arg(long, default_value_t = 43.8, allow_hyphen_values = true)]
    lat: f64,
    /// Azimuth psi (Eq. 7), deg.
    #[arg(long, default_value_t = 65.5378, allow_hyphen_values = true)]
    psi: f64,
    /// Number of positions.
    #[arg(long, default_value_t = 72)]
    n: u16,
    /// Dwell per position, s.
    #[arg(long, default_value_t = 2.0)]
    dwell: f64,
    /// Settle time after each move, s.
    #[arg(long, default_value_t = 0.3)]
    settle: f64,
    /// Gyro white noise of a 2 s dwell mean, deg/h.
    #[arg(long, default_value_t = 0.005)]
    noise: f64,
    /// Gyro bias, deg/h.
    #[arg(long, default_value_t = 0.3, allow_hyphen_values = true)]
    bias: f64,
    /// Linear bias drift, deg/h per s.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    drift: f64,
    /// Bias random walk, deg/h per sqrt(s).
    #[arg(long, default_value_t = 1e-5)]
    walk: f64,
    /// Shaft tilt, deg.
    #[arg(long, default_value_t = 0.002)]
    tilt: f64,
    /// Direction the platform is lowest towards, deg counter-clockwise from gamma = 0.
    #[arg(long, default_value_t = 140.0, allow_hyphen_values = true)]
    tilt_dir: f64,
    /// Gyro axis elevation above the platform (gyro misalignment), deg.
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true)]
    misalignment: f64,
    /// Gyro scale factor.
    #[arg(long, default_value_t = 1.0)]
    scale: f64,
    /// Encoder error amplitude, arcsec.
    #[arg(long, default_value_t = 0.0)]
    encoder_error: f64,
    /// Harmonic of the encoder error (1: eccentricity).
    #[arg(long, default_value_t = 2)]
    encoder_harmonic: u8,
    /// Gyro temperature at the start, C.
    #[arg(long, default_value_t = 40.0, allow_hyphen_values = true)]
    temp: f64,
    /// Temperature ramp, C per s.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    temp_ramp: f64,
    /// Bias temperature coefficient, deg/h per C.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    temp_coef: f64,
    /// Inclinometer noise, deg.
    #[arg(long, default_value_t = 0.0005)]
    incl_noise: f64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output file (default: standard output).
    #[arg(long, short)]
    out: Option<String>,
    /// Print a JSON summary (the truth and the run's result) on stderr.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum TiltArg {
    /// The best the recording allows.
    Auto,
    None,
    FirstOrder,
    Exact,
}

#[derive(Clone, Copy, ValueEnum)]
enum DriftArg {
    None,
    Linear,
    Quadratic,
}

#[derive(clap::Args)]
struct FitArgs {
    /// The recording (CSV, shared/recording-format.md).
    recording: String,
    /// Tilt correction.
    #[arg(long, value_enum, default_value = "auto")]
    tilt: TiltArg,
    /// Time terms in the fit.
    #[arg(long, value_enum, default_value = "none")]
    drift: DriftArg,
    /// Highest harmonic fitted (1 to 3).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=3))]
    harmonics: u8,
    /// Encoder uncertainty for the budgets, deg.
    #[arg(long, default_value_t = 0.001)]
    sigma_encoder: f64,
    /// Shaft-tilt uncertainty for the paper's budget (and the exact one when uncorrected), deg.
    #[arg(long, default_value_t = 0.003)]
    sigma_tilt: f64,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
    /// Plot gyro output, fitted curve and residuals (*.svg or *.png).
    #[arg(long)]
    plot: Option<String>,
}

#[derive(clap::Args)]
struct PlanArgs {
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

#[derive(clap::Args)]
struct PaperArgs {
    #[arg(long)]
    json: bool,
    /// Plot Fig. 6 (Eq. 24) and Fig. 7 (Eq. 30 against the exact model), *.svg or *.png.
    #[arg(long)]
    plot: Option<String>,
}

#[derive(clap::Args)]
struct LogArgs {
    /// The log file ('-' for standard input).
    log: String,
    /// Output file (default: standard output).
    #[arg(long, short)]
    out: Option<String>,
}

/// A failure to report: the message and the exit code.
struct Fail(String, u8);

impl From<String> for Fail {
    fn from(s: String) -> Self {
        Fail(s, 1)
    }
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let r = match cli.cmd {
        Cmd::Simulate(a) => cmd_simulate(a),
        Cmd::Fit(a) => cmd_fit(a),
        Cmd::Plan(a) => cmd_plan(a),
        Cmd::Paper(a) => cmd_paper(a),
        Cmd::Log(a) => cmd_log(a),
        Cmd::Diagnose(a) => cmd_diagnose(a),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(Fail(msg, code)) => {
            eprintln!("nf: {msg}");
            ExitCode::from(code)
        }
    }
}

/// `x > 0`, false for NaN.
fn positive(x: f64) -> bool {
    x > 0.0
}

fn write_out(out: &Option<String>, text: &str) -> Result<(), Fail> {
    match out {
        Some(p) => std::fs::write(p, text).map_err(|e| Fail(format!("cannot write {p}: {e}"), 1)),
        None => {
            print!("{text}");
            Ok(())
        }
    }
}

fn cmd_simulate(a: SimArgs) -> Result<(), Fail> {
    if !(positive(a.dwell) && a.dwell <= 600.0) || a.n < 4 || a.n > 720 || !(-89.0..=89.0).contains(&a.lat) {
        return Err(Fail(
            "need 4 <= n <= 720, 0 < dwell <= 600 s and |lat| <= 89 deg".into(),
            2,
        ));
    }
    let mut twin = TwinConfig::default();
    twin.instrument.latitude_deg = a.lat;
    twin.instrument.psi_deg = a.psi;
    twin.instrument.tilt_deg = a.tilt;
    twin.instrument.tilt_dir_deg = a.tilt_dir;
    twin.instrument.gyro_elev_deg = a.misalignment;
    twin.instrument.scale = a.scale;
    twin.instrument.bias_dph = a.bias;
    twin.noise = nf_model::noise::NoiseModel {
        rrw_dph_rth: a.walk * 60.0,
        ..nf_model::noise::NoiseModel::white(a.noise, 2.0)
    };
    twin.bias_drift_dph_per_s = a.drift;
    twin.encoder_error = [(a.encoder_harmonic, a.encoder_error, 0.0), (1, 0.0, 0.0)];
    twin.temp0_c = a.temp;
    twin.temp_ramp_c_per_s = a.temp_ramp;
    twin.bias_temp_dph_per_c = a.temp_coef;
    twin.incl_noise_deg = a.incl_noise;
    twin.seed = a.seed;
    let run = RunConfig {
        positions: a.n,
        dwell_ms: (a.dwell * 1000.0).round() as u32,
        settle_ms: (a.settle * 1000.0).round() as u32,
        latitude_deg: a.lat as f32,
        tilt_policy: TiltPolicy::Warn,
        ..RunConfig::default()
    };
    let mut rec = Recorder::default();
    let (report, world) = simulate(&twin, &run, &mut rec);
    write_out(&a.out, &rec.text())?;
    let az = report.azimuth;
    if a.json {
        let j = json!({
            "true_psi_deg": a.psi,
            "positions": report.positions,
            "duration_s": world.t_s(),
            "firmware_azimuth_deg": az.map(|x| x.psi_deg),
            "firmware_sigma_arcsec": az.map(|x| x.sigma_arcsec),
            "error": report.result.err().map(|e| format!("{e:?}")),
        });
        eprintln!("{j}");
    } else if let Some(x) = az {
        eprintln!(
            "simulated {} positions over {:.0} s; firmware fit: psi {:.4} deg +- {:.1}\" (truth {:.4})",
            report.positions,
            world.t_s(),
            x.psi_deg,
            x.sigma_arcsec,
            a.psi
        );
    }
    match report.result {
        Ok(()) => Ok(()),
        Err(e) => Err(Fail(
            format!(
                "the run failed at {:?}: {:?}; {} positions written",
                e.stage, e.fault, report.positions
            ),
            1,
        )),
    }
}

fn fit_json(an: &Analysis) -> Value {
    let f = &an.fit;
    let (d1, d2) = f.drift();
    let b = |b: &Budget<f64>| json!({"gyro_arcsec": b.gyro_arcsec, "encoder_arcsec": b.encoder_arcsec, "tilt_arcsec": b.tilt_arcsec, "total_arcsec": b.total_arcsec});
    json!({
        "azimuth_deg": f.psi_deg,
        "surveying_azimuth_deg": surveying_azimuth_deg(f.psi_deg),
        "sigma_arcsec": f.sigma_psi_deg * 3600.0,
        "rss": f.rss,
        "n": f.n,
        "dof": f.dof,
        "latitude_deg": an.latitude_deg,
        "amplitude_dph": f.amplitude_dph,
        "amplitude_predicted_dph": an.amplitude_predicted_dph,
        "scale_factor": f.amplitude_dph / an.amplitude_predicted_dph,
        "offset_dph": f.offset_dph,
        "sigma_gyro_dph": an.sigma_gyro_dph,
        "drift_dph_per_s": d1,
        "drift_dph_per_s2": d2,
        "tilt_correction": an.method.name(),
        "shaft_tilt_deg": an.shaft.map(|s| s.tilt_deg),
        "shaft_tilt_dir_deg": an.shaft.map(|s| s.tilt_dir_deg),
        "budget_eq31_paper": b(&an.budget_paper),
        "budget_exact": b(&an.budget_exact),
    })
}

fn cmd_fit(a: FitArgs) -> Result<(), Fail> {
    let rec = Recording::read(&a.recording).map_err(|e| Fail(e.to_string(), 2))?;
    let opt = Options {
        tilt: match a.tilt {
            TiltArg::Auto => None,
            TiltArg::None => Some(TiltMethod::None),
            TiltArg::FirstOrder => Some(TiltMethod::FirstOrder),
            TiltArg::Exact => Some(TiltMethod::Exact),
        },
        drift: match a.drift {
            DriftArg::None => Drift::None,
            DriftArg::Linear => Drift::Linear,
            DriftArg::Quadratic => Drift::Quadratic,
        },
        harmonics: a.harmonics,
        sigma_encoder_deg: a.sigma_encoder,
        sigma_tilt_deg: a.sigma_tilt,
        ..Options::default()
    };
    let an = analyse(&rec, &opt).map_err(|e| Fail(format!("{}: {e}", a.recording), 1))?;
    if let Some(p) = &a.plot {
        plot::write(p, &fit_panels(&an))?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&fit_json(&an)).unwrap_or_default());
        return Ok(());
    }
    let f = &an.fit;
    println!(
        "recording      {} ({} positions, latitude {} deg)",
        a.recording, f.n, an.latitude_deg
    );
    println!(
        "azimuth psi    {:.5} deg  (Eq. 7: rate = WE cos(lat) cos(gamma + psi))",
        f.psi_deg
    );
    println!(
        "surveying az.  {:.5} deg  (clockwise from true north, of the gamma = 0 direction)",
        surveying_azimuth_deg(f.psi_deg)
    );
    println!(
        "sigma          {:.2} arcsec  (1 sigma, from the residuals, {} dof)",
        f.sigma_psi_deg * 3600.0,
        f.dof
    );
    println!(
        "amplitude      {:.5} deg/h  (latitude predicts {:.5}: scale factor {:.5})",
        f.amplitude_dph,
        an.amplitude_predicted_dph,
        f.amplitude_dph / an.amplitude_predicted_dph
    );
    println!("bias (offset)  {:.5} +- {:.5} deg/h", f.offset_dph, f.sigma_offset_dph);
    println!(
        "residuals      RSS {:.6e} (deg/h)^2, rms {:.5} deg/h",
        f.rss, an.sigma_gyro_dph
    );
    match (an.method, an.shaft) {
        (TiltMethod::Exact, Some(s)) => println!(
            "tilt           corrected with the exact model: shaft tilt {:.4} deg towards {:.1} deg (from {} X/Y readings)",
            s.tilt_deg, s.tilt_dir_deg, f.n
        ),
        (TiltMethod::FirstOrder, _) => println!("tilt           corrected per position from tilt_x (first order)"),
        _ => println!("tilt           not corrected (no inclinometer columns, or --tilt none)"),
    }
    let (d1, d2) = f.drift();
    if opt.drift != Drift::None {
        println!("drift          {d1:.3e} deg/h/s, {d2:.3e} deg/h/s^2");
    }
    for (name, b) in [("Eq. 31 (paper)", &an.budget_paper), ("exact model", &an.budget_exact)] {
        println!(
            "{name:<14} total {:.2}\" = gyro {:.2}\" (+) encoder {:.2}\" (+) tilt {:.2}\"",
            b.total_arcsec, b.gyro_arcsec, b.encoder_arcsec, b.tilt_arcsec
        );
    }
    Ok(())
}

fn fit_panels(an: &Analysis) -> Vec<Panel> {
    let curve: Vec<(f64, f64)> = (0..=360)
        .map(|g| {
            let g = g as f64;
            (g, an.fit.predict(g, an.fit.t0_s, None))
        })
        .collect();
    vec![
        Panel {
            title: format!("gyro output, psi = {:.4} deg", an.fit.psi_deg),
            x_label: "encoder angle gamma (deg)".into(),
            y_label: "rate (deg/h)".into(),
            series: vec![
                Series {
                    name: "measured".into(),
                    points: an.points.iter().map(|p| (p[0], p[2])).collect(),
                    style: Style::Points,
                },
                Series {
                    name: "fitted A cos + B sin + C".into(),
                    points: curve,
                    style: Style::Line,
                },
            ],
            log_x: false,
        },
        Panel {
            title: format!("residuals, RSS = {:.3e} (deg/h)^2", an.fit.rss),
            x_label: "encoder angle gamma (deg)".into(),
            y_label: "residual (deg/h)".into(),
            series: vec![Series {
                name: "residual".into(),
                points: an.points.iter().map(|p| (p[0], p[4])).collect(),
                style: Style::Points,
            }],
            log_x: false,
        },
    ]
}

fn cmd_plan(a: PlanArgs) -> Result<(), Fail> {
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

fn cmd_paper(a: PaperArgs) -> Result<(), Fail> {
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
        };
        let mut fig7 = Panel {
            title: "Fig. 7: shaft tilt, Eq. 30 (eta = sigma_eta, n = 180, psi = 45) and the exact model".into(),
            x_label: "shaft misalignment eta (deg)".into(),
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
    if a.json {
        let j = json!({
            "eq24_arcsec": ns.iter().map(|&n| json!({"n": n, "values": sws.iter().map(|&s| json!({"sigma_w_dph": s, "arcsec": eq24_arcsec(n, s, paper::LAT)})).collect::<Vec<_>>()})).collect::<Vec<_>>(),
            "fig7": etas.iter().map(|&h| json!({"eta_deg": h, "eq30_arcsec": epss.iter().map(|&e| eq30_arcsec(180, paper::LAT, 45.0, h, e, h)).collect::<Vec<_>>(), "exact_arcsec": tilt_arcsec(h, paper::LAT)})).collect::<Vec<_>>(),
            "tables": tables.iter().map(|(t, r)| json!({
                "table": t.number, "n": t.n,
                "stated": {"mean_deg": t.stated_mean_deg, "sd_arcsec": t.stated_sd_arcsec, "rss_max": t.stated_rss_max},
                "recomputed": {"mean_deg": r.mean_deg, "sd_arcsec": r.sd_arcsec, "rss_max": r.rss_max},
                "rss_unit": t.rss_unit,
            })).collect::<Vec<_>>(),
            "eq31": paper::STATED_EQ31.iter().map(|&(n, s)| json!({"n": n, "stated_arcsec": s, "paper_equations_arcsec": paper::eq31_paper(n), "exact_arcsec": paper::eq31_exact(n)})).collect::<Vec<_>>(),
            "findings": findings,
        });
        println!("{}", serde_json::to_string_pretty(&j).unwrap_or_default());
        return Ok(());
    }
    println!("Eq. 24 (Fig. 6): azimuth uncertainty in arcsec at latitude 43.8 deg");
    print!("{:>10}", "sigma_w");
    for n in ns {
        print!("{:>9}", format!("n={n}"));
    }
    println!();
    for s in sws {
        print!("{s:>10}");
        for n in ns {
            print!("{:>9.2}", eq24_arcsec(n, s, paper::LAT));
        }
        println!();
    }
    println!("\nFig. 7: shaft misalignment (arcsec), Eq. 30 as printed (sigma_eta = eta, n = 180, psi = 45) and exact");
    println!(
        "{:>8} {:>12} {:>12} {:>12} {:>14}",
        "eta", "eps=0.001", "eps=0.01", "eps=0.1", "exact (max)"
    );
    for h in etas {
        let e: Vec<f64> = epss
            .iter()
            .map(|&e| eq30_arcsec(180, paper::LAT, 45.0, h, e, h))
            .collect();
        println!(
            "{h:>8} {:>12.3} {:>12.3} {:>12.3} {:>14.3}",
            e[0],
            e[1],
            e[2],
            tilt_arcsec(h, paper::LAT)
        );
    }
    println!("\nTables 1-4, ten runs each: stated against recomputed from the rows");
    println!(
        "{:>6} {:>5} {:>12} {:>12} {:>9} {:>9} {:>9} {:>9}",
        "table", "n", "mean stated", "recomputed", "sd stat.", "recomp.", "RSS<", "max"
    );
    for (t, r) in &tables {
        println!(
            "{:>6} {:>5} {:>12.4} {:>12.5} {:>8}\" {:>8.1}\" {:>9} {:>9}",
            t.number, t.n, t.stated_mean_deg, r.mean_deg, t.stated_sd_arcsec, r.sd_arcsec, t.stated_rss_max, r.rss_max
        );
    }
    println!("\nEq. 31 (simulated uncertainty): stated, from the paper's own equations, and exact");
    for (n, stated) in paper::STATED_EQ31 {
        println!(
            "  n = {n:>3}: stated {stated}\", Eq. 24+26+30 give {:.2}\", exact model {:.2}\"",
            paper::eq31_paper(n),
            paper::eq31_exact(n)
        );
    }
    println!("\nWhere the paper disagrees with its tables or the physics:");
    for f in &findings {
        println!("- {f}");
    }
    Ok(())
}

fn cmd_log(a: LogArgs) -> Result<(), Fail> {
    let text = if a.log == "-" {
        std::io::read_to_string(std::io::stdin()).map_err(|e| Fail(format!("cannot read standard input: {e}"), 2))?
    } else {
        std::fs::read_to_string(&a.log).map_err(|e| Fail(format!("cannot read {}: {e}", a.log), 2))?
    };
    let lines = logparse::extract(&text);
    if lines.is_empty() {
        return Err(Fail(
            format!("{}: no 'rec' lines: is this the firmware's defmt log?", a.log),
            1,
        ));
    }
    let out: String = lines.iter().map(|l| format!("{l}\n")).collect();
    // Check it as any reader would; a log cut short still gives the positions it holds.
    let rec =
        Recording::parse(&out).map_err(|e| Fail(format!("{} (recording extracted from the log): {e}", a.log), 1))?;
    write_out(&a.out, &out)?;
    eprintln!("{} positions recovered from {}", rec.rows.len(), a.log);
    Ok(())
}

fn cmd_diagnose(a: DiagnoseArgs) -> Result<(), Fail> {
    if !(a.alpha > 0.0 && a.alpha < 1.0) {
        return Err(Fail("--alpha must be between 0 and 1".into(), 2));
    }
    if a.evaluate {
        return diagnose_evaluate(&a);
    }
    let path = a
        .recording
        .as_deref()
        .ok_or_else(|| Fail("give a recording, or --evaluate".into(), 2))?;
    let rec = Recording::read(path).map_err(|e| Fail(e.to_string(), 2))?;
    let d = diagnose(&rec, a.alpha).map_err(|e| Fail(format!("{path}: {e}"), 1))?;
    if let Some(p) = &a.plot {
        let panel = |title: &str, pts: &[(f64, f64)]| Panel {
            title: title.into(),
            x_label: "encoder angle gamma (deg)".into(),
            y_label: "residual (deg/h)".into(),
            series: vec![Series {
                name: "residual".into(),
                points: pts.to_vec(),
                style: Style::Points,
            }],
            log_x: false,
        };
        plot::write(
            p,
            &[
                panel("residuals of Eq. 7 (before)", &d.residuals_before),
                panel("residuals with the findings modelled (after)", &d.residuals_after),
            ],
        )?;
    }
    if a.json {
        let f: Vec<Value> = d
            .findings
            .iter()
            .map(|f| {
                let params: serde_json::Map<String, Value> =
                    f.parameters.iter().map(|p| (p.name.clone(), json!({"value": p.value, "sigma": p.sigma}))).collect();
                json!({"effect": f.effect, "parameters": params, "p_value": f.p_value, "where": f.location,
                       "rss_after": f.rss_after, "azimuth_deg_after": f.azimuth_deg_after, "sigma_arcsec_after": f.sigma_arcsec_after})
            })
            .collect();
        let j = json!({
            "alpha": d.alpha,
            "baseline": {"azimuth_deg": d.baseline.azimuth_deg, "rss": d.baseline.rss, "sigma_arcsec": d.baseline.sigma_arcsec},
            "findings": f,
            "final": {"azimuth_deg": d.final_.azimuth_deg, "rss": d.final_.rss, "sigma_arcsec": d.final_.sigma_arcsec},
            "notes": d.notes,
        });
        println!("{}", serde_json::to_string_pretty(&j).unwrap_or_default());
        return Ok(());
    }
    let b = d.baseline;
    println!(
        "baseline (Eq. 7, level ideal instrument): psi {:.5} deg +- {:.2}\", RSS {:.4e} (deg/h)^2",
        b.azimuth_deg, b.sigma_arcsec, b.rss
    );
    if d.findings.is_empty() {
        println!(
            "no effect is significant (family-wise false-alarm rate {} per step): the recording agrees with the model",
            d.alpha
        );
    }
    for (i, f) in d.findings.iter().enumerate() {
        println!("{}. {} (p = {:.2e}), in {}", i + 1, f.effect, f.p_value, f.location);
        for p in &f.parameters {
            match p.sigma {
                Some(s) => println!("     {} = {:.6} +- {:.6}", p.name, p.value, s),
                None => println!("     {} = {:.6}", p.name, p.value),
            }
        }
        println!(
            "     with it: RSS {:.4e} (deg/h)^2, psi {:.5} deg +- {:.2}\" ({:+.2}\" from the baseline)",
            f.rss_after,
            f.azimuth_deg_after,
            f.sigma_arcsec_after,
            nf_model::angle::wrap_180(f.azimuth_deg_after - b.azimuth_deg) * 3600.0
        );
    }
    let fz = d.final_;
    println!(
        "final: psi {:.5} deg +- {:.2}\", RSS {:.4e} (deg/h)^2",
        fz.azimuth_deg, fz.sigma_arcsec, fz.rss
    );
    for n in &d.notes {
        println!("note: {n}");
    }
    Ok(())
}

fn diagnose_evaluate(a: &DiagnoseArgs) -> Result<(), Fail> {
    let total = (a.seeds as u64) * (diagnose::EFFECTS.len() * diagnose_eval::LEVELS.len()) as u64 + a.clean as u64;
    let bar = indicatif::ProgressBar::new(total);
    let ev = diagnose_eval::evaluate(a.seeds, a.clean, &[0, 1, 2], a.alpha, || bar.inc(1));
    bar.finish_and_clear();
    let fa = ev.false_alarms as f64 / ev.clean_runs.max(1) as f64;
    if a.json {
        let cells: Vec<Value> = ev
            .cells
            .iter()
            .map(|(e, l, c)| json!({"effect": e, "level": l, "runs": c.runs, "named_first_rate": c.named_first as f64 / c.runs.max(1) as f64,
                                   "named_rate": c.named as f64 / c.runs.max(1) as f64, "rms_error_before_arcsec": c.rms_before, "rms_error_after_arcsec": c.rms_after}))
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(
                &json!({"alpha": a.alpha, "cells": cells, "clean_runs": ev.clean_runs, "false_alarm_rate": fa})
            )
            .unwrap_or_default()
        );
        return Ok(());
    }
    println!(
        "{:<20} {:<9} {:>5} {:>12} {:>8} {:>12} {:>12}",
        "effect", "level", "runs", "named first", "named", "rms err bef.", "rms err aft."
    );
    for (e, l, c) in &ev.cells {
        let k = c.runs.max(1) as f64;
        println!(
            "{e:<20} {l:<9} {:>5} {:>11.0}% {:>7.0}% {:>11.1}\" {:>11.1}\"",
            c.runs,
            100.0 * c.named_first as f64 / k,
            100.0 * c.named as f64 / k,
            c.rms_before,
            c.rms_after
        );
    }
    println!(
        "clean recordings: {} runs, false-alarm rate {:.1}% (alpha {} per step)",
        ev.clean_runs,
        100.0 * fa,
        a.alpha
    );
    for (e, k) in ev.false_by_effect.iter().filter(|e| e.1 > 0) {
        println!("  named on clean runs: {e} x{k}");
    }
    Ok(())
}
