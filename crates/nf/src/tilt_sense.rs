//! Which way the inclinometer's readings turn round the tilt circle. With Y 90 deg
//! counter-clockwise from X and the encoder angle growing counter-clockwise, a tilted shaft
//! draws `sin x = cx + a cos g + b sin g`, `sin y = cy - a sin g + b cos g`. A Y read with the
//! opposite sign, X and Y swapped, or an encoder counting the other way draw the mirror
//! image, `sin y = cy + a sin g - b cos g`, which the proper circle cannot fit: its tilt would
//! come out near zero while both axes plainly swing.

use crate::linfit;
use crate::stats::f_sf;

/// One axis's reading: `sin` of the elevation, at an encoder angle; `y` for the Y axis.
#[derive(Debug, Clone, Copy)]
pub struct AxisReading {
    pub gamma_deg: f64,
    pub sin_elev: f64,
    pub y: bool,
}

/// The proper circle rejected below this p-value (against X and Y each with its own first
/// harmonic) while the mirror image is not.
const REJECT: f64 = 1e-6;
/// The mirror image is consistent with the free fit at this level.
const CONSISTENT: f64 = 1e-3;

/// The circle's columns: the offset of each axis read (X's first), then `a` and `b` turning
/// the proper way or the mirror way.
pub fn circle_cols(r: &[AxisReading], mirror: bool) -> Vec<Vec<f64>> {
    let sign = if mirror { -1.0 } else { 1.0 };
    let trig: Vec<(f64, f64)> = r.iter().map(|r| r.gamma_deg.to_radians().sin_cos()).collect();
    let mut cols: Vec<Vec<f64>> = [false, true]
        .into_iter()
        .filter(|&y| r.iter().any(|r| r.y == y))
        .map(|y| r.iter().map(|r| f64::from(u8::from(r.y == y))).collect())
        .collect();
    cols.push(
        r.iter()
            .zip(&trig)
            .map(|(r, (s, c))| if r.y { -sign * s } else { *c })
            .collect(),
    );
    cols.push(
        r.iter()
            .zip(&trig)
            .map(|(r, (s, c))| if r.y { sign * c } else { *s })
            .collect(),
    );
    cols
}

/// Each axis with its own offset and first harmonic.
fn free_cols(r: &[AxisReading]) -> Vec<Vec<f64>> {
    let on = |y: bool, f: fn(f64) -> f64| -> Vec<f64> {
        r.iter()
            .map(|r| if r.y == y { f(r.gamma_deg.to_radians()) } else { 0.0 })
            .collect()
    };
    vec![
        on(false, |_| 1.0),
        on(false, f64::cos),
        on(false, f64::sin),
        on(true, |_| 1.0),
        on(true, f64::cos),
        on(true, f64::sin),
    ]
}

/// The p-value of a circle against the free fit: two constraints.
fn p_against_free(rss: f64, free_rss: f64, free_dof: usize) -> f64 {
    if free_rss <= 0.0 {
        return if rss > 0.0 { 0.0 } else { 1.0 };
    }
    let f = ((rss - free_rss).max(0.0) / 2.0) / (free_rss / free_dof as f64);
    f_sf(f, 2.0, free_dof as f64)
}

/// The p-values of the proper circle and of its mirror image, when both axes are read on
/// four positions or more.
fn senses(r: &[AxisReading]) -> Option<(f64, f64)> {
    let count = |y: bool| r.iter().filter(|r| r.y == y).count();
    if count(false) < 4 || count(true) < 4 {
        return None;
    }
    let y: Vec<f64> = r.iter().map(|r| r.sin_elev).collect();
    let free = linfit::fit(&free_cols(r), &y)?;
    if free.dof == 0 {
        return None;
    }
    let proper = linfit::fit(&circle_cols(r, false), &y)?;
    let mirror = linfit::fit(&circle_cols(r, true), &y)?;
    Some((
        p_against_free(proper.rss, free.rss, free.dof),
        p_against_free(mirror.rss, free.rss, free.dof),
    ))
}

/// The readings turn the mirror way: the proper circle is rejected and its mirror image fits.
pub fn turns_the_wrong_way(r: &[AxisReading]) -> bool {
    senses(r).is_some_and(|(proper, mirror)| proper < REJECT && mirror >= CONSISTENT)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nf_model::exact::Instrument;
    use nf_model::rng::Rng;

    /// Readings of the exact instrument at `n` positions, Y's sign flipped or X and Y swapped
    /// on request, with `noise_deg` of Gaussian noise.
    fn readings(tilt_deg: f64, n: usize, flip_y: bool, swap: bool, noise_deg: f64, seed: u64) -> Vec<AxisReading> {
        let ins = Instrument {
            tilt_deg,
            tilt_dir_deg: 140.0,
            ..Instrument::level(43.8, 65.5)
        };
        let mut rng = Rng::new(seed);
        (0..n)
            .flat_map(|i| {
                let g = 7.0 + 360.0 * i as f64 / n as f64;
                let (mut x, mut y) = ins.inclinometer_deg(g, 0.01, -0.02);
                if flip_y {
                    y = -y;
                }
                if swap {
                    (x, y) = (y, x);
                }
                [(x, false), (y, true)].map(|(v, is_y)| AxisReading {
                    gamma_deg: g,
                    sin_elev: (v + noise_deg * rng.gauss()).to_radians().sin(),
                    y: is_y,
                })
            })
            .collect()
    }

    #[test]
    fn a_proper_circle_turns_the_right_way_at_every_tilt() {
        for (k, tilt) in [0.0, 0.002, 0.1, 3.0, 10.0].into_iter().enumerate() {
            let r = readings(tilt, 36, false, false, 5e-4, k as u64);
            assert!(!turns_the_wrong_way(&r), "tilt {tilt}: {:?}", senses(&r));
        }
    }

    #[test]
    fn a_flipped_y_and_swapped_axes_turn_the_wrong_way() {
        for (flip, swap) in [(true, false), (false, true)] {
            let r = readings(0.002, 36, flip, swap, 5e-4, 3);
            assert!(turns_the_wrong_way(&r), "flip {flip} swap {swap}: {:?}", senses(&r));
        }
        // No tilt to speak of: either way fits, nothing is said.
        let r = readings(1e-5, 36, true, false, 5e-4, 4);
        assert!(!turns_the_wrong_way(&r), "{:?}", senses(&r));
    }

    /// The proper circle's p-value is a p-value: at 1 % it rejects about 1 % of noisy
    /// proper circles, and far below `REJECT` never.
    #[test]
    fn the_proper_circles_p_value_holds_its_level() {
        let runs = 2000;
        let (mut at_1pc, mut at_reject) = (0, 0);
        for seed in 0..runs {
            let r = readings(0.05, 24, false, false, 1e-3, 100 + seed);
            let (p, _) = senses(&r).unwrap();
            at_1pc += usize::from(p < 0.01);
            at_reject += usize::from(p < REJECT);
        }
        let share = at_1pc as f64 / runs as f64;
        assert!((0.005..0.018).contains(&share), "share {share}");
        assert_eq!(at_reject, 0);
    }
}
