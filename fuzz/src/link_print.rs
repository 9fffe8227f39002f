//! Host-link commands printed back in the link's syntax (`crates/instrument/src/link.rs`).

use nf_instrument::decimal::pow10;
use nf_instrument::link::{
    ANGLE_DECIMALS, CAL_SCALE_DECIMALS, CAL_ZERO_DECIMALS, Command, NOISE_DECIMALS, NoiseTerm, Setting, TARGET_DECIMALS,
};
use nf_model::order::{Order, VisitList};
use std::fmt::Write;

fn list(l: &VisitList) -> String {
    let mut s = String::new();
    for (i, p) in l.as_slice().iter().enumerate() {
        if i > 0 {
            s.push(',');
        }
        let _ = write!(s, "{p}");
    }
    s
}

/// `units` of `10^-decimals` as a plain decimal, every decimal written.
pub fn fixed(units: i64, decimals: u32) -> String {
    let p = pow10(decimals);
    let sign = if units < 0 { "-" } else { "" };
    let m = units.unsigned_abs();
    if decimals == 0 {
        return format!("{sign}{m}");
    }
    format!("{sign}{}.{:0w$}", m / p, m % p, w = decimals as usize)
}

pub fn noise_key(t: NoiseTerm) -> &'static str {
    match t {
        NoiseTerm::Arw => "arw",
        NoiseTerm::BiasInstability => "bias_instability",
        NoiseTerm::Rrw => "rrw",
        NoiseTerm::GmSigma => "gm_sigma",
        NoiseTerm::GmTau => "gm_tau",
    }
}

/// The line that sets `s`: fixed-point values with all their decimals.
pub fn setting(s: &Setting) -> String {
    match s {
        Setting::Positions(n) => format!("SET n {n}"),
        Setting::DwellMs(v) => format!("SET dwell_ms {v}"),
        Setting::SettleMs(v) => format!("SET settle_ms {v}"),
        Setting::LatitudeUdeg(v) => format!("SET lat {}", fixed(*v, ANGLE_DECIMALS)),
        Setting::TiltLimitUdeg(v) => format!("SET tilt_limit {}", fixed(*v, ANGLE_DECIMALS)),
        Setting::TiltRefuse(true) => "SET tilt_policy refuse".into(),
        Setting::TiltRefuse(false) => "SET tilt_policy warn".into(),
        Setting::Order(Order::List(l)) => format!("SET order {}", list(l)),
        Setting::Order(o) => format!("SET order {}", o.name()),
        Setting::OrderMore(l) => format!("SET order+ {}", list(l)),
        Setting::TargetUarcsec(v) => format!("SET target_arcsec {}", fixed(*v, TARGET_DECIMALS)),
        Setting::Noise(t, v) => format!("SET {} {}", noise_key(*t), fixed(*v, NOISE_DECIMALS)),
        Setting::CalZero(v) => format!("SET cal_zero {}", fixed(*v, CAL_ZERO_DECIMALS)),
        Setting::CalScale(v) => format!("SET cal_scale {}", fixed(*v, CAL_SCALE_DECIMALS)),
    }
}

pub fn command(c: &Command) -> String {
    match c {
        Command::Set(s) => setting(s),
        Command::Start => "START".into(),
        Command::Abort => "ABORT".into(),
        Command::Status => "STATUS".into(),
        Command::Config => "CONFIG".into(),
        Command::Save => "SAVE".into(),
        Command::Defaults => "DEFAULTS".into(),
    }
}
