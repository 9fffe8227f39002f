//! `nf diagnose`: where a recording departs from the model the simulation used (Eq. 7 on a
//! level, ideal instrument), which physical effect was left out, its fitted parameters, and
//! the fit and azimuth once it is modelled.
//!
//! Each effect is a physical model with a signature in the data. Most are extra columns of
//! the linear model. A bias jump and the outliers are scans, over the change time and over
//! the positions. The shaft tilt is read from the inclinometer, not from the residuals. A
//! finding needs a nested-model test (F or t) significant at `alpha / m`, where `m` counts
//! the tests made in that step (Bonferroni, scans included). So a clean recording is named
//! for nothing with probability at least `1 - alpha` (`alpha` = 0.05 by default). Effects
//! are added one at a time, most significant first, until none is left.

use crate::analysis::TiltMethod;
use crate::linfit::{self, Ls};
use crate::recording::Recording;
use crate::stats::{f_sf, t_sf2};
use crate::tilt;
use nf_model::EARTH_RATE_DPH;
use nf_model::angle::atan2_deg;

/// Most tests in one step: drift (2 forms), thermal, encoder (3 harmonics), nonlinearity,
/// jump, outliers, settling, scale factor, and the shaft tilt.
const FIRST_STEP_TESTS: usize = 12;

/// The effects `nf diagnose` knows, by the identifiers it reports.
pub const EFFECTS: [&str; 9] = [
    "bias_drift",
    "bias_jump",
    "thermal_drift",
    "shaft_tilt",
    "encoder_error",
    "scale_factor",
    "nonlinearity",
    "settling_transient",
    "outliers",
];

#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    pub name: String,
    pub value: f64,
    /// Standard error, where the fit gives one.
    pub sigma: Option<f64>,
}

#[derive(Debug, Clone)]
pub struct Finding {
    pub effect: &'static str,
    pub parameters: Vec<Param>,
    /// Bonferroni-adjusted p-value of the test that found it.
    pub p_value: f64,
    /// Where in the recording it shows.
    pub location: String,
    pub rss_after: f64,
    pub azimuth_deg_after: f64,
    pub sigma_arcsec_after: f64,
}

#[derive(Debug, Clone, Copy)]
pub struct Summary {
    pub azimuth_deg: f64,
    pub rss: f64,
    pub sigma_arcsec: f64,
}

#[derive(Debug, Clone)]
pub struct Diagnosis {
    pub alpha: f64,
    pub baseline: Summary,
    pub findings: Vec<Finding>,
    pub final_: Summary,
    /// What cannot be told apart, and other cautions.
    pub notes: Vec<String>,
    /// `(gamma, residual)` before and after, for the plots.
    pub residuals_before: Vec<(f64, f64)>,
    pub residuals_after: Vec<(f64, f64)>,
}

/// The recording as columns, in visiting order.
struct Data {
    lat: f64,
    gamma: Vec<f64>,
    t: Vec<f64>,
    rate: Vec<f64>,
    temp: Option<Vec<f64>>,
    quarters: Option<Vec<[f64; 4]>>,
}

/// The model as it grows: columns besides `1, cos, sin`, and the rates it fits.
#[derive(Clone)]
struct Model {
    extra: Vec<(&'static str, Vec<f64>)>,
    y: Vec<f64>,
}

fn ones(n: usize) -> Vec<f64> {
    vec![1.0; n]
}

impl Data {
    fn n(&self) -> usize {
        self.gamma.len()
    }

    fn base_cols(&self) -> Vec<Vec<f64>> {
        vec![
            ones(self.n()),
            self.gamma.iter().map(|g| g.to_radians().cos()).collect(),
            self.gamma.iter().map(|g| g.to_radians().sin()).collect(),
        ]
    }

    fn cols(&self, m: &Model, more: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let mut c = self.base_cols();
        c.extend(m.extra.iter().map(|e| e.1.clone()));
        c.extend(more.iter().cloned());
        c
    }

    fn fit(&self, m: &Model, more: &[Vec<f64>]) -> Option<Ls> {
        linfit::fit(&self.cols(m, more), &m.y)
    }

    /// Time scaled to about [-1, 1] over the run.
    fn tau(&self) -> Vec<f64> {
        let (lo, hi) = self
            .t
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &t| (a.min(t), b.max(t)));
        let (mid, half) = ((lo + hi) / 2.0, ((hi - lo) / 2.0).max(1e-9));
        self.t.iter().map(|t| (t - mid) / half).collect()
    }
}

fn summary(ls: &Ls) -> Summary {
    let (a, b) = (ls.coef[1], ls.coef[2]);
    let r2 = a * a + b * b;
    let v =
        ls.s2() * (b * b * ls.cov_unit[1][1] + a * a * ls.cov_unit[2][2] - 2.0 * a * b * ls.cov_unit[1][2]) / (r2 * r2);
    Summary {
        azimuth_deg: atan2_deg(-b, a),
        rss: ls.rss,
        sigma_arcsec: v.max(0.0).sqrt().to_degrees() * 3600.0,
    }
}

/// F-test of `big` (with `q` more columns) against `small`.
fn nested_p(small: &Ls, big: &Ls, q: usize) -> f64 {
    if big.dof == 0 || small.rss <= big.rss {
        return 1.0;
    }
    let f = ((small.rss - big.rss) / q as f64) / big.s2();
    f_sf(f, q as f64, big.dof as f64)
}

fn corr(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

/// A candidate change to the model, with the test that supports it.
struct Candidate {
    effect: &'static str,
    p: f64,
    model: Model,
    parameters: Vec<Param>,
    location: String,
}

fn param(name: &str, value: f64, sigma: Option<f64>) -> Param {
    Param {
        name: name.into(),
        value,
        sigma,
    }
}

fn with_extra(m: &Model, name: &'static str, cols: Vec<Vec<f64>>) -> Model {
    let mut m = m.clone();
    m.extra.extend(cols.into_iter().map(|c| (name, c)));
    m
}

/// Diagnoses a recording at family-wise false-alarm rate `alpha` per step.
pub fn diagnose(rec: &Recording, alpha: f64) -> Result<Diagnosis, String> {
    let n = rec.rows.len();
    if n < 8 {
        return Err(format!("{n} positions: diagnosing needs at least 8"));
    }
    let d = Data {
        lat: rec.latitude_deg,
        gamma: rec.rows.iter().map(|r| r.encoder_deg).collect(),
        t: rec.rows.iter().map(|r| r.t_s).collect(),
        rate: rec.rows.iter().map(|r| r.rate_dph).collect(),
        temp: rec.rows.iter().map(|r| r.temp_c).collect(),
        quarters: rec.rows.iter().map(|r| r.quarters_dph).collect(),
    };
    let mut model = Model {
        extra: Vec::new(),
        y: d.rate.clone(),
    };
    let base = d
        .fit(&model, &[])
        .ok_or("the positions do not determine A cos + B sin + C")?;
    let baseline = summary(&base);
    let mut notes = Vec::new();
    let mut findings: Vec<Finding> = Vec::new();
    let mut current = base.clone();
    let residuals_before = d.gamma.iter().copied().zip(base.resid.iter().copied()).collect();

    // The shaft tilt comes from the inclinometer, not the residuals, and is corrected first by
    // `nf fit`'s own path (measured physics, applied whether or not it is significant); a tilt
    // circle that stands out of the inclinometer's noise is reported as a finding.
    let mut tilt_tested = false;
    if let Some((c, p)) = shaft_tilt(&d, rec)? {
        tilt_tested = true;
        model = c.model.clone();
        current = d.fit(&model, &[]).ok_or("the tilt-corrected model does not fit")?;
        if p < alpha / FIRST_STEP_TESTS as f64 {
            push(&mut findings, c, p, &current);
        } else {
            notes.push(format!(
                "shaft tilt corrected from the inclinometer; its circle is within the readings' noise (p = {p:.3})"
            ));
        }
    }

    let mut steps = 0;
    while steps < 12 {
        steps += 1;
        let mut cands: Vec<Candidate> = Vec::new();
        let mut tests = 0usize;
        let s = summary(&current);
        let amp = current.coef[1].hypot(current.coef[2]);
        let done = |e: &str| findings.iter().any(|f| f.effect == e);
        let mut try_cols = |effect: &'static str,
                            name: &'static str,
                            cols: Vec<Vec<f64>>,
                            params: &dyn Fn(&Ls) -> Vec<Param>,
                            loc: String| {
            tests += 1;
            let m = with_extra(&model, name, cols.clone());
            if let Some(big) = d.fit(&m, &[]) {
                let p = nested_p(&current, &big, cols.len());
                cands.push(Candidate {
                    effect,
                    p,
                    parameters: params(&big),
                    model: m,
                    location: loc,
                });
            }
        };
        let tau = d.tau();
        let half_t =
            (d.t.iter().cloned().fold(f64::MIN, f64::max) - d.t.iter().cloned().fold(f64::MAX, f64::min)) / 2.0;
        if !done("bias_drift") {
            let np = 3 + model.extra.len();
            try_cols(
                "bias_drift",
                "drift",
                vec![tau.clone()],
                &|l: &Ls| vec![param("rate_dph_per_s", l.coef[np] / half_t, Some(l.sigma(np) / half_t))],
                "grows with time over the run".into(),
            );
            try_cols(
                "bias_drift",
                "drift",
                vec![tau.clone(), tau.iter().map(|v| v * v).collect()],
                &|l: &Ls| {
                    vec![
                        param("rate_dph_per_s", l.coef[np] / half_t, Some(l.sigma(np) / half_t)),
                        param(
                            "rate_dph_per_s2",
                            l.coef[np + 1] / (half_t * half_t),
                            Some(l.sigma(np + 1) / (half_t * half_t)),
                        ),
                    ]
                },
                "curves with time over the run".into(),
            );
        }
        if !done("thermal_drift")
            && let Some(temp) = &d.temp
        {
            let m = temp.iter().sum::<f64>() / n as f64;
            let dt: Vec<f64> = temp.iter().map(|v| v - m).collect();
            if dt.iter().any(|v| v.abs() > 1e-6) {
                let np = 3 + model.extra.len();
                try_cols(
                    "thermal_drift",
                    "thermal",
                    vec![dt],
                    &|l: &Ls| vec![param("dph_per_degc", l.coef[np], Some(l.sigma(np)))],
                    "follows the recorded temperature".into(),
                );
            }
        }
        if !done("encoder_error") {
            // The rate at the true angle gamma + e(gamma): -R sin(gamma + psi) e(gamma), linearised.
            let slope: Vec<f64> = d
                .gamma
                .iter()
                .map(|g| -amp * (g + s.azimuth_deg).to_radians().sin())
                .collect();
            for k in [1u32, 2, 3] {
                let np = 3 + model.extra.len();
                let cols = vec![
                    slope
                        .iter()
                        .zip(&d.gamma)
                        .map(|(sl, g)| sl * (k as f64 * g).to_radians().cos())
                        .collect(),
                    slope
                        .iter()
                        .zip(&d.gamma)
                        .map(|(sl, g)| sl * (k as f64 * g).to_radians().sin())
                        .collect(),
                ];
                let shows = match k {
                    1 => "the second harmonic of the residuals (no azimuth bias)".to_string(),
                    2 => "the third harmonic of the residuals; it biases the azimuth".to_string(),
                    _ => format!("harmonics {} and {} of the residuals", k - 1, k + 1),
                };
                try_cols(
                    "encoder_error",
                    "encoder",
                    cols,
                    &move |l: &Ls| {
                        let (a, b) = (l.coef[np], l.coef[np + 1]);
                        let amp = a.hypot(b).to_degrees() * 3600.0;
                        vec![
                            param("harmonic", k as f64, None),
                            param("amplitude_arcsec", amp, Some(l.sigma(np).to_degrees() * 3600.0)),
                            param("phase_deg", atan2_deg(a, b), None),
                        ]
                    },
                    shows,
                );
            }
        }
        if !done("nonlinearity") {
            let np = 3 + model.extra.len();
            let col: Vec<f64> = d
                .gamma
                .iter()
                .map(|g| (2.0 * (g + s.azimuth_deg)).to_radians().cos())
                .collect();
            try_cols(
                "nonlinearity",
                "nonlinearity",
                vec![col],
                // k2 R^2 / 2 is the amplitude of cos(2 (gamma + psi)).
                &|l: &Ls| {
                    vec![param(
                        "k2_per_dph",
                        2.0 * l.coef[np] / (amp * amp),
                        Some(2.0 * l.sigma(np) / (amp * amp)),
                    )]
                },
                "a second harmonic locked to 2 psi".into(),
            );
        }
        // Bias jump: a step between two positions, scanned over the visiting order.
        if !done("bias_jump") && n >= 10 {
            tests += 1;
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by(|&a, &b| d.t[a].total_cmp(&d.t[b]));
            let mut best: Option<(f64, usize, Ls)> = None;
            for (j, &oj) in order.iter().enumerate().take(n - 2).skip(2) {
                let at = d.t[oj];
                let col: Vec<f64> = d.t.iter().map(|&t| if t >= at { 1.0 } else { 0.0 }).collect();
                if let Some(big) = d.fit(&model, &[col]) {
                    let p = nested_p(&current, &big, 1);
                    if best.as_ref().is_none_or(|b| p < b.0) {
                        best = Some((p, j, big));
                    }
                }
            }
            if let Some((p, j, big)) = best {
                let at = d.t[order[j]];
                let np = big.coef.len() - 1;
                let col: Vec<f64> = d.t.iter().map(|&t| if t >= at { 1.0 } else { 0.0 }).collect();
                cands.push(Candidate {
                    effect: "bias_jump",
                    p: (p * (n - 4) as f64).min(1.0),
                    model: with_extra(&model, "jump", vec![col]),
                    parameters: vec![
                        param("size_dph", big.coef[np], Some(big.sigma(np))),
                        param("time_s", (d.t[order[j - 1]] + at) / 2.0, None),
                        param("first_index_after", rec.rows[order[j]].index as f64, None),
                    ],
                    location: format!(
                        "between t = {:.1} s and {:.1} s (before position {})",
                        d.t[order[j - 1]],
                        at,
                        rec.rows[order[j]].index
                    ),
                });
            }
        }
        // Outliers: the largest externally studentised residual, Bonferroni over positions.
        if current.dof > 2 {
            tests += 1;
            let s2 = current.s2();
            let dof = current.dof as f64;
            let (i, t) = (0..n)
                .map(|i| {
                    let h = current.hat[i].min(1.0 - 1e-12);
                    let r = current.resid[i];
                    let s2i = (s2 * dof - r * r / (1.0 - h)) / (dof - 1.0);
                    (i, r / (s2i.max(1e-300) * (1.0 - h)).sqrt())
                })
                .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
                .unwrap_or((0, 0.0));
            let p = (t_sf2(t, dof - 1.0) * n as f64).min(1.0);
            let col: Vec<f64> = (0..n).map(|k| if k == i { 1.0 } else { 0.0 }).collect();
            cands.push(Candidate {
                effect: "outliers",
                p,
                model: with_extra(&model, "outlier", vec![col]),
                parameters: vec![
                    param("index", rec.rows[i].index as f64, None),
                    param("size_dph", current.resid[i] / (1.0 - current.hat[i]), None),
                ],
                location: format!(
                    "position {} (line {}, gamma {:.2} deg)",
                    rec.rows[i].index, rec.rows[i].line, d.gamma[i]
                ),
            });
        }
        // Settling transient: the first quarter of each dwell against the other three.
        if !done("settling_transient")
            && let Some(q) = &d.quarters
        {
            tests += 1;
            let (p, params, y) = settling(q, n);
            let mut m = model.clone();
            // The dwell means without the first quarter, with the corrections of the model kept.
            m.y = model
                .y
                .iter()
                .zip(&d.rate)
                .zip(&y)
                .map(|((my, r), yy)| my - r + yy)
                .collect();
            cands.push(Candidate {
                effect: "settling_transient",
                p: (p * 2.0).min(1.0),
                model: m,
                parameters: params,
                location: "the first quarter of each dwell".into(),
            });
        }
        // Scale factor: the amplitude against the latitude's prediction; the residuals do not change.
        if !done("scale_factor") {
            tests += 1;
            let (a, b) = (current.coef[1], current.coef[2]);
            let v = current.s2()
                * (a * a * current.cov_unit[1][1]
                    + b * b * current.cov_unit[2][2]
                    + 2.0 * a * b * current.cov_unit[1][2])
                / (a * a + b * b);
            let pred = EARTH_RATE_DPH * d.lat.to_radians().cos();
            let z = (amp - pred) / v.sqrt();
            cands.push(Candidate {
                effect: "scale_factor",
                // The variance comes from the residuals: Student's t, not the normal tail.
                p: t_sf2(z, current.dof as f64),
                model: model.clone(),
                parameters: vec![
                    param("scale", amp / pred, Some(v.sqrt() / pred)),
                    param("amplitude_dph", amp, Some(v.sqrt())),
                ],
                location: format!("the first-harmonic amplitude, {amp:.5} deg/h against {pred:.5} predicted"),
            });
        }
        // Each candidate test is judged at alpha / tests (the first step's family includes the tilt).
        let family = tests + (steps == 1 && tilt_tested) as usize;
        debug_assert!(steps > 1 || family <= FIRST_STEP_TESTS);
        let limit = alpha / family.max(1) as f64;
        cands.retain(|c| c.p < limit);
        // The amplitude is judged on the complete model: a left-out drift or jump also moves
        // it. So the scale factor stands only when nothing else is significant.
        if cands.iter().any(|c| c.effect != "scale_factor") {
            cands.retain(|c| c.effect != "scale_factor");
        }
        if cands.is_empty() {
            break;
        }
        cands.sort_by(|a, b| a.p.total_cmp(&b.p));
        indistinguishable(&cands, &d, &mut notes);
        // Only the two forms of one effect can both stand: keep the best.
        let c = cands.swap_remove(0);
        let effect = c.effect;
        model = c.model.clone();
        current = d.fit(&model, &[]).ok_or("the extended model does not fit")?;
        let p = c.p;
        // Further outliers join the first finding of them.
        if effect == "outliers"
            && let Some(f) = findings.iter_mut().find(|f| f.effect == "outliers")
        {
            f.parameters.extend(c.parameters);
            f.location = format!("{}; {}", f.location, c.location);
            let s = summary(&current);
            (f.rss_after, f.azimuth_deg_after, f.sigma_arcsec_after) = (s.rss, s.azimuth_deg, s.sigma_arcsec);
            continue;
        }
        push(&mut findings, c, p, &current);
    }
    if findings.iter().any(|f| f.effect == "scale_factor") {
        notes.push(
            "scale_factor: an amplitude off the latitude's prediction is also what a wrong latitude_deg would give"
                .into(),
        );
    }
    if findings.iter().any(|f| f.effect == "encoder_error") {
        notes.push("encoder_error: a genuine third (or second) harmonic of the gyro output would look the same in this recording alone; a second run with the encoder turned against the gyro tells them apart".into());
    }
    let final_ = summary(&current);
    Ok(Diagnosis {
        alpha,
        baseline,
        findings,
        final_,
        notes,
        residuals_before,
        residuals_after: d.gamma.iter().copied().zip(current.resid.iter().copied()).collect(),
    })
}

fn push(findings: &mut Vec<Finding>, c: Candidate, p: f64, after: &Ls) {
    let s = summary(after);
    findings.push(Finding {
        effect: c.effect,
        parameters: c.parameters,
        p_value: p,
        location: c.location,
        rss_after: s.rss,
        azimuth_deg_after: s.azimuth_deg,
        sigma_arcsec_after: s.sigma_arcsec,
    });
}

/// Notes for pairs of significant candidates that explain the same signature.
fn indistinguishable(cands: &[Candidate], d: &Data, notes: &mut Vec<String>) {
    let has = |e: &str| cands.iter().any(|c| c.effect == e);
    let mut note = |s: String| {
        if !notes.contains(&s) {
            notes.push(s);
        }
    };
    if has("bias_drift")
        && has("thermal_drift")
        && let Some(temp) = &d.temp
    {
        let r = corr(temp, &d.t);
        if r.abs() > 0.95 {
            note(format!(
                "bias_drift and thermal_drift cannot be told apart: the temperature follows time (r = {r:.3})"
            ));
        }
    }
    let second = cands
        .iter()
        .any(|c| c.effect == "encoder_error" && c.parameters.first().is_some_and(|p| p.value == 1.0));
    if has("nonlinearity") && second {
        note("nonlinearity and encoder eccentricity (encoder_error, harmonic 1) both make a second harmonic: with psi fixed they differ only in its phase".into());
    }
    if has("bias_jump") && has("bias_drift") {
        note("bias_jump and bias_drift both move the bias with time: the step fits better where one is named".into());
    }
}

/// The tilt correction by `nf fit`'s path, and the test of the inclinometer's circle against
/// constant readings (X and Y together with both columns, X alone otherwise).
fn shaft_tilt(d: &Data, rec: &Recording) -> Result<Option<(Candidate, f64)>, String> {
    let method = tilt::auto_method(rec);
    if method == TiltMethod::None {
        return Ok(None);
    }
    let t = tilt::correct(rec, method, |corr| {
        let m = Model {
            extra: Vec::new(),
            y: d.rate.iter().zip(corr).map(|(r, c)| r - c).collect(),
        };
        let f = d
            .fit(&m, &[])
            .ok_or("the positions do not determine A cos + B sin + C")?;
        Ok((summary(&f).azimuth_deg, f.coef[1].hypot(f.coef[2])))
    })?;
    let axes: Vec<Vec<(f64, f64)>> = match method {
        TiltMethod::Exact => vec![
            rec.rows
                .iter()
                .filter_map(|r| Some((r.encoder_deg, r.tilt_x_deg?)))
                .collect(),
            rec.rows
                .iter()
                .filter_map(|r| Some((r.encoder_deg, r.tilt_y_deg?)))
                .collect(),
        ],
        _ => vec![
            rec.rows
                .iter()
                .filter_map(|r| Some((r.encoder_deg, r.tilt_x_deg?)))
                .collect(),
        ],
    };
    let p = circle_p(&axes);
    let model = Model {
        extra: Vec::new(),
        y: d.rate.iter().zip(&t.corrections).map(|(r, c)| r - c).collect(),
    };
    let mut parameters = Vec::new();
    if let Some(s) = t.shaft {
        let sigma_tilt = s.rms_deg * (2.0 / (rec.rows.len() - t.bridged) as f64).sqrt();
        parameters.extend([
            param("tilt_deg", s.tilt_deg, Some(sigma_tilt)),
            param("tilt_dir_deg", s.tilt_dir_deg, None),
            param("offset_x_deg", s.offset_x_deg, None),
            param("offset_y_deg", s.offset_y_deg, None),
        ]);
    }
    Ok(Some((
        Candidate {
            effect: "shaft_tilt",
            p,
            model,
            parameters,
            location: format!(
                "the inclinometer's tilt circle ({}; {} positions bridged); a first harmonic of the gyro, invisible in its residuals",
                method.name(),
                t.bridged
            ),
        },
        p,
    )))
}

/// F-test of a circle `C + A cos + B sin` in every axis against constant readings.
fn circle_p(axes: &[Vec<(f64, f64)>]) -> f64 {
    let (mut rss0, mut rss1, mut dof) = (0.0, 0.0, 0usize);
    for axis in axes {
        let n = axis.len();
        let cols = vec![
            vec![1.0; n],
            axis.iter().map(|(g, _)| g.to_radians().cos()).collect(),
            axis.iter().map(|(g, _)| g.to_radians().sin()).collect(),
        ];
        let y: Vec<f64> = axis.iter().map(|(_, v)| *v).collect();
        let Some(ls) = linfit::fit(&cols, &y) else { return 1.0 };
        let mean = y.iter().sum::<f64>() / n as f64;
        rss0 += y.iter().map(|v| (v - mean).powi(2)).sum::<f64>();
        rss1 += ls.rss;
        dof += n.saturating_sub(3);
    }
    let q = 2.0 * axes.len() as f64;
    if dof == 0 {
        return 1.0;
    }
    let f = ((rss0 - rss1) / q) / (rss1 / dof as f64).max(1e-300);
    f_sf(f, q, dof as f64)
}

/// Test of the first quarters against the other three: their mean offset (t test) and their
/// scatter (F test against the scatter within quarters 2-4), the smaller p-value doubled by
/// the caller. Returns the dwell means without the first quarter too.
fn settling(q: &[[f64; 4]], n: usize) -> (f64, Vec<Param>, Vec<f64>) {
    let rest: Vec<f64> = q.iter().map(|q| (q[1] + q[2] + q[3]) / 3.0).collect();
    let dq: Vec<f64> = q.iter().zip(&rest).map(|(q, r)| q[0] - r).collect();
    // Scatter of one quarter mean from quarters 2-4 (2 dof per position).
    let s2q: f64 = q
        .iter()
        .zip(&rest)
        .map(|(q, r)| (1..4).map(|k| (q[k] - r).powi(2)).sum::<f64>())
        .sum::<f64>()
        / (2 * n) as f64;
    let var_d = s2q * (1.0 + 1.0 / 3.0);
    let mean = dq.iter().sum::<f64>() / n as f64;
    let t = mean / (var_d / n as f64).sqrt();
    let p_mean = t_sf2(t, (2 * n) as f64);
    let f = dq.iter().map(|v| v * v).sum::<f64>() / n as f64 / var_d;
    let p_var = f_sf(f, n as f64, (2 * n) as f64);
    let rms = (dq.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
    (
        p_mean.min(p_var),
        vec![
            param("first_quarter_offset_dph", mean, Some((var_d / n as f64).sqrt())),
            param("first_quarter_rms_dph", rms, None),
        ],
        rest,
    )
}
