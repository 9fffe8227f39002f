//! Replicates of a recording drawn from a noise model on the recording's own schedule, for
//! the parametric bootstraps of `nf fit`'s sigma and of `nf diagnose`'s drift tests.

use crate::gls::Cov;
use crate::noise_est::Data;
use crate::quarter_contrasts::Quarters;
use crate::sample_spread::{self, Spread};
use nf_model::noise::NoiseModel;
use nf_model::rng::Rng;

/// Noise for the dwells of a recording: with quarters, the four quarter means of every dwell
/// drawn jointly (the dwell mean is their mean); without, the dwell means, and the samples'
/// spread where the recording has it.
pub struct Draw {
    cov: Cov,
    /// The dwells with quarters (the first ones: a recording has them on every row or none).
    quarters: usize,
    model: NoiseModel,
    /// Each dwell's length.
    dwells_s: Vec<f64>,
    /// The samples and dwell of each spread.
    spread: Vec<(u32, f64)>,
}

/// One replicate: the dwell means, the quarters and the spreads (of as many dwells as the
/// recording has them).
pub struct Replica {
    pub y: Vec<f64>,
    pub quarters: Vec<Quarters>,
    pub spread: Vec<Spread>,
}

impl Draw {
    pub fn new(data: &Data<'_>, model: &NoiseModel) -> Option<Draw> {
        let cov = if data.quarters.is_empty() {
            Cov::of_windows(model, data.t_s, data.dwells_s)?
        } else {
            let (t, q): (Vec<f64>, Vec<f64>) = data
                .t_s
                .iter()
                .zip(data.dwells_s)
                .flat_map(|(&t, &d)| (0..4).map(move |k| (t + (k as f64 - 1.5) * d / 4.0, d / 4.0)))
                .unzip();
            Cov::of_windows(model, &t, &q)?
        };
        Some(Draw {
            cov,
            quarters: data.quarters.len(),
            model: *model,
            dwells_s: data.dwells_s.to_vec(),
            spread: data.spread.iter().map(|s| (s.samples, s.dwell_s)).collect(),
        })
    }

    pub fn replicate(&self, rng: &mut Rng, fitted: &[f64]) -> Replica {
        let n = fitted.len();
        let m = if self.quarters == 0 { n } else { 4 * n };
        let v = self.cov.colour(&(0..m).map(|_| rng.gauss()).collect::<Vec<_>>());
        let spread = self
            .spread
            .iter()
            .map(|&(samples, dwell_s)| Spread {
                sd_dph: sample_spread::draw(rng, &self.model, samples, dwell_s),
                samples,
                dwell_s,
            })
            .collect();
        if self.quarters == 0 {
            return Replica {
                y: fitted.iter().zip(&v).map(|(f, e)| f + e).collect(),
                quarters: Vec::new(),
                spread,
            };
        }
        let quarters: Vec<Quarters> = (0..n)
            .map(|i| Quarters {
                dph: core::array::from_fn(|k| fitted[i] + v[4 * i + k]),
                dwell_s: self.dwells_s[i],
            })
            .collect();
        Replica {
            y: quarters.iter().map(|q| q.dph.iter().sum::<f64>() / 4.0).collect(),
            quarters: quarters.into_iter().take(self.quarters).collect(),
            spread,
        }
    }
}

/// A seed from the data, so that a recording's bootstrap is the same at every run of it.
pub fn seed_of(y: &[f64]) -> u64 {
    y.iter().fold(0xcbf2_9ce4_8422_2325, |h, v| {
        (h ^ v.to_bits()).wrapping_mul(0x0100_0000_01b3)
    })
}

/// `one` of every replicate `0..replicates`, each with its own generator seeded from `seed`,
/// on every core; the replicates that give nothing are left out.
pub fn run<T: Send>(replicates: usize, seed: u64, one: impl Fn(&mut Rng) -> Option<T> + Sync) -> Vec<T> {
    let draw = |b: usize| one(&mut Rng::new(seed ^ (b as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15)));
    crate::cores::each(replicates, draw).into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replicates_carry_the_model_in_the_dwell_means_and_the_quarters() {
        // 48 dwells of 2 s, 2.5 s apart, a signal on them; 10 of them with quarters.
        let t: Vec<f64> = (0..48).map(|i| 10.0 + 2.5 * i as f64).collect();
        let fitted: Vec<f64> = (0..48).map(|i| 0.3 + 0.01 * (i as f64 / 7.0).cos()).collect();
        let some = [Quarters {
            dph: [0.0; 4],
            dwell_s: 2.0,
        }; 10];
        let dwells = [2.0; 48];
        let data = Data {
            t_s: &t,
            dwell_s: 2.0,
            dwells_s: &dwells,
            cols: &[],
            y: &fitted,
            quarters: &some,
            spread: &[],
            extra: None,
        };
        let model = NoiseModel::white(0.005, 2.0);
        let draw = Draw::new(&data, &model).unwrap();
        let mut rng = Rng::new(4);
        let (mut dwell, mut quarter, mut k) = (0.0, 0.0, 0.0);
        for _ in 0..400 {
            let Replica { y, quarters: q, .. } = draw.replicate(&mut rng, &fitted);
            assert_eq!(q.len(), 10, "as many dwells with quarters as the recording has");
            for (i, q) in q.iter().enumerate() {
                let mean = q.dph.iter().sum::<f64>() / 4.0;
                assert!((mean - y[i]).abs() < 1e-12, "a dwell mean is its quarters' mean");
                quarter += q.dph.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 3.0;
            }
            dwell += y.iter().zip(&fitted).map(|(a, b)| (a - b).powi(2)).sum::<f64>() / y.len() as f64;
            k += 1.0;
        }
        // White noise of 0.005 deg/h for a 2 s mean: a quarter mean has twice that.
        let (dwell, quarter) = ((dwell / k).sqrt(), (quarter / (10.0 * k)).sqrt());
        assert!((dwell / 0.005 - 1.0).abs() < 0.03, "dwell means: {dwell}");
        assert!((quarter / 0.010 - 1.0).abs() < 0.04, "quarters: {quarter}");
    }

    #[test]
    fn a_dwell_of_a_sixteenth_the_length_has_sixteen_times_the_white_variance() {
        let t: Vec<f64> = (0..40).map(|i| 10.0 * i as f64).collect();
        let dwells: Vec<f64> = (0..40).map(|i| if i % 2 == 0 { 0.5 } else { 8.0 }).collect();
        let quarters: Vec<Quarters> = dwells
            .iter()
            .map(|&dwell_s| Quarters { dph: [0.0; 4], dwell_s })
            .collect();
        let fitted = vec![0.0; 40];
        let data = Data {
            t_s: &t,
            dwell_s: 8.0,
            dwells_s: &dwells,
            cols: &[],
            y: &fitted,
            quarters: &quarters,
            spread: &[],
            extra: None,
        };
        let draw = Draw::new(&data, &NoiseModel::white(0.005, 8.0)).unwrap();
        let mut rng = Rng::new(5);
        let (mut short, mut long) = (0.0, 0.0);
        for _ in 0..300 {
            let r = draw.replicate(&mut rng, &fitted);
            assert_eq!(r.quarters[3].dwell_s, 8.0);
            short += r.y.iter().step_by(2).map(|v| v * v).sum::<f64>();
            long += r.y.iter().skip(1).step_by(2).map(|v| v * v).sum::<f64>();
        }
        assert!((short / long / 16.0 - 1.0).abs() < 0.1, "{}", short / long);
    }

    #[test]
    fn runs_are_repeatable_and_skip_what_gives_nothing() {
        let odd = |rng: &mut Rng| {
            let v = rng.gauss();
            (v > 0.0).then_some(v)
        };
        let a = super::run(50, 7, odd);
        assert!(a.len() > 10 && a.len() < 40, "about half kept: {}", a.len());
        assert!(a.iter().all(|v| *v > 0.0));
        let mut b = super::run(50, 7, odd);
        let mut a2 = a.clone();
        a2.sort_by(f64::total_cmp);
        b.sort_by(f64::total_cmp);
        assert_eq!(a2, b, "the same seed, the same replicates");
    }
}
