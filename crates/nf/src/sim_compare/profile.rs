//! What a recording and a simulation are compared by: the numbers of its Eq. 7 fit, its
//! harmonics, its noise at several time scales and its inclinometer. (The temperature is not
//! compared: a replay follows the recording's.)

use crate::allan;
use crate::linfit;
use crate::recording::Recording;
use crate::stats::chi2_quantile;
use nf_model::angle::atan2_deg;
use std::fmt;

/// One quantity of a profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Quantity {
    /// Eq. 7's amplitude sqrt(A^2 + B^2), deg/h.
    Amplitude,
    /// Eq. 7's constant C, deg/h.
    Bias,
    /// Eq. 7's psi, deg.
    Azimuth,
    /// Amplitude of harmonic k of the rates, deg/h.
    Harmonic(u8),
    /// Scatter left by Eq. 7 and harmonics 2 to 4, deg/h.
    ResidualSd,
    /// Allan deviation of those residuals in time order over m positions (1, 2, 4, ...), deg/h.
    Allan(u32),
    /// Scatter of a quarter mean about its dwell's mean, deg/h.
    QuarterSd,
    /// Mean spread of the samples in a dwell, deg/h.
    SampleSd,
    /// Excess kurtosis of the samples, as the spread of the dwells' sample variances shows it
    /// (heavy-tailed samples, a ring-laser gyro's dither say, scatter them beyond the
    /// `2 / (m - 1)` of Gaussian ones).
    SampleKurtosis,
    /// First harmonic of the X inclinometer (the shaft tilt), deg.
    TiltCircle,
    /// Mean of the X inclinometer (its offset), deg.
    TiltOffset,
    /// Mean of the Y inclinometer (its offset), deg.
    TiltOffsetY,
}

impl Quantity {
    /// The noise's scatters (the residual's, the Allan deviations, the quarters' and the
    /// samples'): what the fix's noise acts on. Judged on the log scale: they are positive
    /// and spread by a factor, and a replay that met a long burst scatters far more than the
    /// rest (shocks only the simulation had: the replays' residual sd 0.020 +- 0.005 deg/h
    /// against the recording's 0.0046, z -2.9 on the linear scale and no mismatch).
    pub fn is_scatter(self) -> bool {
        matches!(
            self,
            Quantity::ResidualSd | Quantity::Allan(_) | Quantity::QuarterSd | Quantity::SampleSd
        )
    }

    /// Quantities that are angles and wrap.
    pub fn wraps(self) -> bool {
        self == Quantity::Azimuth
    }

    /// The smallest difference that counts, for a simulation without noise in it.
    pub fn resolution(self) -> f64 {
        match self {
            Quantity::TiltCircle | Quantity::TiltOffset | Quantity::TiltOffsetY => 1e-6,
            Quantity::Azimuth => 1e-7,
            _ => 1e-9,
        }
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Quantity::Amplitude => write!(f, "amplitude_dph"),
            Quantity::Bias => write!(f, "bias_dph"),
            Quantity::Azimuth => write!(f, "azimuth_deg"),
            Quantity::Harmonic(k) => write!(f, "harmonic_{k}_dph"),
            Quantity::ResidualSd => write!(f, "residual_sd_dph"),
            Quantity::Allan(m) => write!(f, "allan_{m}_positions_dph"),
            Quantity::QuarterSd => write!(f, "quarter_sd_dph"),
            Quantity::SampleSd => write!(f, "sample_sd_dph"),
            Quantity::SampleKurtosis => write!(f, "sample_excess_kurtosis"),
            Quantity::TiltCircle => write!(f, "tilt_circle_deg"),
            Quantity::TiltOffset => write!(f, "tilt_offset_x_deg"),
            Quantity::TiltOffsetY => write!(f, "tilt_offset_y_deg"),
        }
    }
}

/// Harmonics of the angle beyond Eq. 7 that a profile measures.
const HARMONICS: [u8; 3] = [2, 3, 4];

/// The quantities of one recording, in the order of `Quantity`.
pub type Profile = Vec<(Quantity, f64)>;

fn harmonic_cols(gamma: &[f64], k: u8) -> [Vec<f64>; 2] {
    let arg = |g: &f64| (k as f64 * g).to_radians();
    [
        gamma.iter().map(|g| arg(g).cos()).collect(),
        gamma.iter().map(|g| arg(g).sin()).collect(),
    ]
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len().max(1) as f64
}

/// First-harmonic amplitude and mean of `(gamma, v)`.
fn circle(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let g: Vec<f64> = points.iter().map(|p| p.0).collect();
    let v: Vec<f64> = points.iter().map(|p| p.1).collect();
    let [c, s] = harmonic_cols(&g, 1);
    let f = linfit::fit(&[c, s, vec![1.0; g.len()]], &v)?;
    Some((f.coef[0].hypot(f.coef[1]), f.coef[2]))
}

/// The pooled scatter of each dwell's quarter means about their mean, leaving out a dwell whose
/// quarters scatter beyond what white noise gives one in a thousand runs: a burst within a
/// dwell shifts its quarters unevenly (an outlier, not the white level), and one such dwell
/// of 72 raised the pooled scatter by 8 %.
fn quarter_sd(quarters: &[[f64; 4]]) -> Option<f64> {
    // Each dwell's quarter variance: a chi-square of 3 dof times the white variance.
    let v: Vec<f64> = quarters
        .iter()
        .map(|q| {
            let m = mean(q);
            q.iter().map(|x| (x - m).powi(2)).sum::<f64>() / 3.0
        })
        .collect();
    if v.is_empty() {
        return None;
    }
    let mut sorted = v.clone();
    sorted.sort_by(f64::total_cmp);
    // The median of a chi-square of 3 dof over 3.
    let scale = sorted[sorted.len() / 2] / (chi2_quantile(0.5, 3.0) / 3.0);
    let bound = scale * chi2_quantile(1.0 - 1e-3 / v.len() as f64, 3.0) / 3.0;
    let kept: Vec<f64> = v.into_iter().filter(|x| *x <= bound).collect();
    Some(mean(&kept).sqrt())
}

/// The samples' excess kurtosis from each dwell's sample sd and count `(s, m)`: a sample
/// variance of `m` values has variance `sigma^4 (2 / (m - 1) + kurtosis / m)`. `None` under
/// eight dwells of four samples or more.
fn excess_kurtosis(spreads: &[(f64, f64)]) -> Option<f64> {
    let v: Vec<(f64, f64)> = spreads
        .iter()
        .filter(|(s, m)| *m >= 4.0 && s.is_finite())
        .map(|(s, m)| (s * s, *m))
        .collect();
    if v.len() < 8 {
        return None;
    }
    let mu = v.iter().map(|x| x.0).sum::<f64>() / v.len() as f64;
    (mu > 0.0).then(|| {
        mean(
            &v.iter()
                .map(|(s2, m)| m * ((s2 / mu - 1.0).powi(2) - 2.0 / (m - 1.0)))
                .collect::<Vec<_>>(),
        )
    })
}

/// The profile of `rec`; `None` when its positions do not determine the fit.
pub fn profile(rec: &Recording) -> Option<Profile> {
    let mut rows: Vec<_> = rec.rows.iter().collect();
    rows.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    let gamma: Vec<f64> = rows.iter().map(|r| r.encoder_deg).collect();
    let t: Vec<f64> = rows.iter().map(|r| r.t_s).collect();
    let y: Vec<f64> = rows.iter().map(|r| r.rate_dph).collect();
    let [c1, s1] = harmonic_cols(&gamma, 1);
    let mut cols = vec![c1, s1, vec![1.0; y.len()]];
    for k in HARMONICS {
        cols.extend(harmonic_cols(&gamma, k));
    }
    let f = linfit::fit(&cols, &y)?;
    let mut p: Profile = vec![
        (Quantity::Amplitude, f.coef[0].hypot(f.coef[1])),
        (Quantity::Bias, f.coef[2]),
        // rate = A cos g + B sin g = R cos(g + psi): A = R cos psi, B = -R sin psi.
        (Quantity::Azimuth, atan2_deg(-f.coef[1], f.coef[0]).rem_euclid(360.0)),
    ];
    for (i, k) in HARMONICS.iter().enumerate() {
        p.push((Quantity::Harmonic(*k), f.coef[3 + 2 * i].hypot(f.coef[4 + 2 * i])));
    }
    p.push((Quantity::ResidualSd, f.s2().sqrt()));
    let step = if t.len() > 1 {
        (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64
    } else {
        1.0
    };
    for pt in allan::oavar(&[&f.resid], step, &allan::octaves(f.resid.len())) {
        if pt.avar.is_finite() {
            p.push((Quantity::Allan(pt.m as u32), pt.avar.sqrt()));
        }
    }
    let quarters: Vec<[f64; 4]> = rows.iter().filter_map(|r| r.quarters_dph).collect();
    if let Some(sd) = quarter_sd(&quarters) {
        p.push((Quantity::QuarterSd, sd));
    }
    let sds: Vec<f64> = rows.iter().filter_map(|r| r.rate_sd_dph).collect();
    if !sds.is_empty() {
        p.push((Quantity::SampleSd, mean(&sds)));
    }
    let spreads: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| Some((r.rate_sd_dph?, f64::from(r.samples?))))
        .collect();
    if let Some(k) = excess_kurtosis(&spreads) {
        p.push((Quantity::SampleKurtosis, k));
    }
    let read = |axis: fn(&crate::recording::Row) -> Option<f64>| {
        let tilt: Vec<(f64, f64)> = rows.iter().filter_map(|r| Some((r.encoder_deg, axis(r)?))).collect();
        (tilt.len() >= 4).then(|| circle(&tilt)).flatten()
    };
    if let Some((amp, offset)) = read(|r| r.tilt_x_deg) {
        p.push((Quantity::TiltCircle, amp));
        p.push((Quantity::TiltOffset, offset));
    }
    // The Y axis reads the same circle a quarter turn on: only its offset is its own.
    if let Some((_, offset)) = read(|r| r.tilt_y_deg) {
        p.push((Quantity::TiltOffsetY, offset));
    }
    Some(p)
}
