//! The exact vector model of the gyro output: the default physics of the project.
//!
//! Frames: ENU (east, north, up) on the Earth; the level frame L has `x` along the encoder's
//! `gamma = 0` direction projected on the horizontal, `y` 90 deg counter-clockwise from it and
//! `z` up. The pedestal (base) frame is L tilted by the smallest rotation that carries `z` onto
//! the shaft axis. The shaft top leans by `tilt` towards `tilt_dir` (counter-clockwise from
//! `gamma = 0`), so the platform is lowest towards `tilt_dir`. The gyro axis lies at encoder
//! angle `gamma` in the platform and is raised by `gyro_elev` above the platform plane.
//!
//! To first order a tilt `eta` gives the gyro axis the elevation `-eta cos(gamma - tau)`, which
//! couples the vertical Earth rate into a first harmonic: it shifts the azimuth by up to
//! `eta tan(lat)` and leaves no residual. The paper's Eq. 19 drops that sign
//! (see [`crate::paper::eq19_rate`]).

use crate::angle::sincos_deg;
use crate::{EARTH_RATE_DPH, Float, c};

/// A north finder on the Earth: everything the gyro output depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instrument<F> {
    /// Geographic latitude.
    pub latitude_deg: F,
    /// The azimuth `psi` of the paper's Eq. 7.
    pub psi_deg: F,
    /// Shaft tilt `eta` from the vertical.
    pub tilt_deg: F,
    /// Direction `tau` the shaft top leans to, counter-clockwise from `gamma = 0`.
    pub tilt_dir_deg: F,
    /// Gyro axis elevation `epsilon` above the platform plane (gyro misalignment).
    pub gyro_elev_deg: F,
    /// Scale factor: output per input rate, 1 for an ideal gyro.
    pub scale: F,
    /// Gyro bias.
    pub bias_dph: F,
}

/// Partial derivatives of the gyro rate (deg/h) with respect to each quantity, per degree for
/// angles, per unit for the scale, per deg/h for the bias.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RateJacobian<F> {
    pub psi: F,
    pub tilt: F,
    pub tilt_dir: F,
    pub gyro_elev: F,
    pub scale: F,
    pub bias: F,
    pub latitude: F,
    pub gamma: F,
}

type V3<F> = [F; 3];

fn dot<F: Float>(a: V3<F>, b: V3<F>) -> F {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<F: Float>(a: V3<F>, b: V3<F>) -> V3<F> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn axpy<F: Float>(v: V3<F>, s: F, w: V3<F>) -> V3<F> {
    [v[0] + s * w[0], v[1] + s * w[1], v[2] + s * w[2]]
}

fn scale3<F: Float>(s: F, v: V3<F>) -> V3<F> {
    [s * v[0], s * v[1], s * v[2]]
}

/// The tilt rotation: Rodrigues about `k = (-sin tau, cos tau, 0)` by `eta`.
struct Tilt<F> {
    k: V3<F>,
    dk: V3<F>,
    ce: F,
    se: F,
}

impl<F: Float> Tilt<F> {
    fn new(tilt_deg: F, tilt_dir_deg: F) -> Self {
        let (st, ct) = sincos_deg(tilt_dir_deg);
        let (se, ce) = sincos_deg(tilt_deg);
        Tilt {
            k: [-st, ct, F::zero()],
            dk: [-ct, -st, F::zero()],
            ce,
            se,
        }
    }

    fn apply(&self, v: V3<F>) -> V3<F> {
        let one = F::one();
        let r = axpy(scale3(self.ce, v), self.se, cross(self.k, v));
        axpy(r, dot(self.k, v) * (one - self.ce), self.k)
    }

    /// d(apply)/d(eta), per radian.
    fn d_eta(&self, v: V3<F>) -> V3<F> {
        let r = axpy(scale3(-self.se, v), self.ce, cross(self.k, v));
        axpy(r, dot(self.k, v) * self.se, self.k)
    }

    /// d(apply)/d(tau), per radian.
    fn d_tau(&self, v: V3<F>) -> V3<F> {
        let one_c = F::one() - self.ce;
        let r = axpy(scale3(self.se, cross(self.dk, v)), dot(self.k, v) * one_c, self.dk);
        axpy(r, dot(self.dk, v) * one_c, self.k)
    }
}

impl<F: Float> Instrument<F> {
    /// A level, ideal instrument: Eq. 7 without bias.
    pub fn level(latitude_deg: F, psi_deg: F) -> Self {
        Instrument {
            latitude_deg,
            psi_deg,
            tilt_deg: F::zero(),
            tilt_dir_deg: F::zero(),
            gyro_elev_deg: F::zero(),
            scale: F::one(),
            bias_dph: F::zero(),
        }
    }

    /// The gyro axis in the level frame L at encoder angle `gamma_deg`.
    pub fn axis_level(&self, gamma_deg: F) -> [F; 3] {
        Tilt::new(self.tilt_deg, self.tilt_dir_deg).apply(self.platform_axis(gamma_deg, self.gyro_elev_deg))
    }

    fn platform_axis(&self, gamma_deg: F, elev_deg: F) -> V3<F> {
        let (sg, cg) = sincos_deg(gamma_deg);
        let (se, ce) = sincos_deg(elev_deg);
        [ce * cg, ce * sg, se]
    }

    /// Components of a level-frame vector along north and up.
    fn north_up(&self, v: V3<F>) -> (F, F) {
        let (sp, cp) = sincos_deg(self.psi_deg);
        (v[0] * cp - v[1] * sp, v[2])
    }

    /// The gyro axis in ENU at encoder angle `gamma_deg`.
    pub fn axis_enu(&self, gamma_deg: F) -> [F; 3] {
        let g = self.axis_level(gamma_deg);
        let (sp, cp) = sincos_deg(self.psi_deg);
        // x_L = (-sin psi, cos psi, 0), y_L = (-cos psi, -sin psi, 0) in ENU.
        [-g[0] * sp - g[1] * cp, g[0] * cp - g[1] * sp, g[2]]
    }

    /// The Earth rate seen along the gyro axis, before scale factor and bias.
    pub fn earth_rate_dph(&self, gamma_deg: F) -> F {
        let (n, u) = self.north_up(self.axis_level(gamma_deg));
        let (sl, cl) = sincos_deg(self.latitude_deg);
        c::<F>(EARTH_RATE_DPH) * (n * cl + u * sl)
    }

    /// The gyro output (noise-free) at encoder angle `gamma_deg`.
    pub fn rate_dph(&self, gamma_deg: F) -> F {
        self.scale * self.earth_rate_dph(gamma_deg) + self.bias_dph
    }

    /// Elevation (deg) of a platform-fixed axis that points `axis_deg` counter-clockwise from
    /// the gyro direction and is raised by `mount_deg`: the inclinometer's X axis is
    /// `(0, offset_x)`, its Y axis `(90, offset_y)`.
    pub fn elevation_deg(&self, gamma_deg: F, axis_deg: F, mount_deg: F) -> F {
        let v = Tilt::new(self.tilt_deg, self.tilt_dir_deg).apply(self.platform_axis(gamma_deg + axis_deg, mount_deg));
        v[2].max(-F::one()).min(F::one()).asin().to_degrees()
    }

    /// Both inclinometer readings `(x, y)` at `gamma_deg` for the given mounting offsets.
    pub fn inclinometer_deg(&self, gamma_deg: F, offset_x_deg: F, offset_y_deg: F) -> (F, F) {
        (
            self.elevation_deg(gamma_deg, F::zero(), offset_x_deg),
            self.elevation_deg(gamma_deg, c(90.0), offset_y_deg),
        )
    }

    /// Analytic partial derivatives of [`Self::rate_dph`].
    pub fn jacobian(&self, gamma_deg: F) -> RateJacobian<F> {
        let per_deg = c::<F>(core::f64::consts::PI / 180.0);
        let we = c::<F>(EARTH_RATE_DPH);
        let (sl, cl) = sincos_deg(self.latitude_deg);
        let (sp, cp) = sincos_deg(self.psi_deg);
        let tilt = Tilt::new(self.tilt_deg, self.tilt_dir_deg);
        let v = self.platform_axis(gamma_deg, self.gyro_elev_deg);
        let g = tilt.apply(v);
        let proj = |d: V3<F>| {
            let (n, u) = self.north_up(d);
            self.scale * we * (n * cl + u * sl) * per_deg
        };
        let (sg, cg) = sincos_deg(gamma_deg);
        let (se, ce) = sincos_deg(self.gyro_elev_deg);
        let (n, u) = self.north_up(g);
        RateJacobian {
            psi: self.scale * we * cl * (-g[0] * sp - g[1] * cp) * per_deg,
            tilt: proj(tilt.d_eta(v)),
            tilt_dir: proj(tilt.d_tau(v)),
            gyro_elev: proj(tilt.apply([-se * cg, -se * sg, ce])),
            scale: we * (n * cl + u * sl),
            bias: F::one(),
            latitude: self.scale * we * (-n * sl + u * cl) * per_deg,
            gamma: proj(tilt.apply([-ce * sg, ce * cg, F::zero()])),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inst() -> Instrument<f64> {
        Instrument {
            latitude_deg: 43.8,
            psi_deg: 65.5,
            tilt_deg: 0.7,
            tilt_dir_deg: 210.0,
            gyro_elev_deg: 0.3,
            scale: 1.002,
            bias_dph: 0.4,
        }
    }

    #[test]
    fn level_instrument_is_eq7() {
        let m = Instrument::level(43.8, 65.5378);
        for i in 0..72 {
            let g = i as f64 * 5.0;
            let eq7 = EARTH_RATE_DPH * 43.8f64.to_radians().cos() * (g + 65.5378f64).to_radians().cos();
            assert!((m.rate_dph(g) - eq7).abs() < 1e-12);
        }
    }

    #[test]
    fn largest_output_at_paper_latitude() {
        let m = Instrument::level(43.8, 0.0);
        assert!((m.rate_dph(0.0) - 10.856).abs() < 5e-4, "{}", m.rate_dph(0.0));
    }

    #[test]
    fn axis_is_unit_and_north_at_minus_psi() {
        let m = inst();
        for i in 0..36 {
            let a = m.axis_enu(i as f64 * 10.0);
            assert!((dot(a, a) - 1.0).abs() < 1e-14);
        }
        // Level: the gyro points north when gamma = -psi, east when gamma = -psi - 90 (clockwise).
        let l = Instrument::level(10.0, 30.0);
        let n = l.axis_enu(-30.0);
        assert!((n[1] - 1.0).abs() < 1e-14);
        let e = l.axis_enu(-120.0);
        assert!((e[0] - 1.0).abs() < 1e-14, "{e:?}");
    }

    #[test]
    fn tilt_lowers_the_platform_towards_tilt_dir() {
        let m = Instrument {
            tilt_deg: 1.0,
            tilt_dir_deg: 30.0,
            ..Instrument::level(0.0, 0.0)
        };
        assert!((m.elevation_deg(30.0, 0.0, 0.0) + 1.0).abs() < 1e-12);
        assert!((m.elevation_deg(210.0, 0.0, 0.0) - 1.0).abs() < 1e-12);
        assert!(m.elevation_deg(120.0, 0.0, 0.0).abs() < 1e-12);
        // Y is 90 deg counter-clockwise from X.
        let (x, y) = m.inclinometer_deg(300.0, 0.0, 0.0);
        assert!(x.abs() < 1e-12 && (y + 1.0).abs() < 1e-12, "{x} {y}");
    }

    #[test]
    fn first_order_tilt_is_a_vertical_rate_first_harmonic() {
        // eta = 10": second-order terms are 1e-9 of the rate.
        let eta = 10.0 / 3600.0;
        let lat: f64 = 43.8;
        let m = Instrument {
            tilt_deg: eta,
            tilt_dir_deg: 75.0,
            ..Instrument::level(lat, 20.0)
        };
        let l = Instrument::level(lat, 20.0);
        for i in 0..36 {
            let g = i as f64 * 10.0;
            let expect = -EARTH_RATE_DPH * lat.to_radians().sin() * eta.to_radians() * (g - 75.0f64).to_radians().cos();
            let d = m.rate_dph(g) - l.rate_dph(g) - expect;
            assert!(d.abs() < 1e-8, "{g}: {d}");
        }
    }

    #[test]
    fn analytic_jacobian_matches_central_differences() {
        let base = inst();
        let h = 1e-5;
        for i in 0..24 {
            let g = i as f64 * 15.0 + 3.0;
            let j = base.jacobian(g);
            let num = |f: &dyn Fn(&mut Instrument<f64>, f64)| {
                let (mut p, mut m) = (base, base);
                f(&mut p, h);
                f(&mut m, -h);
                (p.rate_dph(g) - m.rate_dph(g)) / (2.0 * h)
            };
            let checks = [
                (j.psi, num(&|m, d| m.psi_deg += d)),
                (j.tilt, num(&|m, d| m.tilt_deg += d)),
                (j.tilt_dir, num(&|m, d| m.tilt_dir_deg += d)),
                (j.gyro_elev, num(&|m, d| m.gyro_elev_deg += d)),
                (j.scale, num(&|m, d| m.scale += d)),
                (j.bias, num(&|m, d| m.bias_dph += d)),
                (j.latitude, num(&|m, d| m.latitude_deg += d)),
                (j.gamma, (base.rate_dph(g + h) - base.rate_dph(g - h)) / (2.0 * h)),
            ];
            for (k, (a, n)) in checks.iter().enumerate() {
                assert!(
                    (a - n).abs() < 1e-7 * (1.0 + n.abs()),
                    "gamma {g} param {k}: {a} vs {n}"
                );
            }
        }
    }
}
