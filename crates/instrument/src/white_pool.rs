//! The white level of a run's dwell means when no noise model gives it: the samples' spread,
//! pooled over the dwells so far. One dwell's spread over a few samples is a poor variance
//! (9 degrees of freedom at 10 samples), and weighing each dwell by its own made the running
//! sigma short: `1 / s^2` is too large on average (by `nu / (nu - 2)`), and the dwells whose
//! spread came out small weigh most.

/// The pooled variance of one sample, (deg/h)^2, and its degrees of freedom.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WhitePool {
    sum_sq: f32,
    dof: f32,
}

impl WhitePool {
    /// Takes a dwell's samples' sd (deg/h) over `samples` and gives the variance of its mean
    /// under the pool so far, at least `floor` per sample (the quantisation of one count).
    /// NaN while the pool has no degree of freedom (dwells of one sample): such a dwell cannot
    /// be weighed.
    pub fn add(&mut self, sd_dph: f32, samples: u32, floor: f32) -> f32 {
        if samples > 1 && sd_dph.is_finite() {
            let dof = (samples - 1) as f32;
            self.sum_sq += sd_dph * sd_dph * dof;
            self.dof += dof;
        }
        let var = self.sum_sq / self.dof;
        let var = if var < floor { floor } else { var };
        var / samples.max(1) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pool_weighs_each_dwell_by_its_degrees_of_freedom() {
        let mut p = WhitePool::default();
        // 10 samples at sd 2: 4 / 10.
        assert_eq!(p.add(2.0, 10, 0.0), 0.4);
        // 4 samples at sd 1 join 9 dof of 4 with 3 of 1: (36 + 3) / 12 = 3.25, over 4 samples.
        assert_eq!(p.add(1.0, 4, 0.0), 3.25 / 4.0);
        // A dwell of one sample adds nothing to the pool but is weighed by it.
        assert_eq!(p.add(f32::NAN, 1, 0.0), 3.25);
        // The floor holds when the samples are all one count.
        let mut q = WhitePool::default();
        assert_eq!(q.add(0.0, 10, 0.5), 0.05);
    }

    #[test]
    fn with_no_degree_of_freedom_a_dwell_cannot_be_weighed() {
        let mut p = WhitePool::default();
        assert!(p.add(f32::NAN, 1, 0.1).is_nan());
        assert!(p.add(3.0, 1, 0.1).is_nan());
        assert_eq!(p.add(3.0, 2, 0.0), 4.5);
    }
}
