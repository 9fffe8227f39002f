//! Stepper motor through a step/dir driver, with a trapezoidal speed profile; the pulses come
//! from a hardware timer (`step_train`).

/// Why a move failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MotorError {
    /// A step or direction pin could not be driven.
    Pin,
    /// The move was stopped on request.
    Stopped,
}

/// How often a move asks whether to stop, microseconds of stepping.
pub(crate) const STOP_CHECK_US: u32 = 20_000;

/// The motor and its profile.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// Steps (microsteps through the gear) per shaft turn.
    pub steps_per_rev: u32,
    /// Start and stop speed, steps/s.
    pub start_sps: f32,
    /// Cruise speed, steps/s.
    pub max_sps: f32,
    /// Acceleration, steps/s^2.
    pub accel_sps2: f32,
    /// Width of the step pulse, microseconds.
    pub pulse_us: u32,
}

impl Default for Config {
    /// 200-step motor, 16 microsteps, 10:1 gear; a 5 deg move takes about 0.2 s.
    fn default() -> Self {
        Config {
            steps_per_rev: 32_000,
            start_sps: 400.0,
            max_sps: 4_000.0,
            accel_sps2: 40_000.0,
            pulse_us: 2,
        }
    }
}

impl Config {
    /// Microseconds from the start of step `i` to the next, of a move of `steps` steps:
    /// speed `sqrt(v0^2 + 2 a k)` with `k` the steps to the nearer end, capped at `max_sps`.
    pub fn interval_us(&self, i: u32, steps: u32) -> u32 {
        let k = i.min(steps.saturating_sub(1).saturating_sub(i)) as f32;
        // The FPU's VSQRT on the MCU (libm's sqrtf is software), in the step timer's interrupt.
        let v = nf_model::sqrt(self.start_sps * self.start_sps + 2.0 * self.accel_sps2 * k).min(self.max_sps);
        (1e6 / v.max(1.0)) as u32
    }
}

/// Something that turns the shaft by a number of steps (positive: counter-clockwise).
pub trait Motor {
    /// Moves, asking `stop` between steps: when it says so, the motor stops at once and
    /// returns [`MotorError::Stopped`].
    async fn move_steps(&mut self, steps: i32, stop: &mut dyn FnMut() -> bool) -> Result<(), MotorError>;
    fn steps_per_rev(&self) -> u32;
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    #[test]
    fn profile_is_symmetric_trapezoid() {
        let c = Config::default();
        let n = 444; // 5 deg
        let iv: Vec<u32> = (0..n).map(|i| c.interval_us(i, n)).collect();
        assert_eq!(iv[0], 2500);
        assert_eq!(iv[n as usize - 1], 2500);
        assert_eq!(*iv.iter().min().unwrap(), 250);
        for i in 0..n as usize {
            assert_eq!(iv[i], iv[n as usize - 1 - i]);
        }
        // A 5 deg move takes about 0.2 s.
        let total: u64 = iv.iter().map(|&v| v as u64).sum();
        assert!(total < 250_000, "{total}");
    }
}
