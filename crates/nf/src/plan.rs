//! Planning a run with white gyro noise: the uncertainty budget (the paper's Eq. 31 and the
//! exact model), the paper's n for a target, and a Monte Carlo check of the formula. The
//! fastest run under the real noise model is [`crate::plan_noise`]'s.

use nf_model::exact::Instrument;
use nf_model::fit::{AzimuthFit, FitConfig, Obs};
use nf_model::uncertainty::{Budget, Sigmas, min_positions_paper, propagate};
use nf_twin::Rng;

#[derive(Debug, Clone, Copy)]
pub struct Inputs {
    pub latitude_deg: f64,
    /// Gyro noise of one position's mean for a dwell of `ref_dwell_s`.
    pub gyro_dph: f64,
    pub ref_dwell_s: f64,
    pub encoder_deg: f64,
    pub tilt_deg: f64,
    pub n: u32,
    pub dwell_s: f64,
    /// Gyro misalignment for Eq. 30.
    pub gyro_elev_deg: f64,
}

impl Inputs {
    /// White noise: the dwell mean's noise goes as 1/sqrt(dwell).
    pub fn gyro_at(&self, dwell_s: f64) -> f64 {
        self.gyro_dph * (self.ref_dwell_s / dwell_s).sqrt()
    }

    pub fn sigmas(&self, dwell_s: f64) -> Sigmas<f64> {
        Sigmas {
            gyro_dph: self.gyro_at(dwell_s),
            encoder_deg: self.encoder_deg,
            tilt_deg: self.tilt_deg,
        }
    }
}

/// The paper's answer to the same question at the given dwell.
pub fn paper_n(inp: &Inputs, target_arcsec: f64) -> Option<u32> {
    min_positions_paper(
        target_arcsec,
        &inp.sigmas(inp.dwell_s),
        inp.latitude_deg,
        45.0,
        inp.gyro_elev_deg,
        100_000,
    )
}

/// Numerical propagation through the exact model on `n` equal steps.
pub fn numerical(inp: &Inputs) -> Budget<f64> {
    let gammas: Vec<f64> = (0..inp.n).map(|i| i as f64 * 360.0 / inp.n as f64).collect();
    let inst = Instrument::level(inp.latitude_deg, 45.0);
    propagate(&inst, &gammas, FitConfig::default(), &inp.sigmas(inp.dwell_s)).expect("equal steps always fit")
}

/// Monte Carlo: `runs` fits of the exact model with gyro noise, independent encoder errors and
/// a tilt of size `tilt_deg` (Gaussian per axis) in a random direction. Returns the sample
/// standard deviation of the azimuth error (arcsec) and the formula it checks: the closed form
/// with the tilt term as its RMS over directions, `tan(lat) sigma_eta`.
pub fn monte_carlo(inp: &Inputs, runs: u32, seed: u64, mut tick: impl FnMut()) -> (f64, f64) {
    let mut rng = Rng::new(seed);
    let s = inp.sigmas(inp.dwell_s);
    let mut sum2 = 0.0;
    for _ in 0..runs {
        let (tx, ty) = (inp.tilt_deg * rng.gauss(), inp.tilt_deg * rng.gauss());
        let inst = Instrument {
            tilt_deg: tx.hypot(ty),
            tilt_dir_deg: ty.atan2(tx).to_degrees(),
            bias_dph: rng.uniform(-1.0, 1.0),
            ..Instrument::level(inp.latitude_deg, rng.uniform(0.0, 360.0))
        };
        let obs: Vec<Obs<f64>> = (0..inp.n)
            .map(|i| {
                let g = i as f64 * 360.0 / inp.n as f64;
                let seen = g + s.encoder_deg * rng.gauss();
                Obs::new(seen.rem_euclid(360.0), inst.rate_dph(g) + s.gyro_dph * rng.gauss())
            })
            .collect();
        let r = AzimuthFit::fit_all(FitConfig::default(), &obs).expect("equal steps always fit");
        let e = nf_model::angle::wrap_180(r.psi_deg - inst.psi_deg) * 3600.0;
        sum2 += e * e;
        tick();
    }
    // Tilt per axis Gaussian: the first-harmonic term along the Earth-rate quadrature is one
    // axis of it, so its RMS is tan(lat) sigma_eta.
    let cf = Budget::closed_form(inp.n, &s, inp.latitude_deg);
    let formula = (cf.gyro_arcsec.powi(2) + cf.encoder_arcsec.powi(2) + cf.tilt_arcsec.powi(2)).sqrt();
    ((sum2 / runs as f64).sqrt(), formula)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs() -> Inputs {
        Inputs {
            latitude_deg: 43.8,
            gyro_dph: 0.005,
            ref_dwell_s: 2.0,
            encoder_deg: 0.001,
            tilt_deg: 0.001,
            n: 72,
            dwell_s: 2.0,
            gyro_elev_deg: 0.01,
        }
    }

    #[test]
    fn monte_carlo_agrees_with_the_formula() {
        let (mc, formula) = monte_carlo(&inputs(), 4000, 3, || {});
        // 4000 runs: the sample sd is within about 2.2% (1 sigma) of the truth.
        assert!((mc / formula - 1.0).abs() < 0.07, "{mc} vs {formula}");
    }

    #[test]
    fn numerical_propagation_matches_the_closed_form() {
        let inp = inputs();
        let num = numerical(&inp);
        let cf = Budget::closed_form(72, &inp.sigmas(2.0), 43.8);
        assert!((num.total_arcsec - cf.total_arcsec).abs() < 1e-3 * cf.total_arcsec);
    }
}
