//! `nf`, the north finder's host tool.

pub mod allan;
mod allan_cov;
pub mod allan_fit;
pub mod allan_model;
pub mod allan_removed;
pub mod allan_source;
mod amplitude_check;
pub mod analysis;
pub(crate) mod cores;
pub mod diagnose;
pub mod diagnose_eval;
pub mod dwells;
pub mod far_off;
pub mod gap_bridge;
pub mod gls;
pub mod instrument_file;
pub(crate) mod linfit;
pub mod logparse;
pub mod noise_calib;
pub mod noise_est;
pub mod noise_file;
pub mod noise_fit;
pub mod out_path;
pub mod paper;
pub mod plan;
pub mod plan_noise;
pub mod plot;
mod quarter_contrasts;
pub mod range;
pub mod recording;
pub mod replicate;
pub mod report;
pub mod sample_spread;
pub mod schedule;
mod semisep;
pub mod shock_fit;
pub mod sim_compare;
pub mod spikes;
pub mod static_log;
mod stats;
pub mod student_fit;
#[cfg(test)]
mod sweep_run;
pub mod textfile;
pub mod tilt;
mod tilt_sense;
mod toeplitz;
pub mod twin_check;
mod wander_test;

mod cli;

pub use cli::main;
