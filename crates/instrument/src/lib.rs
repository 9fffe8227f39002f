//! The north finder's drivers and run logic, generic over `embedded-hal-async` and
//! `embedded-io-async`: the firmware wires them to the STM32, the digital twin to a simulated
//! instrument in virtual time.
//!
//! Logging goes to `defmt` with the `defmt` feature (firmware) and to `log` with the `log`
//! feature (host).
#![no_std]
#![allow(async_fn_in_trait)]

#[macro_use]
mod fmt;

pub mod adc;
pub mod clock;
pub mod decimal;
pub mod encoder;
pub mod encoder_angle;
mod fault_text;
pub mod inclinometer;
pub mod link;
pub mod link_key;
pub mod record;
pub mod run;
pub mod session;
pub mod settings;
pub mod settings_store;
pub mod step_train;
pub mod stepper;
pub mod white_pool;

#[cfg(test)]
extern crate std;
