//! `nf fit` and `nf diagnose` through a real gyro's noise: recordings whose gyro errors are
//! windows of a static log (the static-log format), scaled, plus the exact Earth rate at a
//! random latitude and azimuth. No catalogue effect is in them: every effect named is a
//! false alarm, and the reported sigmas are judged against the true azimuth (white least
//! squares with its residual sigma beside them).
//!
//! `cargo run --release --example real_noise_bench -- LOG [RECORDINGS] [STRETCH ...] [--allan OTHER]`
//! (default 30 recordings per row, stretches 1 3 10 30). A recording has 36, 48 or 72
//! positions in turn, 1 s dwells 1.35 s apart, in a sweep or in opposite pairs; STRETCH is
//! how many seconds of the log one second of the recording takes, so that a run sees the
//! log's slow wander as a longer run would. The noise is scaled so that the log's Allan
//! deviation at a dwell (of log time, overlapping, as `nf allan` computes it) is 0.01 deg/h,
//! the paper's gyro. Beside the estimate from each recording, `nf fit` and `nf diagnose` are
//! also given the noise model `nf allan` fits to a static log of the gyro (scaled and
//! stretched as the recordings are), as a user who characterised the gyro would: the whole of
//! `LOG`, or `--allan OTHER`, another log of the same gyro.

use nf::allan::oavar;
use nf::allan_fit::fit_series;
use nf::allan_model::Sampling;
use nf::analysis::{Options as FitOptions, analyse};
use nf::diagnose::{Options, diagnose};
use nf::noise_fit::NoiseChoice;
use nf::recording::Recording;
use nf::static_log::StaticLog;
use nf_model::EARTH_RATE_DPH;
use nf_model::angle::wrap_180;
use nf_model::noise::NoiseModel;
use nf_model::rng::Rng;
use nf_twin::QuarteredRecording;
use std::collections::BTreeMap;

/// The Allan deviation of a dwell mean after scaling, deg/h.
const TARGET_DPH: f64 = 0.01;
/// Dwell and spacing of the positions, s of recording time.
const DWELL_S: f64 = 1.0;
const SPACING_S: f64 = 1.35;

#[derive(Default)]
struct Row {
    /// White least squares with its residual sigma, for comparison.
    ols_z2: f64,
    fit_z2: f64,
    /// `nf fit` given the log's noise model from `nf allan`.
    given_z2: f64,
    final_z2: f64,
    /// `nf diagnose` given the log's noise model.
    final_given_z2: f64,
    alarms_given: u32,
    fit_beyond: u32,
    given_beyond: u32,
    final_beyond: u32,
    alarms: u32,
    runs: u32,
    named: BTreeMap<String, u32>,
}

/// Encoder angles of `n` positions from `start` in a sweep, or in opposite pairs.
fn angles(n: usize, start: f64, pairs: bool) -> Vec<f64> {
    let step = 360.0 / n as f64;
    let at = |k: usize| (start + step * k as f64) % 360.0;
    if pairs {
        (0..n / 2).flat_map(|k| [at(k), (at(k) + 180.0) % 360.0]).collect()
    } else {
        (0..n).map(at).collect()
    }
}

/// One recording's text, with its true azimuth.
fn recording(noise: &[f64], rate_hz: f64, n: usize, pairs: bool, rng: &mut Rng) -> (String, f64) {
    let lat = rng.uniform(-60.0, 60.0);
    let psi = rng.uniform(0.0, 360.0);
    let bias = rng.uniform(-1.0, 1.0);
    let amplitude = EARTH_RATE_DPH * lat.to_radians().cos();
    let per_s = noise.len() as f64 / (n as f64 * SPACING_S);
    let quarter = (DWELL_S * per_s / 4.0) as usize;
    let mut rec = QuarteredRecording::new(lat, DWELL_S, rate_hz);
    for (i, gamma) in angles(n, rng.uniform(0.0, 360.0), pairs).into_iter().enumerate() {
        let from = (i as f64 * SPACING_S * per_s) as usize;
        let signal = amplitude * (gamma + psi).to_radians().cos() + bias;
        let q: [f64; 4] = core::array::from_fn(|k| {
            let s = &noise[from + k * quarter..from + (k + 1) * quarter];
            signal + s.iter().sum::<f64>() / quarter as f64
        });
        rec.position(i as f64 * SPACING_S + DWELL_S / 2.0, gamma, q);
    }
    (rec.text().to_string(), psi)
}

/// The log's noise model in recording units: rates times `scale`, `stretch` s of log in 1 s.
fn in_recording(m: &NoiseModel, scale: f64, stretch: f64) -> NoiseModel {
    NoiseModel {
        arw_deg_rth: m.arw_deg_rth * scale / stretch.sqrt(),
        bias_instability_dph: m.bias_instability_dph * scale,
        rrw_dph_rth: m.rrw_dph_rth * scale * stretch.sqrt(),
        gm_sigma_dph: m.gm_sigma_dph * scale,
        gm_tau_s: m.gm_tau_s / stretch,
        quantization_arcsec: m.quantization_arcsec * scale / stretch,
        ..*m
    }
}

fn run_row(log: &StaticLog, allan: &NoiseModel, rate_hz: f64, stretch: f64, pairs: bool, count: u32) -> Row {
    let dwell_samples = (DWELL_S * stretch * rate_hz).round() as usize;
    let avar = oavar(&log.segments(), log.spacing.step_s, &[dwell_samples])[0].avar;
    let scale = TARGET_DPH / avar.sqrt();
    let model = NoiseChoice::Given(in_recording(allan, scale, stretch), "nf allan of the log".into());
    let given = FitOptions {
        noise: model.clone(),
        ..FitOptions::default()
    };
    let given_diag = Options {
        noise: model,
        ..Options::default()
    };
    let mut rng = Rng::new(0x5EA1 ^ stretch.to_bits() ^ u64::from(pairs));
    let mut row = Row::default();
    for r in 0..count {
        let n = [36, 48, 72][r as usize % 3];
        let len = ((n as f64 * SPACING_S + DWELL_S) * stretch * rate_hz) as usize;
        if len >= log.rate_dph.len() {
            continue;
        }
        let from = (rng.unit() * (log.rate_dph.len() - len) as f64) as usize;
        let window = &log.rate_dph[from..from + len];
        let mean = window.iter().sum::<f64>() / len as f64;
        let noise: Vec<f64> = window.iter().map(|v| (v - mean) * scale).collect();
        let (text, psi) = recording(&noise, rate_hz, n, pairs, &mut rng);
        let rec = Recording::parse(&text).expect("the bench writes valid recordings");
        let err = |a: f64| wrap_180(a - psi) * 3600.0;
        let (Ok(fit), Ok(with_allan), Ok(d), Ok(dg)) = (
            analyse(&rec, &FitOptions::default()),
            analyse(&rec, &given),
            diagnose(&rec, &Options::default()),
            diagnose(&rec, &given_diag),
        ) else {
            continue;
        };
        let zo = err(fit.fit.psi_deg) / (fit.fit.sigma_psi_deg * 3600.0);
        let zf = err(fit.gls.psi_deg) / (fit.gls.sigma_psi_deg * 3600.0);
        let zg = err(with_allan.gls.psi_deg) / (with_allan.gls.sigma_psi_deg * 3600.0);
        let zd = err(d.final_.azimuth_deg) / d.final_.sigma_arcsec;
        let zdg = err(dg.final_.azimuth_deg) / dg.final_.sigma_arcsec;
        row.final_given_z2 += zdg * zdg;
        row.alarms_given += u32::from(dg.findings.iter().any(|f| !f.effect.is_noise()));
        row.ols_z2 += zo * zo;
        row.fit_z2 += zf * zf;
        row.given_z2 += zg * zg;
        row.final_z2 += zd * zd;
        row.fit_beyond += u32::from(zf.abs() > 3.0);
        row.given_beyond += u32::from(zg.abs() > 3.0);
        row.final_beyond += u32::from(zd.abs() > 3.0);
        let effects: Vec<_> = d.findings.iter().filter(|f| !f.effect.is_noise()).collect();
        row.alarms += u32::from(!effects.is_empty());
        for f in &d.findings {
            *row.named.entry(f.effect.name().to_string()).or_default() += 1;
        }
        row.runs += 1;
    }
    row
}

fn read(path: &str) -> StaticLog {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    StaticLog::parse(&text).unwrap_or_else(|e| panic!("{}", e.at(path)))
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let other = args.iter().position(|a| a == "--allan").map(|i| {
        let path = args.get(i + 1).cloned().unwrap_or_default();
        args.drain(i..(i + 2).min(args.len()));
        path
    });
    let Some(path) = args.first() else {
        eprintln!("usage: real_noise_bench LOG [RECORDINGS] [STRETCH ...] [--allan OTHER]");
        std::process::exit(2);
    };
    let log = read(path);
    let rate_hz = 1.0 / log.spacing.step_s;
    let count: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(30);
    let stretches: Vec<f64> = match args.get(2..) {
        Some(s) if !s.is_empty() => s.iter().filter_map(|v| v.parse().ok()).collect(),
        _ => vec![1.0, 3.0, 10.0, 30.0],
    };
    let allan_path = other.as_deref().unwrap_or(path);
    let allan_log = read(allan_path);
    let (_, allan) = fit_series(
        &allan_log.segments(),
        Sampling::contiguous(allan_log.spacing.step_s),
        None,
    )
    .unwrap_or_else(|e| panic!("{allan_path}: the Allan fit: {e}"));
    println!("noise model given to nf fit --noise: nf allan of {allan_path}");
    println!("{path}: {} samples at {rate_hz:.3} Hz", log.rate_dph.len());
    println!(
        "order    stretch  runs  RMS z white LS  RMS z fit  RMS z fit --noise  RMS z final  RMS z final --noise  >3 sd fit  >3 sd --noise  >3 sd final  false alarms  false alarms --noise  named"
    );
    for pairs in [false, true] {
        for &stretch in &stretches {
            let r = run_row(&log, &allan.model, rate_hz, stretch, pairs, count);
            let k = f64::from(r.runs.max(1));
            let named: Vec<String> = r.named.iter().map(|(k, v)| format!("{k} x{v}")).collect();
            println!(
                "{:<8} {stretch:>7} {:>5} {:>15.2} {:>10.2} {:>18.2} {:>12.2} {:>20.2} {:>10} {:>14} {:>12} {:>13} {:>21} {}",
                if pairs { "pairs" } else { "sweep" },
                r.runs,
                (r.ols_z2 / k).sqrt(),
                (r.fit_z2 / k).sqrt(),
                (r.given_z2 / k).sqrt(),
                (r.final_z2 / k).sqrt(),
                (r.final_given_z2 / k).sqrt(),
                r.fit_beyond,
                r.given_beyond,
                r.final_beyond,
                r.alarms,
                r.alarms_given,
                named.join(", ")
            );
        }
    }
}
