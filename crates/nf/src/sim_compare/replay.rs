//! An instrument file simulated under a recording's own plan: its positions, in its order, at
//! its times, with its dwell, its sample rate and its columns. The twin's physics and noise
//! run on in continuous time between the dwells, as they do in a run; the temperature follows
//! the recording's thermometer.

use crate::dwells;
use crate::instrument_file::InstrumentFile;
use crate::recording::{Recording, Row};
use nf_twin::{Recorder, World};
use std::collections::BTreeMap;

/// The encoder's error (deg) the instrument file gives at shaft angle `deg`.
fn encoder_error_deg(file: &InstrumentFile, deg: f64) -> f64 {
    file.encoder
        .error
        .iter()
        .map(|e| e.amplitude_arcsec / 3600.0 * (e.harmonic as f64 * deg + e.phase_deg).to_radians().sin())
        .sum()
}

/// One dwell of the twin: mean, spread and quarter means of its samples; the inclinometer and
/// the thermometer read at its middle, as the firmware reads them.
struct Dwell {
    mean: f64,
    sd: f64,
    quarters: [f64; 4],
    samples: u32,
    tilt: (f64, f64),
    temp_c: f64,
}

fn sample_dwell(world: &mut World, file: &InstrumentFile, dwell_s: f64) -> Dwell {
    let m = ((dwell_s * file.run.sample_rate_hz as f64).round() as usize).max(4);
    let cal = world.cfg.calibration;
    let (mut tilt, mut temp_c) = ((0.0, 0.0), 0.0);
    let x: Vec<f64> = (0..m)
        .map(|i| {
            // The twin has no ADC fault here: a conversion always comes.
            let _ = world.wait_conversion();
            if i == m / 2 {
                tilt = world.inclinometer();
                temp_c = world.temperature_c();
            }
            cal.rate_of_counts(world.adc_sample() as f64)
        })
        .collect();
    let mean = x.iter().sum::<f64>() / m as f64;
    let sd = (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (m - 1) as f64).sqrt();
    let q = |k: usize| {
        let part = &x[k * m / 4..(k + 1) * m / 4];
        part.iter().sum::<f64>() / part.len() as f64
    };
    Dwell {
        mean,
        sd,
        quarters: [q(0), q(1), q(2), q(3)],
        samples: m as u32,
        tilt,
        temp_c,
    }
}

/// When, on the twin's clock (from power-on, the clock of an instrument file's times), the
/// file's run starts: after levelling, where the recording's `t_s` counts from.
pub fn run_origin_s(file: &InstrumentFile) -> f64 {
    let mut rec = Recorder {
        abort_after_records: Some(1),
        ..Recorder::default()
    };
    nf_twin::simulate(&file.twin(), &file.run_config(), &mut rec);
    rec.header_at_us.map_or(0.0, |us| us as f64 * 1e-6)
}

/// `file`'s instrument run through `rec`'s plan with noise seed `seed`, the run starting at
/// `origin_s` on the twin's clock.
pub fn replay(file: &InstrumentFile, rec: &Recording, seed: u64, origin_s: f64) -> Recording {
    // The sample rate is the plan's too: the samples' spread depends on it.
    let file = &InstrumentFile {
        run: crate::instrument_file::Run {
            sample_rate_hz: super::plan::sample_rate_hz(rec).unwrap_or(file.run.sample_rate_hz),
            ..file.run.clone()
        },
        ..file.clone()
    };
    let mut twin = file.twin();
    twin.seed = seed;
    // The temperature is the recording's, as its times and angles are.
    twin.temp_trace = rec
        .rows
        .iter()
        .filter_map(|r| Some((r.t_s + origin_s, r.temp_c?)))
        .collect();
    twin.temp_trace.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut world = World::new(twin);
    // The dwells the fit and the noise estimate take for this recording.
    let dw = dwells::of(rec);
    let per_turn = (1u64 << file.encoder.bits) as f64;
    let mut order: Vec<usize> = (0..rec.rows.len()).collect();
    order.sort_by(|&a, &b| rec.rows[a].t_s.total_cmp(&rec.rows[b].t_s));
    let mut rows: Vec<Option<Row>> = vec![None; rec.rows.len()];
    let mut last_deg: Option<f64> = None;
    for i in order {
        let r = &rec.rows[i];
        let dwell = dw.each_s[i];
        let start_s = r.t_s + origin_s - dwell / 2.0;
        // The shaft where the encoder read the recording's angle; a move ends `settle_s`
        // before the dwell, and no move at all leaves the last settling alone.
        let shaft = (r.encoder_deg - encoder_error_deg(file, r.encoder_deg)).rem_euclid(360.0);
        if last_deg.is_none_or(|l| (shaft - l).abs() > 1e-9) {
            world.shaft_deg = shaft;
            world.last_move_end_s = start_s - file.run.settle_s;
            last_deg = Some(shaft);
        }
        let now = world.t_s();
        if start_s > now {
            world.advance(((start_s - now) * 1e6).round() as u64);
        }
        let d = sample_dwell(&mut world, file, dwell);
        let encoder_deg = world
            .encoder_counts()
            .map_or(r.encoder_deg, |c| c as f64 / per_turn * 360.0);
        let (tx, ty) = d.tilt;
        rows[i] = Some(Row {
            line: r.line,
            index: r.index,
            t_s: r.t_s,
            encoder_deg,
            rate_dph: d.mean,
            rate_sd_dph: r.rate_sd_dph.map(|_| d.sd),
            samples: r.samples.map(|_| d.samples),
            temp_c: r.temp_c.map(|_| d.temp_c),
            tilt_x_deg: r.tilt_x_deg.map(|_| tx),
            tilt_y_deg: r.tilt_y_deg.map(|_| ty),
            quarters_dph: r.quarters_dph.map(|_| d.quarters),
        });
    }
    let mut meta = BTreeMap::new();
    meta.insert("format".into(), "northfinder-recording/1".into());
    meta.insert("dwell_s".into(), dw.nominal_s.to_string());
    meta.insert("source".into(), "replay of an instrument file".into());
    Recording {
        latitude_deg: file.site.latitude_deg,
        meta,
        rows: rows.into_iter().flatten().collect(),
        warnings: Vec::new(),
    }
}
