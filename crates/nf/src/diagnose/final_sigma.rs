//! The final azimuth and its sigma under the noise, averaged over the models the selection
//! met, each under the noise estimated with its own columns.
//!
//! The tests' noise is estimated with harmonics 2-4 and the temperature in its design, so
//! that they are not taken for noise; in a sweep those harmonics are where a random walk
//! shows most, and a model without them would be given too little wander. So each model's
//! noise is estimated with its own columns, averaged over the flicker-and-walk models it
//! allows. A false effect that takes up the run's wander leaves its own model's noise white
//! and its sigma small; Eq. 7 beside it keeps the wander as noise, and it explains the
//! recording about as well. So the models are weighed by their full likelihood under their
//! own noise (marginal over the noise models, less half a log n per parameter) and the
//! spread between them is in the sigma. The sigmas are scaled by replicates drawn from the
//! most likely model (as `nf fit` does).

use super::data::Data;
use super::noise::{plausible_candidates, short_time, with_bursts_held_out};
use crate::noise_calib::{self, Calibration, Verdict};
use crate::noise_est::{self, Colours, THINNED};
use crate::noise_fit::{self, azimuth};
use crate::student_fit;
use nf_model::angle::wrap_180;

/// One model the selection met: its columns (Eq. 7's first), the rates it explains, and the
/// parameters a scan chose beside its columns.
pub struct Met<'a> {
    pub cols: Vec<Vec<f64>>,
    pub y: &'a [f64],
    pub scanned: usize,
}

/// The final verdict under the noise, and the calibration behind its sigma.
pub struct FinalSigma {
    pub verdict: Verdict,
    /// `None` when the most likely model's noise is white (its replicates would not scale it).
    pub calibration: Option<Calibration>,
    /// The most likely model's residual degrees of freedom, where they alone measured the
    /// noise ([`by_residuals`]).
    pub residual_dof: Option<usize>,
    /// Each model's weight and calibrated verdict, in the order given; `None` where its
    /// noise could not be estimated.
    pub models: Vec<Option<(f64, Verdict)>>,
    /// Whether a Gauss-Markov bias shorter than three dwell spacings was searched beside
    /// flicker and walk (where it shows, as in `nf fit`).
    pub short_markov: bool,
}

impl FinalSigma {
    /// Where the final sigma under the noise came from, for the report.
    pub fn describe(&self) -> String {
        if let Some(dof) = self.residual_dof {
            return format!(
                "white at each model's residual level ({dof} dof at the most likely: too few to tell a colour by, and no quarter means or samples' spread), each sigma widened by Student's t as `nf fit`'s"
            );
        }
        let scaled = self.calibration.map_or(String::new(), |c| {
            format!(
                ", scaled by {:.2} as {} replicates drawn from the most likely showed",
                c.psi, c.replicates
            )
        });
        let models = match self.models.iter().flatten().count() {
            1 => "the model's own columns".to_string(),
            k => format!("each model's own columns ({k} models met, weighed by their evidence)"),
        };
        let markov = if self.short_markov {
            ", a Gauss-Markov bias shorter than three dwell spacings searched beside flicker and walk (it explains the dwell means' scatter far better)"
        } else {
            ""
        };
        format!("under the noise estimated with {models}{markov}{scaled}")
    }
}

/// One model's verdict averaged over its noise models, and its evidence.
struct Judged {
    verdict: Verdict,
    log_evidence: f64,
    estimate: noise_est::Estimate,
}

/// The verdict averaged over `met` under their own noise. `None` when the noise was thinned
/// for its estimate (it is then known well) or cannot be estimated.
pub fn final_verdict(d: &Data, met: &[Met], replicates: usize) -> Option<FinalSigma> {
    if d.n() > THINNED || met.is_empty() {
        return None;
    }
    let short = short_time(d);
    let designs: Vec<Vec<Vec<f64>>> = met.iter().map(|m| with_bursts_held_out(d, &m.cols, m.y)).collect();
    if short.quarters.is_empty() && short.spread.is_empty() && d.n() <= d.base_cols().len() + student_fit::MOST_DOF {
        return by_residuals(d.n(), &designs, met);
    }
    let base = noise_est::Data {
        t_s: &d.t,
        dwell_s: short.dwell_s,
        dwells_s: &short.dwells_s,
        cols: &designs[0],
        y: met[0].y,
        quarters: &short.quarters,
        spread: &short.spread,
        extra: None,
    };
    let data = |k: usize| noise_est::Data {
        cols: &designs[k],
        y: met[k].y,
        ..base.clone()
    };
    // A short Gauss-Markov bias where it shows, as `nf fit` searches it: flicker's reading of
    // it put a wander at the run's frequency in the sigma (480" for an error of 100").
    let markov = noise_fit::fast_markov_shows(&base);
    let colours = if markov {
        Colours::WithFastMarkov
    } else {
        Colours::FlickerAndWalk
    };
    let mut judged: Vec<Option<Judged>> = (0..met.len()).map(|_| None).collect();
    // The models that explain the same rates share their noise models' factors.
    let mut done = vec![false; met.len()];
    for i in 0..met.len() {
        if done[i] {
            continue;
        }
        let group: Vec<usize> = (i..met.len()).filter(|&k| met[k].y == met[i].y).collect();
        let more: Vec<&[Vec<f64>]> = group[1..].iter().map(|&k| designs[k].as_slice()).collect();
        let estimates = noise_est::estimate_all(data(i), &more, colours);
        for (&k, e) in group.iter().zip(estimates) {
            done[k] = true;
            judged[k] = e.and_then(|e| judge(e, designs[k].len() + met[k].scanned, d.n()));
        }
    }
    let top = (0..met.len())
        .filter_map(|k| Some((k, judged[k].as_ref()?.log_evidence)))
        .max_by(|a, b| a.1.total_cmp(&b.1))?
        .0;
    let lead = judged[top].as_ref()?;
    let evidence: Vec<Option<f64>> = judged.iter().map(|j| j.as_ref().map(|j| j.log_evidence)).collect();
    let weights = weights_of(&evidence, lead.log_evidence);
    let (supported, _) = lead.estimate.supported();
    let calibration = if supported.model.is_coloured() {
        let truth = azimuth(&supported.coef, &supported.cov);
        let refit = |r: noise_est::Data<'_>| noise_est::estimate(r, colours).and_then(|e| averaged(&e));
        let lead_data = data(top);
        noise_calib::calibrate(&lead_data, &supported.model, &supported.coef, &truth, replicates, refit)
    } else {
        None
    };
    let kept = merged(&designs, met, &weights);
    let models: Vec<Option<(f64, Verdict)>> = kept
        .iter()
        .zip(&judged)
        .map(|(w, j)| Some(((*w)?, j.as_ref()?.verdict.calibrated(calibration))))
        .collect();
    let weighted: Vec<(f64, Verdict)> = models.iter().flatten().copied().collect();
    Some(FinalSigma {
        verdict: mixed(&weighted, lead.verdict.psi_deg)?,
        calibration,
        residual_dof: None,
        models,
        short_markov: markov,
    })
}

/// A run whose few residuals alone measure the noise (as `nf fit`'s [`student_fit`]): each
/// model white at its own residual level, its sigma widened by Student's t of its degrees
/// of freedom, weighed by the small-sample information criterion (AICc: its likelihood
/// less k + k (k + 1) / (n - k - 1) for its k parameters, the level and the scanned ones
/// counted). The colour models' REML over five contrasts at times gave a walk a fifth of
/// the white sigma (an outside audit: eight positions in opposite pairs, RMS error/sigma
/// 1.63, 6 of 60 beyond 3 sigma); and half a log n a parameter let an effect named falsely
/// at eight positions, its residual then three contrasts that happened to be small, carry
/// the final (RMS error/sigma 71 over such runs).
fn by_residuals(n: usize, designs: &[Vec<Vec<f64>>], met: &[Met]) -> Option<FinalSigma> {
    let fits: Vec<Option<(f64, student_fit::StudentFit)>> = designs
        .iter()
        .zip(met)
        .map(|(cols, m)| {
            let f = student_fit::fit(cols, m.y)?;
            let rss = f.level_dph.powi(2) * f.dof as f64;
            let k = (cols.len() + m.scanned + 1) as f64;
            let room = n as f64 - k - 1.0;
            let evidence = -0.5 * n as f64 * (rss / n as f64).ln() - k - k * (k + 1.0) / room;
            (room > 0.0 && evidence.is_finite()).then_some((evidence, f))
        })
        .collect();
    let (lead, top) = fits
        .iter()
        .flatten()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(e, f)| (f, *e))?;
    let evidence: Vec<Option<f64>> = fits.iter().map(|f| f.as_ref().map(|(e, _)| *e)).collect();
    let weights = weights_of(&evidence, top);
    let models: Vec<Option<(f64, Verdict)>> = merged(designs, met, &weights)
        .iter()
        .zip(&fits)
        .map(|(w, f)| Some(((*w)?, f.as_ref()?.1.verdict)))
        .collect();
    let weighted: Vec<(f64, Verdict)> = models.iter().flatten().copied().collect();
    Some(FinalSigma {
        verdict: mixed(&weighted, lead.verdict.psi_deg)?,
        calibration: None,
        residual_dof: Some(lead.dof),
        models,
        short_markov: false,
    })
}

/// The models' weights from their log-evidence (`None`: weight 0), `top` the largest.
fn weights_of(evidence: &[Option<f64>], top: f64) -> Vec<f64> {
    let weights: Vec<f64> = evidence.iter().map(|e| e.map_or(0.0, |e| (e - top).exp())).collect();
    let total: f64 = weights.iter().sum();
    weights.iter().map(|w| w / total).collect()
}

/// Models whose designs are the same once bursts are held out (Eq. 7, and Eq. 7 with the
/// outlier named) are one model: its weight the sum of theirs, under the one that names most
/// (scanned most; of equals the later). The others are `None`.
fn merged(designs: &[Vec<Vec<f64>>], met: &[Met], weights: &[f64]) -> Vec<Option<f64>> {
    let same = |a: usize, b: usize| {
        let holds = |x: &[Vec<f64>], y: &[Vec<f64>]| x.iter().all(|c| y.contains(c));
        met[a].y == met[b].y
            && designs[a].len() == designs[b].len()
            && holds(&designs[a], &designs[b])
            && holds(&designs[b], &designs[a])
    };
    (0..met.len())
        .map(|k| {
            let twins: Vec<usize> = (0..met.len()).filter(|&j| same(j, k)).collect();
            let named = twins.iter().copied().max_by_key(|&j| (met[j].scanned, j)).unwrap_or(k);
            (named == k).then(|| twins.iter().map(|&j| weights[j]).sum())
        })
        .collect()
}

/// A model's verdict over its noise models and its evidence: the full likelihood summed over
/// the grid's models (flicker and walk, and the short Gauss-Markov ones where they were
/// searched; each the same prior weight) less half a log n for each of its `params` (columns
/// and scanned parameters).
fn judge(estimate: noise_est::Estimate, params: usize, n: usize) -> Option<Judged> {
    let likelihoods: Vec<f64> = estimate.grid.iter().map(|c| c.full_loglik).collect();
    let top = likelihoods.iter().copied().fold(f64::MIN, f64::max);
    let marginal = top + likelihoods.iter().map(|l| (l - top).exp()).sum::<f64>().ln();
    let penalty = 0.5 * params as f64 * (n as f64).ln();
    Some(Judged {
        verdict: averaged(&estimate)?,
        log_evidence: marginal - penalty,
        estimate,
    })
}

/// The azimuth and amplitude averaged over the plausible models by their likelihood, each
/// variance the mean of theirs plus the spread between them.
fn averaged(e: &noise_est::Estimate) -> Option<Verdict> {
    // Every model the estimate searched: its Gauss-Markov ones are the short ones, where they show.
    let fits: Vec<(f64, Verdict)> = plausible_candidates(e, true)
        .into_iter()
        .map(|(w, c)| (w, azimuth(&c.coef, &c.cov)))
        .collect();
    let first = fits.first()?.1.psi_deg;
    mixed(&fits, first)
}

/// The mixture of weighted verdicts (weights summing to one): the mean and the variance
/// within and between them, the azimuths taken about `about`.
fn mixed(fits: &[(f64, Verdict)], about: f64) -> Option<Verdict> {
    if fits.is_empty() {
        return None;
    }
    let mean = |f: &dyn Fn(&Verdict) -> f64| fits.iter().map(|(w, v)| w * f(v)).sum::<f64>();
    let shift = mean(&|v| wrap_180(v.psi_deg - about));
    let amplitude = mean(&|v| v.amplitude_dph);
    let var_psi = mean(&|v| v.sigma_psi_deg.powi(2) + (wrap_180(v.psi_deg - about) - shift).powi(2));
    let var_amp = mean(&|v| v.sigma_amplitude_dph.powi(2) + (v.amplitude_dph - amplitude).powi(2));
    Some(Verdict {
        psi_deg: about + shift,
        sigma_psi_deg: var_psi.sqrt(),
        amplitude_dph: amplitude,
        sigma_amplitude_dph: var_amp.sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::Recording;
    use nf_model::rng::Rng;

    /// 48 positions of a sweep, white noise of 0.003 deg/h per dwell mean, and a step of
    /// `step` deg/h from the 20th dwell on.
    fn sweep(seed: u64, step: f64) -> Data {
        let mut rng = Rng::new(seed);
        let mut text =
            String::from("# format = northfinder-recording/1\n# latitude_deg = 40\nindex,t_s,encoder_deg,rate_dph\n");
        for i in 0..48 {
            let g = (7.5 * i as f64).to_radians();
            let rate = 0.3 + 0.008 * g.cos() - 0.007 * g.sin() + 0.003 * rng.gauss() + if i >= 20 { step } else { 0.0 };
            text += &format!("{i},{},{},{rate}\n", 2.0 * i as f64, 7.5 * i as f64);
        }
        Data::new(&Recording::parse(&text).unwrap())
    }

    /// Eq. 7 and Eq. 7 with the step column, its place counted as scanned.
    fn weights(d: &Data) -> Vec<f64> {
        let step: Vec<f64> = (0..d.n()).map(|i| f64::from(u8::from(i >= 20))).collect();
        let mut with_step = d.base_cols();
        with_step.push(step);
        let met = [
            Met {
                cols: d.base_cols(),
                y: &d.rate,
                scanned: 0,
            },
            Met {
                cols: with_step,
                y: &d.rate,
                scanned: 1,
            },
        ];
        let f = final_verdict(d, &met, 0).unwrap();
        f.models.iter().map(|m| m.unwrap().0).collect()
    }

    #[test]
    fn a_step_that_is_there_takes_the_weight_and_one_that_is_not_little() {
        let mut without = Vec::new();
        for seed in 1..=10 {
            let w = weights(&sweep(seed, 0.03));
            assert!(w[1] > 0.99, "seed {seed}: a 10-sigma step weighs {}", w[1]);
            without.push(weights(&sweep(seed, 0.0))[1]);
        }
        // Two parameters cost a factor 48 in evidence; a column of noise gains about e^0.5.
        let mean = without.iter().sum::<f64>() / without.len() as f64;
        assert!(
            mean < 0.15,
            "a step that is not there weighs {mean} on average: {without:?}"
        );
    }

    #[test]
    fn models_the_same_once_bursts_are_held_out_are_one_under_the_name_that_names_most() {
        let (a, b, c) = (vec![1.0, 2.0], vec![0.0, 1.0], vec![3.0, 1.0]);
        let y = [0.5, 0.7];
        let met = |scanned| Met {
            cols: Vec::new(),
            y: &y,
            scanned,
        };
        // Eq. 7 with the burst held out, the outlier named (its columns in another order),
        // and another model.
        let designs = [vec![a.clone(), b.clone()], vec![b.clone(), a.clone()], vec![a, c]];
        let kept = merged(&designs, &[met(0), met(1), met(0)], &[0.6, 0.1, 0.3]);
        assert_eq!(kept, [None, Some(0.7), Some(0.3)]);
    }

    #[test]
    fn a_mixture_holds_the_spread_between_its_members() {
        let v = |psi_deg: f64, sigma_psi_deg: f64, amplitude_dph: f64| Verdict {
            psi_deg,
            sigma_psi_deg,
            amplitude_dph,
            sigma_amplitude_dph: 0.001,
        };
        let m = mixed(&[(0.75, v(359.99, 0.01, 0.010)), (0.25, v(0.03, 0.02, 0.014))], 359.99).unwrap();
        // Shifts 0 and 0.04 deg about 359.99: mean 0.01; variances 0.75 1e-4 + 0.25 4e-4 plus
        // 0.75 0.01^2 + 0.25 0.03^2.
        assert!((wrap_180(m.psi_deg - 0.0)).abs() < 1e-12, "{}", m.psi_deg);
        let var: f64 = 0.75e-4 + 1e-4 + 0.75e-4 + 2.25e-4;
        assert!((m.sigma_psi_deg - var.sqrt()).abs() < 1e-12, "{}", m.sigma_psi_deg);
        assert!((m.amplitude_dph - 0.011).abs() < 1e-12);
        let var_amp: f64 = 1e-6 + 0.75 * 1e-6 + 0.25 * 9e-6;
        assert!((m.sigma_amplitude_dph - var_amp.sqrt()).abs() < 1e-12);
    }
}
