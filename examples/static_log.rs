//! A twin static log (`northfinder-static/1`) for `nf allan`, its noise from a noise file:
//! `cargo run --release --example static_log -- OUT HOURS RATE_HZ SEED NOISE_FILE`.

use nf::noise_file;
use nf_twin::StaticLog;
use std::io::Write;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [out, hours, hz, seed, noise] = args.as_slice() else {
        return Err("usage: static_log OUT HOURS RATE_HZ SEED NOISE_FILE".into());
    };
    let num = |s: &str| s.parse::<f64>().map_err(|e| format!("{s}: {e}"));
    let log = StaticLog {
        noise: noise_file::read(noise)?,
        // A bias plus the Earth rate's projection: the Allan variance does not see it.
        rate_dph: 7.3,
        sample_rate_hz: num(hz)?,
        duration_s: num(hours)? * 3600.0,
        seed: seed.parse().map_err(|e| format!("{seed}: {e}"))?,
    };
    let file = std::fs::File::create(out).map_err(|e| format!("{out}: {e}"))?;
    let mut w = std::io::BufWriter::new(file);
    log.write(&mut w)
        .and_then(|_| w.flush())
        .map_err(|e| format!("{out}: {e}"))
}
