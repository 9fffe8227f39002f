//! The fit on any recording the reader accepts: a result or a reason, never a panic. A result
//! has an azimuth in 0..360 and a sigma that is not negative.
#![no_main]

use libfuzzer_sys::fuzz_target;
use nf::analysis::{Options, analyse};
use nf::recording::Recording;

/// Positions past which an input is skipped: each fit estimates the noise over a grid.
const MOST_ROWS: usize = 100;

fuzz_target!(|data: &[u8]| {
    let text = nf_fuzz::text(data);
    let Ok(rec) = Recording::parse(&text) else {
        return;
    };
    if rec.rows.len() > MOST_ROWS {
        return;
    }
    let opt = Options {
        replicates: 4,
        ..Options::default()
    };
    let Ok(a) = analyse(&rec, &opt) else {
        return;
    };
    let (psi, sigma) = (a.gls.psi_deg, a.gls.sigma_psi_deg);
    assert!((0.0..360.0).contains(&psi), "psi {psi}\n{text}");
    assert!(sigma >= 0.0, "sigma {sigma}\n{text}");
});
