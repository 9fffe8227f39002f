//! A digital twin of the north finder. It speaks the instrument's wire protocols (BiSS-C frames
//! on an SPI bus, ADS1256 samples behind a DRDY pin, inclinometer lines on a UART, step and
//! direction pins) with the exact physics of `nf-model`, noise, motor and sensor faults, in
//! virtual time: the firmware's own drivers and run logic run against it unchanged, and a
//! 400 s run takes a fraction of a second.

mod bias_step;
pub mod biss;
mod bridge;
mod devices;
mod encoder_error;
mod gm_process;
pub mod noise;
mod quartered;
mod shocks;
mod static_log;
mod step_timer;
mod temp_swing;
mod world;

pub use bias_step::{BiasJump, Disturbance};
pub use devices::{TwinInstrument, instrument};
pub use encoder_error::EncoderHarmonic;
pub use nf_model::rng::Rng;
pub use quartered::QuarteredRecording;
pub use shocks::{Shocks, WindowShift};
pub use static_log::StaticLog;
pub use temp_swing::TempSwing;
pub use world::{Faults, InclinometerFault, TwinConfig, World, virtual_now_us};

use nf_instrument::run::{RunConfig, RunReport, Sink, run};

/// A sink that keeps the recording lines.
#[derive(Default, Debug, Clone)]
pub struct Recorder {
    pub lines: Vec<String>,
    /// Abort when this many record lines have been received.
    pub abort_after_records: Option<usize>,
    /// Abort from this virtual time on, microseconds.
    pub abort_at_us: Option<u64>,
    /// Virtual time the header line came, microseconds: the run's time 0 (`t_s` counts from it).
    pub header_at_us: Option<u64>,
}

impl Recorder {
    /// The recording as one text, with line ends.
    pub fn text(&self) -> String {
        self.lines.iter().map(|l| format!("{l}\n")).collect()
    }

    /// Number of position records (lines that are neither metadata nor the header).
    pub fn records(&self) -> usize {
        self.lines
            .iter()
            .filter(|l| !l.starts_with('#') && !l.starts_with("index"))
            .count()
    }
}

impl Sink for Recorder {
    async fn line(&mut self, line: &str) {
        if line.starts_with("index") {
            self.header_at_us = Some(virtual_now_us());
        }
        self.lines.push(line.to_string());
    }

    fn abort_requested(&mut self) -> bool {
        self.abort_at_us.is_some_and(|t| virtual_now_us() >= t)
            || self.abort_after_records.is_some_and(|n| self.records() >= n)
    }
}

/// Runs the firmware's run logic against a twin built from `twin`.
pub fn simulate(twin: &TwinConfig, cfg: &RunConfig, sink: &mut impl Sink) -> (RunReport, World) {
    let (mut hw, world) = instrument(twin, cfg);
    let report = embassy_futures::block_on(run(&mut hw, cfg, sink));
    let w = world.borrow().clone();
    (report, w)
}
