//! The north finder's firmware. On the MCU (`cargo fw`, see the README) it wires the
//! STM32F407VG to the drivers and run logic of `nf-instrument`; on the host (`cargo run`) the
//! same logic runs against the digital twin of `nf-twin`.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(target_os = "none")]
mod board;
#[cfg(target_os = "none")]
mod firmware;
#[cfg(target_os = "none")]
mod step_timer;

#[cfg(not(target_os = "none"))]
mod host;

#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    host::main()
}
