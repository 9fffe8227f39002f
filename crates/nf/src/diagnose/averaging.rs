//! Model uncertainty: the final azimuth averages the models the selection met, weighted by
//! their Bayesian information criterion on the whitened data, and its variance adds the spread
//! between them to their own. A weak finding then moves the azimuth only as far as its
//! evidence goes, and two models that explain the data equally share the result.

use super::kind::Kind;
use super::model::{Model, Summary, summary};
use crate::linfit::Ls;
use crate::noise_calib::Verdict;
use nf_model::angle::{wrap_180, wrap_360};

/// A model the selection met: the chain of named effects, or an alternative to a step.
pub struct Variant {
    pub label: String,
    pub model: Model,
    /// Parameters a scan chose, counted by the criterion beside the columns.
    pub scanned: usize,
    /// The effect named at a step and the rival this model has in its place, if it is one.
    pub rival: Option<(Kind, Kind)>,
}

#[derive(Debug, Clone)]
pub struct Weighted {
    pub label: String,
    pub weight: f64,
    pub summary: Summary,
    /// As the variant's: the effect named and the rival in its place.
    pub rival: Option<(Kind, Kind)>,
}

/// The Bayesian information criterion of a whitened fit with `scanned` parameters a scan
/// chose beside its columns.
pub fn bic(ls: &Ls, scanned: usize) -> f64 {
    let n = ls.resid.len() as f64;
    n * (ls.rss / n).ln() + (ls.coef.len() + scanned) as f64 * n.ln()
}

/// The averaged summary (RSS of the heaviest model) and each model's weight.
pub fn average(variants: &[Variant]) -> Option<(Summary, Vec<Weighted>)> {
    let fits: Vec<(f64, Summary, &Variant)> = variants
        .iter()
        .filter_map(|v| {
            let ls = v.model.fit()?;
            Some((bic(&ls, v.scanned), summary(&v.model, &ls), v))
        })
        .collect();
    let low = fits.iter().map(|f| f.0).fold(f64::MAX, f64::min);
    let total: f64 = fits.iter().map(|f| (-(f.0 - low) / 2.0).exp()).sum();
    let out: Vec<Weighted> = fits
        .iter()
        .map(|(bic, s, v)| Weighted {
            label: v.label.clone(),
            weight: (-(bic - low) / 2.0).exp() / total,
            summary: *s,
            rival: v.rival,
        })
        .collect();
    let top = out.iter().max_by(|a, b| a.weight.total_cmp(&b.weight))?;
    let psi0 = top.summary.azimuth_deg;
    let shift = |w: &Weighted| wrap_180(w.summary.azimuth_deg - psi0);
    let mean: f64 = out.iter().map(|w| w.weight * shift(w)).sum();
    let var: f64 = out
        .iter()
        .map(|w| w.weight * ((w.summary.sigma_arcsec / 3600.0).powi(2) + (shift(w) - mean).powi(2)))
        .sum();
    let s = Summary {
        azimuth_deg: wrap_360(psi0 + mean),
        rss: top.summary.rss,
        sigma_arcsec: var.sqrt() * 3600.0,
    };
    Some((s, out))
}

/// The models met as weighed and fitted under the noise estimated with their own columns
/// (`final_sigma`, in the order of `variants`), with their whitened RSS under the tests' noise.
pub fn under_own_noise(variants: &[Variant], judged: &[Option<(f64, Verdict)>]) -> Vec<Weighted> {
    variants
        .iter()
        .zip(judged)
        .filter_map(|(v, j)| {
            let (weight, verdict) = (*j)?;
            Some(Weighted {
                label: v.label.clone(),
                weight,
                summary: Summary {
                    azimuth_deg: wrap_360(verdict.psi_deg),
                    rss: v.model.fit()?.rss,
                    sigma_arcsec: verdict.sigma_psi_deg * 3600.0,
                },
                rival: v.rival,
            })
        })
        .collect()
}
