//! `nf`, the north finder's host tool.

pub mod analysis;
pub mod logparse;
pub mod paper;
pub mod plan;
pub mod recording;
pub mod svg;

mod cli;

pub use cli::main;
