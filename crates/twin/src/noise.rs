//! The gyro's noise in continuous time, read by each sample as its mean over the sample
//! period: white (Gaussian or Student-t) per sample, and coloured bias terms that run on
//! through moves and gaps.
//!
//! Flicker is made by a bank of first-order Gauss-Markov processes whose correlation times are
//! spaced three per decade with equal variances: their Lorentzian spectra add up to `h / f`
//! from a decade above the sample rate to a month (Keshner's construction). This is independent of
//! `nf_model::noise`, which states the flicker covariance in closed form; the tests compare them.

use crate::bridge::{self, WindowRead};
use crate::gm_process::GaussMarkov;
use nf_model::noise::NoiseModel;
use nf_model::rng::Rng;

/// Correlation-time ratio between neighbours of the flicker bank.
const BANK_RATIO: f64 = 2.154_434_690_031_884; // 10^(1/3)
/// The longest correlation time of the bank, s: far beyond any run or log.
const BANK_TAU_MAX_S: f64 = 3.0e6;
/// A slow bank member is brought up to date when its time has moved this fraction of tau.
const LAZY_FRACTION: f64 = 0.02;

/// Noise state of one gyro.
#[derive(Debug, Clone)]
pub struct GyroNoise {
    model: NoiseModel,
    rng: Rng,
    /// Draws within a sample period, apart from `rng`, so that the steps' draws do not
    /// depend on how the samples read them.
    within: Rng,
    bank: Vec<GaussMarkov>,
    /// The flicker members faster than the sample rate, stepped at every sample from
    /// `within`: a sample's mean over its period holds their spectrum's share.
    sub_sample: Vec<GaussMarkov>,
    gm: GaussMarkov,
    walk: f64,
    at_s: f64,
}

impl GyroNoise {
    /// Starts the stationary terms in their stationary distribution at time 0. The flicker
    /// bank reaches a decade beyond `sample_rate_hz`.
    pub fn new(model: NoiseModel, sample_rate_hz: f64, seed: u64) -> Self {
        let mut rng = Rng::new(seed ^ 0x5EED_0F40_15E0);
        let mut within = Rng::new(seed ^ 0x3A4D_0F5A_3B1E);
        // Equal variances 2 h ln(r) give a PSD h / f in the band the bank covers.
        let bank_var = 2.0 * model.flicker_h() * BANK_RATIO.ln();
        let fastest = 1.0 / (2.0 * std::f64::consts::PI * sample_rate_hz.max(1e-3));
        let members = |rng: &mut Rng, from: f64, to: f64| {
            let taus = std::iter::successors(Some(from), |t| Some(t * BANK_RATIO)).take_while(|&t| t < to);
            let mut bank = Vec::new();
            if bank_var > 0.0 {
                for tau in taus {
                    bank.push(GaussMarkov::new(bank_var, tau, bank_var.sqrt() * rng.gauss()));
                }
            }
            bank
        };
        let bank = members(&mut rng, fastest, BANK_TAU_MAX_S);
        // The decade below the sample rate's member: three more.
        let sub_sample = members(&mut within, fastest / 10.0, fastest / 1.5);
        let (s, tau) = (model.gm_sigma_dph, model.gm_tau_s);
        let gm = GaussMarkov::new(s * s, tau, s * rng.gauss());
        GyroNoise {
            model,
            rng,
            within,
            bank,
            sub_sample,
            gm,
            walk: 0.0,
            at_s: 0.0,
        }
    }

    pub fn model(&self) -> &NoiseModel {
        &self.model
    }

    /// The coloured bias (deg/h) as a sample ending at `t_s` reads it: its mean over the last
    /// `period_s` (or since the previous sample, if that is shorter). Time only moves forward.
    pub fn bias_dph(&mut self, t_s: f64, period_s: f64) -> f64 {
        let dt = t_s - self.at_s;
        if dt <= 0.0 {
            let bank = self.bank.iter().chain(&self.sub_sample);
            return self.walk + self.gm.value + bank.map(|m| m.value).sum::<f64>();
        }
        let w = period_s.min(dt);
        let mut read = WindowRead::default();
        let k = self.model.rrw_dph_rts();
        let walk = self.walk + k * dt.sqrt() * self.rng.gauss();
        if k > 0.0 {
            read = read.plus(bridge::random_walk(k, dt, w).read(self.walk, walk));
        }
        self.walk = walk;
        if self.model.gm_sigma_dph > 0.0 {
            read = read.plus(self.gm.advance(t_s, w, self.rng.gauss()));
        }
        for m in &mut self.bank {
            if t_s - m.at_s >= LAZY_FRACTION * m.tau_s || m.tau_s < 50.0 * dt {
                read = read.plus(m.advance(t_s, w, self.rng.gauss()));
            } else {
                // Slow against the time since its last step: constant over the window.
                read.mean += m.value;
            }
        }
        for m in &mut self.sub_sample {
            read = read.plus(m.advance(t_s, w, self.within.gauss()));
        }
        self.at_s = t_s;
        // The windows' bridges are independent given the ends: one draw for their sum.
        read.mean + read.var.sqrt() * self.within.gauss()
    }

    /// White noise of one sample (deg/h) taken every `period_s`: ARW density times
    /// `sqrt(rate)`, Gaussian or Student-t of the same variance.
    pub fn white_dph(&mut self, period_s: f64) -> f64 {
        let sd = self.model.white_dph_rts() / period_s.sqrt();
        let nu = self.model.student_t_dof;
        if nu > 0.0 {
            let chi2 = 2.0 * gamma(&mut self.rng, nu / 2.0);
            sd * self.rng.gauss() / (chi2 / nu).sqrt() * ((nu - 2.0) / nu).sqrt()
        } else {
            sd * self.rng.gauss()
        }
    }
}

/// Gamma(shape, 1) variate for shape >= 1 (Marsaglia and Tsang).
fn gamma(rng: &mut Rng, shape: f64) -> f64 {
    let d = shape - 1.0 / 3.0;
    let c = 1.0 / (9.0 * d).sqrt();
    loop {
        let x = rng.gauss();
        let v = (1.0 + c * x).powi(3);
        if v <= 0.0 {
            continue;
        }
        let u = rng.unit();
        if u.ln() < 0.5 * x * x + d - d * v + d * v.ln() {
            return d * v;
        }
    }
}

/// Output quantisation: the integrated angle is read in steps of `Q sqrt(12)` arcsec and the
/// rate is the change of the reading over the sample period.
#[derive(Debug, Clone, Default)]
pub struct Quantiser {
    angle_arcsec: f64,
    last_steps: f64,
}

impl Quantiser {
    /// Counts on through `angle_arcsec` turned between the samples read (a move's): the
    /// next sample's remainder is then the gap's, not the last dwell's.
    pub fn run_on(&mut self, q_arcsec: f64, angle_arcsec: f64) {
        if q_arcsec <= 0.0 {
            return;
        }
        self.angle_arcsec += angle_arcsec;
        self.last_steps = (self.angle_arcsec / step(q_arcsec)).floor();
    }

    pub fn output_dph(&mut self, q_arcsec: f64, rate_dph: f64, period_s: f64) -> f64 {
        if q_arcsec <= 0.0 {
            return rate_dph;
        }
        // deg/h times s is arcsec.
        self.angle_arcsec += rate_dph * period_s;
        let step = step(q_arcsec);
        let steps = (self.angle_arcsec / step).floor();
        let out = (steps - self.last_steps) * step / period_s;
        self.last_steps = steps;
        out
    }
}

/// The angle the quantiser reads in, arcsec: `Q sqrt(12)`.
fn step(q_arcsec: f64) -> f64 {
    q_arcsec * 12f64.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Overlapping Allan variance of a sampled series (written here, apart from the tool's).
    fn avar(x: &[f64], m: usize) -> f64 {
        let c: Vec<f64> = std::iter::once(0.0)
            .chain(x.iter().scan(0.0, |s, v| {
                *s += v;
                Some(*s)
            }))
            .collect();
        let terms = x.len() + 1 - 2 * m;
        let sum: f64 = (0..terms)
            .map(|k| {
                let d = (c[k + 2 * m] - 2.0 * c[k + m] + c[k]) / m as f64;
                d * d
            })
            .sum();
        sum / (2.0 * terms as f64)
    }

    fn series(model: NoiseModel, fs: f64, n: usize, seed: u64) -> Vec<f64> {
        let mut g = GyroNoise::new(model, fs, seed);
        (0..n)
            .map(|i| g.bias_dph(i as f64 / fs, 1.0 / fs) + g.white_dph(1.0 / fs))
            .collect()
    }

    #[test]
    fn flicker_bank_has_the_closed_form_allan_floor() {
        let m = NoiseModel {
            bias_instability_dph: 0.01,
            ..NoiseModel::WHITE_NONE
        };
        // Average over seeds: at tau = 10 s and 100 s, within 8 % of 0.664 B.
        for (tau, n) in [(10.0, 20_000usize), (100.0, 40_000)] {
            let fs = 10.0;
            let m_s = (tau * fs) as usize;
            let mean: f64 = (0..12).map(|s| avar(&series(m, fs, n, s), m_s)).sum::<f64>() / 12.0;
            let want = m.allan_var(tau);
            assert!((mean / want - 1.0).abs() < 0.08, "tau {tau}: {mean} vs {want}");
        }
    }

    #[test]
    fn samples_read_the_bias_as_its_mean_over_their_period() {
        // At a few sample periods the difference shows: point values read 1.42, 1.21 and
        // 1.10 times the deviation at 1, 2 and 4 periods under flicker, 1.68, 1.48 and 1.40
        // under a Gauss-Markov term of 0.3 periods.
        let flicker = NoiseModel {
            bias_instability_dph: 0.01,
            ..NoiseModel::WHITE_NONE
        };
        let gm = NoiseModel {
            gm_sigma_dph: 0.01,
            gm_tau_s: 0.3,
            ..NoiseModel::WHITE_NONE
        };
        for (name, m) in [("flicker", flicker), ("Gauss-Markov", gm)] {
            for m_s in [1usize, 2, 4] {
                let mean: f64 = (0..12).map(|s| avar(&series(m, 1.0, 20_000, s), m_s)).sum::<f64>() / 12.0;
                let ratio = (mean / m.allan_var(m_s as f64)).sqrt();
                println!("{name} at {m_s} s: {ratio:.3} of the model's deviation");
                assert!((ratio - 1.0).abs() < 0.05, "{name} at {m_s} s: {ratio}");
            }
        }
    }

    #[test]
    fn white_random_walk_and_gauss_markov_match_their_allan_variances() {
        let m = NoiseModel {
            arw_deg_rth: 0.002,
            rrw_dph_rth: 0.05,
            gm_sigma_dph: 0.01,
            gm_tau_s: 30.0,
            ..NoiseModel::WHITE_NONE
        };
        let fs = 20.0;
        for tau in [0.5, 5.0, 50.0] {
            let m_s = (tau * fs) as usize;
            let mean: f64 = (0..10).map(|s| avar(&series(m, fs, 40_000, s), m_s)).sum::<f64>() / 10.0;
            let want = m.allan_var(tau);
            assert!((mean / want - 1.0).abs() < 0.1, "tau {tau}: {mean} vs {want}");
        }
    }

    #[test]
    fn student_t_keeps_the_variance_and_fattens_the_tails() {
        let m = NoiseModel {
            arw_deg_rth: 0.01,
            student_t_dof: 4.0,
            ..NoiseModel::WHITE_NONE
        };
        let mut g = GyroNoise::new(m, 100.0, 5);
        let x: Vec<f64> = (0..200_000).map(|_| g.white_dph(0.01)).collect();
        let sd = m.white_dph_rts() / 0.01f64.sqrt();
        let var = x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64;
        assert!((var / (sd * sd) - 1.0).abs() < 0.05, "{var}");
        // A normal has 0.27 % beyond 3 sd; t(4) scaled to unit variance about 1.4 %.
        let beyond = x.iter().filter(|v| v.abs() > 3.0 * sd).count() as f64 / x.len() as f64;
        assert!(beyond > 0.008, "{beyond}");
    }

    #[test]
    fn quantiser_adds_its_allan_term_and_keeps_the_mean() {
        let (fs, qa) = (100.0, 3.0);
        let mut q = Quantiser::default();
        let mut g = GyroNoise::new(NoiseModel::white(5000.0, 0.01), fs, 2);
        let (inp, out): (Vec<f64>, Vec<f64>) = (0..100_000)
            .map(|_| {
                let r = 12.3 + g.white_dph(1.0 / fs);
                (r, q.output_dph(qa, r, 1.0 / fs))
            })
            .unzip();
        let err: Vec<f64> = out.iter().zip(&inp).map(|(o, i)| o - i).collect();
        assert!((err.iter().sum::<f64>() / err.len() as f64).abs() < 1e-2);
        let m = NoiseModel {
            quantization_arcsec: qa,
            ..NoiseModel::WHITE_NONE
        };
        for k in [1usize, 10, 100] {
            let want = m.allan_var(k as f64 / fs);
            assert!(
                (avar(&err, k) / want - 1.0).abs() < 0.1,
                "{k}: {} vs {want}",
                avar(&err, k)
            );
        }
    }
}
