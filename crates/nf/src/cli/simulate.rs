//! `nf simulate`: a recording from the firmware logic on the digital twin.

use super::adc_budget::AdcBudget;
use super::noise_args::NoiseArgs;
use super::{Fail, note, write_out};
use crate::instrument_file::{EncoderError, InstrumentFile, Noise, Shocks, Site};
use crate::range::{MAX_LATITUDE_DEG, above, real};
use nf_instrument::run::Fault;
use nf_instrument::stepper;
use nf_model::noise::NoiseModel;
use nf_model::order::Order;
use nf_twin::{Recorder, simulate};
use serde::Serialize;

#[derive(clap::Args)]
pub struct SimArgs {
    /// The instrument and its run from an instrument file (docs/instrument-file.md) instead
    /// of the flags below; --seed still applies.
    #[arg(long)]
    config: Option<String>,
    /// Write the instrument file of this simulation (from the flags or --config).
    #[arg(long)]
    save_config: Option<String>,
    /// Latitude, deg.
    #[arg(long, conflicts_with = "config", default_value_t = 43.8, allow_hyphen_values = true, value_parser = real(-MAX_LATITUDE_DEG, MAX_LATITUDE_DEG))]
    lat: f64,
    /// Azimuth psi (Eq. 7), deg.
    #[arg(long, conflicts_with = "config", default_value_t = 65.5378, allow_hyphen_values = true, value_parser = real(-360.0, 360.0))]
    psi: f64,
    /// Number of positions.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 72, value_parser = clap::value_parser!(u16).range(4..=720))]
    n: u16,
    /// Visiting order: sequential, forward-back, opposite-pairs, alternating-pairs,
    /// interleaved, or a comma-separated list of position numbers.
    #[arg(long, conflicts_with = "config", default_value = "sequential")]
    order: String,
    /// End the run when the firmware's running sigma under the gyro's noise model reaches this,
    /// arcsec.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, value_parser = above(0.0, 36_000.0))]
    target_arcsec: Option<f64>,
    /// Stepper cruise speed, steps/s.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = stepper::Config::default().max_sps as f64, value_parser = real(stepper::Config::default().start_sps as f64, 1e6))]
    max_sps: f64,
    /// Stepper acceleration, steps/s^2.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = stepper::Config::default().accel_sps2 as f64, value_parser = above(0.0, 1e8))]
    accel: f64,
    /// Dwell per position, s.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 2.0, value_parser = real(0.01, 600.0))]
    dwell: f64,
    /// Settle time after each move, s.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 0.3, value_parser = real(0.0, 60.0))]
    settle: f64,
    /// Gyro white noise of a 2 s dwell mean, deg/h (sets the ARW unless --arw or --noise is given).
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 0.005, value_parser = real(0.0, 10.0))]
    gyro_noise: f64,
    /// Gyro bias, deg/h.
    #[arg(long, conflicts_with = "config", default_value_t = 0.3, allow_hyphen_values = true, value_parser = real(-50.0, 50.0))]
    bias: f64,
    /// Linear bias drift, deg/h per s, from power-on (the levelling, a few seconds, comes before the recording's t_s = 0).
    #[arg(long, conflicts_with = "config", default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-1.0, 1.0))]
    drift: f64,
    /// Shaft tilt, deg.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 0.002, value_parser = real(0.0, 10.0))]
    tilt: f64,
    /// Direction the platform is lowest towards, deg counter-clockwise from gamma = 0.
    #[arg(long, conflicts_with = "config", default_value_t = 140.0, allow_hyphen_values = true, value_parser = real(-360.0, 360.0))]
    tilt_dir: f64,
    /// Gyro axis elevation above the platform (gyro misalignment), deg.
    #[arg(long, conflicts_with = "config", default_value_t = 0.01, allow_hyphen_values = true, value_parser = real(-10.0, 10.0))]
    misalignment: f64,
    /// Gyro scale factor.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 1.0, value_parser = real(0.1, 10.0))]
    scale: f64,
    /// Encoder error amplitude, arcsec.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 0.0, value_parser = real(0.0, 3600.0))]
    encoder_error: f64,
    /// Harmonic of the encoder error (1: eccentricity).
    #[arg(long, conflicts_with = "config", default_value_t = 2, allow_hyphen_values = true, value_parser = clap::value_parser!(u8).range(1..=16))]
    encoder_harmonic: u8,
    /// Gyro temperature at power-on, C (the levelling comes before the recording's t_s = 0).
    #[arg(long, conflicts_with = "config", default_value_t = 40.0, allow_hyphen_values = true, value_parser = real(-60.0, 125.0))]
    temp: f64,
    /// Temperature ramp, C per s, from power-on.
    #[arg(long, conflicts_with = "config", default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-1.0, 1.0))]
    temp_ramp: f64,
    /// Bias temperature coefficient, deg/h per C.
    #[arg(long, conflicts_with = "config", default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-10.0, 10.0))]
    temp_coef: f64,
    /// Inclinometer noise, deg.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 0.0005, value_parser = real(0.0, 1.0))]
    incl_noise: f64,
    /// Shocks: bursts of rate offset at random times, mean number per hour (0: none).
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 0.0, value_parser = real(0.0, 1e6))]
    shocks_per_hour: f64,
    /// Standard deviation of a shock's rate offset, deg/h.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 0.1, value_parser = real(0.0, 1e3))]
    shock_size: f64,
    /// Length of a shock, s.
    #[arg(long, conflicts_with = "config", allow_hyphen_values = true, default_value_t = 1.0, value_parser = real(1e-4, 600.0))]
    shock_duration: f64,
    /// Random seed (default: the instrument file's, or 1).
    #[arg(long, allow_hyphen_values = true)]
    seed: Option<u64>,
    /// Further noise terms (the default gyro has white noise only).
    #[command(flatten)]
    noise_terms: NoiseArgs,
    /// Output file (default: standard output).
    #[arg(long, short)]
    out: Option<String>,
    /// Print a JSON summary (the truth and the run's result) on stderr.
    #[arg(long)]
    json: bool,
}

/// Said where the firmware's running azimuth does not resolve the Earth rate.
pub const UNRESOLVED: &str = "nf: warning: the firmware's running azimuth does not resolve the Earth rate: its amplitude is not WE cos(lat) within half (a calibration, a latitude or a gyro wrong) or its sigma is 10 deg or more (the noise hides it); its azimuth and sigma cannot be trusted";

/// The summary `--json` prints on standard error: the truth and the run's result. The fields
/// are in alphabetical order, the order the keys have always had.
#[derive(Serialize)]
struct SimJson {
    /// Virtual time of the run, s.
    duration_s: f64,
    /// Why the run failed, in words; null when it finished.
    error: Option<String>,
    /// The firmware's azimuth psi, deg; null without a fit.
    firmware_azimuth_deg: Option<f64>,
    /// The firmware's running amplitude is 0.5 to 1.5 times `WE cos(lat)` at the run's
    /// latitude; false: its azimuth and sigma cannot be trusted (and no target was taken as reached).
    firmware_earth_rate_resolved: bool,
    /// The firmware's sigma of psi from the residuals, arcsec; null without a fit or with no
    /// degrees of freedom.
    firmware_sigma_arcsec: Option<f64>,
    /// A fit was made but its sigma is undefined (no degrees of freedom).
    firmware_sigma_undefined: bool,
    /// Dwells measured and written.
    positions: u16,
    /// The run ended early: the running sigma reached the target.
    target_reached: bool,
    /// The simulated azimuth psi, deg.
    true_psi_deg: f64,
    /// The firmware's running azimuth under the noise model; null without one.
    under_noise: Option<UnderNoise>,
}

/// The firmware's running azimuth under the gyro's noise model.
#[derive(Serialize)]
struct UnderNoise {
    /// Dwells in it.
    dwells: u32,
    /// Azimuth psi, deg.
    psi_deg: f64,
    /// Its 1-sigma uncertainty, arcsec.
    sigma_arcsec: f64,
}

/// The instrument file the flags describe.
fn from_flags(a: &SimArgs) -> Result<InstrumentFile, Fail> {
    Order::parse(&a.order)
        .and_then(|o| o.check(a.n))
        .map_err(|e| Fail(format!("--order: {e}"), 2))?;
    let mut f = InstrumentFile {
        site: Site {
            latitude_deg: a.lat,
            azimuth_deg: a.psi,
        },
        ..InstrumentFile::default()
    };
    f.gyro.bias_dph = a.bias;
    f.gyro.scale = a.scale;
    f.gyro.elevation_deg = a.misalignment;
    f.noise = Noise::of(&a.noise_terms.apply(NoiseModel::white(a.gyro_noise, 2.0))?);
    f.drift.linear_dph_per_s = a.drift;
    f.shaft.tilt_deg = a.tilt;
    f.shaft.tilt_dir_deg = a.tilt_dir;
    if a.encoder_error > 0.0 {
        f.encoder.error = vec![EncoderError {
            harmonic: a.encoder_harmonic,
            amplitude_arcsec: a.encoder_error,
            phase_deg: 0.0,
        }];
    }
    f.temperature.start_c = a.temp;
    f.temperature.ramp_c_per_s = a.temp_ramp;
    f.temperature.bias_dph_per_c = a.temp_coef;
    f.inclinometer.noise_deg = a.incl_noise;
    f.shocks = (a.shocks_per_hour > 0.0).then_some(Shocks {
        per_hour: a.shocks_per_hour,
        size_dph: a.shock_size,
        duration_s: a.shock_duration,
    });
    if let Some(e) = f.shocks_too_dense() {
        return Err(Fail(e, 2));
    }
    f.motor.max_sps = a.max_sps;
    f.motor.accel_sps2 = a.accel;
    f.run.positions = a.n;
    f.run.order = a.order.clone();
    f.run.dwell_s = a.dwell;
    f.run.settle_s = a.settle;
    f.run.target_arcsec = a.target_arcsec;
    Ok(f)
}

pub fn cmd_simulate(a: SimArgs) -> Result<(), Fail> {
    super::folders_exist(&[&a.out, &a.save_config])?;
    let mut file = match &a.config {
        Some(path) => {
            if a.noise_terms.any() {
                return Err(Fail(
                    "--config holds the noise model: give no noise flags with it".into(),
                    2,
                ));
            }
            InstrumentFile::read(path).map_err(|e| Fail(e, 2))?
        }
        None => from_flags(&a)?,
    };
    if let Some(seed) = a.seed {
        file.seed = seed;
    }
    let twin = file.twin();
    let run = file.run_config();
    let budget = AdcBudget::of(&twin, &run);
    if budget.always_saturates() || budget.noise_overflows() {
        return Err(Fail(
            format!("this gyro cannot be read by the ADC: {}", budget.explain()),
            2,
        ));
    }
    // Only a file that simulates is written.
    if let Some(p) = &a.save_config {
        write_out(&Some(p.clone()), &file.write(&[]))?;
    }
    if let Some(u) = run.order.uneven(run.positions) {
        let mut msg = String::new();
        let _ = u.write_message(&mut msg, run.positions);
        note!("nf: warning: {msg}");
    }
    let psi = file.site.azimuth_deg;
    let mut rec = Recorder::default();
    let (report, world) = simulate(&twin, &run, &mut rec);
    write_out(&a.out, &rec.text())?;
    let az = report.azimuth;
    if a.json {
        let j = SimJson {
            duration_s: world.t_s(),
            error: report.result.err().map(|e| e.to_string()),
            firmware_azimuth_deg: az.map(|x| f64::from(x.psi_deg)),
            firmware_earth_rate_resolved: report.resolved,
            firmware_sigma_arcsec: az.and_then(|x| x.sigma_arcsec).map(f64::from),
            firmware_sigma_undefined: az.is_some_and(|x| x.sigma_arcsec.is_none()),
            positions: report.positions,
            target_reached: report.target_reached,
            true_psi_deg: psi,
            under_noise: report.under_noise.map(|u| UnderNoise {
                dwells: u.dwells,
                psi_deg: f64::from(u.psi_deg),
                sigma_arcsec: f64::from(u.sigma_psi_deg) * 3600.0,
            }),
        };
        let j = serde_json::to_string(&j).unwrap_or_default();
        note!("{j}");
    } else if let Some(x) = az {
        let sigma = x
            .sigma_arcsec
            .map_or("sigma undefined (0 dof)".into(), |s| format!("+- {s:.1}\""));
        note!(
            "simulated {} dwells over {:.0} s; firmware fit: psi {:.4} deg {sigma} (truth {:.4})",
            report.positions,
            world.t_s(),
            x.psi_deg,
            psi
        );
        if let Some(u) = report.under_noise {
            let target = match file.run.target_arcsec.filter(|t| *t > 0.0) {
                Some(_) if report.target_reached => "; the target was reached and the run ended early".into(),
                Some(t) => format!("; the target of {t}\" was not reached: the run visited every position"),
                None => String::new(),
            };
            note!(
                "firmware under the noise model: psi {:.4} deg +- {:.1}\"{target}",
                u.psi_deg,
                u.sigma_psi_deg * 3600.0,
            );
            if !report.resolved {
                note!("{UNRESOLVED}");
            }
        }
    }
    match report.result {
        Ok(()) => Ok(()),
        Err(e) => {
            let why = match e.fault {
                Fault::AdcSaturated { .. } => format!(" ({})", AdcBudget::of(&twin, &run).explain()),
                _ => String::new(),
            };
            Err(Fail(
                format!("the run failed {e}{why}; {} positions written", report.positions),
                1,
            ))
        }
    }
}
