//! The final model fitted through shocks where the dwell means are heavy-tailed, as `nf fit`
//! fits its model (`crate::shock_fit`): a burst the selection named an outlier has its own
//! column; the rest of the shocks are weighed by how likely each struck its dwell.

use super::data::Data;
use super::noise::dwell_and_quarters;
use crate::gls::WindowSet;
use crate::noise_est::{self, Colours};
use crate::noise_fit::{self, NoiseChoice, Through};
use crate::shock_fit::ShockFit;
use nf_model::noise::NoiseModel;

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
) -> Option<Through> {
    if !noise_fit::heavy_tailed(cols, y) {
        return None;
    }
    let (dwell_s, quarters) = dwell_and_quarters(d);
    let data = noise_est::Data {
        t_s: &d.t,
        dwell_s,
        cols,
        y,
        quarters: &quarters,
        extra: None,
    };
    let windows = WindowSet::new(&d.t, &vec![dwell_s; d.n()]);
    let (start, carried) = match choice {
        NoiseChoice::Given(..) => (*model, (1.0, 1.0)),
        NoiseChoice::Estimate => {
            let g = noise_fit::gaussian(&data, Colours::WithShocks, replicates).ok()?;
            (g.judged.model, g.carried())
        }
    };
    noise_fit::through(&data, &windows, &start, choice, &d.rec.rows, carried)
}

/// What the report says of the shocks.
pub fn note(d: &Data, s: &ShockFit) -> String {
    let lines: Vec<usize> = s.struck.iter().map(|&i| d.rec.rows[i].line).collect();
    format!(
        "the dwell means are heavy-tailed: the final azimuth is fitted through shocks, each dwell weighed by how likely a shock struck it ({} of {} read as struck, a share of {:.2}, a shift of sd {:.5} deg/h; lines {})",
        s.struck.len(),
        d.n(),
        s.share,
        s.shift_dph,
        noise_fit::lines_text(&lines)
    )
}
