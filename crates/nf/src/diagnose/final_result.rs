//! The final azimuth and its sigma, and the baseline's sigma beside it: from the models the
//! selection met, each weighed and fitted under its own noise, or through shocks, or (the
//! noise given, or thinned) averaged over the noise models the recording allows; then
//! carried through the tilt correction.

use super::Options;
use super::averaging::{self, Weighted};
use super::data::Data;
use super::final_shocks::FinalShocks;
use super::final_sigma::{self, FinalSigma};
use super::model::{Model, Summary, summary};
use super::noise;
use super::select::Selection;
use crate::noise_calib;
use crate::noise_fit::NoiseChoice;
use crate::tilt::Sensitivity;

/// What the tilt correction adds to the azimuth's sigma.
pub(super) struct TiltShare {
    /// The tilt circle's own uncertainty, measured apart from the gyro.
    pub sigma_arcsec: f64,
    /// How the exact correction carries the fit's sigmas.
    pub sensitivity: Sensitivity,
}

pub(super) struct Final {
    pub summary: Summary,
    /// Each model met weighed and fitted under its own noise, where it was.
    pub own: Option<FinalSigma>,
    pub models: Vec<Weighted>,
    /// The baseline's sigma as the final's is taken, where the noise was estimated.
    pub baseline_sigma_arcsec: Option<f64>,
    pub unresolved: Option<String>,
}

impl Final {
    pub(super) fn new(
        d: &Data,
        sel: &Selection,
        noise: &noise::Noise,
        (averaged, models): (Summary, Vec<Weighted>),
        shocks: Option<&FinalShocks>,
        tilt: TiltShare,
        opt: &Options,
    ) -> Final {
        // Through shocks the result is the shocks' fit's; else each model met is weighed and
        // fitted under the noise estimated with its own columns.
        let own = match (&opt.noise, shocks) {
            (NoiseChoice::Estimate, None) => {
                let met: Vec<final_sigma::Met> = sel
                    .variants
                    .iter()
                    .map(|v| final_sigma::Met {
                        cols: v.model.raw_cols(),
                        y: &v.model.y,
                        scanned: v.scanned,
                    })
                    .collect();
                final_sigma::final_verdict(d, &met, opt.replicates)
            }
            _ => None,
        };
        let models = match &own {
            Some(o) => averaging::under_own_noise(&sel.variants, &o.models),
            None => models,
        };
        let mut final_ = noise_averaged(
            averaged,
            &sel.model,
            summary(&sel.model, &sel.fit),
            noise,
            own.as_ref(),
            shocks.map(|s| &s.through.verdict),
        );
        let baseline_sigma_arcsec = baseline_sigma(d, sel, own.as_ref(), shocks, opt);
        let s2 = sel.fit.s2();
        let cov: Vec<Vec<f64>> = sel
            .fit
            .cov_unit
            .iter()
            .map(|r| r.iter().map(|c| c * s2).collect())
            .collect();
        let amp = crate::noise_fit::azimuth(&sel.fit.coef, &cov);
        let sigma_amplitude = match (shocks, &own) {
            (Some(s), _) => s.through.verdict.sigma_amplitude_dph,
            (None, Some(o)) => o.verdict.sigma_amplitude_dph,
            (None, None) => amp.sigma_amplitude_dph,
        };
        let (carried, sigma_amplitude) = tilt.sensitivity.carried(final_.sigma_arcsec / 3600.0, sigma_amplitude);
        // The tilt circle is measured apart from the gyro: its uncertainty adds.
        final_.sigma_arcsec = (carried * 3600.0).hypot(tilt.sigma_arcsec);
        let unresolved = crate::noise_fit::unresolved(
            final_.sigma_arcsec / 3600.0,
            amp.amplitude_dph,
            sigma_amplitude,
            nf_model::uncertainty::amplitude_dph(d.rec.latitude_deg),
        );
        Final {
            summary: final_,
            own,
            models,
            baseline_sigma_arcsec,
            unresolved,
        }
    }
}

/// The baseline's sigma as the final's is taken (`nf fit --tilt none`'s way): under the
/// noise estimated with its own columns, over the models the recording allows, calibrated.
/// Its plain GLS sigma under the tests' noise was up to 5 times smaller than `nf fit`'s on
/// Gauss-Markov recordings, which made a finding look far from it.
fn baseline_sigma(
    d: &Data,
    sel: &Selection,
    own: Option<&FinalSigma>,
    shocks: Option<&FinalShocks>,
    opt: &Options,
) -> Option<f64> {
    match (&opt.noise, shocks) {
        (NoiseChoice::Estimate, None) if sel.variants.len() == 1 && sel.model.y == d.rate => {
            own.map(|o| o.verdict.sigma_psi_deg * 3600.0)
        }
        (NoiseChoice::Estimate, None) => {
            let base = final_sigma::Met {
                cols: d.base_cols(),
                y: &d.rate,
                scanned: 0,
            };
            final_sigma::final_verdict(d, &[base], opt.replicates).map(|o| o.verdict.sigma_psi_deg * 3600.0)
        }
        _ => None,
    }
}

/// The result. Where each model met was weighed and fitted under its own noise (`own`),
/// theirs. Through shocks, the selected model's azimuth and sigma are those of its fit
/// through them (as `nf fit`'s). Else (the noise given, or thinned) the averaged result with
/// the noise model's own uncertainty added: the selected model is fitted under every noise
/// model the recording allows and averaged by their likelihoods, and the spread the model
/// averaging added is kept on top.
fn noise_averaged(
    averaged: Summary,
    selected: &Model,
    main: Summary,
    noise: &noise::Noise,
    own: Option<&final_sigma::FinalSigma>,
    shocks: Option<&noise_calib::Verdict>,
) -> Summary {
    if let Some(o) = own {
        return Summary {
            azimuth_deg: nf_model::angle::wrap_360(o.verdict.psi_deg),
            sigma_arcsec: o.verdict.sigma_psi_deg * 3600.0,
            ..averaged
        };
    }
    let model_spread = (averaged.sigma_arcsec.powi(2) - main.sigma_arcsec.powi(2)).max(0.0);
    if let Some(v) = shocks {
        let moved = nf_model::angle::wrap_180(v.psi_deg - main.azimuth_deg);
        return Summary {
            azimuth_deg: nf_model::angle::wrap_360(averaged.azimuth_deg + moved),
            sigma_arcsec: ((v.sigma_psi_deg * 3600.0).powi(2) + model_spread).sqrt(),
            ..averaged
        };
    }
    let fits: Vec<(f64, Summary)> = noise
        .plausible
        .iter()
        .filter_map(|(w, m)| {
            let wh = noise.whitening.of(m).ok()?;
            let m = selected.rewhiten(&wh);
            Some((*w, summary(&m, &m.fit()?)))
        })
        .collect();
    let total: f64 = fits.iter().map(|f| f.0).sum();
    if fits.is_empty() || total <= 0.0 {
        return averaged;
    }
    let shift = |s: &Summary| nf_model::angle::wrap_180(s.azimuth_deg - main.azimuth_deg) * 3600.0;
    let mean = fits.iter().map(|(w, s)| w * shift(s)).sum::<f64>() / total;
    // As `nf fit`'s: the most likely model's variance and the models' spread. The weighted
    // mean of their variances let unlikely walks widen a white run of 5000 positions 2.2
    // times (an outside audit; `nf fit` 82.8", diagnose 179.2").
    let likeliest = fits
        .iter()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(0.0, |(_, s)| s.sigma_arcsec);
    let var = likeliest.powi(2) + fits.iter().map(|(w, s)| w * (shift(s) - mean).powi(2)).sum::<f64>() / total;
    Summary {
        azimuth_deg: nf_model::angle::wrap_360(averaged.azimuth_deg + mean / 3600.0),
        sigma_arcsec: (var + model_spread).sqrt(),
        ..averaged
    }
}
