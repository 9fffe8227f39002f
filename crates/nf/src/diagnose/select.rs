//! Forward selection: each step tests every effect against the current model; an effect is
//! significant when its p-value is below `alpha / m`, `m` the tests of that step (Bonferroni
//! over the catalogue; a scan corrects inside its own test), and of the significant ones the
//! one whose model has the best BIC is named. So a recording that has none of the effects is
//! named for one with probability at most `alpha`.

use super::averaging::{self, Variant};
use super::data::Data;
use super::effect::{Change, Draws, Effect, Frame, Param, Proposal, State};
use super::kind::Kind;
use super::model::{Model, Summary, summary};
use super::tails::TailLaw;
use super::whiten::Whitener;
use crate::linfit::Ls;
use crate::wander_test::{LazyNull, WanderTest};

/// Steps before the selection stops regardless.
const MAX_STEPS: usize = 12;

#[derive(Debug, Clone)]
pub struct Finding {
    pub effect: Kind,
    pub parameters: Vec<Param>,
    /// Bonferroni-adjusted p-value of the test that found it.
    pub p_value: f64,
    /// Where in the recording it shows.
    pub location: String,
    /// The fit with it: whitened RSS, azimuth and sigma.
    pub after: Summary,
}

/// An effect its own test finds and the wander test holds back: not named, as the noise's
/// own wander explains the recording as well.
#[derive(Debug, Clone)]
pub struct Undecided {
    pub effect: Kind,
    /// Its own test's p-value, under the noise it is judged by.
    pub own_p: f64,
    /// With the noise re-estimated with and without it (the wander test's).
    pub p_value: f64,
    /// Whether `p_value` is only a lower bound: the F law's, where draws of the null were not
    /// made as it already stood at or above the step's level.
    pub at_least: bool,
    /// The step's level, which the wander test's p-value did not get under.
    pub level: f64,
    /// Its size, if it is one.
    pub parameters: Vec<Param>,
    pub location: String,
}

pub struct Selection {
    pub model: Model,
    pub fit: Ls,
    pub findings: Vec<Finding>,
    /// Every model met: the chain and the alternatives to each step.
    pub variants: Vec<Variant>,
    /// Competing significant explanations at a step.
    pub rivals: Vec<(Kind, Kind)>,
    /// Effects the last step's own tests found and the wander test did not confirm: the
    /// noise's wander explains them as well.
    pub undecided: Vec<Undecided>,
    /// Steps taken: each tests every effect against the model so far.
    pub steps: usize,
}

pub struct Selector<'a> {
    pub data: &'a Data,
    pub whitener: &'a Whitener,
    /// The most coloured noise the recording allows, for the tests of slow wander.
    pub cautious: &'a Whitener,
    /// The most coloured noise with a drift in its design, for the tests of drift and jump.
    pub drift: &'a Whitener,
    /// The effects a wandering bias can mimic, also under the noise profiled with and
    /// without them.
    pub wander: Option<&'a WanderTest>,
    pub effects: &'a [Box<dyn Effect>],
    pub tails: TailLaw,
    pub alpha: f64,
}

impl<'a> Selector<'a> {
    pub fn run(&self, start: Model) -> Result<Selection, String> {
        let w = self.whitener;
        let mut model = start;
        let mut fit = model.fit().ok_or("the positions do not determine A cos + B sin + C")?;
        let mut findings: Vec<Finding> = Vec::new();
        let mut variants = vec![variant("Eq. 7", &model, 0, None)];
        let mut rivals = Vec::new();
        let mut scanned = 0;
        let mut steps = 0;
        let mut undecided = Vec::new();
        let mut label = String::from("Eq. 7");
        // The wider forms named in place of the narrower (the drift's curve), for the labels.
        let mut widened: Vec<(Kind, &'static str)> = Vec::new();
        for _ in 0..MAX_STEPS {
            steps += 1;
            let named: Vec<Kind> = findings.iter().map(|f| f.effect).collect();
            let (mut cands, unconfirmed) = self.step(&model, &fit, &named);
            undecided = unconfirmed;
            let Some(chosen) = cands.first().cloned() else { break };
            for alt in cands.drain(1..) {
                if alt.kind != chosen.kind {
                    rivals.push((chosen.kind, alt.kind));
                }
                if let Change::Columns(cols) = &alt.change {
                    let m = model.with(Some(alt.kind), cols.clone(), w);
                    meet(
                        &mut variants,
                        false,
                        variant(
                            &rival_label(&chain_label(&findings, &widened), &chosen, alt.kind),
                            &m,
                            scanned + alt.scanned,
                            Some((chosen.kind, alt.kind)),
                        ),
                    );
                }
            }
            if findings.iter().any(|f| f.effect == chosen.kind)
                && let Some(form) = self.form_of(chosen.kind, &model)
            {
                widened.push((chosen.kind, form));
            }
            model = match &chosen.change {
                Change::Columns(cols) => model.with(Some(chosen.kind), cols.clone(), w),
                Change::Response(y) => model.with_y(y.clone(), w),
                Change::Nothing => model,
            };
            fit = model.fit().ok_or("the extended model does not fit")?;
            let columns = matches!(chosen.change, Change::Columns(_));
            scanned += if columns { chosen.scanned } else { 0 };
            absorb(&mut findings, chosen, summary(&model, &fit));
            if columns {
                label = chain_label(&findings, &widened);
                meet(&mut variants, true, variant(&label, &model, scanned, None));
            }
        }
        // The wider forms of what was named, as rivals of the chain even where their test
        // is not significant: in a sweep the drift's curve is mostly the first harmonic, so
        // it can move the azimuth by several of the line's sigmas while its own test, beyond
        // the line, stays near one sigma. Averaged in by its weight, its spread is in the
        // sigma.
        for e in self.effects {
            if let Some(ext) = e.extension(self.data, &model) {
                let m = model.with(Some(e.kind()), ext.cols, w);
                let name = format!("{label} ({} {})", e.kind().name(), ext.form);
                meet(&mut variants, false, variant(&name, &m, scanned, None));
            }
        }
        Ok(Selection {
            model,
            fit,
            findings,
            variants,
            rivals,
            undecided,
            steps,
        })
    }

    /// The name of the wider form of `kind` that `model` has room for.
    fn form_of(&self, kind: Kind, model: &Model) -> Option<&'static str> {
        let e = self.effects.iter().find(|e| e.kind() == kind)?;
        e.extension(self.data, model).map(|x| x.form)
    }

    /// The significant proposals of one step, the one to name first (best BIC), then the rest
    /// by p-value; and those only the wander test holds back.
    fn step(&self, model: &Model, fit: &Ls, named: &[Kind]) -> (Vec<Proposal>, Vec<Undecided>) {
        let main = Frame {
            whitener: self.whitener,
            model: model.clone(),
            fit: fit.clone(),
        };
        let under = |w: &'a Whitener| {
            let rewhitened = model.rewhiten(w);
            match rewhitened.fit() {
                Some(fit) => Frame {
                    whitener: w,
                    model: rewhitened,
                    fit,
                },
                None => Frame {
                    whitener: self.whitener,
                    model: model.clone(),
                    fit: fit.clone(),
                },
            }
        };
        let (cautious, drift) = (under(self.cautious), under(self.drift));
        let cols = match self.wander {
            Some(_) => model.raw_cols(),
            None => Vec::new(),
        };
        let null = LazyNull::new(self.wander, cols, model.y.clone());
        let state = State {
            data: self.data,
            main: &main,
            cautious: &cautious,
            drift: &drift,
            wander: &null,
            summary: summary(model, fit),
            named,
            tails: self.tails,
            alpha: self.alpha,
        };
        let mut cands: Vec<Proposal> = self.effects.iter().flat_map(|e| e.test(&state)).collect();
        let limit = self.alpha / cands.len().max(1) as f64;
        state.read_draws(&mut cands, limit);
        // A left-out drift or jump also moves the amplitude: the scale factor stands only
        // when nothing else is significant, by its own test even where the wander test does
        // not confirm it.
        let others = cands
            .iter()
            .any(|c| c.kind != Kind::ScaleFactor && c.own_p.unwrap_or(c.p) < limit);
        let unconfirmed = undecided(&cands, limit);
        cands.retain(|c| c.p < limit);
        if others {
            cands.retain(|c| c.kind != Kind::ScaleFactor);
        }
        cands.sort_by(|a, b| a.p.total_cmp(&b.p));
        // Two forms of one effect are one explanation: keep its best.
        let mut seen = Vec::new();
        cands.retain(|c| {
            let fresh = !seen.contains(&c.kind);
            seen.push(c.kind);
            fresh
        });
        // Among significant models the one the averaging weighs most leads: p-values of tests
        // under different noise models do not rank explanations.
        let bic = |c: &Proposal| match &c.change {
            Change::Columns(cols) => model
                .with(Some(c.kind), cols.clone(), self.whitener)
                .fit()
                .map(|f| averaging::bic(&f, c.scanned)),
            _ => None,
        };
        if cands.first().is_some_and(|c| matches!(c.change, Change::Columns(_))) {
            let best = (0..cands.len())
                .filter_map(|i| Some((i, bic(&cands[i])?)))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((i, _)) = best {
                let c = cands.remove(i);
                cands.insert(0, c);
            }
        }
        (cands, unconfirmed)
    }
}

/// The proposals whose own p-value is under `limit` and the wander test's is not, the most
/// significant form of each effect.
fn undecided(cands: &[Proposal], limit: f64) -> Vec<Undecided> {
    let mut held: Vec<(f64, &Proposal)> = cands
        .iter()
        .filter(|c| c.p >= limit)
        .filter_map(|c| Some((c.own_p.filter(|&p| p < limit)?, c)))
        .collect();
    held.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<Undecided> = Vec::new();
    for (own_p, c) in held {
        if out.iter().all(|u| u.effect != c.kind) {
            out.push(Undecided {
                effect: c.kind,
                own_p,
                p_value: c.p,
                at_least: c.draws == Draws::Skipped,
                level: limit,
                parameters: c.parameters.clone(),
                location: c.location.clone(),
            });
        }
    }
    out
}

/// Adds a model the selection met, once: an effect that adds no column (the tilt, corrected
/// beforehand) leaves the model as it was, so its rival at that step is the next step's
/// chain, and counted twice it would weigh twice in the average. The chain's label is kept.
fn meet(variants: &mut Vec<Variant>, chain: bool, v: Variant) {
    let holds = |a: &Model, b: &Model| b.cols.iter().all(|c| a.cols.iter().any(|d| d.raw == c.raw));
    let same = |a: &Model, b: &Model| a.y == b.y && a.cols.len() == b.cols.len() && holds(a, b) && holds(b, a);
    match variants.iter_mut().find(|w| same(&w.model, &v.model)) {
        Some(w) if chain => w.label = v.label,
        Some(_) => {}
        None => variants.push(v),
    }
}

/// The findings so far joined, each in the wider form named in its place.
fn chain_label(findings: &[Finding], widened: &[(Kind, &'static str)]) -> String {
    let names: Vec<String> = findings
        .iter()
        .map(|f| match widened.iter().find(|w| w.0 == f.effect) {
            Some((_, form)) => format!("{} ({form})", f.effect.name()),
            None => f.effect.name().to_string(),
        })
        .collect();
    match names.is_empty() {
        true => "Eq. 7".into(),
        false => names.join(" + "),
    }
}

/// A rival's model is the chain so far with the rival's columns: where the step's choice adds
/// none (the tilt's correction is in the data from the start) it keeps the choice too.
fn rival_label(chain: &str, chosen: &Proposal, rival: Kind) -> String {
    let kept: Vec<&str> = std::iter::once(chain)
        .filter(|c| *c != "Eq. 7")
        .chain(matches!(chosen.change, Change::Nothing).then_some(chosen.kind.name()))
        .collect();
    match (kept.is_empty(), &chosen.change) {
        (true, _) => format!("{} instead of {}", rival.name(), chosen.kind.name()),
        (false, Change::Nothing) => format!("{} + {}", kept.join(" + "), rival.name()),
        (false, _) => format!(
            "{} + {} instead of {}",
            kept.join(" + "),
            rival.name(),
            chosen.kind.name()
        ),
    }
}

fn variant(label: &str, model: &Model, scanned: usize, rival: Option<(Kind, Kind)>) -> Variant {
    Variant {
        label: label.into(),
        model: model.clone(),
        scanned,
        rival,
    }
}

/// Adds a finding; further outliers join the first finding of them, and a drift's curve
/// beyond its line takes the line's place (its parameters are both).
fn absorb(findings: &mut Vec<Finding>, c: Proposal, after: Summary) {
    if let Some(f) = findings.iter_mut().find(|f| f.effect == c.kind) {
        if c.kind == Kind::Outliers {
            f.parameters.extend(c.parameters);
            f.location = format!("{}; {}", f.location, c.location);
        } else {
            f.parameters = c.parameters;
            f.location = c.location;
            f.p_value = f.p_value.max(c.p);
        }
        f.after = after;
        return;
    }
    findings.push(Finding {
        effect: c.kind,
        parameters: c.parameters,
        p_value: c.p,
        location: c.location,
        after,
    });
}

#[cfg(test)]
mod tests {
    use super::super::effect::param;
    use super::*;

    #[test]
    fn only_effects_the_wander_test_held_back_are_undecided_the_strongest_form_of_each() {
        let prop = |kind, p, own_p, form: &str| Proposal {
            kind,
            p,
            change: Change::Nothing,
            parameters: vec![param(form, 1.0, None)],
            location: String::new(),
            scanned: 0,
            own_p,
            draws: Draws::No,
        };
        let skipped = |p: Proposal| Proposal {
            draws: Draws::Skipped,
            ..p
        };
        let cands = [
            prop(Kind::BiasDrift, 0.2, Some(1e-4), "linear"),
            prop(Kind::BiasDrift, 0.3, Some(1e-6), "curved"),
            skipped(prop(Kind::ThermalDrift, 2e-3, Some(1e-4), "temperature")),
            // Confirmed: named, not undecided.
            prop(Kind::BiasJump, 1e-4, Some(1e-5), "step"),
            // Its own test does not find it.
            prop(Kind::ThermalDrift, 0.5, Some(0.2), "temperature"),
            // Not asked of the wander test.
            prop(Kind::Outliers, 0.5, None, "dwell"),
        ];
        let held = undecided(&cands, 1e-3);
        assert_eq!(held.len(), 2);
        let u = &held[0];
        assert_eq!(u.effect, Kind::BiasDrift);
        assert_eq!(u.parameters[0].name, "curved");
        assert_eq!((u.own_p, u.p_value, u.at_least, u.level), (1e-6, 0.3, false, 1e-3));
        // Its draws not made: its p-value only a bound.
        assert_eq!((held[1].effect, held[1].at_least), (Kind::ThermalDrift, true));
    }

    #[test]
    fn a_rival_is_labelled_by_what_its_model_holds() {
        let proposal = |kind, change| Proposal {
            kind,
            p: 1e-6,
            change,
            parameters: Vec::new(),
            location: String::new(),
            scanned: 0,
            own_p: None,
            draws: Draws::No,
        };
        let tilt = proposal(Kind::ShaftTilt, Change::Nothing);
        let drift = proposal(Kind::BiasDrift, Change::Columns(Vec::new()));
        // The tilt's correction is in the rates from the start: its rival keeps it.
        assert_eq!(
            rival_label("Eq. 7", &tilt, Kind::ThermalDrift),
            "shaft_tilt + thermal_drift"
        );
        assert_eq!(
            rival_label("shaft_tilt", &drift, Kind::ThermalDrift),
            "shaft_tilt + thermal_drift instead of bias_drift"
        );
        assert_eq!(
            rival_label("Eq. 7", &drift, Kind::BiasJump),
            "bias_jump instead of bias_drift"
        );
    }

    #[test]
    fn a_model_met_twice_is_kept_once_under_the_chains_label() {
        let w = Whitener::identity();
        let base = Model::new(vec![vec![1.0; 6], (0..6).map(f64::from).collect()], vec![1.0; 6], &w);
        let step: Vec<f64> = (0..6).map(|i| f64::from(u8::from(i >= 3))).collect();
        let jump = base.with(Some(Kind::BiasJump), vec![step.clone()], &w);
        let mut met = Vec::new();
        meet(&mut met, true, variant("Eq. 7", &base, 0, None));
        let rival = Some((Kind::ShaftTilt, Kind::BiasJump));
        meet(
            &mut met,
            false,
            variant("bias_jump instead of shaft_tilt", &jump, 1, rival),
        );
        // The tilt adds no column: the next step's chain is the same model.
        meet(&mut met, true, variant("shaft_tilt + bias_jump", &jump, 1, None));
        assert_eq!(
            met.iter().map(|v| v.label.as_str()).collect::<Vec<_>>(),
            ["Eq. 7", "shaft_tilt + bias_jump"]
        );
        // A step elsewhere is another model.
        let other: Vec<f64> = (0..6).map(|i| f64::from(u8::from(i >= 2))).collect();
        meet(
            &mut met,
            false,
            variant("a", &base.with(Some(Kind::BiasJump), vec![other], &w), 1, None),
        );
        assert_eq!(met.len(), 3);
    }
}
