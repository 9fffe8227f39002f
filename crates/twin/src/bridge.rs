//! What a sampling gyro reads of a wandering bias: its mean over the sample period, not its
//! value at an instant. The bias processes are stepped exactly from sample to sample; the
//! mean over the last `w` seconds of a step of `d` seconds is then drawn from its
//! distribution given both ends (a bridge), so the steps' own draws stay what they were.

/// The mean over `(d - w, d]` of a process known at 0 and `d`: given those values, Gaussian
/// with mean `from_start x0 + from_end x1` and variance `var`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bridge {
    pub from_start: f64,
    pub from_end: f64,
    pub var: f64,
}

impl Bridge {
    pub fn mean(&self, x0: f64, x1: f64) -> f64 {
        self.from_start * x0 + self.from_end * x1
    }

    /// The window's mean given the ends `x0` and `x1`, with the variance left.
    pub fn read(&self, x0: f64, x1: f64) -> WindowRead {
        WindowRead {
            mean: self.mean(x0, x1),
            var: self.var,
        }
    }
}

/// A window's mean given a process's ends, and the variance it keeps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WindowRead {
    pub mean: f64,
    pub var: f64,
}

impl WindowRead {
    pub fn plus(self, other: WindowRead) -> WindowRead {
        WindowRead {
            mean: self.mean + other.mean,
            var: self.var + other.var,
        }
    }
}

/// A stationary Gauss-Markov process of variance `var` and correlation time `tau`.
pub fn gauss_markov(var: f64, tau: f64, d: f64, w: f64) -> Bridge {
    // Times in units of tau: the whole step a, the window b, the gap before the window c.
    let (a, b) = (d / tau, w / tau);
    let c = a - b;
    let (ea, ec) = ((-a).exp(), (-c).exp());
    // 1 - e^-b, and e^-c - e^-a = e^-c (1 - e^-b), without the differences of near equals.
    let eb = -(-b).exp_m1();
    // Given x0 alone: the window's mean (per x0), its variance and covariance with the end.
    let mean0 = ec * eb / b;
    let var0 = var / (b * b) * (2.0 * (b + (-b).exp_m1()) - (ec * eb).powi(2));
    let cov = var / b * eb * -(-(a + c)).exp_m1();
    let var_end = -var * (-2.0 * a).exp_m1();
    let from_end = cov / var_end;
    Bridge {
        from_start: mean0 - from_end * ea,
        from_end,
        var: (var0 - cov * from_end).max(0.0),
    }
}

/// A random walk of `k^2` per second.
pub fn random_walk(k: f64, d: f64, w: f64) -> Bridge {
    let gap = d - w;
    let from_end = (gap + w / 2.0) / d;
    Bridge {
        from_start: 1.0 - from_end,
        from_end,
        var: k * k * w * (4.0 * gap + w) / (12.0 * d),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nf_model::rng::Rng;

    /// A fine Euler path of the process from `x0`: its window mean and its end.
    fn path(rng: &mut Rng, step: impl Fn(&mut Rng, f64) -> f64, x0: f64, d: f64, w: f64) -> (f64, f64) {
        let m = 2000;
        let h = d / m as f64;
        let (mut x, mut sum, mut count) = (x0, 0.0, 0);
        for i in 0..m {
            let next = step(rng, x);
            if (i as f64 + 0.5) * h > d - w {
                sum += 0.5 * (x + next);
                count += 1;
            }
            x = next;
        }
        (sum / count as f64, x)
    }

    /// Regression of the window mean on the end, over fine paths from one start: the bridge's
    /// mean is linear in the end, and its variance is what the regression leaves.
    fn check(step: impl Fn(&mut Rng, f64) -> f64, bridge: Bridge, x0: f64, d: f64, w: f64) {
        let mut rng = Rng::new(9);
        let draws: Vec<(f64, f64)> = (0..3000).map(|_| path(&mut rng, &step, x0, d, w)).collect();
        let n = draws.len() as f64;
        let (mi, me) = (
            draws.iter().map(|p| p.0).sum::<f64>() / n,
            draws.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let see = draws.iter().map(|p| (p.1 - me).powi(2)).sum::<f64>();
        let slope = draws.iter().map(|p| (p.0 - mi) * (p.1 - me)).sum::<f64>() / see;
        let left = draws
            .iter()
            .map(|p| (p.0 - mi - slope * (p.1 - me)).powi(2))
            .sum::<f64>()
            / (n - 2.0);
        assert!(
            (slope - bridge.from_end).abs() < 0.03,
            "slope {slope} vs {}",
            bridge.from_end
        );
        assert!((mi - bridge.mean(x0, me)).abs() < 0.03, "mean {mi}");
        assert!(
            (left / bridge.var - 1.0).abs() < 0.1,
            "variance {left} vs {}",
            bridge.var
        );
    }

    #[test]
    fn gauss_markov_bridge_matches_fine_paths() {
        let (var, tau): (f64, f64) = (1.0, 0.3);
        for (d, w) in [(0.2f64, 0.2), (1.0, 0.25), (0.05, 0.01)] {
            let h = d / 2000.0;
            let step = |rng: &mut Rng, x: f64| x - x / tau * h + (2.0 * var / tau * h).sqrt() * rng.gauss();
            check(step, gauss_markov(var, tau, d, w), 0.7, d, w);
        }
    }

    #[test]
    fn bridges_hold_from_far_faster_to_far_slower_than_their_window() {
        for tau in [1e-6, 1e-3, 1.0, 1e3, 3e6] {
            for (d, w) in [(1e-3, 1e-3), (0.5, 1e-3), (6e4, 1e-3)] {
                let b = gauss_markov(2.0, tau, d, w);
                // Given both ends the window's mean lies between them, and varies less than
                // the process.
                assert!(
                    b.var.is_finite() && (0.0..=2.0).contains(&b.var),
                    "{tau} {d} {w}: {b:?}"
                );
                assert!(b.from_start >= -1e-12 && b.from_end >= -1e-12, "{tau} {d} {w}: {b:?}");
                assert!(b.from_start + b.from_end <= 1.0 + 1e-12, "{tau} {d} {w}: {b:?}");
            }
        }
        // Much slower than the step, a Gauss-Markov process is a random walk of 2 var / tau
        // per second.
        let (var, tau, d, w) = (2.0, 1e6, 10.0, 1.0);
        let (gm, walk) = (
            gauss_markov(var, tau, d, w),
            random_walk((2.0 * var / tau).sqrt(), d, w),
        );
        assert!((gm.from_end - walk.from_end).abs() < 1e-4, "{gm:?} {walk:?}");
        assert!((gm.from_start - walk.from_start).abs() < 1e-4, "{gm:?} {walk:?}");
        assert!((gm.var / walk.var - 1.0).abs() < 1e-3, "{gm:?} {walk:?}");
    }

    #[test]
    fn random_walk_bridge_matches_fine_paths() {
        let k = 2.0;
        for (d, w) in [(0.5f64, 0.5), (2.0, 0.3)] {
            let h = d / 2000.0;
            let step = |rng: &mut Rng, x: f64| x + k * h.sqrt() * rng.gauss();
            check(step, random_walk(k, d, w), -0.4, d, w);
        }
    }
}
