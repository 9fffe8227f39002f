//! The short-time noise from the spread of the samples inside each dwell (`rate_sd_dph` over
//! `samples`), for a run of a few positions without quarter means: its dwell means leave the
//! white level one to five residual degrees of freedom, and the sigma from them is a guess.
//!
//! A gyro's samples are often filtered or coloured, so their spread is not quite a dwell
//! mean's white noise (an ADIS16405 log's spread over 100 samples is 1.35 times too small for
//! the variance of their 1 s mean; an XSens log's over 1000 samples, 2 times). Each dwell
//! counts for at most [`DOF_PER_DWELL`] degrees of freedom, the weight its quarter means would
//! have had, not its samples' hundreds, and a run whose dwell means leave [`FEW_DOF`] or more
//! does without it: on sweeps of those logs (36-72 positions) the spread moved `nf fit`'s RMS
//! of error/sigma further from 1 than the dwell means alone (docs/noise.md).

use crate::linfit;
use crate::quarter_contrasts::Part;
use crate::recording::Row;
use crate::stats::chi2_sf;
use nf_model::noise::NoiseModel;
use nf_model::rng::Rng;

/// What one dwell's samples show: their standard deviation and how many there were, over
/// the dwell's length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    pub sd_dph: f64,
    pub samples: u32,
    pub dwell_s: f64,
}

impl Spread {
    /// Whether it says anything: one sample or none has no spread, and a spread of 0 over
    /// more was not written or comes from a stuck sensor.
    fn tells(&self) -> bool {
        self.samples > 1 && self.sd_dph > 0.0
    }
}

/// The most degrees of freedom a dwell's spread counts for in a likelihood.
pub const DOF_PER_DWELL: u32 = 3;

/// The spreads of a recording's dwells, grouped by their sample count and length.
#[derive(Debug, Clone)]
pub struct SampleSpread {
    groups: Vec<Group>,
}

#[derive(Debug, Clone)]
struct Group {
    samples: u32,
    dwell_s: f64,
    dwells: usize,
    sum_var: f64,
}

impl SampleSpread {
    /// Dwells of one sample or of no spread say nothing of it and are left out.
    pub fn new(spreads: &[Spread]) -> SampleSpread {
        let mut groups: Vec<Group> = Vec::new();
        for s in spreads.iter().filter(|s| s.tells()) {
            let var = s.sd_dph * s.sd_dph;
            match groups
                .iter_mut()
                .find(|g| g.samples == s.samples && g.dwell_s == s.dwell_s)
            {
                Some(g) => {
                    g.dwells += 1;
                    g.sum_var += var;
                }
                None => groups.push(Group {
                    samples: s.samples,
                    dwell_s: s.dwell_s,
                    dwells: 1,
                    sum_var: var,
                }),
            }
        }
        SampleSpread { groups }
    }

    /// The degrees of freedom they count for.
    pub fn count(&self) -> usize {
        self.groups.iter().map(|g| g.dwells * dof(g.samples)).sum()
    }

    /// Their part of the likelihood under `m`; `None` where `m` gives the samples no spread.
    pub fn part(&self, m: &NoiseModel) -> Option<Part> {
        let mut part = Part {
            log_det: 0.0,
            quad: 0.0,
            count: 0,
        };
        for g in &self.groups {
            let e = expected_var(m, g.samples, g.dwell_s);
            if e.is_nan() || e <= 0.0 {
                return None;
            }
            let k = dof(g.samples);
            part = part.plus(Part {
                log_det: (g.dwells * k) as f64 * e.ln(),
                quad: k as f64 * g.sum_var / e,
                count: g.dwells * k,
            });
        }
        Some(part)
    }
}

/// The residual degrees of freedom of the dwell means from which on their own scatter
/// measures the white level, and the spread is not used.
pub const FEW_DOF: usize = 6;

/// The spreads of `rows` (each with its dwell's length) that have one, for a fit that leaves the dwell means `dof()` residual
/// degrees of freedom; none from [`FEW_DOF`] on, or when any row has quarter means (they show
/// the short-time noise at the scale of the dwell and are not thrown by filtered samples).
/// `dof` is asked only where there are spreads: `nf diagnose` builds its design for it.
pub fn of_rows<'a>(rows: impl Iterator<Item = (&'a Row, f64)> + Clone, dof: impl FnOnce() -> usize) -> Vec<Spread> {
    if rows.clone().any(|(r, _)| r.quarters_dph.is_some()) {
        return Vec::new();
    }
    let spreads: Vec<Spread> = rows
        .filter_map(|(r, dwell_s)| {
            Some(Spread {
                sd_dph: r.rate_sd_dph?,
                samples: r.samples?,
                dwell_s,
            })
        })
        .filter(Spread::tells)
        .collect();
    if spreads.is_empty() || dof() >= FEW_DOF {
        return Vec::new();
    }
    spreads
}

/// The chance, either way, below which the dwell means' scatter is said to disagree with the
/// spread: a spread written as the mean's standard error or in deg/s (off by the samples'
/// count or 3600^2 in variance) is mostly caught even with a single residual degree of
/// freedom (the standard error of 400 samples in 84 % of runs); a filtered gyro's (1.35 to 2
/// times small in variance) is not.
pub const AGREE: f64 = 1e-4;

/// What a run's dwell means and their samples' spread say of a dwell mean's white noise.
#[derive(Debug, Clone, PartialEq)]
pub struct Checked {
    /// The spreads to use: none where they disagree with the dwell means.
    pub spreads: Vec<Spread>,
    /// Where they disagree: the dwell means' least-squares variance over the white variance
    /// the spreads give a dwell mean (`sd^2 / samples`, averaged).
    pub refused_ratio: Option<f64>,
}

/// `spreads` checked against the least-squares fit of the dwell means `y ~ cols` (no fit
/// with a residual degree of freedom: nothing to check them by).
pub fn checked(spreads: Vec<Spread>, cols: &[Vec<f64>], y: &[f64]) -> Checked {
    let fit = linfit::fit(cols, y).filter(|_| !spreads.is_empty());
    let Some(ls) = fit else {
        return Checked {
            spreads,
            refused_ratio: None,
        };
    };
    let white: f64 = spreads
        .iter()
        .map(|s| s.sd_dph * s.sd_dph / f64::from(s.samples))
        .sum::<f64>()
        / spreads.len() as f64;
    let ratio = ls.rss / ls.dof as f64 / white;
    let k = ls.dof as f64;
    let upper = chi2_sf(ratio * k, k);
    if upper.min(1.0 - upper) < AGREE / 2.0 {
        Checked {
            spreads: Vec::new(),
            refused_ratio: Some(ratio),
        }
    } else {
        Checked {
            spreads,
            refused_ratio: None,
        }
    }
}

fn dof(samples: u32) -> usize {
    (samples - 1).min(DOF_PER_DWELL) as usize
}

/// The expected square of a dwell's sample standard deviation under `m`: `n / (n - 1)` times
/// a sample's variance less the dwell mean's, for `n` samples; exact for the generalised
/// covariances of flicker and walk too (the spread is a contrast).
pub fn expected_var(m: &NoiseModel, samples: u32, dwell_s: f64) -> f64 {
    let n = f64::from(samples);
    let ts = dwell_s / n;
    n / (n - 1.0) * (m.mean_cov(0.0, ts, ts, true) - m.mean_cov(0.0, dwell_s, dwell_s, true))
}

/// A dwell's sample standard deviation drawn under `m` for its `samples`, at least 2 (the
/// chi-square of `samples - 1` degrees of freedom, by Wilson and Hilferty's cube past 30).
pub fn draw(rng: &mut Rng, m: &NoiseModel, samples: u32, dwell_s: f64) -> f64 {
    let samples = samples.max(2);
    let nu = f64::from(samples - 1);
    let chi2 = if samples <= 31 {
        (1..samples).map(|_| rng.gauss().powi(2)).sum::<f64>()
    } else {
        let c = 2.0 / (9.0 * nu);
        nu * (1.0 - c + rng.gauss() * c.sqrt()).max(0.0).powi(3)
    };
    (expected_var(m, samples, dwell_s) * chi2 / nu).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_samples_spread_as_the_density_says() {
        // 0.01 deg/h for a 2 s mean: over 400 samples each has 0.2 deg/h.
        let m = NoiseModel::white(0.01, 2.0);
        assert!((expected_var(&m, 400, 2.0) / 0.04 - 1.0).abs() < 1e-9);
        let mut rng = Rng::new(3);
        for samples in [2, 20, 400] {
            let e = expected_var(&m, samples, 2.0);
            let mean: f64 = (0..4000).map(|_| draw(&mut rng, &m, samples, 2.0).powi(2)).sum::<f64>() / 4000.0;
            assert!((mean / e - 1.0).abs() < 0.05, "{samples} samples: {mean} against {e}");
        }
    }

    #[test]
    fn flicker_adds_the_same_spread_for_every_octave_of_samples() {
        let white = NoiseModel::white(0.01, 2.0);
        let flicker = NoiseModel {
            arw_deg_rth: 0.0,
            bias_instability_dph: 0.5,
            ..white
        };
        let both = NoiseModel {
            bias_instability_dph: 0.5,
            ..white
        };
        let e = |m: &NoiseModel, n: u32| expected_var(m, n, 2.0);
        assert!((e(&both, 400) - e(&white, 400) - e(&flicker, 400)).abs() < 1e-12);
        // 1/f noise: equal power in every octave, so each doubling of the samples adds the same.
        let (a, b) = (e(&flicker, 400) - e(&flicker, 200), e(&flicker, 800) - e(&flicker, 400));
        assert!(a > 0.0 && (b / a - 1.0).abs() < 0.05, "{a} {b}");
    }

    #[test]
    fn the_part_profiles_to_the_white_level_with_three_dof_a_dwell() {
        let m = NoiseModel::white(1.0, 1.0);
        let spreads = [
            Spread {
                sd_dph: 0.3,
                samples: 100,
                dwell_s: 1.0,
            },
            Spread {
                sd_dph: 0.5,
                samples: 100,
                dwell_s: 1.0,
            },
            Spread {
                sd_dph: 9.0,
                samples: 1,
                dwell_s: 1.0,
            },
            Spread {
                sd_dph: 0.0,
                samples: 50,
                dwell_s: 1.0,
            },
        ];
        let spread = SampleSpread::new(&spreads);
        let part = spread.part(&m).unwrap();
        assert_eq!((spread.count(), part.count), (6, 6), "two dwells count, three dof each");
        // The white level that fits (a 1 s mean's variance): the mean sample variance over
        // the 100 samples.
        let (_, w) = part.profiled().unwrap();
        let want = (0.09 + 0.25) / 2.0 / 100.0;
        assert!((w / want - 1.0).abs() < 1e-9, "{w} {want}");
    }

    #[test]
    fn a_spread_that_disagrees_with_the_dwell_means_is_left_out() {
        // Four positions (one residual degree of freedom), white dwell means of 0.03 deg/h,
        // 400 samples of 0.6 deg/h each: as written, and as the mean's standard error.
        let gamma = [0.0f64, 90.0, 180.0, 270.0];
        let cols = vec![
            vec![1.0; 4],
            gamma.iter().map(|g| g.to_radians().cos()).collect(),
            gamma.iter().map(|g| g.to_radians().sin()).collect(),
        ];
        let spreads = |sd_dph: f64| {
            vec![
                Spread {
                    sd_dph,
                    samples: 400,
                    dwell_s: 1.0
                };
                4
            ]
        };
        let mut rng = Rng::new(11);
        let (mut kept, mut caught) = (0, 0);
        for _ in 0..2000 {
            let y: Vec<f64> = cols[1].iter().map(|c| 5.0 * c + 0.7 + 0.03 * rng.gauss()).collect();
            kept += checked(spreads(0.6), &cols, &y).refused_ratio.is_none() as usize;
            let c = checked(spreads(0.03), &cols, &y);
            if c.refused_ratio.is_some() {
                assert!(c.spreads.is_empty());
                caught += 1;
            }
        }
        // 1e-4 either way: none of 2000 expected. One dof: the standard error's 400 times too
        // small a variance is missed where the residual's chi-square falls under 0.04.
        assert!(kept >= 1998, "{kept}");
        assert!((1550..1800).contains(&caught), "{caught}");
        // As many positions as unknowns: nothing to check by.
        let c = checked(
            spreads(0.03),
            &[cols[0][..3].to_vec(), cols[1][..3].to_vec(), cols[2][..3].to_vec()],
            &[1.0, 2.0, 3.0],
        );
        assert_eq!((c.spreads.len(), c.refused_ratio), (4, None));
    }
}
