//! A first-order Gauss-Markov process stepped exactly from sample to sample and read as its
//! mean over each sample's window. Samples keep their spacing, so a step's coefficients are
//! kept from one sample to the next.

use crate::bridge::{self, Bridge, WindowRead};

#[derive(Debug, Clone)]
pub struct GaussMarkov {
    pub tau_s: f64,
    var: f64,
    pub value: f64,
    pub at_s: f64,
    step: Step,
}

/// A step of `dt` whose window is its last `w`.
#[derive(Debug, Clone, Copy)]
struct Step {
    dt: f64,
    w: f64,
    decay: f64,
    sd: f64,
    bridge: Bridge,
}

impl GaussMarkov {
    /// Variance `var`, starting from `value` at time 0.
    pub fn new(var: f64, tau_s: f64, value: f64) -> Self {
        let step = Step {
            dt: f64::NAN,
            w: f64::NAN,
            decay: 0.0,
            sd: 0.0,
            bridge: Bridge {
                from_start: 0.0,
                from_end: 0.0,
                var: 0.0,
            },
        };
        GaussMarkov {
            tau_s,
            var,
            value,
            at_s: 0.0,
            step,
        }
    }

    /// Steps to `t_s` with the standard normal `z`; the window is the last `w` seconds.
    pub fn advance(&mut self, t_s: f64, w: f64, z: f64) -> WindowRead {
        let dt = t_s - self.at_s;
        let s = &self.step;
        // Sample times read from a clock in seconds differ from their spacing by rounding.
        let kept = (s.dt - dt).abs() <= 1e-9 * dt && (s.w - w).abs() <= 1e-9 * w;
        if !kept {
            let decay = (-dt / self.tau_s).exp();
            self.step = Step {
                dt,
                w,
                decay,
                sd: (self.var * (1.0 - decay * decay)).sqrt(),
                bridge: bridge::gauss_markov(self.var, self.tau_s, dt, w),
            };
        }
        let s = &self.step;
        let start = self.value;
        self.value = s.decay * start + s.sd * z;
        self.at_s = t_s;
        s.bridge.read(start, self.value)
    }
}
