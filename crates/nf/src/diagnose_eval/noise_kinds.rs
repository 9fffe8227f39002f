//! The kinds of gyro noise the suite's recordings have, each sized against the white noise of a
//! dwell mean, `s`, by a ratio drawn log-uniform per recording.

use super::cases::{Case, DwellShift, log_uniform};
use nf_twin::Rng;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseKind {
    White,
    /// Bias instability B = ratio * s (flicker).
    Flicker,
    /// Rate random walk whose wander over the run, K sqrt(T), is ratio * s.
    RandomWalk,
    /// Gauss-Markov bias with tau between T/10 and T, whose change over the run has sd ratio * s.
    GaussMarkov,
    /// Student-t (3 dof) samples, and a Student-t (3 dof) shift of each dwell of sd ratio * s:
    /// the samples alone average to Gaussian dwell means, the shifts make the dwell-level tails
    /// heavy (as from shocks and vibration bursts).
    HeavyTails,
}

impl NoiseKind {
    pub fn name(self) -> &'static str {
        match self {
            NoiseKind::White => "white",
            NoiseKind::Flicker => "flicker",
            NoiseKind::RandomWalk => "random_walk",
            NoiseKind::GaussMarkov => "gauss_markov",
            NoiseKind::HeavyTails => "heavy_tails",
        }
    }

    /// The ratio of this recording's noise term to `s`: 0.1 to 10 for the coloured terms. The
    /// dwell tails take 0.3 to 3: below that they hardly show, above it they swamp every effect.
    pub fn draw_ratio(self, rng: &mut Rng) -> f64 {
        match self {
            NoiseKind::HeavyTails => log_uniform(rng, 0.3, 3.0),
            _ => log_uniform(rng, 0.1, 10.0),
        }
    }

    /// Adds this kind's term at `ratio` times `s` to a case with white noise.
    pub fn apply(self, case: &mut Case, ratio: f64, rng: &mut Rng) {
        let size = ratio * case.sigma();
        let run_s = case.duration_s();
        let noise = &mut case.twin.noise;
        match self {
            NoiseKind::White => {}
            NoiseKind::Flicker => noise.bias_instability_dph = size,
            // K in deg/h per sqrt(s), the model's unit per sqrt(h).
            NoiseKind::RandomWalk => noise.rrw_dph_rth = size / run_s.sqrt() * 3600f64.sqrt(),
            NoiseKind::GaussMarkov => {
                let tau = log_uniform(rng, run_s / 10.0, run_s);
                // The difference of the bias a run apart has variance 2 sigma^2 (1 - e^(-T/tau)).
                noise.gm_sigma_dph = size / (2.0 * (1.0 - (-run_s / tau).exp())).sqrt();
                noise.gm_tau_s = tau;
            }
            NoiseKind::HeavyTails => {
                noise.student_t_dof = 3.0;
                case.dwell_shifts = (0..case.visits())
                    .map(|visit| DwellShift {
                        visit,
                        dph: size * student_t3(rng),
                    })
                    .collect();
            }
        }
    }
}

/// Student-t with 3 degrees of freedom, scaled to unit variance.
fn student_t3(rng: &mut Rng) -> f64 {
    let chi2: f64 = (0..3).map(|_| rng.gauss().powi(2)).sum();
    rng.gauss() / (chi2 / 3.0).sqrt() / 3f64.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose_eval::cases::{Site, random_case};
    use nf_model::order::Order;

    /// The gyro noise of each dwell mean of recordings with `kind` at `ratio`: the rate less
    /// the twin's own rate at the encoder angle. Short runs at 100 Hz keep the test quick.
    fn dwell_noise(kind: NoiseKind, ratio: f64, recordings: u64) -> Vec<Vec<f64>> {
        (0..recordings)
            .map(|seed| {
                let mut rng = Rng::new(100 + seed);
                let mut case = random_case(&mut rng, &Site::ORDINARY, Order::Sequential);
                (case.twin.sample_rate_hz, case.run.sample_rate_hz) = (100, 100);
                kind.apply(&mut case, ratio, &mut rng);
                let s = case.sigma();
                let rec = case.record();
                let truth = case.twin.instrument;
                rec.rows
                    .iter()
                    .map(|r| (r.rate_dph - truth.rate_dph(r.encoder_deg)) / s)
                    .collect()
            })
            .collect()
    }

    /// Overlapping Allan variance of dwell means, `m` dwells per cluster, pooled over runs.
    fn avar(runs: &[Vec<f64>], m: usize) -> f64 {
        let (mut sum, mut terms) = (0.0, 0);
        for x in runs {
            for k in 0..x.len() + 1 - 2 * m {
                let a: f64 = x[k..k + m].iter().sum();
                let b: f64 = x[k + m..k + 2 * m].iter().sum();
                sum += ((b - a) / m as f64).powi(2);
                terms += 1;
            }
        }
        sum / (2.0 * terms as f64)
    }

    /// Allan deviation at 8 dwells over that at 1: 1/sqrt(8) = 0.35 for white noise.
    fn flattening(kind: NoiseKind) -> f64 {
        let runs = dwell_noise(kind, 10.0, 6);
        (avar(&runs, 8) / avar(&runs, 1)).sqrt()
    }

    #[test]
    fn coloured_kinds_flatten_or_raise_the_dwell_allan_deviation() {
        let white = flattening(NoiseKind::White);
        assert!((0.25..0.45).contains(&white), "white {white}");
        let flicker = flattening(NoiseKind::Flicker);
        assert!((0.75..1.3).contains(&flicker), "flicker {flicker}");
        for kind in [NoiseKind::RandomWalk, NoiseKind::GaussMarkov] {
            let r = flattening(kind);
            assert!(r > 1.0, "{}: {r}", kind.name());
        }
    }

    /// Share of the values beyond 3 robust (median absolute deviation) standard deviations.
    fn tail_share(runs: &[Vec<f64>]) -> f64 {
        let mut x: Vec<f64> = runs.iter().flat_map(|r| r.iter().copied()).collect();
        let mut abs: Vec<f64> = x.iter().map(|v| v.abs()).collect();
        abs.sort_by(f64::total_cmp);
        let sd = abs[abs.len() / 2] / 0.6745;
        x.retain(|v| v.abs() > 3.0 * sd);
        x.len() as f64 / abs.len() as f64
    }

    #[test]
    fn heavy_tails_show_in_the_dwell_means() {
        // A normal puts 0.27 % beyond 3 sd; with dwell shifts of 3 s it is 3.2 % (2000 dwells here).
        let white = tail_share(&dwell_noise(NoiseKind::White, 3.0, 40));
        let heavy = tail_share(&dwell_noise(NoiseKind::HeavyTails, 3.0, 40));
        assert!(white < 0.008, "white {white}");
        assert!(heavy > 0.016, "heavy {heavy}");
    }

    #[test]
    fn student_t3_has_unit_variance() {
        let mut rng = Rng::new(3);
        let n = 400_000;
        let var = (0..n).map(|_| student_t3(&mut rng).powi(2)).sum::<f64>() / n as f64;
        // The fourth moment is infinite: the sample variance converges slowly.
        assert!((var - 1.0).abs() < 0.1, "{var}");
    }
}
