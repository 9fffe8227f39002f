//! The main job on the host: one full north-finding run of the firmware logic against the
//! digital twin, its log on stderr, the recording written to a file, and the result.

use clap::Parser;
use nf::range::{MAX_LATITUDE_DEG, above, real};
use nf_instrument::run::{Fault, RunConfig, RunReport, Sink, TiltPolicy};
use nf_model::angle::wrap_180;
use nf_model::order::Order;
use nf_twin::{Recorder, TwinConfig, simulate, virtual_now_us};
use std::io::Write;
use std::process::ExitCode;

struct VirtualTimeLogger;

impl log::Log for VirtualTimeLogger {
    fn enabled(&self, m: &log::Metadata) -> bool {
        m.level() <= log::Level::Info
    }

    fn log(&self, r: &log::Record) {
        if self.enabled(r.metadata()) {
            eprintln!(
                "{:>10.3}s {:<5} {}",
                virtual_now_us() as f64 * 1e-6,
                r.level(),
                r.args()
            );
        }
    }

    fn flush(&self) {}
}

/// One run of the firmware logic against the twin; the defaults are the paper's run.
#[derive(Parser)]
#[command(name = "north-finder", version)]
struct Args {
    /// The twin's random seed.
    #[arg(long, default_value_t = TwinConfig::default().seed, allow_hyphen_values = true)]
    seed: u64,
    /// Positions per turn, 4 to 720.
    #[arg(long, default_value_t = RunConfig::DEFAULT.positions, allow_hyphen_values = true,
          value_parser = clap::value_parser!(u16).range(4..=720))]
    positions: u16,
    /// Visiting order: a name (sequential, forward-back, opposite-pairs, alternating-pairs,
    /// interleaved) or a list of position numbers (0 to n - 1), at most 256.
    #[arg(long, default_value = "sequential")]
    order: String,
    /// Dwell per position, ms, 10 to 600000.
    #[arg(long, default_value_t = RunConfig::DEFAULT.dwell_ms, allow_hyphen_values = true,
          value_parser = clap::value_parser!(u32).range(10..=600_000))]
    dwell_ms: u32,
    /// End the run when the running sigma under the noise model reaches this, arcsec (above 0,
    /// up to 36000).
    #[arg(long, allow_hyphen_values = true, value_parser = above(0.0, 36_000.0))]
    target_arcsec: Option<f64>,
    /// The twin's true azimuth psi (Eq. 7), deg, -360 to 360.
    #[arg(long, default_value_t = TwinConfig::default().instrument.psi_deg, allow_hyphen_values = true,
          value_parser = real(-360.0, 360.0))]
    psi: f64,
    /// Latitude, deg, -89 to 89.
    #[arg(long, default_value_t = TwinConfig::default().instrument.latitude_deg, allow_hyphen_values = true,
          value_parser = real(-MAX_LATITUDE_DEG, MAX_LATITUDE_DEG))]
    lat: f64,
    /// The twin's shaft tilt, deg, 0 to 10.
    #[arg(long, default_value_t = TwinConfig::default().instrument.tilt_deg, allow_hyphen_values = true,
          value_parser = real(0.0, 10.0))]
    tilt: f64,
    /// Largest shaft tilt the levelling check accepts (as the host link's `SET tilt_limit`),
    /// deg, 0 to 10.
    #[arg(long, default_value_t = decimal(RunConfig::DEFAULT.tilt_limit_deg), allow_hyphen_values = true,
          value_parser = real(0.0, 10.0))]
    tilt_limit: f64,
    /// A tilt beyond the limit ends the run (refuse) or is logged and the run goes on (warn),
    /// as the host link's `SET tilt_policy`.
    #[arg(long, value_enum, default_value = "refuse")]
    tilt_policy: Policy,
    /// Where the recording goes (`-`: standard output, the summary then on standard error).
    #[arg(long, default_value = "north-finder-run.csv")]
    out: String,
    /// No run log on stderr.
    #[arg(long)]
    quiet: bool,
}

/// An `f32` setting as the shortest decimal that is that `f32` (the help says `0.05`, not
/// `0.05000000074505806`).
fn decimal(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(f64::from(x))
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Policy {
    Refuse,
    Warn,
}

/// The recording, each line also logged as `rec <line>`, as the firmware logs it (so that
/// `nf log` reads this log as it reads the firmware's).
struct LoggedRecorder(Recorder);

impl Sink for LoggedRecorder {
    async fn line(&mut self, line: &str) {
        log::info!("rec {line}");
        self.0.line(line).await;
    }

    fn abort_requested(&mut self) -> bool {
        self.0.abort_requested()
    }
}

pub fn main() -> ExitCode {
    let a = Args::parse();
    let order = match Order::parse(&a.order).and_then(|o| o.check(a.positions).map(|()| o)) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: invalid value '{}' for '--order': {e}", a.order);
            return ExitCode::from(2);
        }
    };
    let mut twin = TwinConfig {
        seed: a.seed,
        ..TwinConfig::default()
    };
    twin.instrument.psi_deg = a.psi;
    twin.instrument.latitude_deg = a.lat;
    twin.instrument.tilt_deg = a.tilt;
    let cfg = RunConfig {
        positions: a.positions,
        order,
        dwell_ms: a.dwell_ms,
        target_arcsec: a.target_arcsec.unwrap_or(0.0) as f32,
        latitude_deg: a.lat as f32,
        tilt_limit_deg: a.tilt_limit as f32,
        tilt_policy: match a.tilt_policy {
            Policy::Refuse => TiltPolicy::Refuse,
            Policy::Warn => TiltPolicy::Warn,
        },
        ..RunConfig::default()
    };
    // `-`: the recording to standard output, the summary to standard error.
    let to_stdout = a.out == "-";
    if let Some(why) = nf::out_path::unwritable(&a.out).filter(|_| !to_stdout) {
        eprintln!("error: cannot write the recording to '{}': {why}", a.out);
        return ExitCode::from(2);
    }
    if !a.quiet {
        log::set_logger(&VirtualTimeLogger).ok();
        log::set_max_level(log::LevelFilter::Info);
    }
    let wall = std::time::Instant::now();
    let mut rec = LoggedRecorder(Recorder::default());
    let (report, world) = simulate(&twin, &cfg, &mut rec);
    let wall = wall.elapsed();
    // A run that recorded nothing leaves a file of an earlier run as it was.
    let written = if rec.0.lines.is_empty() {
        eprintln!("nothing recorded: {} not written", a.out);
        Ok(())
    } else if to_stdout {
        std::io::stdout().lock().write_all(rec.0.text().as_bytes())
    } else {
        std::fs::write(&a.out, rec.0.text())
    };
    let summary = Summary {
        out: (!rec.0.lines.is_empty()).then_some(if to_stdout { "standard output" } else { a.out.as_str() }),
        wall_s: wall.as_secs_f64(),
        virtual_s: world.t_s(),
        truth_deg: twin.instrument.psi_deg,
        target_arcsec: a.target_arcsec,
    };
    // The summary still goes out when the recording could not be written: it is the result.
    let printed = match to_stdout {
        true => summary.print(&mut std::io::stderr().lock(), &report),
        false => summary.print(&mut std::io::stdout().lock(), &report),
    };
    // A reader of standard output that has gone (`cargo run | head`) is no failure.
    let gone = |e: &std::io::Error| e.kind() == std::io::ErrorKind::BrokenPipe;
    if let Some(e) = written.as_ref().err().filter(|e| !gone(e)) {
        eprintln!("cannot write the recording to {}: {e}", a.out);
        return ExitCode::FAILURE;
    }
    if let Some(e) = printed.as_ref().err().filter(|e| !gone(e)) {
        eprintln!("cannot write the summary: {e}");
        return ExitCode::FAILURE;
    }
    match report.result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("run failed {e}");
            if let Fault::TiltOverLimit { .. } = e.fault {
                eprintln!("(--tilt-limit DEG raises the limit; --tilt-policy warn runs on with a warning)");
            }
            ExitCode::FAILURE
        }
    }
}

/// What the run's summary on standard output needs besides the report.
struct Summary<'a> {
    /// Where the recording went, if anything was recorded.
    out: Option<&'a str>,
    wall_s: f64,
    virtual_s: f64,
    truth_deg: f64,
    target_arcsec: Option<f64>,
}

/// Degrees of freedom below which the residual sigma is called rough.
const FEW_DOF: u32 = 5;

impl Summary<'_> {
    fn print(&self, o: &mut impl Write, report: &RunReport) -> std::io::Result<()> {
        writeln!(
            o,
            "run of {:.1} s (virtual) in {:.3} s: {} positions recorded{}",
            self.virtual_s,
            self.wall_s,
            report.positions,
            self.out.map_or(String::new(), |o| format!(" to {o}"))
        )?;
        if let Some(l) = report.levelling {
            writeln!(
                o,
                "levelling (Eq. 32): shaft tilt {:.4} deg towards {:.1} deg",
                l.tilt_deg, l.tilt_dir_deg
            )?;
        }
        if let Some(a) = report.azimuth {
            let err = wrap_180(a.psi_deg as f64 - self.truth_deg) * 3600.0;
            writeln!(o, "azimuth psi       {:.5} deg (Eq. 7 convention)", a.psi_deg)?;
            writeln!(
                o,
                "surveying azimuth {:.5} deg of the gamma = 0 direction",
                nf_model::angle::surveying_azimuth_deg(a.psi_deg)
            )?;
            // C, A and B: a residual sigma on a handful of degrees of freedom is itself a
            // guess, a tenth or ten times the true one.
            let dof = a.n.saturating_sub(3);
            let rough = dof < FEW_DOF;
            match a.sigma_arcsec {
                Some(s) if rough => writeln!(
                    o,
                    "uncertainty       {s:.2} arcsec (1 sigma, from the residuals with only {dof} degree(s) of freedom, widened by Student's t: rough; see the noise model's below)"
                )?,
                Some(s) => writeln!(
                    o,
                    "uncertainty       {s:.2} arcsec (1 sigma, from the residuals, widened by Student's t over {dof} dof)"
                )?,
                None => writeln!(o, "uncertainty       undefined (0 dof: as many unknowns as positions)")?,
            }
            writeln!(o, "residual SS       {:.6} (deg/h)^2 over {} positions", a.rss, a.n)?;
            writeln!(
                o,
                "amplitude         {:.4} deg/h, offset {:.4} deg/h",
                a.amplitude_dph, a.offset_dph
            )?;
            let truth = nf_model::angle::wrap_360(self.truth_deg);
            write!(o, "twin's true psi   {truth:.5} deg: error {err:+.2} arcsec")?;
            match a.sigma_arcsec {
                Some(s) if !rough => writeln!(o, " = {:+.2} sigma", err / s as f64)?,
                _ => writeln!(o)?,
            }
        }
        if report.under_noise.is_some() && !report.resolved {
            writeln!(
                o,
                "WARNING: the Earth rate is not resolved: the running amplitude is not WE cos(lat) within half (a calibration, a latitude or a gyro wrong) or the sigma is 10 deg or more (the noise hides it); the azimuth and its sigma cannot be trusted"
            )?;
        }
        if let Some(u) = report.under_noise {
            writeln!(
                o,
                "under the noise model: psi {:.5} deg +- {:.2} arcsec after {} dwells{}",
                u.psi_deg,
                u.sigma_psi_deg * 3600.0,
                u.dwells,
                match (report.target_reached, self.target_arcsec) {
                    (true, _) => " (target reached, run ended early)".into(),
                    (false, Some(t)) => format!(" (target {t} arcsec NOT reached)"),
                    (false, None) => String::new(),
                }
            )?;
        }
        o.flush()
    }
}
