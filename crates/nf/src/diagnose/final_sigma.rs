//! The final azimuth's sigma under the noise. The tests' noise is estimated with harmonics
//! 2-4 and the temperature in its design, so that they are not taken for noise; in a sweep
//! those harmonics are where a random walk shows most, and the final model, which has not
//! got them, would be given too little wander. So the final sigma comes from the noise
//! estimated under the final model's own columns, averaged over the flicker-and-walk models
//! it allows, and scaled by replicates drawn from its supported model (as `nf fit` does).
//! On 1000 clean random-walk recordings of the suite the finals beyond 3 sigma went from 37
//! to 17 (docs/diagnose.md, item 5).

use super::data::Data;
use super::noise::{dwell_and_quarters, plausible_candidates, with_bursts_held_out};
use crate::noise_calib::{self, Calibration, Verdict};
use crate::noise_est::{self, Colours, THINNED};
use crate::noise_fit::azimuth;
use nf_model::angle::wrap_180;

/// The sigma of the final model's azimuth and amplitude, and the calibration behind it.
pub struct FinalSigma {
    pub verdict: Verdict,
    /// `None` when the supported model is white (its replicates would not scale it).
    pub calibration: Option<Calibration>,
}

impl FinalSigma {
    /// Where the final sigma under the noise came from, for the report.
    pub fn describe(&self) -> String {
        let scaled = self.calibration.map_or(String::new(), |c| {
            format!(
                ", scaled by {:.2} as {} replicates drawn from it showed",
                c.psi, c.replicates
            )
        });
        format!("under the noise estimated with the final model's columns{scaled}")
    }
}

/// The sigma of a fit of `y` to `cols` (Eq. 7's columns first) under the noise estimated
/// with them. `None` when the noise was thinned for its estimate (it is then known well) or
/// cannot be estimated.
pub fn final_sigma(d: &Data, cols: &[Vec<f64>], y: &[f64], replicates: usize) -> Option<FinalSigma> {
    if d.n() > THINNED {
        return None;
    }
    let design = with_bursts_held_out(d, cols, y);
    let (dwell_s, quarters) = dwell_and_quarters(d);
    let data = noise_est::Data {
        t_s: &d.t,
        dwell_s,
        cols: &design,
        y,
        quarters: &quarters,
        extra: None,
    };
    let e = noise_est::estimate(data.clone(), Colours::FlickerAndWalk)?;
    let verdict = averaged(&e)?;
    let (supported, _) = e.supported();
    let calibration = if supported.model.is_coloured() {
        let truth = azimuth(&supported.coef, &supported.cov);
        let judge = |r: noise_est::Data<'_>| noise_est::estimate(r, Colours::FlickerAndWalk).and_then(|e| averaged(&e));
        noise_calib::calibrate(&data, &supported.model, &supported.coef, &truth, replicates, judge)
    } else {
        None
    };
    Some(FinalSigma {
        verdict: verdict.calibrated(calibration),
        calibration,
    })
}

/// The azimuth and amplitude averaged over the plausible models by their likelihood, each
/// variance the mean of theirs plus the spread between them.
fn averaged(e: &noise_est::Estimate) -> Option<Verdict> {
    let fits: Vec<(f64, Verdict)> = plausible_candidates(e)
        .into_iter()
        .map(|(w, c)| (w, azimuth(&c.coef, &c.cov)))
        .collect();
    let first = fits.first()?.1;
    let mean = |f: &dyn Fn(&Verdict) -> f64| fits.iter().map(|(w, v)| w * f(v)).sum::<f64>();
    let shift = mean(&|v| wrap_180(v.psi_deg - first.psi_deg));
    let amplitude = mean(&|v| v.amplitude_dph);
    let var_psi = mean(&|v| v.sigma_psi_deg.powi(2) + (wrap_180(v.psi_deg - first.psi_deg) - shift).powi(2));
    let var_amp = mean(&|v| v.sigma_amplitude_dph.powi(2) + (v.amplitude_dph - amplitude).powi(2));
    Some(Verdict {
        psi_deg: first.psi_deg + shift,
        sigma_psi_deg: var_psi.sqrt(),
        amplitude_dph: amplitude,
        sigma_amplitude_dph: var_amp.sqrt(),
    })
}
