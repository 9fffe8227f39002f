//! The model's fit and the run sequencer on an emulated Cortex-M4F (QEMU `mps2-an386`).
//!
//! Prints one line per result for `tests/qemu.rs`, which computes the same on the host:
//!
//!     fit n=180 psi_deg=... sigma_arcsec=... instructions=...
//!     run psi_deg=... sigma_arcsec=... noise_psi_deg=... noise_sigma_arcsec=... positions=... lines=...
//!
//! and exits through semihosting: 0 when both ran, 1 after a panic.
#![no_std]
#![no_main]

mod count;
mod fake;
mod synthetic;

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use nf_mem as _;
use nf_model::fit::{AzimuthFit, FitConfig};

#[entry]
fn main() -> ! {
    let p = cortex_m::Peripherals::take().expect("taken once, at start");
    let counter = count::Instructions::new(p.SYST);

    let obs = core::hint::black_box(synthetic::observations::<f32>());
    let (fit, instructions) = counter.measure(|| AzimuthFit::fit_all(FitConfig::default(), &obs));
    let fit = fit.expect("the synthetic observations fit");
    hprintln!(
        "fit n={} psi_deg={} sigma_arcsec={} instructions={}",
        fit.n,
        fit.psi_deg,
        fit.sigma_psi_deg * 3600.0,
        instructions
    );

    let (report, lines) = fake::run();
    report.result.expect("the run on the fake instrument finishes");
    let azimuth = report.azimuth.expect("a finished run has an azimuth");
    let noise = report.under_noise.expect("a run with dwells has a running azimuth");
    hprintln!(
        "run psi_deg={} sigma_arcsec={} noise_psi_deg={} noise_sigma_arcsec={} positions={} lines={}",
        azimuth.psi_deg,
        azimuth.sigma_arcsec.unwrap_or(f32::NAN),
        noise.psi_deg,
        noise.sigma_psi_deg * 3600.0,
        report.positions,
        lines
    );
    debug::exit(debug::EXIT_SUCCESS);
    unreachable!("semihosting exit returned")
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("panic: {}", info);
    debug::exit(debug::EXIT_FAILURE);
    // Not reached: QEMU has ended.
    cortex_m::asm::udf()
}
