//! The run's settings and the gyro's calibration as bytes for the MCU's flash: a version byte,
//! then every field little-endian. A record read back is checked as the host link checks a
//! `SET`: a stored value out of range is refused, not used.

use crate::run::{RunConfig, TiltPolicy};
use nf_model::dwell::Calibration;
use nf_model::noise_terms::NoiseTerms;
use nf_model::order::{MAX_VISITS, Order, VisitList};

/// Format of the record; a record of another version is not read.
pub const VERSION: u8 = 2;
/// The longest record: the fixed fields and a full listed order.
pub const MAX_BYTES: usize = 128 + 2 * MAX_VISITS;

/// Why a stored record was not taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SettingsError {
    /// Written by another firmware version.
    Version(u8),
    /// Shorter than its fields, or longer.
    Length,
    /// A field out of its range; names it.
    Invalid(&'static str),
}

/// Writes `cfg` into `out`; returns the bytes used.
pub fn encode(cfg: &RunConfig, out: &mut [u8; MAX_BYTES]) -> usize {
    let mut w = Writer { out, at: 0 };
    w.put(&[VERSION]);
    w.put(&cfg.positions.to_le_bytes());
    match cfg.order {
        Order::List(l) => {
            w.put(&[u8::MAX]);
            w.put(&(l.as_slice().len() as u16).to_le_bytes());
            for p in l.as_slice() {
                w.put(&p.to_le_bytes());
            }
        }
        named => w.put(&[named.named_index().unwrap_or(0) as u8]),
    }
    for v in [cfg.dwell_ms, cfg.settle_ms, cfg.sample_rate_hz] {
        w.put(&v.to_le_bytes());
    }
    for v in [
        cfg.latitude_deg,
        cfg.tilt_limit_deg,
        cfg.position_tol_deg,
        cfg.target_arcsec,
    ] {
        w.put(&v.to_le_bytes());
    }
    w.put(&[
        (cfg.tilt_policy == TiltPolicy::Refuse) as u8,
        cfg.max_corrections,
        cfg.tilt_correction as u8,
    ]);
    let m = cfg.noise;
    for v in [
        m.arw_deg_rth,
        m.bias_instability_dph,
        m.rrw_dph_rth,
        m.gm_sigma_dph,
        m.gm_tau_s,
        m.quantization_arcsec,
    ] {
        w.put(&v.to_le_bytes());
    }
    for v in [cfg.calibration.zero_micro_counts, cfg.calibration.femto_dph_per_count] {
        w.put(&v.to_le_bytes());
    }
    w.at
}

/// Reads a record written by [`encode`] and checks every field.
pub fn decode(bytes: &[u8]) -> Result<RunConfig, SettingsError> {
    let mut r = Reader { bytes, at: 0 };
    let version = r.u8()?;
    if version != VERSION {
        return Err(SettingsError::Version(version));
    }
    let positions = r.u16()?;
    let order = match r.u8()? {
        u8::MAX => {
            let mut l = VisitList::EMPTY;
            for _ in 0..r.u16()? {
                l.push(r.u16()?).map_err(|_| SettingsError::Invalid("order"))?;
            }
            Order::List(l)
        }
        k => Order::named(k as usize).ok_or(SettingsError::Invalid("order"))?,
    };
    let (dwell_ms, settle_ms, sample_rate_hz) = (r.u32()?, r.u32()?, r.u32()?);
    let (latitude_deg, tilt_limit_deg, position_tol_deg, target_arcsec) = (r.f32()?, r.f32()?, r.f32()?, r.f32()?);
    let (refuse, max_corrections, tilt_correction) = (r.u8()?, r.u8()?, r.u8()?);
    let noise = NoiseTerms {
        arw_deg_rth: r.f32()?,
        bias_instability_dph: r.f32()?,
        rrw_dph_rth: r.f32()?,
        gm_sigma_dph: r.f32()?,
        gm_tau_s: r.f32()?,
        quantization_arcsec: r.f32()?,
    };
    let calibration = Calibration {
        zero_micro_counts: r.i64()?,
        femto_dph_per_count: r.i64()?,
    };
    if r.at != bytes.len() {
        return Err(SettingsError::Length);
    }
    let cfg = RunConfig {
        positions,
        order,
        dwell_ms,
        settle_ms,
        sample_rate_hz,
        latitude_deg,
        tilt_limit_deg,
        tilt_policy: if refuse == 1 {
            TiltPolicy::Refuse
        } else {
            TiltPolicy::Warn
        },
        position_tol_deg,
        max_corrections,
        tilt_correction: tilt_correction == 1,
        noise,
        target_arcsec,
        calibration,
    };
    check(&cfg)?;
    Ok(cfg)
}

/// The ranges the host link accepts, and what a run needs. Whether the order fits `n` is left
/// to START, which says so (SAVE refuses such settings, so only an older firmware's record
/// can hold one, and it loads).
fn check(c: &RunConfig) -> Result<(), SettingsError> {
    let within = |ok: bool, name| if ok { Ok(()) } else { Err(SettingsError::Invalid(name)) };
    within((4..=720).contains(&c.positions), "n")?;
    within((10..=600_000).contains(&c.dwell_ms), "dwell_ms")?;
    within(c.settle_ms <= 60_000, "settle_ms")?;
    within((1..=30_000).contains(&c.sample_rate_hz), "sample_rate_hz")?;
    within((-89.0..=89.0).contains(&c.latitude_deg), "lat")?;
    within((0.0..=10.0).contains(&c.tilt_limit_deg), "tilt_limit")?;
    within(c.position_tol_deg > 0.0 && c.position_tol_deg < 1.0, "position_tol")?;
    within((0.0..=36_000.0).contains(&c.target_arcsec), "target_arcsec")?;
    within(c.noise.validate().is_ok(), "noise model")?;
    within(c.calibration.is_valid(), "cal")
}

struct Writer<'a> {
    out: &'a mut [u8; MAX_BYTES],
    at: usize,
}

impl Writer<'_> {
    fn put(&mut self, b: &[u8]) {
        self.out[self.at..self.at + b.len()].copy_from_slice(b);
        self.at += b.len();
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], SettingsError> {
        let b = self.bytes.get(self.at..self.at + N).ok_or(SettingsError::Length)?;
        self.at += N;
        b.try_into().map_err(|_| SettingsError::Length)
    }
    fn u8(&mut self) -> Result<u8, SettingsError> {
        Ok(self.take::<1>()?[0])
    }
    fn u16(&mut self) -> Result<u16, SettingsError> {
        self.take().map(u16::from_le_bytes)
    }
    fn u32(&mut self) -> Result<u32, SettingsError> {
        self.take().map(u32::from_le_bytes)
    }
    fn f32(&mut self) -> Result<f32, SettingsError> {
        self.take().map(f32::from_le_bytes)
    }
    fn i64(&mut self) -> Result<i64, SettingsError> {
        self.take().map(i64::from_le_bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_setting_round_trips() {
        let mut cfg = RunConfig {
            positions: 36,
            order: Order::parse("0,18,19,1,2,20").unwrap(),
            dwell_ms: 1500,
            settle_ms: 250,
            latitude_deg: -33.9,
            tilt_limit_deg: 0.2,
            tilt_policy: TiltPolicy::Warn,
            target_arcsec: 18.0,
            ..RunConfig::DEFAULT
        };
        cfg.noise.bias_instability_dph = 0.004;
        cfg.calibration.zero_micro_counts = -1_234_500_000;
        let mut buf = [0; MAX_BYTES];
        let n = encode(&cfg, &mut buf);
        assert_eq!(decode(&buf[..n]), Ok(cfg));
        for order in Order::NAMED {
            let c = RunConfig {
                order,
                ..RunConfig::DEFAULT
            };
            let n = encode(&c, &mut buf);
            assert_eq!(decode(&buf[..n]), Ok(c));
        }
    }

    #[test]
    fn a_bad_record_is_refused_and_says_why() {
        let mut buf = [0; MAX_BYTES];
        let n = encode(&RunConfig::DEFAULT, &mut buf);
        assert_eq!(decode(&buf[..n - 1]), Err(SettingsError::Length));
        // Version 1 kept the calibration in f64.
        let mut v1 = buf;
        v1[0] = 1;
        assert_eq!(decode(&v1[..n]), Err(SettingsError::Version(1)));
        // n = 3 positions.
        let mut bad = buf;
        bad[1] = 3;
        assert_eq!(decode(&bad[..n]), Err(SettingsError::Invalid("n")));
        let lat = RunConfig {
            latitude_deg: f32::NAN,
            ..RunConfig::DEFAULT
        };
        let n = encode(&lat, &mut buf);
        assert_eq!(decode(&buf[..n]), Err(SettingsError::Invalid("lat")));
        let mut cal = RunConfig::DEFAULT;
        cal.calibration.femto_dph_per_count = 0;
        let n = encode(&cal, &mut buf);
        assert_eq!(decode(&buf[..n]), Err(SettingsError::Invalid("cal")));
    }
}
