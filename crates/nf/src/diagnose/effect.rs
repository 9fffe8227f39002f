//! The trait every effect implements, and what a test proposes.

use super::data::Data;
use super::kind::Kind;
use super::model::{Model, Summary};
use super::tails::TailLaw;
use super::whiten::Whitener;
use crate::linfit::Ls;
use crate::stats::f_sf;
use crate::wander_test::{Alternative, ChangePoints, LazyNull};

#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    pub name: String,
    pub value: f64,
    /// Standard error, where the fit gives one.
    pub sigma: Option<f64>,
}

pub fn param(name: &str, value: f64, sigma: Option<f64>) -> Param {
    Param {
        name: name.into(),
        value,
        sigma,
    }
}

/// How a named effect changes the model.
#[derive(Clone)]
pub enum Change {
    /// Columns added to the linear model.
    Columns(Vec<Vec<f64>>),
    /// The rates replaced (the dwell means without their settling quarter).
    Response(Vec<f64>),
    /// Nothing to fit: the effect is already corrected, or changes no residual.
    Nothing,
}

/// One effect's test against the current model.
#[derive(Clone)]
pub struct Proposal {
    pub kind: Kind,
    /// p-value, already corrected for any scan inside the test.
    pub p: f64,
    pub change: Change,
    pub parameters: Vec<Param>,
    pub location: String,
    /// Parameters chosen by a scan (a change time, a position): counted by the information
    /// criterion of the model averaging.
    pub scanned: usize,
    /// The effect's own test's p-value where the wander test raised `p`.
    pub own_p: Option<f64>,
    /// Where the wander test's ratio stands against draws of its null.
    pub draws: Draws,
}

/// Whether a proposal's wander test is read against draws of its null.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Draws {
    /// Not asked: its p-value is final.
    No,
    /// To be read once the step's level is known ([`State::read_draws`]).
    Pending(Drawn),
    /// Read: `p` is at least their p-value.
    Read,
    /// Not made, `p` (its own test's and the F law's) being at or above the step's level
    /// already: a lower bound of the test's.
    Skipped,
}

/// What a proposal's draws test beyond the null.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drawn {
    /// Its columns.
    Columns,
    /// A step at any of these change points ([`Alternative::Step`]): the jump, whose column
    /// a scan of them chose.
    Step(ChangePoints),
}

/// A fit of the model on columns whitened by one noise model.
pub struct Frame<'a> {
    pub whitener: &'a Whitener,
    pub model: Model,
    pub fit: Ls,
}

impl Frame<'_> {
    /// The F test (a GLS likelihood-ratio test on whitened columns) of the model with `cols`
    /// added. `params` reads the effect's parameters from the bigger fit, given the index of
    /// its first new coefficient.
    pub fn nested(
        &self,
        kind: Kind,
        cols: Vec<Vec<f64>>,
        params: impl Fn(&Ls, usize) -> Vec<Param>,
        location: String,
    ) -> Option<Proposal> {
        let white: Vec<Vec<f64>> = cols.iter().map(|c| self.whitener.apply(c)).collect();
        let big = self.model.fit_plus(&white)?;
        Some(Proposal {
            kind,
            p: nested_p(&self.fit, &big, cols.len()),
            parameters: params(&big, self.model.cols.len()),
            change: Change::Columns(cols),
            location,
            scanned: 0,
            own_p: None,
            draws: Draws::No,
        })
    }
}

/// Draws of the null at most for a p-value of the wander test: p down to 1/401.
const DRAWS: usize = 400;

/// What a test sees: the recording and the model so far, fitted under three noise models.
/// - `main`, the estimate: local tests (outliers, settling).
/// - `cautious`, the most coloured model the recording allows: encoder harmonics, and the
///   amplitude and the 2 psi harmonic of a nonlinearity where they are slow in time
///   ([`Data::slow_in_time`]; under `main` elsewhere), because the low harmonics of the angle
///   can be the slow wander of time.
/// - `drift`, the estimate made with a drift in the design: drift, jump and temperature,
///   because a random walk wanders at every scale and a drift does not.
pub struct State<'a> {
    pub data: &'a Data,
    pub main: &'a Frame<'a>,
    pub cautious: &'a Frame<'a>,
    pub drift: &'a Frame<'a>,
    /// The model so far as the null of the test of an effect a wandering bias can mimic,
    /// with the noise profiled under each hypothesis; it has none where the drift frame's F
    /// test stands alone.
    pub wander: &'a LazyNull<'a>,
    pub summary: Summary,
    pub named: &'a [Kind],
    /// The tails the whitened noise allows.
    pub tails: TailLaw,
    /// The step's family-wise level: a p-value at or above it is not significant, whatever
    /// else is tested.
    pub alpha: f64,
}

impl State<'_> {
    pub fn amplitude(&self) -> f64 {
        self.main.fit.coef[1].hypot(self.main.fit.coef[2])
    }

    pub fn is_named(&self, k: Kind) -> bool {
        self.named.contains(&k)
    }

    /// `p` judged also by the wander test, where there is one: an effect whose shape a
    /// wandering bias can take (drift, jump, temperature, encoder harmonics, the 2 psi
    /// harmonic) is significant only when its F test and the wander test both say so (an
    /// intersection-union test: its size is at most either's). Over one run a random walk
    /// and a drift are one wander, and each test alone takes one for the other in a
    /// different share of runs. `p.p` comes corrected for the candidates a scan chose from.
    pub fn wander_judged(&self, mut p: Proposal, law: Law) -> Proposal {
        if p.p >= self.alpha {
            return p;
        }
        if let Change::Columns(cols) = &p.change
            && let Some(null) = self.wander.get()
            && let Some(pw) = null.p_value(cols)
        {
            let pw = match law {
                Law::F { scan } => (pw * scan as f64).min(1.0),
                Law::Drawn => {
                    p.draws = Draws::Pending(Drawn::Columns);
                    pw
                }
                Law::DrawnStep { tried } => {
                    if null.draws() {
                        p.draws = Draws::Pending(Drawn::Step(tried));
                    }
                    (pw * tried.count() as f64).min(1.0)
                }
            };
            p.own_p = Some(p.p);
            p.p = p.p.max(pw);
        }
        p
    }

    /// Each pending proposal's `p` raised to the p-value of the wander test's ratio against
    /// draws of its null (never below the F law's), where that can decide: where `p` is under
    /// the step's level `limit`. Above it the effect is not named whatever the draws say, and
    /// they are not made. The proposals share the draws (one null), and each stops once its
    /// p-value cannot fall under the level.
    pub fn read_draws(&self, cands: &mut [Proposal], limit: f64) {
        let asked: Vec<(usize, Alternative)> = cands
            .iter()
            .enumerate()
            .filter(|(_, p)| p.p < limit)
            .filter_map(|(i, p)| match (p.draws, &p.change) {
                (Draws::Pending(Drawn::Step(tried)), _) => Some((i, Alternative::Step(tried))),
                (Draws::Pending(Drawn::Columns), Change::Columns(cols)) => Some((i, Alternative::Columns(cols))),
                _ => None,
            })
            .collect();
        let drawn = match self.wander.get() {
            Some(null) if !asked.is_empty() => {
                let extras: Vec<Alternative> = asked.iter().map(|(_, a)| *a).collect();
                null.p_drawn(&extras, DRAWS, limit)
            }
            _ => Vec::new(),
        };
        let asked: Vec<usize> = asked.into_iter().map(|(i, _)| i).collect();
        for p in cands.iter_mut().filter(|p| matches!(p.draws, Draws::Pending(_))) {
            p.draws = if p.p >= limit { Draws::Skipped } else { Draws::No };
        }
        for (i, d) in asked.into_iter().zip(drawn) {
            if let Some(d) = d {
                cands[i].p = cands[i].p.max(d);
                cands[i].draws = Draws::Read;
            }
        }
    }
}

/// How the wander test's likelihood ratio is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Law {
    /// As an F statistic, corrected for the `scan` candidates a scan chose from (1 without
    /// one). The encoder harmonics and the 2 psi harmonic: drawn from a null that takes
    /// them for wander, the moderate nonlinearity on white noise was named in 55 % of the
    /// suite's runs instead of 90 %.
    F { scan: usize },
    /// Against draws from the null's own noise model (`Null::p_drawn`) where the noise is
    /// estimated from the run, else as an F statistic: the drift and the temperature, the
    /// shapes a walk takes most often.
    Drawn,
    /// The jump scanned over change points `tried`: as `F { scan }` with the scan their
    /// count, and where the noise is estimated from the run also the best step's ratio
    /// against the best step's in draws of the null. A walk is a sum of steps, which the F
    /// law under-reads; and where the null lacks another effect (a drift's curve) the
    /// draws, which know nothing of it, over-read the step that takes its place, which the
    /// scan's Bonferroni correction guards.
    DrawnStep { tried: ChangePoints },
}

/// F test of `big` (with `q` more columns) against `small`.
pub fn nested_p(small: &Ls, big: &Ls, q: usize) -> f64 {
    f_test(small.rss, big.rss, q, big.dof)
}

/// F test of a fit with RSS `big_rss` and `big_dof` degrees of freedom against one with `q`
/// columns fewer and RSS `small_rss`.
pub fn f_test(small_rss: f64, big_rss: f64, q: usize, big_dof: usize) -> f64 {
    if big_dof == 0 || small_rss <= big_rss {
        return 1.0;
    }
    let f = ((small_rss - big_rss) / q as f64) / (big_rss / big_dof as f64);
    f_sf(f, q as f64, big_dof as f64)
}

/// An effect of the catalogue: its signature in the data and its test.
pub trait Effect {
    fn kind(&self) -> Kind;
    /// The tests of the effect's forms against the current model; empty where it does not
    /// apply (already named, a column the recording lacks, too few positions).
    fn test(&self, s: &State) -> Vec<Proposal>;
    /// A wider form of the effect as named in `m` (the drift's curve beyond its line): its
    /// name and columns. The averaging meets it as a rival of the chain even where its test
    /// is not significant, since the narrower form leaves its part in the azimuth.
    fn extension(&self, _d: &Data, _m: &Model) -> Option<Extension> {
        None
    }
}

pub struct Extension {
    pub form: &'static str,
    pub cols: Vec<Vec<f64>>,
}
