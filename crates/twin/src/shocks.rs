//! Shocks: bursts of rate disturbance at random times (vibration, knocks), a Poisson process
//! in continuous time. Each burst adds a Gaussian rate offset for its duration. Most dwells
//! meet none and the few that do are shifted, so the dwell means are heavy-tailed where a
//! Student-t of the samples would average out to a Gaussian.

use nf_model::rng::Rng;

/// The bursts' rate, size and length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shocks {
    /// Mean number of bursts per hour.
    pub per_hour: f64,
    /// Standard deviation of a burst's rate offset, deg/h.
    pub size_dph: f64,
    /// Length of each burst, s.
    pub duration_s: f64,
}

/// What shocks do to the mean over a window: the chance that a burst touches it, and the
/// RMS shift one burst gives the mean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowShift {
    pub share: f64,
    pub shift_dph: f64,
}

impl Shocks {
    pub const NONE: Shocks = Shocks {
        per_hour: 0.0,
        size_dph: 0.0,
        duration_s: 1.0,
    };

    /// More bursts at once than this are a Gaussian process, not shocks.
    pub const MAX_UNDER_WAY: f64 = 100.0;

    /// Bursts under way at once, on average: each costs the twin an addition per sample.
    pub fn under_way(&self) -> f64 {
        self.per_hour / 3600.0 * self.duration_s
    }

    /// The share of means over `window_s` that a burst touches, and the RMS shift of such a
    /// mean (one burst; several are rare where the share is small).
    pub fn per_window(&self, window_s: f64) -> WindowShift {
        let (t, d) = (window_s, self.duration_s);
        let (short, long) = (t.min(d), t.max(d));
        // A burst touches the window when it starts in (-d, t); its overlap then rises,
        // holds and falls: the mean square of overlap / t over those starts.
        let overlap2 = 2.0 * short.powi(3) / 3.0 + short * short * (long - short);
        WindowShift {
            share: 1.0 - (-self.per_hour / 3600.0 * (t + d)).exp(),
            shift_dph: self.size_dph * (overlap2 / ((t + d) * t * t)).sqrt(),
        }
    }

    /// Bursts one window long that give means over `window_s` this share and RMS shift.
    pub fn for_window(w: WindowShift, window_s: f64) -> Shocks {
        let share = w.share.clamp(0.0, 0.99);
        Shocks {
            per_hour: -(1.0 - share).ln() / (2.0 * window_s) * 3600.0,
            // A burst as long as the window shifts its mean by a uniform share of its size.
            size_dph: w.shift_dph * 3f64.sqrt(),
            duration_s: window_s,
        }
    }
}

/// The bursts as they come, from a generator of their own (so that a twin without shocks
/// draws what it drew before they existed).
#[derive(Debug, Clone)]
pub struct ShockTrain {
    shocks: Shocks,
    rng: Rng,
    /// When the next burst starts, s.
    next_s: f64,
    active: Vec<Burst>,
}

/// A burst under way.
#[derive(Debug, Clone, Copy)]
struct Burst {
    end_s: f64,
    offset_dph: f64,
}

impl ShockTrain {
    pub fn new(shocks: Shocks, seed: u64) -> ShockTrain {
        let mut train = ShockTrain {
            shocks,
            rng: Rng::new(seed ^ 0x5CC0_CC5E_0B57),
            // Bursts under way at time 0 started before it.
            next_s: -shocks.duration_s,
            active: Vec::new(),
        };
        train.next_s += train.gap_s();
        train
    }

    fn gap_s(&mut self) -> f64 {
        let rate = self.shocks.per_hour / 3600.0;
        if rate <= 0.0 {
            return f64::INFINITY;
        }
        -(1.0 - self.rng.unit()).ln() / rate
    }

    /// The bursts' offset at `t_s` (not earlier than the last call's), deg/h.
    pub fn at(&mut self, t_s: f64) -> f64 {
        while self.next_s <= t_s {
            self.active.push(Burst {
                end_s: self.next_s + self.shocks.duration_s,
                offset_dph: self.shocks.size_dph * self.rng.gauss(),
            });
            self.next_s += self.gap_s();
        }
        self.active.retain(|b| b.end_s > t_s);
        self.active.iter().map(|b| b.offset_dph).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Means over windows of `window_s` every `spacing_s`.
    fn window_means(shocks: Shocks, window_s: f64, spacing_s: f64, n: usize, seed: u64) -> Vec<f64> {
        let mut train = ShockTrain::new(shocks, seed);
        let dt = 0.01;
        let per = (window_s / dt).round() as usize;
        (0..n)
            .map(|i| {
                let start = i as f64 * spacing_s;
                (0..per).map(|k| train.at(start + (k as f64 + 0.5) * dt)).sum::<f64>() / per as f64
            })
            .collect()
    }

    #[test]
    fn the_share_of_windows_hit_and_their_shift_are_as_predicted() {
        for (shocks, window) in [
            (
                Shocks {
                    per_hour: 180.0,
                    size_dph: 1.0,
                    duration_s: 2.0,
                },
                2.0,
            ),
            (
                Shocks {
                    per_hour: 360.0,
                    size_dph: 1.0,
                    duration_s: 0.5,
                },
                2.0,
            ),
        ] {
            let m = window_means(shocks, window, 3.0, 20_000, 5);
            let hit: Vec<f64> = m.into_iter().filter(|v| *v != 0.0).collect();
            let share = hit.len() as f64 / 20_000.0;
            let rms = (hit.iter().map(|v| v * v).sum::<f64>() / hit.len() as f64).sqrt();
            let want = shocks.per_window(window);
            assert!(
                (share / want.share - 1.0).abs() < 0.06,
                "share {share} want {}",
                want.share
            );
            // Two bursts in one window are rare here, not absent.
            assert!(
                (rms / want.shift_dph - 1.0).abs() < 0.08,
                "rms {rms} want {}",
                want.shift_dph
            );
        }
    }

    #[test]
    fn bursts_made_for_a_window_give_it_the_share_and_shift_asked() {
        let asked = WindowShift {
            share: 0.1,
            shift_dph: 0.3,
        };
        let s = Shocks::for_window(asked, 1.5);
        let got = s.per_window(1.5);
        assert!(
            (got.share - 0.1).abs() < 1e-12 && (got.shift_dph - 0.3).abs() < 1e-12,
            "{got:?}"
        );
    }

    #[test]
    fn no_shocks_no_draws() {
        let mut t = ShockTrain::new(Shocks::NONE, 1);
        assert_eq!((t.at(0.0), t.at(1e9)), (0.0, 0.0));
    }
}
