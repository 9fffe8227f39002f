//! Levelling: the shaft tilt from inclinometer readings, and the knob turns that remove it.

use crate::angle::{atan2_deg, sincos_deg};
use crate::fit::{FitError, Lsq, hypot};
use crate::{Float, asin, c, is_f32, sqrt};

/// One inclinometer reading at encoder angle `gamma`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TiltReading<F> {
    pub gamma_deg: F,
    pub x_deg: F,
    pub y_deg: F,
}

/// The shaft tilt and the inclinometer's mounting offsets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShaftTilt<F> {
    /// Tilt `eta` of the shaft from the vertical.
    pub tilt_deg: F,
    /// Direction `tau` (counter-clockwise from `gamma = 0`) the platform is lowest towards.
    pub tilt_dir_deg: F,
    /// Mounting offsets of the inclinometer's X and Y axes.
    pub offset_x_deg: F,
    pub offset_y_deg: F,
    /// RMS of the fit residuals (deg): the inclinometer noise, with enough readings.
    pub rms_deg: F,
}

/// Least-squares fit of the tilt circle to readings at any angles (at least two, not both at
/// the same angle).
///
/// It fits `sin(x) = cx + a cos(gamma) + b sin(gamma)` and `sin(y) = cy - a sin(gamma) + b
/// cos(gamma)`, which is exact for a tilted shaft (up to the ratio of the cosines of the two
/// mounting offsets): `a = -sin(eta) cos(tau)`, `b = -sin(eta) sin(tau)`. With two readings
/// 180 deg apart it is Eq. 32; with more it separates the tilt from the mounting offsets.
pub fn fit_tilt<F: Float>(readings: &[TiltReading<F>]) -> Result<ShaftTilt<F>, FitError> {
    let mut lsq = Lsq::new(4);
    for (i, r) in readings.iter().enumerate() {
        if !(r.gamma_deg.is_finite() && r.x_deg.is_finite() && r.y_deg.is_finite()) {
            return Err(FitError::NonFinite { index: i as u32 });
        }
        let (sg, cg) = sincos_deg(r.gamma_deg);
        let (o, z) = (F::one(), F::zero());
        lsq.add_row(&[o, z, cg, sg], sincos_deg(r.x_deg).0, o);
        lsq.add_row(&[z, o, -sg, cg], sincos_deg(r.y_deg).0, o);
    }
    let sol = lsq.solve()?;
    let [cx, cy, a, b, ..] = sol.coef;
    let dof = sol.n as i64 - 4;
    let rms = if dof > 0 {
        // Straight from the integer: no f64 on the way (soft on the M4F).
        asin(sqrt(sol.rss / F::from(dof).unwrap_or_else(F::nan))).to_degrees()
    } else {
        F::zero()
    };
    Ok(ShaftTilt::from_circle(cx, cy, a, b, rms))
}

impl<F: Float> ShaftTilt<F> {
    /// The tilt and the offsets from the fitted circle `sin(x) = cx + a cos(gamma) + b
    /// sin(gamma)`, `sin(y) = cy - a sin(gamma) + b cos(gamma)`, and the fit's RMS (deg). An
    /// axis never read has a NaN offset term: the tilt then comes from the other's.
    pub fn from_circle(cx: F, cy: F, a: F, b: F, rms_deg: F) -> Self {
        // In f32 not `libm`'s `hypotf`, which computes in f64.
        let r = if is_f32::<F>() { hypot(a, b) } else { a.hypot(b) };
        // sin^2(eta) from c = sin(o) cos(eta) and r = cos(o) sin(eta): the smaller root.
        let c0 = if cx.is_nan() { cy } else { cx };
        let q = F::one() + r * r - c0 * c0;
        let disc = (q * q - c::<F>(4.0) * r * r).max(F::zero());
        let s2 = (c::<F>(2.0) * r * r / (q + sqrt(disc))).min(F::one());
        let ceta = sqrt(F::one() - s2);
        let off = |v: F| match v.is_nan() {
            true => v,
            false => asin((v / ceta).max(-F::one()).min(F::one())).to_degrees(),
        };
        ShaftTilt {
            tilt_deg: asin(sqrt(s2)).to_degrees(),
            tilt_dir_deg: atan2_deg(-b, -a),
            offset_x_deg: off(cx),
            offset_y_deg: off(cy),
            rms_deg,
        }
    }
}

/// The three-leg pedestal: leg positions and the knobs' thread.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pedestal<F> {
    /// Distance of each leg from the shaft.
    pub radius_mm: F,
    /// Direction of each leg, counter-clockwise from `gamma = 0`.
    pub legs_deg: [F; 3],
    /// Height change per knob turn (positive: a clockwise turn, seen from above, raises the leg).
    pub mm_per_turn: F,
}

impl<F: Float> Default for Pedestal<F> {
    fn default() -> Self {
        // The paper's 420 mm pedestal, M6-class fine thread.
        Pedestal {
            radius_mm: c(180.0),
            legs_deg: [c(0.0), c(120.0), c(240.0)],
            mm_per_turn: c(0.5),
        }
    }
}

/// How to turn one knob.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KnobTurn<F> {
    pub leg: usize,
    /// Height change of the leg (always a raise: the highest leg is left alone).
    pub raise_mm: F,
    /// Turns of the knob (positive: clockwise seen from above).
    pub turns: F,
}

impl<F: Float> Pedestal<F> {
    /// The knob turns that level a shaft tilted by `tilt`, in the order to make them (largest
    /// first); the leg already highest is the reference and gets no turn.
    pub fn level(&self, tilt: &ShaftTilt<F>) -> [KnobTurn<F>; 3] {
        let t = sincos_deg(tilt.tilt_deg);
        let tan_eta = t.0 / t.1;
        // The pedestal is lowest towards tau: raise each leg by its depth below the highest.
        let depth = self
            .legs_deg
            .map(|l| self.radius_mm * tan_eta * sincos_deg(l - tilt.tilt_dir_deg).1);
        let top = depth.iter().fold(F::infinity(), |m, &d| m.min(d));
        let mut turns = [0usize, 1, 2].map(|leg| {
            let raise_mm = depth[leg] - top;
            KnobTurn {
                leg,
                raise_mm,
                turns: raise_mm / self.mm_per_turn,
            }
        });
        turns.sort_unstable_by(|a, b| {
            b.raise_mm
                .partial_cmp(&a.raise_mm)
                .unwrap_or(core::cmp::Ordering::Equal)
        });
        turns
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::Instrument;
    use crate::paper::eq32_tilt_deg;

    fn readings(inst: &Instrument<f64>, ox: f64, oy: f64, gammas: &[f64]) -> std::vec::Vec<TiltReading<f64>> {
        gammas
            .iter()
            .map(|&g| {
                let (x, y) = inst.inclinometer_deg(g, ox, oy);
                TiltReading {
                    gamma_deg: g,
                    x_deg: x,
                    y_deg: y,
                }
            })
            .collect()
    }

    #[test]
    fn recovers_tilt_and_offsets_exactly() {
        for (eta, tau, ox, oy) in [
            (1.0, 30.0, 0.2, -0.15),
            (0.003, 250.0, 0.02, 0.02),
            (3.0, 359.0, -0.5, 0.5),
        ] {
            let inst = Instrument {
                tilt_deg: eta,
                tilt_dir_deg: tau,
                ..Instrument::level(43.8, 10.0)
            };
            let gs: std::vec::Vec<f64> = (0..12).map(|i| i as f64 * 30.0 + 7.0).collect();
            let t = fit_tilt(&readings(&inst, ox, oy, &gs)).unwrap();
            // Unequal offsets leave a relative error of (ox^2 - oy^2) / 2 on the tilt.
            let tol = 1e-9 + eta * (ox * ox - oy * oy).abs().to_radians().to_radians();
            assert!((t.tilt_deg - eta).abs() < tol, "{t:?}");
            assert!(crate::angle::wrap_180(t.tilt_dir_deg - tau).abs() < 1e-4, "{t:?}");
            assert!(
                (t.offset_x_deg - ox).abs() < 1e-4 && (t.offset_y_deg - oy).abs() < 1e-4,
                "{t:?}"
            );
        }
    }

    #[test]
    fn a_circle_of_one_axis_keeps_the_other_offset_unknown() {
        let both = ShaftTilt::from_circle(0.003, -0.002, -0.01, 0.02, 0.0);
        let x_alone = ShaftTilt::from_circle(0.003, f64::NAN, -0.01, 0.02, 0.0);
        let y_alone = ShaftTilt::from_circle(f64::NAN, -0.002, -0.01, 0.02, 0.0);
        assert!(x_alone.offset_y_deg.is_nan() && y_alone.offset_x_deg.is_nan());
        assert_eq!(
            (x_alone.tilt_deg, x_alone.offset_x_deg),
            (both.tilt_deg, both.offset_x_deg)
        );
        assert_eq!(x_alone.tilt_dir_deg, both.tilt_dir_deg);
        assert!(
            (y_alone.tilt_deg - both.tilt_deg).abs() < 1e-4 * both.tilt_deg,
            "{y_alone:?}"
        );
    }

    #[test]
    fn two_readings_half_a_turn_apart_give_eq32() {
        let inst = Instrument {
            tilt_deg: 0.4,
            tilt_dir_deg: 100.0,
            ..Instrument::level(43.8, 0.0)
        };
        let r = readings(&inst, 0.1, 0.1, &[0.0, 180.0]);
        let t = fit_tilt(&r).unwrap();
        let e32 = eq32_tilt_deg(r[0].x_deg, r[0].y_deg, r[1].x_deg, r[1].y_deg);
        assert!(
            (t.tilt_deg - e32).abs() < 1e-5 && (t.tilt_deg - 0.4).abs() < 1e-6,
            "{} {}",
            t.tilt_deg,
            e32
        );
        assert!(fit_tilt(&r[..1]).is_err());
    }

    #[test]
    fn knob_turns_level_the_pedestal() {
        let ped = Pedestal::<f64>::default();
        let tilt = ShaftTilt {
            tilt_deg: 0.2,
            tilt_dir_deg: 75.0,
            offset_x_deg: 0.0,
            offset_y_deg: 0.0,
            rms_deg: 0.0,
        };
        let turns = ped.level(&tilt);
        assert_eq!(turns[2].raise_mm, 0.0);
        assert!(turns[0].raise_mm >= turns[1].raise_mm);
        // After the turns the three legs lie in a level plane: heights h(l) = -r tan(eta) cos(l - tau) + raise.
        let h: std::vec::Vec<f64> = turns
            .iter()
            .map(|k| {
                -ped.radius_mm * 0.2f64.to_radians().tan() * (ped.legs_deg[k.leg] - 75.0).to_radians().cos()
                    + k.raise_mm
            })
            .collect();
        assert!((h[0] - h[1]).abs() < 1e-12 && (h[1] - h[2]).abs() < 1e-12, "{h:?}");
        // The lowest leg is the one nearest the tilt direction (leg at 120 deg).
        assert_eq!(turns[0].leg, 1);
        assert!((turns[0].turns - turns[0].raise_mm / 0.5).abs() < 1e-12);
    }
}
