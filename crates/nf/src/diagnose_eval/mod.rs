//! The diagnose test suite: twin recordings with real-gyro-like noise (white, flicker, random
//! walk, Gauss-Markov, heavy tails), with catalogue effects concealed in random instruments at
//! named levels, and clean ones for the false-alarm rate; in categories that also cover two
//! effects at once, other visiting orders, lost inclinometer data, large tilts and high
//! latitudes.
//!
//! The suite sees a diagnosis only through [`Outcome`], so that any diagnosis can be measured
//! by it (the algorithm and the suite change separately).

mod cases;
mod categories;
mod conceal;
mod damage;
mod metrics;
mod noise_kinds;
mod table;

use crate::diagnose::{Diagnosis, Kind};
use crate::recording::Recording;
use categories::Category;
use nf_twin::Rng;

pub use conceal::LEVELS;
pub use metrics::{Missed, Tally, Truth};
pub use table::{json, text};

/// What the suite needs of one diagnosis.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Catalogue effects (and `unexplained`) named, in the order found.
    pub effects: Vec<Kind>,
    /// Noise findings named; never false alarms.
    pub noise_terms: Vec<Kind>,
    pub baseline_deg: f64,
    pub baseline_sigma_arcsec: f64,
    pub final_deg: f64,
    pub final_sigma_arcsec: f64,
}

#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EvalOptions {
    /// Recordings per effect row.
    pub seeds: u32,
    /// Clean recordings per clean row (one per noise kind, order and the high latitudes).
    pub clean: u32,
    /// Run this category only; `None` for all.
    pub category: Option<String>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RowResult {
    pub label: String,
    pub tally: Tally,
}

#[derive(Debug, Clone, PartialEq)]
pub struct CategoryResult {
    pub name: &'static str,
    pub about: &'static str,
    pub rows: Vec<RowResult>,
    /// All its rows together.
    pub total: Tally,
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Evaluation {
    pub categories: Vec<CategoryResult>,
}

/// The suite's view of a diagnosis: its noise findings apart from its effects.
pub fn outcome_of(d: &Diagnosis) -> Outcome {
    let (noise_terms, effects) = d.findings.iter().map(|f| f.effect).partition(|k| k.is_noise());
    Outcome {
        effects,
        noise_terms,
        baseline_deg: d.baseline.azimuth_deg,
        baseline_sigma_arcsec: d.baseline.sigma_arcsec,
        final_deg: d.final_.azimuth_deg,
        final_sigma_arcsec: d.final_.sigma_arcsec,
    }
}

/// The names `--category` takes.
pub fn category_names() -> [&'static str; Category::ALL.len()] {
    Category::ALL.map(Category::name)
}

/// The categories chosen, with their places in the full list (which seed their rows).
fn chosen(opts: &EvalOptions) -> impl Iterator<Item = (usize, Category)> + '_ {
    Category::ALL
        .into_iter()
        .enumerate()
        .filter(|(_, c)| opts.category.as_deref().is_none_or(|n| n == c.name()))
}

/// Recordings [`evaluate`] will make (for a progress bar).
pub fn planned_runs(opts: &EvalOptions) -> u64 {
    chosen(opts)
        .flat_map(|(_, c)| c.rows(opts))
        .map(|r| r.runs as u64)
        .sum()
}

/// One recording of the suite, as it was diagnosed.
pub struct Seen<'a> {
    pub category: &'static str,
    pub row: &'a str,
    /// Its number in the row, from 0.
    pub number: u32,
    /// The recording's text, as the diagnosis read it.
    pub text: &'a str,
    pub truth: &'a Truth,
    /// `None` where the diagnosis refused the recording.
    pub missed: Option<Missed>,
}

/// Runs the suite: for each recording, `diag` gives the outcome (`None` when it refuses the
/// recording) and `seen` is told of it. Each row draws from its own seed, so that one category
/// run alone gives the same numbers as in the full suite.
pub fn evaluate(
    opts: &EvalOptions,
    diag: &dyn Fn(&Recording) -> Option<Outcome>,
    seen: &mut dyn FnMut(&Seen<'_>),
) -> Evaluation {
    let mut ev = Evaluation::default();
    for (at, category) in chosen(opts) {
        let mut rows = Vec::new();
        let mut total = Tally::default();
        for (r, spec) in category.rows(opts).into_iter().enumerate() {
            let mut rng = Rng::new(0xD1A6 ^ ((at as u64) << 32) ^ r as u64);
            let mut tally = Tally::default();
            for number in 0..spec.runs {
                let (case, truth) = spec.setup.draw(&mut rng);
                let text = case.text();
                // The twin always writes a valid recording; a failed parse would be a bug of the suite.
                let outcome = diag(&Recording::parse(&text).expect("twin recordings parse"));
                tally.add(&truth, outcome.as_ref());
                seen(&Seen {
                    category: category.name(),
                    row: &spec.label,
                    number,
                    text: &text,
                    truth: &truth,
                    missed: outcome.as_ref().map(|o| Missed::of(&truth, o)),
                });
            }
            total.merge(&tally);
            rows.push(RowResult {
                label: spec.label,
                tally,
            });
        }
        ev.categories.push(CategoryResult {
            name: category.name(),
            about: category.about(),
            rows,
            total,
        });
    }
    ev
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_category_alone_is_reproducible_and_ticks_once_per_recording() {
        let one = |category: &str| EvalOptions {
            seeds: 1,
            clean: 1,
            category: Some(category.into()),
        };
        // A stand-in diagnosis: the truth's azimuth is not known to it, the recording's first rate is.
        let diag = |rec: &Recording| {
            Some(Outcome {
                effects: if rec.rows[0].rate_dph > 0.0 {
                    vec![Kind::BiasDrift]
                } else {
                    Vec::new()
                },
                noise_terms: Vec::new(),
                baseline_deg: rec.rows[0].rate_dph,
                baseline_sigma_arcsec: 1.0,
                final_deg: rec.rows[1].rate_dph,
                final_sigma_arcsec: 1.0,
            })
        };
        let mut ticks = 0;
        let alone = evaluate(&one("large_tilt"), &diag, &mut |_| ticks += 1);
        assert_eq!(ticks as u64, planned_runs(&one("large_tilt")));
        assert_eq!(alone.categories.len(), 1);
        assert_eq!(alone.categories[0].name, "large_tilt");
        let again = evaluate(&one("large_tilt"), &diag, &mut |_| {});
        assert_eq!(alone, again);
        assert_eq!(planned_runs(&one("no_such_category")), 0);
        assert!(category_names().contains(&"heavy_tails"));
    }
}
