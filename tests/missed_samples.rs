//! Samples the gyro source loses during a dwell (a queue that overran) are counted, written in
//! the dwell's `missed` column, totalled in the run report, and not averaged.

use nf::recording::Recording;
use nf_instrument::adc::AdcError;
use nf_instrument::run::{GyroSource, Instrument, RunConfig, TiltPolicy, run};
use nf_twin::{Recorder, TwinConfig, instrument};

/// The twin's ADC, losing every `every`-th sample it converts.
struct Lossy<G> {
    inner: G,
    every: u32,
    seen: u32,
    missed: u32,
}

impl<G: GyroSource> GyroSource for Lossy<G> {
    async fn next_sample(&mut self) -> Result<i32, AdcError> {
        self.seen += 1;
        if self.seen.is_multiple_of(self.every) {
            let _ = self.inner.next_sample().await?;
            self.missed += 1;
        }
        self.inner.next_sample().await
    }

    fn discard_pending(&mut self) {
        self.inner.discard_pending();
    }

    fn take_missed(&mut self) -> u32 {
        std::mem::take(&mut self.missed)
    }
}

#[test]
fn each_dwell_reports_the_samples_it_lost() {
    let cfg = RunConfig {
        positions: 8,
        dwell_ms: 500,
        settle_ms: 100,
        tilt_policy: TiltPolicy::Warn,
        ..RunConfig::default()
    };
    let (hw, _world) = instrument(&TwinConfig::default(), &cfg);
    let mut hw = Instrument {
        motor: hw.motor,
        encoder: hw.encoder,
        gyro: Lossy {
            inner: hw.gyro,
            every: 50,
            seen: 0,
            missed: 0,
        },
        inclinometer: hw.inclinometer,
        thermometer: hw.thermometer,
        clock: hw.clock,
    };
    let mut sink = Recorder::default();
    let report = embassy_futures::block_on(run(&mut hw, &cfg, &mut sink));
    assert!(report.result.is_ok(), "{:?}", report.result);
    let text = sink.text();
    let header = text.lines().find(|l| l.starts_with("index")).unwrap();
    let col = header.split(',').position(|c| c == "missed").expect("a missed column");
    let expected = cfg.dwell_ms * cfg.sample_rate_hz / 1000;
    let mut total = 0;
    for line in text.lines().filter(|l| l.as_bytes()[0].is_ascii_digit()) {
        let missed: u32 = line.split(',').nth(col).unwrap().parse().unwrap();
        // One in 50 requests also loses a sample: about a 50th of each dwell.
        assert!(
            missed.abs_diff(expected / 50) <= 1,
            "{missed} missed of {expected}: {line}"
        );
        total += missed;
    }
    assert_eq!(report.missed_samples, total);
    // The reader ignores the column and still counts what was averaged.
    let rec = Recording::parse(&text).unwrap();
    assert!(rec.rows.iter().all(|r| r.samples == Some(expected)));
}
