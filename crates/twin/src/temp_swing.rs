//! A cycling temperature, as from a heater's control loop.

/// `amplitude sin(2 pi t / period + phase)`, C, at `t` s on the twin's clock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TempSwing {
    pub amplitude_c: f64,
    pub period_s: f64,
    pub phase_deg: f64,
}

impl TempSwing {
    /// No swing.
    pub const NONE: TempSwing = TempSwing {
        amplitude_c: 0.0,
        period_s: 600.0,
        phase_deg: 0.0,
    };

    /// The swing's part of the temperature at `t_s`, C.
    pub fn at(&self, t_s: f64) -> f64 {
        self.amplitude_c * (std::f64::consts::TAU * t_s / self.period_s + self.phase_deg.to_radians()).sin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_phase_shifts_the_cycle() {
        let s = TempSwing {
            amplitude_c: 2.0,
            period_s: 40.0,
            phase_deg: 90.0,
        };
        assert!((s.at(0.0) - 2.0).abs() < 1e-12);
        assert!((s.at(10.0)).abs() < 1e-12);
        assert!((s.at(20.0) + 2.0).abs() < 1e-12);
        assert_eq!(TempSwing::NONE.at(123.0), 0.0);
    }
}
