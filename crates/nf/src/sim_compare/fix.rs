//! The instrument file with what the recording showed put in: each effect the simulation
//! lacks or sizes differently set to its fitted value, each it alone has taken out, the noise
//! model replaced by the recording's own where the noise differs, and the Eq. 7 numbers, the
//! inclinometer and the thermometer moved onto the recording's.

use super::compare::Comparison;
use super::physics::{Physics, Verdict, middle_s, noise_of, param};
use super::plan;
use super::profile::Quantity;
use super::thermometer;
use crate::diagnose::{CYCLE_AMPLITUDE, Diagnosis, Kind};
use crate::instrument_file::{Disturbance, EncoderError, InstrumentFile, Jump, Noise, Shocks};
use crate::recording::Recording;
use nf_model::noise::NoiseModel;
use nf_twin::WindowShift;

/// Sets one effect to the recording's fit; what was done, or why not.
fn set(file: &mut InstrumentFile, p: &Physics, rec: &Recording, dwell_s: f64, origin_s: f64) -> String {
    let v = |name: &str| param(&p.found, name).map_or(0.0, |x| x.value);
    let remove = p.verdict == Verdict::OnlyInSimulation;
    match p.kind {
        Kind::BiasDrift => {
            let q = if remove { 0.0 } else { v("rate_dph_per_s2") };
            file.drift.quadratic_dph_per_s2 = q;
            // The diagnosis gives the slope at the run's middle.
            file.drift.linear_dph_per_s = if remove {
                0.0
            } else {
                v("rate_dph_per_s") - 2.0 * q * (middle_s(rec) + origin_s)
            };
        }
        Kind::BiasJump => {
            file.jump = (!remove).then(|| Jump {
                time_s: v("time_s") + origin_s,
                size_dph: v("size_dph"),
            });
        }
        // A cycle found without a recorded temperature is a heater's swing of 1 C.
        Kind::ThermalDrift if !remove && param(&p.found, CYCLE_AMPLITUDE).is_some() => {
            let t = &mut file.temperature;
            let period = v("cycle_period_s");
            (t.swing_c, t.swing_period_s, t.bias_dph_per_c) = (1.0, period, v(CYCLE_AMPLITUDE));
            // The phase is on the recording's clock from its first dwell: the file's runs from
            // its origin.
            let first = rec.rows.iter().map(|r| r.t_s).fold(f64::INFINITY, f64::min);
            let turned = v("cycle_phase_deg") - 360.0 * (first + origin_s) / period;
            t.swing_phase_deg = turned.rem_euclid(360.0);
        }
        Kind::ThermalDrift => file.temperature.bias_dph_per_c = if remove { 0.0 } else { v("dph_per_degc") },
        Kind::ShaftTilt if remove => file.shaft.tilt_deg = 0.0,
        Kind::ShaftTilt => {
            file.shaft.tilt_deg = v("tilt_deg");
            file.shaft.tilt_dir_deg = v("tilt_dir_deg");
            // An axis the recording never read keeps the file's offset.
            for (name, o) in [
                ("offset_x_deg", &mut file.inclinometer.offset_x_deg),
                ("offset_y_deg", &mut file.inclinometer.offset_y_deg),
            ] {
                if let Some(x) = param(&p.found, name) {
                    *o = x.value;
                }
            }
        }
        Kind::EncoderError => {
            let h = v("harmonic") as u8;
            file.encoder.error.retain(|e| e.harmonic != h);
            if !remove {
                if file.encoder.error.len() >= 2 {
                    file.encoder.error.remove(0);
                }
                file.encoder.error.push(EncoderError {
                    harmonic: h,
                    amplitude_arcsec: v("amplitude_arcsec"),
                    phase_deg: v("phase_deg"),
                });
            }
        }
        Kind::ScaleFactor => file.gyro.scale = if remove { 1.0 } else { v("scale") },
        Kind::Nonlinearity => file.gyro.nonlinearity_per_dph = if remove { 0.0 } else { v("k2_per_dph") },
        Kind::SettlingTransient => {
            if remove {
                file.settling.size_dph = 0.0;
            } else {
                let Some((size, tau)) = settling_fit(rec, file.run.settle_s, dwell_s) else {
                    return "settling_transient: no decay fits the quarter means; set [settling] by hand".into();
                };
                file.settling.size_dph = size;
                file.settling.tau_s = tau;
            }
        }
        Kind::Outliers => {
            let Some(r) = rec.rows.iter().find(|r| r.index as f64 == v("index")) else {
                return "outliers: the position is not in the recording".into();
            };
            file.disturbance.push(Disturbance {
                from_s: (r.t_s + origin_s - dwell_s / 2.0).max(0.0),
                to_s: r.t_s + origin_s + dwell_s / 2.0,
                size_dph: v("size_dph"),
            });
        }
        Kind::HeavyTails if remove => file.shocks = None,
        Kind::HeavyTails => {
            let w = WindowShift {
                share: v("shock_share"),
                shift_dph: v("shock_shift_dph"),
            };
            if !(w.share > 0.0 && w.shift_dph > 0.0) {
                return "heavy_tails: no share of shifted dwells fits the residuals; set [shocks] by hand".into();
            }
            file.shocks = Some(Shocks::of(nf_twin::Shocks::for_window(w, dwell_s)));
        }
        Kind::BiasInstability | Kind::RateRandomWalk | Kind::CorrelatedNoise | Kind::Unexplained => {
            return String::new();
        }
    }
    format!(
        "{}: {}",
        p.kind.name(),
        if remove {
            "removed"
        } else {
            "set to the recording's fit"
        }
    )
}

/// Quarter k's mean of `exp(-t / tau)` less the dwell's, the move ending `settle_s` before.
fn decay_pattern(tau: f64, settle_s: f64, dwell_s: f64) -> [f64; 4] {
    let q = dwell_s / 4.0;
    let mean_over = |a: f64| tau * ((-a / tau).exp() - (-(a + q) / tau).exp()) / q;
    let p = [0, 1, 2, 3].map(|k| mean_over(settle_s + k as f64 * q));
    let m = p.iter().sum::<f64>() / 4.0;
    p.map(|v| v - m)
}

/// Size (deg/h) and time constant (s) of the decay that best fits the recording's mean
/// quarter pattern, over a grid of time constants.
pub fn settling_fit(rec: &Recording, settle_s: f64, dwell_s: f64) -> Option<(f64, f64)> {
    let q: Vec<[f64; 4]> = rec.rows.iter().filter_map(|r| r.quarters_dph).collect();
    if q.is_empty() {
        return None;
    }
    let n = q.len() as f64;
    let d = [0, 1, 2, 3].map(|k| q.iter().map(|q| q[k] - q.iter().sum::<f64>() / 4.0).sum::<f64>() / n);
    (0..60)
        .map(|i| 1e-3 * 1.2f64.powi(i))
        .filter(|tau| *tau <= 600.0)
        .filter_map(|tau| {
            let p = decay_pattern(tau, settle_s, dwell_s);
            let pp: f64 = p.iter().map(|v| v * v).sum();
            (pp > 1e-30).then(|| {
                let size = p.iter().zip(&d).map(|(a, b)| a * b).sum::<f64>() / pp;
                let rss: f64 = p.iter().zip(&d).map(|(a, b)| (b - size * a).powi(2)).sum();
                (rss, size, tau)
            })
        })
        .filter(|(_, size, _)| size.abs() <= 50.0)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, size, tau)| (size, tau))
}

/// The factor within which the white level the samples' spread gives and the recording's
/// estimate from its dwell and quarter means must agree for the samples' to be taken: beyond
/// it the gyro's samples are not white (a sensor's filter, a correlation over seconds), and
/// the dwell means, which the azimuth is fitted to, decide.
const SAMPLES_AGREE: f64 = 1.5;

/// The angle random walk of `f` (the recording's estimate put in) from the samples' spread:
/// `before`'s replays have `file`'s white level, and the spread of thousands of samples in a
/// dwell is almost all white noise, which it measures far better than the dwell means do.
/// A file without white noise gives no ratio: the level is then the samples' own (a sample
/// the mean over `1 / rate` s has sd `60 N sqrt(rate)` deg/h).
fn white_from_samples(f: &mut InstrumentFile, file: &InstrumentFile, cmp: &Comparison) -> Option<String> {
    let l = cmp.line(Quantity::SampleSd)?;
    let from_samples = if file.noise.arw_deg_rth > 0.0 && l.simulated > 0.0 {
        file.noise.arw_deg_rth * l.recording / l.simulated
    } else {
        l.recording / (60.0 * f64::from(f.run.sample_rate_hz).sqrt())
    };
    let estimate = f.noise.arw_deg_rth;
    if !(from_samples > 0.0 && estimate > 0.0) || (from_samples / estimate).ln().abs() > SAMPLES_AGREE.ln() {
        return None;
    }
    f.noise.arw_deg_rth = from_samples;
    Some(format!(
        "noise: angle random walk {from_samples:.4e} deg/sqrt(h) from the samples' spread (the estimate's {estimate:.4e})"
    ))
}

/// RMS (C) by which the file's temperature may miss the recording's before the file takes
/// the recording's ramp.
const TEMP_TOLERANCE_C: f64 = 0.1;

/// The recording's temperature as a ramp and a swing, where the file's misses it.
fn temperature(f: &mut InstrumentFile, rec: &Recording, origin_s: f64) -> Option<String> {
    let temp: Vec<(f64, f64)> = rec
        .rows
        .iter()
        .filter_map(|r| Some((r.t_s + origin_s, r.temp_c?)))
        .collect();
    let n = temp.len() as f64;
    let miss = (temp.iter().map(|p| (p.1 - f.temperature.at(p.0)).powi(2)).sum::<f64>() / n).sqrt();
    if temp.len() < 2 || miss <= TEMP_TOLERANCE_C {
        return None;
    }
    let fit = thermometer::fit(&temp)?;
    let t = &mut f.temperature;
    t.ramp_c_per_s = fit.ramp_c_per_s.clamp(-1.0, 1.0);
    t.start_c = fit.start_c.clamp(-60.0, 125.0);
    let swing = match fit.swing {
        Some(s) => {
            t.swing_c = s.amplitude_c.min(100.0);
            t.swing_period_s = s.period_s.clamp(1.0, 1e7);
            t.swing_phase_deg = s.phase_deg;
            format!(
                " and a swing of {:.3} C, period {:.1} s, phase {:.0} deg",
                t.swing_c, t.swing_period_s, t.swing_phase_deg
            )
        }
        None => {
            t.swing_c = 0.0;
            " (no swing)".into()
        }
    };
    Some(format!(
        "temperature: the file missed the recording's by {miss:.3} C RMS; now {:.3} C at 0 s, {:+.6} C/s{swing}, {:.3} C RMS from the recording's",
        t.start_c, t.ramp_c_per_s, fit.rms_c
    ))
}

/// How far (s) the file's mean spacing of dwells may be from the recording's before its
/// settling time is changed: the firmware's times are whole milliseconds.
const SAME_PACE_S: f64 = 0.005;

/// The recording's plan where the file's differs: positions and order (when its angles lie
/// on an equal grid), dwell, pace (the settling time) and sample rate.
fn run_plan(f: &mut InstrumentFile, rec: &Recording, dwell_s: f64) -> Vec<String> {
    let mut notes = Vec::new();
    if let Some((n, order)) = plan::infer(rec)
        && (n, order.as_str()) != (f.run.positions, f.run.order.as_str())
    {
        notes.push(format!(
            "run: {n} positions, order {order} (the recording's; the file had {}, {})",
            f.run.positions, f.run.order
        ));
        (f.run.positions, f.run.order) = (n, order);
    }
    if (dwell_s - f.run.dwell_s).abs() > 1e-3 {
        notes.push(format!(
            "run: dwell {dwell_s:.3} s (the recording's; the file had {} s)",
            f.run.dwell_s
        ));
        f.run.dwell_s = dwell_s.clamp(0.01, 600.0);
    }
    if let Some(p) = plan::pace(rec, f).filter(|p| (p.recorded_s - p.planned_s).abs() > SAME_PACE_S) {
        let motor = if p.motor_factor == 1.0 {
            String::new()
        } else {
            f.motor = f.motor.sped_up(p.motor_factor);
            format!(
                ", and the motor {:.3} times as fast (no settling time keeps the pace with the file's)",
                p.motor_factor
            )
        };
        notes.push(format!(
            "run: settle {:.3} s (the file had {} s){motor}: the recording's dwells are {:.3} s apart on average, the file's run's were {:.3} s",
            p.settle_s, f.run.settle_s, p.recorded_s, p.planned_s
        ));
        f.run.settle_s = p.settle_s;
    }
    if let Some(r) = plan::sample_rate_hz(rec).filter(|r| *r != f.run.sample_rate_hz) {
        notes.push(format!(
            "run: {r} samples/s (the recording's; the file had {})",
            f.run.sample_rate_hz
        ));
        f.run.sample_rate_hz = r;
    }
    notes
}

/// The effects from the diagnosis.
pub fn effects(
    file: &InstrumentFile,
    physics: &[Physics],
    rec: &Recording,
    dwell_s: f64,
    origin_s: f64,
) -> (InstrumentFile, Vec<String>) {
    let mut f = file.clone();
    let mut notes = Vec::new();
    if (rec.latitude_deg - f.site.latitude_deg).abs() > 1e-9 {
        notes.push(format!(
            "latitude: {} -> {} (the recording's)",
            f.site.latitude_deg, rec.latitude_deg
        ));
        f.site.latitude_deg = rec.latitude_deg;
    }
    if let Some(n) = temperature(&mut f, rec, origin_s) {
        notes.push(n);
    }
    notes.extend(run_plan(&mut f, rec, dwell_s));
    for p in physics.iter().filter(|p| p.verdict.needs_change()) {
        let n = set(&mut f, p, rec, dwell_s, origin_s);
        if !n.is_empty() {
            notes.push(n);
        }
    }
    let scale_set = physics
        .iter()
        .any(|p| p.kind == Kind::ScaleFactor && p.verdict.needs_change() && p.verdict != Verdict::OnlyInSimulation);
    if scale_set && let Some(n) = scale_beside_nonlinearity(&mut f) {
        notes.push(n);
    }
    (f, notes)
}

/// The twin's nonlinearity squares the whole rate, its bias included, so it gains the first
/// harmonic by `1 + 2 k c` (`c` the rate's mean over a turn) where the fitted scale factor,
/// the recording's amplitude over the predicted, already holds that gain: the file's scale is
/// the fit's over it (an outside audit's file with `k` 3e-4 and a bias of 0.3 deg/h got
/// scale 1.00023 beside the fitted `k`, twice the amplitude's change).
fn scale_beside_nonlinearity(f: &mut InstrumentFile) -> Option<String> {
    let k = f.gyro.nonlinearity_per_dph;
    if k == 0.0 {
        return None;
    }
    let inst = f.twin().instrument;
    const TURN: usize = 72;
    let c = (0..TURN)
        .map(|i| inst.rate_dph(i as f64 * 360.0 / TURN as f64))
        .sum::<f64>()
        / TURN as f64;
    let gain = 1.0 + 2.0 * k * c;
    if !(gain.is_finite() && gain > 0.0) {
        return None;
    }
    f.gyro.scale /= gain;
    Some(format!(
        "scale_factor: the fit's over the nonlinearity's own gain of the amplitude, {gain:.6} (1 + 2 k times the rate's mean, {c:.5} deg/h)"
    ))
}

/// `file` with its noise model replaced by the recording's (or its white level scaled) where
/// `cmp`, of replays of `file` with the effects put in, finds the noise apart.
pub fn noise(
    file: &InstrumentFile,
    cmp: &Comparison,
    physics: &[Physics],
    diag: &Diagnosis,
) -> (InstrumentFile, Vec<String>) {
    let mut f = file.clone();
    let mut notes = Vec::new();
    // A term only a replay named is no reason to take the recording's estimate: one run of
    // the recording may simply not show it.
    let noise_named = physics.iter().any(|p| {
        p.kind.is_noise() && p.kind != Kind::HeavyTails && matches!(p.verdict, Verdict::Missing | Verdict::Different)
    });
    let off = |q: Quantity| cmp.line(q).filter(|l| l.mismatch).map(|l| (l.recording, l.simulated));
    let within_dwell = |q: Quantity| matches!(q, Quantity::SampleSd | Quantity::QuarterSd);
    // Only the noise within a dwell differs: the white level, which thousands of samples
    // measure better than the recording's estimate from its dwell means does (a file with
    // no white noise to scale takes the estimate).
    let white_scale = [Quantity::SampleSd, Quantity::QuarterSd]
        .into_iter()
        .find_map(|q| Some((q, off(q)?)))
        .filter(|(_, (_, s))| *s > 0.0 && f.noise.arw_deg_rth > 0.0)
        .filter(|_| !noise_named && !cmp.any(|q| q.is_scatter() && !within_dwell(q)));
    if let Some((q, (r, s))) = white_scale {
        f.noise.arw_deg_rth *= r / s;
        notes.push(format!("noise: angle random walk times {:.4} (the {q})", r / s));
    } else if noise_named || cmp.any(Quantity::is_scatter) {
        let how = if noise_of(diag) == diag.noise_model {
            ""
        } else {
            ", made with the named effects in the design"
        };
        let what = format!("the recording's estimate ({}{how})", diag.noise_source);
        return with_noise(file, cmp, &noise_of(diag), &what);
    }
    (f, notes)
}

/// `file` with its noise model replaced by `model` (`what` names it; the white level from
/// the samples' spread where `cmp` has it), the file's tails kept.
pub fn with_noise(
    file: &InstrumentFile,
    cmp: &Comparison,
    model: &NoiseModel,
    what: &str,
) -> (InstrumentFile, Vec<String>) {
    let mut f = file.clone();
    f.noise = Noise {
        student_t_dof: f.noise.student_t_dof,
        ..Noise::of(model)
    };
    let mut notes = vec![format!("noise: {what}")];
    notes.extend(white_from_samples(&mut f, file, cmp));
    (f, notes)
}

/// The recording's wander as `diag` estimated it, where it wanders beyond `file`'s noise (a
/// flicker, walk or Gauss-Markov term larger than the file's), and what it is: its estimate
/// with the named effects in the design, else the most coloured model its likelihood allows.
pub fn wander(diag: &Diagnosis, file: &InstrumentFile) -> Option<(NoiseModel, &'static str)> {
    let n = &file.noise;
    let beyond = |m: &NoiseModel| {
        m.bias_instability_dph > n.bias_instability_dph
            || m.rrw_dph_rth > n.rrw_dph_rth
            || m.gm_sigma_dph > n.gm_sigma_dph
    };
    [
        (noise_of(diag), "the recording's estimate"),
        (
            diag.cautious_model,
            "the most coloured noise model the recording allows",
        ),
    ]
    .into_iter()
    .find(|(m, _)| beyond(m))
}

/// A bias change `db` as the gyro axis's elevation would make it, through the Earth rate's
/// vertical part `WE sin(lat) sin(e)`: within one run the two are the same constant.
fn as_elevation(file: &InstrumentFile, db: f64) -> String {
    let vertical = nf_model::EARTH_RATE_DPH * file.site.latitude_deg.to_radians().sin() * file.gyro.scale;
    let e0 = file.gyro.elevation_deg.to_radians();
    let now = e0.sin() + db / vertical;
    if vertical.abs() < 0.5 || now.abs() > 0.5 {
        return String::new();
    }
    format!(
        " (or, the same in one run, the gyro axis's elevation moved by {:+.4} deg: the Earth rate's vertical part)",
        (now.asin() - e0).to_degrees()
    )
}

/// How many of the recording's final sigmas its azimuth must lie from the file's before the
/// fix moves the site: the replays' Eq. 7 azimuth also differs from the recording's by what
/// the fitted effects miss (a jump fitted 1 sigma short moved the site 86" in an outside
/// audit), which the comparison's spread, of replays with the effects exact, does not hold.
const SITE_SIGMAS: f64 = 3.0;

/// `file` with the bias, the site azimuth and the inclinometer's offsets moved onto the
/// recording's where `cmp`, the comparison with replays of `file` under its final noise,
/// still finds them apart; and the quantities moved. A coloured noise the fix put in widens
/// their spread, and one run's wander is no reason to move the site: the azimuth moves only
/// where the recording's final azimuth (`diag`, with its sigma) is off the file's too, and
/// the scale only as the scale factor the diagnosis names.
pub fn moments(
    file: &InstrumentFile,
    cmp: &Comparison,
    diag: &Diagnosis,
) -> (InstrumentFile, Vec<String>, Vec<Quantity>) {
    let mut f = file.clone();
    let mut notes = Vec::new();
    let mut moved = Vec::new();
    let off = |q: Quantity| cmp.line(q).filter(|l| l.mismatch).map(|l| (l.recording, l.simulated));
    if let Some((r, s)) = off(Quantity::Bias) {
        f.gyro.bias_dph = (f.gyro.bias_dph + r - s).clamp(-50.0, 50.0);
        notes.push(format!(
            "bias: moved by {:+.5} deg/h{}",
            r - s,
            as_elevation(file, r - s)
        ));
        moved.push(Quantity::Bias);
    }
    if let Some((r, s)) = off(Quantity::Azimuth) {
        let fin = &diag.final_;
        let apart = (fin.azimuth_deg - f.site.azimuth_deg + 180.0).rem_euclid(360.0) - 180.0;
        if diag.unresolved.is_none() && apart.abs() * 3600.0 > SITE_SIGMAS * fin.sigma_arcsec {
            f.site.azimuth_deg = (fin.azimuth_deg + 180.0).rem_euclid(360.0) - 180.0;
            notes.push(format!(
                "azimuth: moved by {apart:+.5} deg to the recording's final ({:.5} deg +- {:.2}\")",
                fin.azimuth_deg, fin.sigma_arcsec
            ));
            moved.push(Quantity::Azimuth);
        } else {
            notes.push(format!(
                "azimuth: the site left as it is: Eq. 7's azimuth differs from the replays' by {:+.5} deg, but the recording's final azimuth is {:.1} of its sigmas from the file's ({:.5} deg +- {:.2}\"): what the fitted effects miss, not the site",
                r - s,
                apart.abs() * 3600.0 / fin.sigma_arcsec.max(f64::MIN_POSITIVE),
                fin.azimuth_deg,
                fin.sigma_arcsec
            ));
        }
    }
    let axes = [
        (Quantity::TiltOffset, "X", &mut f.inclinometer.offset_x_deg),
        (Quantity::TiltOffsetY, "Y", &mut f.inclinometer.offset_y_deg),
    ];
    for (q, axis, o) in axes {
        if let Some((r, s)) = off(q) {
            *o = (*o + r - s).clamp(-10.0, 10.0);
            notes.push(format!("inclinometer {axis} offset: moved by {:+.5} deg", r - s));
            moved.push(q);
        }
    }
    (f, notes, moved)
}
