//! The final model fitted through shocks where the dwell means are heavy-tailed, as `nf fit`
//! fits its model (`crate::shock_fit`): a burst the selection named an outlier has its own
//! column; the rest of the shocks are weighed by how likely each struck its dwell. The shocks
//! are then the heavy tails' finding, and the noise estimated again beside them is the one
//! whose colours are named: the Gaussian estimates take the shocks' scatter beyond the
//! quarters for flicker.

use super::data::Data;
use super::effect::param;
use super::kind::Kind;
use super::noise::{NO_FIT, SHOCK_RMS, short_time};
use super::select::Finding;
use super::tails::Tails;
use crate::gls::WindowSet;
use crate::noise_est::{self, Colours, THINNED};
use crate::noise_fit::{self, NoiseChoice, Through};
use nf_model::noise::NoiseModel;

/// The final fit through shocks, and the tails of the final model's least-squares residuals
/// that let it in.
pub struct FinalShocks {
    pub through: Through,
    pub tails: Tails,
    /// The factor the Gaussian estimate's replicates scaled its sigma by, which the fit
    /// through the shocks carries (`None`: not scaled).
    pub calibration: Option<f64>,
}

/// The fit of `y ~ cols` (the final model) through shocks, under the given noise `model` or,
/// as `nf fit` fits, from the Gaussian estimate that reads the shocks as a short Gauss-Markov
/// bias (the tests' estimate may have read them as flicker, and the shocks' EM under that
/// finds few), its sigma keeping what that estimate's carried beyond its own GLS (`replicates`
/// calibrate it); `None` where the dwell means are not heavy-tailed or no dwell stands out.
pub fn through(
    d: &Data,
    cols: &[Vec<f64>],
    y: &[f64],
    model: &NoiseModel,
    choice: &NoiseChoice,
    replicates: usize,
) -> Option<FinalShocks> {
    let tails = noise_fit::shock_tails(cols, y)?;
    let short = short_time(d);
    let dwell_s = short.dwell_s;
    let data = noise_est::Data {
        t_s: &d.t,
        dwell_s,
        dwells_s: &short.dwells_s,
        cols,
        y,
        quarters: &short.quarters,
        spread: &short.spread,
        extra: None,
    };
    let windows = WindowSet::new(&d.t, &short.dwells_s);
    let (start, carried, calibration) = match choice {
        NoiseChoice::Given(..) => (*model, (1.0, 1.0), None),
        NoiseChoice::Estimate => {
            // As the final sigma's: replicates up to THINNED positions, past which the noise
            // is known well and each would cost a long run's estimate.
            let replicates = if d.n() > THINNED { 0 } else { replicates };
            let g = noise_fit::gaussian(&data, Colours::WithShocks, replicates).ok()?;
            (g.judged.model, g.carried(), g.calibration.map(|c| c.psi))
        }
    };
    let through = noise_fit::through(&data, &windows, &start, choice, &d.rec.rows, carried)?;
    Some(FinalShocks {
        through,
        tails,
        calibration,
    })
}

impl FinalShocks {
    /// The heavy tails as a finding, sized by the shocks' fit (its share and shift are what
    /// `--fix` writes).
    pub fn finding(&self, d: &Data) -> Finding {
        let s = &self.through.shocks;
        Finding {
            effect: Kind::HeavyTails,
            parameters: vec![
                param("student_t_dof", self.tails.dof, None),
                param("shock_share", s.share, None),
                param("shock_shift_dph", s.shift_dph, None),
                param(SHOCK_RMS, s.share.sqrt() * s.shift_dph, None),
                param("struck_dwells", s.struck.len() as f64, None),
            ],
            p_value: self.tails.p,
            location: format!(
                "the final model's least-squares residuals: the final azimuth is fitted through the shocks (dwells read as struck at lines {})",
                self.lines(d)
            ),
            after: NO_FIT,
        }
    }

    /// Where the final sigma came from, for the report.
    pub fn describe(&self) -> String {
        match self.through.estimate {
            Some(_) => format!(
                "through the shocks, under the noise (flicker and walk) estimated again beside them, times {:.2} carried from the Gaussian estimate (its noise models' spread and replicates)",
                self.through.carried
            ),
            None => "through the shocks, under the given noise model".into(),
        }
    }

    /// What the report says of the shocks.
    pub fn note(&self, d: &Data) -> String {
        let s = &self.through.shocks;
        format!(
            "the dwell means are heavy-tailed: the final azimuth is fitted through shocks, each dwell weighed by how likely a shock struck it ({} of {} read as struck, a share of {:.2}, a shift of sd {:.5} deg/h; lines {})",
            s.struck.len(),
            d.n(),
            s.share,
            s.shift_dph,
            self.lines(d)
        )
    }

    fn lines(&self, d: &Data) -> String {
        let lines: Vec<usize> = self.through.shocks.struck.iter().map(|&i| d.rec.rows[i].line).collect();
        noise_fit::lines_text(&lines)
    }
}
