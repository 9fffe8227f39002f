//! The fit's test case: dwell means of a level instrument at the paper's latitude, with a bias
//! and white noise from a fixed seed. The same file builds them on the MCU and on the host
//! (`tests/qemu.rs`), in `f64` and then converted, so both fit the same numbers.

use nf_model::fit::Obs;
use nf_model::rng::Rng;
use nf_model::{EARTH_RATE_DPH, Float};

/// Positions over the turn: the size whose instruction count the issue asks for.
pub const N: usize = 180;
pub const LATITUDE_DEG: f64 = 43.8;
pub const PSI_DEG: f64 = 65.5;
const BIAS_DPH: f64 = 0.7;
/// White noise of a dwell mean.
const NOISE_DPH: f64 = 0.005;
const SEED: u64 = 10;

/// The `N` dwell means, 2.3 s apart.
pub fn observations<F: Float>() -> [Obs<F>; N] {
    let mut rng = Rng::new(SEED);
    let amplitude = EARTH_RATE_DPH * Float::cos(LATITUDE_DEG.to_radians());
    let f = |x: f64| F::from(x).expect("finite values convert");
    core::array::from_fn(|i| {
        let gamma_deg = i as f64 * 360.0 / N as f64;
        let rate = amplitude * Float::cos((gamma_deg + PSI_DEG).to_radians()) + BIAS_DPH + NOISE_DPH * rng.gauss();
        Obs {
            gamma_deg: f(gamma_deg),
            t_s: f(i as f64 * 2.3),
            rate_dph: f(rate),
            tilt_x_deg: None,
            weight: F::one(),
        }
    })
}
