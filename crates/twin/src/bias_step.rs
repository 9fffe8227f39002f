//! Steps of the gyro bias at set times: a jump that stays, and a disturbance over an interval.

/// The bias steps by `size_dph` at `time_s` and stays there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiasJump {
    pub time_s: f64,
    pub size_dph: f64,
}

impl BiasJump {
    /// The jump's part of the bias at `t_s`, deg/h.
    pub fn at(&self, t_s: f64) -> f64 {
        if t_s >= self.time_s { self.size_dph } else { 0.0 }
    }
}

/// `size_dph` is added to the gyro output from `from_s` until `to_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disturbance {
    pub from_s: f64,
    pub to_s: f64,
    pub size_dph: f64,
}

impl Disturbance {
    /// The disturbance's part of the output at `t_s`, deg/h.
    pub fn at(&self, t_s: f64) -> f64 {
        if (self.from_s..self.to_s).contains(&t_s) {
            self.size_dph
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_jump_stays_and_a_disturbance_ends() {
        let j = BiasJump {
            time_s: 10.0,
            size_dph: 0.5,
        };
        assert_eq!((j.at(9.999), j.at(10.0), j.at(1e6)), (0.0, 0.5, 0.5));
        let d = Disturbance {
            from_s: 10.0,
            to_s: 12.0,
            size_dph: -0.2,
        };
        assert_eq!(
            (d.at(9.999), d.at(10.0), d.at(11.9), d.at(12.0)),
            (0.0, -0.2, -0.2, 0.0)
        );
    }
}
