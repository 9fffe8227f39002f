//! Step pulses timed by a hardware timer: PWM mode 2 at 1 MHz ticks, so that each period of
//! the timer ends with one STEP pulse, and the period register (ARR) and the compare register
//! (CCR) preloaded, so that the values written during one period take effect at the next. The
//! update interrupt only writes the period after next, and on the last period sets one-pulse
//! mode, which stops the counter at its end with the pin low. [`Train`] is what that
//! interrupt computes, free of any timer, so that the host tests it against a model of the
//! preload rules; [`TimedStepDir`] moves the motor with it.

use crate::stepper::{Config, Motor, MotorError, STOP_CHECK_US};
use embedded_hal::digital::OutputPin;

/// The longest period the 16-bit counter holds at 1 MHz.
const MAX_TICKS: u32 = 1 << 16;

/// Microseconds from the start of a train to its first step: the driver's direction setup
/// time after DIR changed (5 us covers the common drivers).
pub const DIR_SETUP_US: u32 = 5;

/// One period of the timer in ticks (microseconds): the pulse is its last `pulse` ticks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Period {
    /// The auto-reload value: the period is `arr + 1` ticks.
    pub arr: u16,
    /// The compare value: the pin is high from this tick to the end of the period.
    pub ccr: u16,
}

/// What the update interrupt does after a period has ended (one more pulse made).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Update {
    /// Preload the period after the one now running.
    Load(Period),
    /// The running period is the last: set one-pulse mode so that the counter stops at its end.
    Last,
    /// Every pulse is made; the counter has stopped.
    Done,
}

/// A move's step train.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Train {
    cfg: Config,
    steps: u32,
    pulses: u32,
}

/// How a train starts: the first period (loaded by an update event before the counter runs),
/// the second (preloaded), and whether the first is also the last.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Start {
    pub first: Period,
    pub second: Option<Period>,
    pub one_pulse: bool,
}

impl Train {
    /// A train of `steps` (at least one) with `cfg`'s profile.
    pub fn new(cfg: Config, steps: u32) -> Train {
        Train {
            cfg,
            steps: steps.max(1),
            pulses: 0,
        }
    }

    pub fn steps(&self) -> u32 {
        self.steps
    }

    /// Pulses made so far.
    pub fn pulses(&self) -> u32 {
        self.pulses
    }

    /// Period `k`. Step `k`'s pulse ends it, so it lasts the profile's interval before step
    /// `k` (the first, the direction's setup time), within what the counter holds and never
    /// shorter than the pulse and one low tick.
    pub fn period(&self, k: u32) -> Period {
        let pulse = self.cfg.pulse_us.clamp(1, MAX_TICKS - 2);
        let interval = match k {
            0 => DIR_SETUP_US + pulse,
            _ => self.cfg.interval_us(k - 1, self.steps),
        };
        let ticks = interval.clamp(pulse + 1, MAX_TICKS);
        Period {
            arr: (ticks - 1) as u16,
            ccr: (ticks - pulse) as u16,
        }
    }

    pub fn start(&self) -> Start {
        Start {
            first: self.period(0),
            second: (self.steps > 1).then(|| self.period(1)),
            one_pulse: self.steps == 1,
        }
    }

    /// After an update event: one more pulse was made and the next period runs.
    pub fn on_update(&mut self) -> Update {
        self.pulses = (self.pulses + 1).min(self.steps);
        let running = self.pulses;
        if running >= self.steps {
            Update::Done
        } else if running + 1 == self.steps {
            Update::Last
        } else {
            Update::Load(self.period(running + 1))
        }
    }
}

/// A timer that makes a [`Train`]'s pulses.
pub trait StepTimer {
    /// Starts the train; returns at once.
    fn start(&mut self, train: Train);
    /// Waits until the train has ended, at most `us` microseconds; whether it has.
    async fn wait_end(&mut self, us: u32) -> bool;
    /// Stops at once with the pin low.
    fn stop(&mut self);
}

/// A step/dir driver whose STEP pin is a timer's output.
pub struct TimedStepDir<T, DIR> {
    timer: T,
    dir: DIR,
    cfg: Config,
}

impl<T: StepTimer, DIR: OutputPin> TimedStepDir<T, DIR> {
    pub fn new(timer: T, dir: DIR, cfg: Config) -> Self {
        TimedStepDir { timer, dir, cfg }
    }
}

impl<T: StepTimer, DIR: OutputPin> Motor for TimedStepDir<T, DIR> {
    async fn move_steps(&mut self, steps: i32, stop: &mut dyn FnMut() -> bool) -> Result<(), MotorError> {
        if steps >= 0 {
            self.dir.set_high()
        } else {
            self.dir.set_low()
        }
        .map_err(|_| MotorError::Pin)?;
        if steps == 0 {
            return Ok(());
        }
        if stop() {
            return Err(MotorError::Stopped);
        }
        self.timer.start(Train::new(self.cfg, steps.unsigned_abs()));
        loop {
            if self.timer.wait_end(STOP_CHECK_US).await {
                return Ok(());
            }
            if stop() {
                self.timer.stop();
                return Err(MotorError::Stopped);
            }
        }
    }

    fn steps_per_rev(&self) -> u32 {
        self.cfg.steps_per_rev
    }
}

#[cfg(test)]
mod tests;
