//! The main job on the host: one full north-finding run of the firmware logic against the
//! digital twin, its log on stderr, the recording written to a file, and the result.

use nf_instrument::run::{Fault, RunConfig};
use nf_model::angle::wrap_180;
use nf_model::order::Order;
use nf_twin::{Recorder, TwinConfig, simulate, virtual_now_us};
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

const USAGE: &str = "usage: north-finder [--seed N] [--positions N] [--order NAME|LIST] [--dwell-ms MS] [--target-arcsec S] [--psi DEG] [--lat DEG] [--tilt DEG] [--out FILE] [--quiet]";

fn parse<T: std::str::FromStr>(flag: &str, v: Option<String>) -> Result<T, String> {
    let v = v.ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
    v.parse()
        .map_err(|_| format!("{flag}: '{v}' is not a valid value\n{USAGE}"))
}

pub fn main() -> ExitCode {
    let mut twin = TwinConfig::default();
    let mut cfg = RunConfig::default();
    let mut out = String::from("north-finder-run.csv");
    let mut quiet = false;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let r = match a.as_str() {
            "--seed" => parse(&a, args.next()).map(|v| twin.seed = v),
            "--positions" => parse(&a, args.next()).map(|v| cfg.positions = v),
            "--order" => parse::<String>(&a, args.next()).and_then(|v| {
                cfg.order = Order::parse(&v).map_err(|e| format!("--order: {e}\n{USAGE}"))?;
                Ok(())
            }),
            "--target-arcsec" => parse(&a, args.next()).map(|v| cfg.target_arcsec = v),
            "--dwell-ms" => parse(&a, args.next()).map(|v| cfg.dwell_ms = v),
            "--psi" => parse(&a, args.next()).map(|v| twin.instrument.psi_deg = v),
            "--lat" => parse(&a, args.next()).map(|v: f64| {
                twin.instrument.latitude_deg = v;
                cfg.latitude_deg = v as f32;
            }),
            "--tilt" => parse(&a, args.next()).map(|v| twin.instrument.tilt_deg = v),
            "--out" => parse(&a, args.next()).map(|v| out = v),
            "--quiet" => {
                quiet = true;
                Ok(())
            }
            "-h" | "--help" => {
                println!("{USAGE}");
                return ExitCode::SUCCESS;
            }
            _ => Err(format!("unknown argument '{a}'\n{USAGE}")),
        };
        if let Err(e) = r {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    }
    if !quiet {
        log::set_logger(&VirtualTimeLogger).ok();
        log::set_max_level(log::LevelFilter::Info);
    }
    let wall = std::time::Instant::now();
    let mut rec = Recorder::default();
    let (report, world) = simulate(&twin, &cfg, &mut rec);
    let wall = wall.elapsed();
    if let Err(e) = std::fs::write(&out, rec.text()) {
        eprintln!("cannot write the recording to {out}: {e}");
        return ExitCode::FAILURE;
    }
    println!(
        "run of {:.1} s (virtual) in {:.3} s: {} positions recorded to {out}",
        world.t_s(),
        wall.as_secs_f64(),
        report.positions
    );
    if let Some(l) = report.levelling {
        println!(
            "levelling (Eq. 32): shaft tilt {:.4} deg towards {:.1} deg",
            l.tilt_deg, l.tilt_dir_deg
        );
    }
    if let Some(a) = report.azimuth {
        let truth = twin.instrument.psi_deg;
        let err = wrap_180(a.psi_deg as f64 - truth) * 3600.0;
        println!("azimuth psi       {:.5} deg (Eq. 7 convention)", a.psi_deg);
        println!(
            "surveying azimuth {:.5} deg of the gamma = 0 direction",
            nf_model::angle::surveying_azimuth_deg(a.psi_deg)
        );
        println!(
            "uncertainty       {:.2} arcsec (1 sigma, from the residuals)",
            a.sigma_arcsec
        );
        println!("residual SS       {:.6} (deg/h)^2 over {} positions", a.rss, a.n);
        println!(
            "amplitude         {:.4} deg/h, offset {:.4} deg/h",
            a.amplitude_dph, a.offset_dph
        );
        println!(
            "twin's true psi   {truth:.5} deg: error {err:+.2} arcsec = {:+.2} sigma",
            err / a.sigma_arcsec as f64
        );
    }
    if let Some(u) = report.under_noise {
        println!(
            "under the noise model: psi {:.5} deg +- {:.2} arcsec after {} dwells{}",
            u.psi_deg,
            u.sigma_psi_deg * 3600.0,
            u.dwells,
            if report.target_reached {
                " (target reached, run ended early)"
            } else {
                ""
            }
        );
    }
    match report.result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let what = match e.fault {
                Fault::Aborted => "aborted".to_string(),
                f => format!("{f:?}"),
            };
            eprintln!("run failed at {:?}: {what}", e.stage);
            ExitCode::FAILURE
        }
    }
}
