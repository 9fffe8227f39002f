//! `nf simulate`: a recording from the firmware logic on the digital twin.

use super::noise_args::NoiseArgs;
use super::{Fail, note, write_out};
use crate::range::{MAX_LATITUDE_DEG, above, real};
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_instrument::stepper;
use nf_model::noise::NoiseModel;
use nf_model::order::Order;
use nf_twin::{Recorder, TwinConfig, simulate};
use serde_json::json;

#[derive(clap::Args)]
pub struct SimArgs {
    /// Latitude, deg.
    #[arg(long, default_value_t = 43.8, allow_hyphen_values = true, value_parser = real(-MAX_LATITUDE_DEG, MAX_LATITUDE_DEG))]
    lat: f64,
    /// Azimuth psi (Eq. 7), deg.
    #[arg(long, default_value_t = 65.5378, allow_hyphen_values = true, value_parser = real(-360.0, 360.0))]
    psi: f64,
    /// Number of positions.
    #[arg(long, allow_hyphen_values = true, default_value_t = 72, value_parser = clap::value_parser!(u16).range(4..=720))]
    n: u16,
    /// Visiting order: sequential, forward-back, opposite-pairs, interleaved, or a
    /// comma-separated list of position numbers.
    #[arg(long, default_value = "sequential")]
    order: String,
    /// End the run when the firmware's running sigma under the gyro's noise model reaches this,
    /// arcsec.
    #[arg(long, allow_hyphen_values = true, value_parser = above(0.0, 36_000.0))]
    target_arcsec: Option<f64>,
    /// Stepper cruise speed, steps/s.
    #[arg(long, allow_hyphen_values = true, default_value_t = stepper::Config::default().max_sps as f64, value_parser = real(stepper::Config::default().start_sps as f64, 1e6))]
    max_sps: f64,
    /// Stepper acceleration, steps/s^2.
    #[arg(long, allow_hyphen_values = true, default_value_t = stepper::Config::default().accel_sps2 as f64, value_parser = above(0.0, 1e8))]
    accel: f64,
    /// Dwell per position, s.
    #[arg(long, allow_hyphen_values = true, default_value_t = 2.0, value_parser = real(0.01, 600.0))]
    dwell: f64,
    /// Settle time after each move, s.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.3, value_parser = real(0.0, 60.0))]
    settle: f64,
    /// Gyro white noise of a 2 s dwell mean, deg/h (sets the ARW unless --arw or --noise is given).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.005, value_parser = real(0.0, 10.0))]
    gyro_noise: f64,
    /// Gyro bias, deg/h.
    #[arg(long, default_value_t = 0.3, allow_hyphen_values = true, value_parser = real(-50.0, 50.0))]
    bias: f64,
    /// Linear bias drift, deg/h per s.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-1.0, 1.0))]
    drift: f64,
    /// Shaft tilt, deg.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.002, value_parser = real(0.0, 10.0))]
    tilt: f64,
    /// Direction the platform is lowest towards, deg counter-clockwise from gamma = 0.
    #[arg(long, default_value_t = 140.0, allow_hyphen_values = true, value_parser = real(-360.0, 360.0))]
    tilt_dir: f64,
    /// Gyro axis elevation above the platform (gyro misalignment), deg.
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true, value_parser = real(-10.0, 10.0))]
    misalignment: f64,
    /// Gyro scale factor.
    #[arg(long, allow_hyphen_values = true, default_value_t = 1.0, value_parser = real(0.1, 10.0))]
    scale: f64,
    /// Encoder error amplitude, arcsec.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0, value_parser = real(0.0, 3600.0))]
    encoder_error: f64,
    /// Harmonic of the encoder error (1: eccentricity).
    #[arg(long, default_value_t = 2, allow_hyphen_values = true)]
    encoder_harmonic: u8,
    /// Gyro temperature at the start, C.
    #[arg(long, default_value_t = 40.0, allow_hyphen_values = true, value_parser = real(-60.0, 125.0))]
    temp: f64,
    /// Temperature ramp, C per s.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-1.0, 1.0))]
    temp_ramp: f64,
    /// Bias temperature coefficient, deg/h per C.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-10.0, 10.0))]
    temp_coef: f64,
    /// Inclinometer noise, deg.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0005, value_parser = real(0.0, 1.0))]
    incl_noise: f64,
    /// Random seed.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    seed: u64,
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

pub fn cmd_simulate(a: SimArgs) -> Result<(), Fail> {
    let order = Order::parse(&a.order)
        .and_then(|o| o.check(a.n).map(|()| o))
        .map_err(|e| Fail(format!("--order: {e}"), 2))?;
    let mut twin = TwinConfig::default();
    twin.motor.max_sps = a.max_sps as f32;
    twin.motor.accel_sps2 = a.accel as f32;
    twin.instrument.latitude_deg = a.lat;
    twin.instrument.psi_deg = a.psi;
    twin.instrument.tilt_deg = a.tilt;
    twin.instrument.tilt_dir_deg = a.tilt_dir;
    twin.instrument.gyro_elev_deg = a.misalignment;
    twin.instrument.scale = a.scale;
    twin.instrument.bias_dph = a.bias;
    twin.noise = a.noise_terms.apply(NoiseModel::white(a.gyro_noise, 2.0))?;
    twin.bias_drift_dph_per_s = a.drift;
    twin.encoder_error = [(a.encoder_harmonic, a.encoder_error, 0.0), (1, 0.0, 0.0)];
    twin.temp0_c = a.temp;
    twin.temp_ramp_c_per_s = a.temp_ramp;
    twin.bias_temp_dph_per_c = a.temp_coef;
    twin.incl_noise_deg = a.incl_noise;
    twin.seed = a.seed;
    let run = RunConfig {
        positions: a.n,
        order,
        noise: twin.noise,
        target_arcsec: a.target_arcsec.unwrap_or(0.0) as f32,
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
            "firmware_sigma_arcsec": az.and_then(|x| x.sigma_arcsec),
            "firmware_sigma_undefined": az.is_some_and(|x| x.sigma_arcsec.is_none()),
            "under_noise": report.under_noise.map(|u| json!({"psi_deg": u.psi_deg, "sigma_arcsec": u.sigma_psi_deg * 3600.0, "dwells": u.dwells})),
            "target_reached": report.target_reached,
            "error": report.result.err().map(|e| format!("{e:?}")),
        });
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
            a.psi
        );
        if let Some(u) = report.under_noise {
            note!(
                "firmware under the noise model: psi {:.4} deg +- {:.1}\"{}",
                u.psi_deg,
                u.sigma_psi_deg * 3600.0,
                if report.target_reached {
                    "; the target was reached and the run ended early"
                } else {
                    ""
                }
            );
        }
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
