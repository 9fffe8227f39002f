//! Host-link commands printed back in the link's syntax (`crates/instrument/src/link.rs`).

use nf_instrument::link::{Command, NoiseTerm, Setting};
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

pub fn noise_key(t: NoiseTerm) -> &'static str {
    match t {
        NoiseTerm::Arw => "arw",
        NoiseTerm::BiasInstability => "bias_instability",
        NoiseTerm::Rrw => "rrw",
        NoiseTerm::GmSigma => "gm_sigma",
        NoiseTerm::GmTau => "gm_tau",
    }
}

/// The line that sets `s`. Floats print as the shortest text that reads back to the same
/// value; a noise term is an `f32` on the link.
pub fn setting(s: &Setting) -> String {
    match s {
        Setting::Positions(n) => format!("SET n {n}"),
        Setting::DwellMs(v) => format!("SET dwell_ms {v}"),
        Setting::SettleMs(v) => format!("SET settle_ms {v}"),
        Setting::LatitudeDeg(v) => format!("SET lat {v}"),
        Setting::TiltLimitDeg(v) => format!("SET tilt_limit {v}"),
        Setting::TiltRefuse(true) => "SET tilt_policy refuse".into(),
        Setting::TiltRefuse(false) => "SET tilt_policy warn".into(),
        Setting::Order(Order::List(l)) => format!("SET order {}", list(l)),
        Setting::Order(o) => format!("SET order {}", o.name()),
        Setting::OrderMore(l) => format!("SET order+ {}", list(l)),
        Setting::TargetArcsec(v) => format!("SET target_arcsec {v}"),
        Setting::Noise(t, v) => format!("SET {} {}", noise_key(*t), *v as f32),
        Setting::CalZero(v) => format!("SET cal_zero {}", *v as f32),
        Setting::CalScale(v) => format!("SET cal_scale {}", *v as f32),
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
