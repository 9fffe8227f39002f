//! The suite's categories of recordings and the rows of each: what the instrument, its noise,
//! its visiting order and its file are like, and which effects are concealed.

use super::EvalOptions;
use super::cases::{Case, Site, random_case};
use super::conceal::{LEVELS, MODERATE, conceal};
use super::damage::Loss;
use super::metrics::Truth;
use super::noise_kinds::NoiseKind;
use crate::diagnose::Kind;
use nf_model::order::Order;
use nf_twin::Rng;

/// A group of rows in the table, selectable with `--category`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    /// One noise kind: clean recordings and each effect on its own.
    Noise(NoiseKind),
    TwoEffects,
    Orders,
    MissingTilt,
    LargeTilt,
    HighLatitude,
}

/// Which effects a row's recordings get.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pick {
    Nothing,
    One(Kind),
    /// This one and another drawn from the rest of the catalogue.
    PairWith(Kind),
    /// One drawn from the catalogue without this one.
    AnyBut(Kind),
}

/// Everything that makes a row's recordings what they are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setup {
    pub noise: NoiseKind,
    pub order: Order,
    pub site: Site,
    pub pick: Pick,
    /// Index into [`LEVELS`] of the concealed effects.
    pub level: usize,
    pub loss: Loss,
}

#[derive(Debug, Clone)]
pub struct RowSpec {
    pub label: String,
    pub runs: u32,
    pub setup: Setup,
}

const PLAIN: Setup = Setup {
    noise: NoiseKind::White,
    order: Order::Sequential,
    site: Site::ORDINARY,
    pick: Pick::Nothing,
    level: MODERATE,
    loss: Loss::Nothing,
};

/// Orders other than one sweep, run with flicker noise (the wander they are meant to beat).
const ORDERS: [Order; 3] = [Order::ForwardBack, Order::OppositePairs, Order::Interleaved];

/// A shaft tilted this much, deg, in the missing-tilt rows, and up to this in the large ones.
const TILT_DEG: (f64, f64) = (0.05, 1.0);
const LARGE_TILT_DEG: (f64, f64) = (0.05, 10.0);

impl Category {
    pub const ALL: [Category; 10] = [
        Category::Noise(NoiseKind::White),
        Category::Noise(NoiseKind::Flicker),
        Category::Noise(NoiseKind::RandomWalk),
        Category::Noise(NoiseKind::GaussMarkov),
        Category::Noise(NoiseKind::HeavyTails),
        Category::TwoEffects,
        Category::Orders,
        Category::MissingTilt,
        Category::LargeTilt,
        Category::HighLatitude,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Category::Noise(kind) => kind.name(),
            Category::TwoEffects => "two_effects",
            Category::Orders => "orders",
            Category::MissingTilt => "missing_tilt",
            Category::LargeTilt => "large_tilt",
            Category::HighLatitude => "high_latitude",
        }
    }

    pub fn about(self) -> &'static str {
        match self {
            Category::Noise(NoiseKind::White) => "white noise; each effect at each level",
            Category::Noise(NoiseKind::Flicker) => "bias instability 0.1-10 s (s: white noise of a dwell mean)",
            Category::Noise(NoiseKind::RandomWalk) => "rate random walk, 0.1-10 s over the run",
            Category::Noise(NoiseKind::GaussMarkov) => "Gauss-Markov bias, tau T/10-T, 0.1-10 s over the run",
            Category::Noise(NoiseKind::HeavyTails) => "Student-t(3) samples and Student-t(3) dwell shifts of 0.3-3 s",
            Category::TwoEffects => "two distinct effects at once, moderate; white noise",
            Category::Orders => "forward-back, opposite pairs, interleaved; flicker noise",
            Category::MissingTilt => "shaft tilt 0.05-1 deg; tilt_y column gone, or 1-3 tilt readings blank",
            Category::LargeTilt => "shaft tilt 0.05-10 deg (log-uniform), both tilt columns",
            Category::HighLatitude => "|latitude| 60-85 deg; white noise",
        }
    }

    /// The rows, with `seeds` recordings per effect row and `clean` per clean row.
    pub fn rows(self, o: &EvalOptions) -> Vec<RowSpec> {
        match self {
            Category::Noise(NoiseKind::White) => effect_rows("", o, &[0, 1, 2], PLAIN),
            Category::Noise(noise) => effect_rows("", o, &[MODERATE], Setup { noise, ..PLAIN }),
            Category::TwoEffects => Kind::CATALOGUE
                .iter()
                .map(|&e| row(format!("{e} + other"), o.seeds, Pick::PairWith(e), PLAIN))
                .collect(),
            Category::Orders => ORDERS
                .iter()
                .flat_map(|&order| {
                    let setup = Setup {
                        noise: NoiseKind::Flicker,
                        order,
                        ..PLAIN
                    };
                    effect_rows(&format!("{} ", order.name()), o, &[MODERATE], setup)
                })
                .collect(),
            Category::MissingTilt => [
                ("no tilt_y column", Loss::TiltYColumn),
                ("1-3 tilt readings blank", Loss::TiltReadings),
            ]
            .iter()
            .flat_map(|&(label, loss)| tilted_rows(label, o, TILT_DEG, loss))
            .collect(),
            Category::LargeTilt => tilted_rows("tilt 0.05-10 deg", o, LARGE_TILT_DEG, Loss::Nothing),
            Category::HighLatitude => {
                let site = Site {
                    abs_lat_deg: (60.0, 85.0),
                    tilt_deg: None,
                };
                effect_rows("", o, &[MODERATE], Setup { site, ..PLAIN })
            }
        }
    }
}

fn row(label: String, runs: u32, pick: Pick, base: Setup) -> RowSpec {
    RowSpec {
        label,
        runs,
        setup: Setup { pick, ..base },
    }
}

/// A clean row and one row per effect and level, labels after `prefix`.
fn effect_rows(prefix: &str, o: &EvalOptions, levels: &[usize], base: Setup) -> Vec<RowSpec> {
    let mut rows = vec![row(format!("{prefix}clean"), o.clean, Pick::Nothing, base)];
    for effect in Kind::CATALOGUE {
        for &level in levels {
            let label = format!("{prefix}{effect} {}", LEVELS[level]);
            rows.push(row(label, o.seeds, Pick::One(effect), Setup { level, ..base }));
        }
    }
    rows
}

/// A tilted shaft (the shaft tilt is then the concealed effect) alone and with one more effect.
fn tilted_rows(label: &str, o: &EvalOptions, tilt_deg: (f64, f64), loss: Loss) -> Vec<RowSpec> {
    let base = Setup {
        site: Site {
            tilt_deg: Some(tilt_deg),
            ..Site::ORDINARY
        },
        loss,
        ..PLAIN
    };
    vec![
        row(label.to_string(), o.seeds, Pick::Nothing, base),
        row(
            format!("{label} + effect"),
            o.seeds,
            Pick::AnyBut(Kind::ShaftTilt),
            base,
        ),
    ]
}

impl Pick {
    fn draw(self, rng: &mut Rng) -> Vec<Kind> {
        let other = |rng: &mut Rng, not: Kind| {
            let rest: Vec<Kind> = Kind::CATALOGUE.iter().copied().filter(|e| *e != not).collect();
            rest[(rng.next_u64() % rest.len() as u64) as usize]
        };
        match self {
            Pick::Nothing => Vec::new(),
            Pick::One(e) => vec![e],
            Pick::PairWith(e) => vec![e, other(rng, e)],
            Pick::AnyBut(e) => vec![other(rng, e)],
        }
    }
}

impl Setup {
    /// One random recording's case, and what it really has.
    pub fn draw(&self, rng: &mut Rng) -> (Case, Truth) {
        let mut case = random_case(rng, &self.site, self.order);
        let ratio = self.noise.draw_ratio(rng);
        self.noise.apply(&mut case, ratio, rng);
        let mut effects = self.pick.draw(rng);
        for effect in &effects {
            conceal(&mut case, *effect, self.level, rng);
        }
        if self.site.tilt_deg.is_some() {
            effects.push(Kind::ShaftTilt);
        }
        case.damage = self.loss.draw(rng, case.visits());
        let truth = Truth {
            effects,
            psi_deg: case.twin.instrument.psi_deg,
        };
        (case, truth)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_distinct_and_every_row_runs() {
        let o = EvalOptions {
            seeds: 3,
            clean: 5,
            category: None,
        };
        for (i, c) in Category::ALL.iter().enumerate() {
            assert!(Category::ALL[..i].iter().all(|d| d.name() != c.name()));
            let rows = c.rows(&o);
            assert!(!rows.is_empty());
            assert!(rows.iter().all(|r| r.runs
                == if r.setup.pick == Pick::Nothing && r.setup.site.tilt_deg.is_none() {
                    5
                } else {
                    3
                }));
        }
        // White: clean and 9 effects at 3 levels; orders: 3 x (clean and 9 effects).
        assert_eq!(Category::Noise(NoiseKind::White).rows(&o).len(), 28);
        assert_eq!(Category::Orders.rows(&o).len(), 30);
    }

    #[test]
    fn drawn_cases_carry_their_truth() {
        let mut rng = Rng::new(4);
        let pair = Setup {
            pick: Pick::PairWith(Kind::Outliers),
            ..PLAIN
        };
        for _ in 0..20 {
            let (case, truth) = pair.draw(&mut rng);
            assert_eq!(truth.effects.len(), 2);
            assert_eq!(truth.effects[0], Kind::Outliers);
            assert_ne!(truth.effects[1], Kind::Outliers);
            assert!(!case.dwell_shifts.is_empty());
        }
        let tilted = &Category::MissingTilt.rows(&EvalOptions::default())[3].setup;
        let (case, truth) = tilted.draw(&mut rng);
        assert!((0.05..=1.0).contains(&case.twin.instrument.tilt_deg));
        assert_eq!(truth.effects.len(), 2);
        assert_eq!(truth.effects[1], Kind::ShaftTilt);
        assert_eq!(tilted.loss, Loss::TiltReadings);
    }
}
