//! When each dwell of a run happens: the positions in visiting order, the firmware's stepper
//! profile for each move (a half turn costs more than a small step), the settling time and the
//! dwell. The planner needs it to know the time structure the gyro's noise acts on.

use nf_instrument::step_train::Train;
use nf_instrument::stepper;
use nf_model::order::Order;

/// What a run's time is made of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timing {
    pub motor: stepper::Config,
    pub settle_s: f64,
    pub dwell_s: f64,
    /// Fixed time per position besides move, settle and dwell (the inclinometer reading).
    pub per_position_s: f64,
}

impl Default for Timing {
    fn default() -> Self {
        Timing {
            motor: stepper::Config::default(),
            settle_s: 0.3,
            dwell_s: 2.0,
            per_position_s: 0.0045,
        }
    }
}

impl Timing {
    /// Time of a move over `steps` motor steps: the firmware's step train, the trapezoidal
    /// profile as its timer makes it (the move ends with the last pulse).
    pub fn move_s(&self, steps: u32) -> f64 {
        if steps == 0 {
            return 0.0;
        }
        let train = Train::new(self.motor, steps);
        (0..steps).map(|k| train.period(k).arr as f64 + 1.0).sum::<f64>() * 1e-6
    }

    /// Motor steps of the shortest move between positions `a` and `b` of `n`.
    fn steps_between(&self, a: usize, b: usize, n: usize) -> u32 {
        let per = self.motor.steps_per_rev as i64;
        let at = |k: usize| (k as i64 * per + n as i64 / 2) / n as i64;
        let d = (at(b) - at(a)).rem_euclid(per);
        d.min(per - d) as u32
    }
}

/// A run's positions in visiting order and their times.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    pub gamma_deg: Vec<f64>,
    /// Centre of each dwell, s from the start of the first move.
    pub t_mid_s: Vec<f64>,
    pub dwell_s: f64,
    /// From the first move to the end of the last dwell, s.
    pub duration_s: f64,
}

impl Schedule {
    /// The schedule of visiting `n` equal steps in `order` (checked for `n`), starting at
    /// position `start` (the levelling leaves the shaft at half a turn).
    pub fn new(order: &Order, n: usize, start: usize, timing: &Timing) -> Schedule {
        let mut t = 0.0;
        let mut at = start;
        let visits = order.visits(n as u16) as usize;
        let (mut gamma_deg, mut t_mid_s) = (Vec::with_capacity(visits), Vec::with_capacity(visits));
        // A run has few distinct move lengths: time each once.
        let mut moves: Vec<(u32, f64)> = Vec::new();
        for k in order.positions(n as u16).map(usize::from) {
            let steps = timing.steps_between(at, k, n);
            let m = match moves.iter().find(|m| m.0 == steps) {
                Some(m) => m.1,
                None => {
                    let m = timing.move_s(steps);
                    moves.push((steps, m));
                    m
                }
            };
            t += m + timing.settle_s;
            gamma_deg.push(k as f64 * 360.0 / n as f64);
            t_mid_s.push(t + timing.dwell_s / 2.0);
            t += timing.dwell_s + timing.per_position_s;
            at = k;
        }
        Schedule {
            gamma_deg,
            t_mid_s,
            dwell_s: timing.dwell_s,
            duration_s: t,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_half_turn_costs_more_than_a_step_and_moves_go_the_short_way() {
        let tm = Timing::default();
        let small = tm.move_s(tm.steps_between(0, 1, 72));
        let half = tm.move_s(tm.steps_between(0, 36, 72));
        assert!(half > 3.0 * small, "{half} vs {small}");
        // Across zero the short way too (to a step of rounding).
        assert!(tm.steps_between(71, 1, 72).abs_diff(tm.steps_between(0, 2, 72)) <= 1);
        let s = Schedule::new(&Order::parse("0,1,2").unwrap(), 72, 0, &tm);
        assert_eq!(s.gamma_deg, vec![0.0, 5.0, 10.0]);
        let cycle = s.t_mid_s[2] - s.t_mid_s[1];
        let step12 = tm.move_s(tm.steps_between(1, 2, 72));
        assert!((cycle - (step12 + tm.settle_s + tm.dwell_s + tm.per_position_s)).abs() < 1e-12);
    }
}
