//! Host-link commands. On any text: no panic, and a command that parses prints back (in the
//! link's syntax, values in fixed point) to a line that parses to the same command. Model:
//! commands built from the input, printed, parse back to themselves when their values are in
//! range and are refused as out of range when not; applied in turn to the run's
//! configuration, each changes just its own setting, a refused one changes nothing, and an
//! order that passes its check visits only positions below `n`.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf_fuzz::link_print;
use nf_instrument::decimal::to_f32;
use nf_instrument::link::{
    self, ANGLE_DECIMALS, Command, LinkError, NOISE_DECIMALS, NoiseTerm, Setting, TARGET_DECIMALS,
};
use nf_instrument::run::{RunConfig, TiltPolicy};
use nf_model::order::{MAX_VISITS, Order, VisitList};

fn list(u: &mut Unstructured) -> Result<VisitList> {
    let mut l = VisitList::EMPTY;
    let n = u.int_in_range(1..=MAX_VISITS)?;
    let small = u.arbitrary::<bool>()?;
    for _ in 0..n {
        let p = if small { u.int_in_range(0..=80)? } else { u.arbitrary()? };
        if l.push(p).is_err() {
            break;
        }
    }
    Ok(l)
}

/// A fixed-point value (units of the setting's decimals) that is sometimes in range,
/// sometimes just outside it, sometimes anything.
fn fixed(u: &mut Unstructured, lo: i64, hi: i64) -> Result<i64> {
    Ok(match u.int_in_range(0..=5u8)? {
        0 => u.arbitrary()?,
        1 => lo,
        2 => hi,
        3 => [lo - 1, hi + 1, i64::MIN, i64::MAX, 0][u.int_in_range(0..=4usize)?],
        _ => u.int_in_range(lo..=hi)?,
    })
}

fn int<T: TryFrom<i64>>(u: &mut Unstructured, lo: i64, hi: i64) -> Result<T> {
    let v = match u.int_in_range(0..=3u8)? {
        0 => lo - 1,
        1 => hi + 1,
        _ => u.int_in_range(lo..=hi)?,
    };
    T::try_from(v.max(0)).map_err(|_| arbitrary::Error::IncorrectFormat)
}

/// A command and whether its values are in the link's ranges.
fn command(u: &mut Unstructured) -> Result<(Command, bool)> {
    let terms = [
        NoiseTerm::Arw,
        NoiseTerm::BiasInstability,
        NoiseTerm::Rrw,
        NoiseTerm::GmSigma,
        NoiseTerm::GmTau,
    ];
    let r = |v: i64, lo: i64, hi: i64| v >= lo && v <= hi;
    let s = match u.int_in_range(0..=18u8)? {
        0 => return Ok((Command::Start, true)),
        1 => return Ok((Command::Abort, true)),
        2 => return Ok((Command::Status, true)),
        3 => return Ok((Command::Config, true)),
        15 => return Ok((Command::Save, true)),
        16 => return Ok((Command::Defaults, true)),
        17 => {
            let v = fixed(u, -8_388_608_000_000, 8_388_608_000_000)?;
            (Setting::CalZero(v), r(v, -8_388_608_000_000, 8_388_608_000_000))
        }
        18 => {
            let max = 1_000_000_000_000_000;
            let v = fixed(u, -max, max)?;
            (Setting::CalScale(v), v != 0 && r(v, -max, max))
        }
        4 => {
            let n: u16 = int(u, 4, 720)?;
            (Setting::Positions(n), (4..=720).contains(&n))
        }
        5 => {
            let v: u32 = int(u, 10, 600_000)?;
            (Setting::DwellMs(v), (10..=600_000).contains(&v))
        }
        6 => {
            let v: u32 = int(u, 0, 60_000)?;
            (Setting::SettleMs(v), v <= 60_000)
        }
        7 => {
            let v = fixed(u, -89_000_000, 89_000_000)?;
            (Setting::LatitudeUdeg(v), r(v, -89_000_000, 89_000_000))
        }
        8 => {
            let v = fixed(u, 0, 10_000_000)?;
            (Setting::TiltLimitUdeg(v), r(v, 0, 10_000_000))
        }
        9 => (Setting::TiltRefuse(u.arbitrary()?), true),
        10 => {
            let o = if u.arbitrary()? {
                *u.choose(&Order::NAMED)?
            } else {
                Order::List(list(u)?)
            };
            (Setting::Order(o), true)
        }
        11 => (Setting::OrderMore(list(u)?), true),
        12 => {
            let v = fixed(u, 0, 36_000_000_000)?;
            (Setting::TargetUarcsec(v), r(v, 0, 36_000_000_000))
        }
        _ => {
            let v = fixed(u, 0, 1_000_000_000_000_000)?;
            (Setting::Noise(*u.choose(&terms)?, v), r(v, 0, 1_000_000_000_000_000))
        }
    };
    Ok((Command::Set(s.0), s.1))
}

/// The configuration as `s` would leave it, or `None` when `s` must be refused.
fn model(cfg: &RunConfig, s: &Setting) -> Option<RunConfig> {
    let mut c = *cfg;
    match *s {
        Setting::Positions(n) => c.positions = n,
        Setting::DwellMs(v) => c.dwell_ms = v,
        Setting::SettleMs(v) => c.settle_ms = v,
        Setting::LatitudeUdeg(v) => c.latitude_deg = to_f32(v, ANGLE_DECIMALS),
        Setting::TiltLimitUdeg(v) => c.tilt_limit_deg = to_f32(v, ANGLE_DECIMALS),
        Setting::TiltRefuse(r) => c.tilt_policy = if r { TiltPolicy::Refuse } else { TiltPolicy::Warn },
        Setting::Order(o) => c.order = o,
        Setting::TargetUarcsec(v) => c.target_arcsec = to_f32(v, TARGET_DECIMALS),
        Setting::CalZero(v) => c.calibration.zero_micro_counts = v,
        Setting::CalScale(v) => c.calibration.femto_dph_per_count = v,
        Setting::Noise(t, v) => {
            let v = to_f32(v, NOISE_DECIMALS);
            let m = &mut c.noise;
            match t {
                NoiseTerm::Arw => m.arw_deg_rth = v,
                NoiseTerm::BiasInstability => m.bias_instability_dph = v,
                NoiseTerm::Rrw => m.rrw_dph_rth = v,
                NoiseTerm::GmSigma => m.gm_sigma_dph = v,
                NoiseTerm::GmTau => m.gm_tau_s = v,
            }
        }
        Setting::OrderMore(more) => {
            let Order::List(l) = cfg.order else { return None };
            let all: Vec<u16> = l.as_slice().iter().chain(more.as_slice()).copied().collect();
            if all.len() > MAX_VISITS {
                return None;
            }
            let mut longer = VisitList::EMPTY;
            all.iter().for_each(|&p| longer.push(p).unwrap());
            c.order = Order::List(longer);
        }
    }
    Some(c)
}

fn structured(u: &mut Unstructured) -> Result<()> {
    let mut cfg = RunConfig::DEFAULT;
    for _ in 0..u.int_in_range(1..=16)? {
        let (cmd, in_range) = command(u)?;
        let line = link_print::command(&cmd);
        let parsed = link::parse(&line);
        if in_range {
            assert_eq!(parsed, Ok(cmd), "{line}");
        } else {
            assert!(matches!(parsed, Err(LinkError::OutOfRange(_))), "{line}: {parsed:?}");
        }
        let Ok(Command::Set(s)) = parsed else { continue };
        let want = model(&cfg, &s);
        let before = cfg;
        match link::apply(&mut cfg, s) {
            Ok(()) => assert_eq!(Some(cfg), want, "{line}"),
            Err(e) => {
                assert!(want.is_none(), "{line}: {e}");
                assert_eq!(cfg, before, "{line} was refused ({e}) but changed the configuration");
            }
        }
        if cfg.order.check(cfg.positions).is_ok() {
            let n = cfg.positions;
            let visits = cfg.order.positions(n).inspect(|&p| assert!(p < n)).count();
            assert_eq!(visits, cfg.order.visits(n) as usize);
        }
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let text = nf_fuzz::text(data);
    for line in text.split(['\n', '\r']) {
        if let Ok(cmd) = link::parse(line) {
            let printed = link_print::command(&cmd);
            assert_eq!(link::parse(&printed), Ok(cmd), "{line:?} printed as {printed:?}");
        }
    }
    let _ = structured(&mut Unstructured::new(data));
});
