//! Tasks of the firmware: the gyro ADC, the host link (receive and send), and the run
//! sequencer that drives the stepper, the encoder and the inclinometer through
//! `nf-instrument`'s drivers.

use crate::board::{self, GyroThermometer};
use core::cell::Cell;
use core::fmt::Write as _;
use core::sync::atomic::{AtomicBool, Ordering};
use defmt::{error, info, warn};
use embassy_executor::Spawner;
use embassy_stm32::exti::ExtiInput;
use embassy_stm32::gpio::Output;
use embassy_stm32::mode::Async;
use embassy_stm32::spi::{self, Spi};
use embassy_stm32::usart::{UartRx, UartTx};
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::channel::Channel;
use embassy_sync::signal::Signal;
use embassy_time::{Delay, Instant, Timer};
use embedded_hal_bus::spi::ExclusiveDevice;
use heapless::String;
use nf_instrument::adc::{AdcError, Ads1256};
use nf_instrument::clock::Clock;
use nf_instrument::encoder::{self, BissEncoder};
use nf_instrument::inclinometer::Inclinometer;
use nf_instrument::link::{self, Command};
use nf_instrument::record::{MAX_LINE, write_fixed};
use nf_instrument::run::{self, GyroSource, Instrument, RunConfig, RunReport, Sink};
use nf_instrument::stepper::{self, StepDir};
use {defmt_rtt as _, panic_probe as _};

type Line = String<MAX_LINE>;
type M = CriticalSectionRawMutex;

/// Samples from the ADC task to the sequencer: 0.25 s of buffer at 1 kHz.
static SAMPLES: Channel<M, Result<i32, AdcError>, 256> = Channel::new();
/// Lines to the host.
static TX: Channel<M, Line, 8> = Channel::new();
static START: Signal<M, ()> = Signal::new();
static ABORT: AtomicBool = AtomicBool::new(false);
static RUNNING: AtomicBool = AtomicBool::new(false);
static CONFIG: Mutex<M, Cell<RunConfig>> = Mutex::new(Cell::new(RunConfig::DEFAULT));
static LAST: Mutex<M, Cell<Option<RunReport>>> = Mutex::new(Cell::new(None));

/// embassy-time as the run logic's clock.
#[derive(Clone, Copy)]
struct EmbassyClock;

impl Clock for EmbassyClock {
    fn now_us(&self) -> u64 {
        Instant::now().as_micros()
    }

    async fn delay_us(&mut self, us: u64) {
        Timer::after_micros(us).await;
    }
}

/// The sequencer's view of the ADC task.
struct SampleQueue;

impl GyroSource for SampleQueue {
    async fn next_sample(&mut self) -> Result<i32, AdcError> {
        SAMPLES.receive().await
    }

    fn discard_pending(&mut self) {
        while SAMPLES.try_receive().is_ok() {}
    }
}

/// Recording lines go to the host link, and to the defmt log for `nf log`.
struct HostSink;

impl Sink for HostSink {
    async fn line(&mut self, line: &str) {
        info!("rec {=str}", line);
        let mut l = Line::new();
        let _ = l.push_str(line);
        TX.send(l).await;
    }

    fn abort_requested(&mut self) -> bool {
        ABORT.load(Ordering::Relaxed)
    }
}

type AdcSpi = ExclusiveDevice<Spi<'static, Async, spi::mode::Master>, Output<'static>, Delay>;

#[embassy_executor::task]
async fn gyro_task(mut adc: Ads1256<AdcSpi, ExtiInput<'static, Async>>) {
    if let Err(e) = adc.start(&Default::default()).await {
        error!("adc: start failed: {:?}", e);
    }
    loop {
        let s = adc.next_sample().await;
        // A full queue means nobody is dwelling: the sample is not wanted.
        let _ = SAMPLES.try_send(s);
    }
}

#[embassy_executor::task]
async fn link_tx_task(mut tx: UartTx<'static, Async>) {
    loop {
        let line = TX.receive().await;
        if tx.write(line.as_bytes()).await.and(tx.write(b"\r\n").await).is_err() {
            warn!("host link: write failed");
        }
    }
}

async fn reply(s: &str) {
    let mut l = Line::new();
    let _ = l.push_str(s);
    TX.send(l).await;
}

fn status_line() -> Line {
    let mut l = Line::new();
    let running = RUNNING.load(Ordering::Relaxed);
    let _ = write!(l, "STATUS {}", if running { "running" } else { "idle" });
    if let Some(r) = LAST.lock(|c| c.get()) {
        let _ = write!(l, " last: {} positions", r.positions);
        if let Some(a) = r.azimuth {
            let _ = l.push_str(" psi ");
            let _ = write_fixed(&mut l, a.psi_deg as f64, 5);
            let _ = l.push_str(" sigma_arcsec ");
            let _ = match a.sigma_arcsec {
                Some(s) => write_fixed(&mut l, s as f64, 2),
                // No degrees of freedom: zero would claim a perfect azimuth.
                None => l.write_str("undefined"),
            };
        }
        if let Some(u) = r.under_noise {
            let _ = l.push_str(" under_noise_sigma_arcsec ");
            let _ = write_fixed(&mut l, u.sigma_psi_deg * 3600.0, 2);
        }
        if r.target_reached {
            let _ = l.push_str(" target_reached");
        }
        let _ = l.push_str(if r.result.is_ok() { " ok" } else { " failed" });
    }
    l
}

#[embassy_executor::task]
async fn link_rx_task(mut rx: UartRx<'static, Async>) {
    let mut line = String::<80>::new();
    loop {
        let mut b = [0u8; 1];
        if rx.read(&mut b).await.is_err() {
            warn!("host link: receive error, line dropped");
            line.clear();
            continue;
        }
        match b[0] {
            b'\n' | b'\r' => {
                if line.is_empty() {
                    continue;
                }
                match link::parse(&line) {
                    Ok(cmd) => handle(cmd).await,
                    Err(e) => {
                        let mut l = Line::new();
                        let _ = write!(l, "ERR {e}");
                        TX.send(l).await;
                    }
                }
                line.clear();
            }
            c => {
                if line.push(c as char).is_err() {
                    line.clear();
                    reply("ERR line too long").await;
                }
            }
        }
    }
}

async fn handle(cmd: Command) {
    let running = RUNNING.load(Ordering::Relaxed);
    match cmd {
        Command::Set(_) | Command::Start if running => reply("ERR a run is in progress").await,
        Command::Set(s) => {
            let r = CONFIG.lock(|c| {
                let mut cfg = c.get();
                let r = link::apply(&mut cfg, s);
                c.set(cfg);
                r
            });
            match r {
                Ok(()) => reply("OK").await,
                Err(e) => {
                    let mut l = Line::new();
                    let _ = write!(l, "ERR {e}");
                    TX.send(l).await;
                }
            }
        }
        Command::Start => {
            ABORT.store(false, Ordering::Relaxed);
            START.signal(());
            reply("OK").await;
        }
        Command::Abort => {
            ABORT.store(true, Ordering::Relaxed);
            reply("OK").await;
        }
        Command::Status => TX.send(status_line()).await,
        Command::Config => {
            let c = CONFIG.lock(|c| c.get());
            let mut l = Line::new();
            let _ = write!(
                l,
                "CONFIG n {} order {} dwell_ms {} settle_ms {} lat ",
                c.positions,
                c.order.name(),
                c.dwell_ms,
                c.settle_ms
            );
            let _ = write_fixed(&mut l, c.latitude_deg as f64, 5);
            let _ = l.push_str(" tilt_limit ");
            let _ = write_fixed(&mut l, c.tilt_limit_deg as f64, 4);
            let _ = l.push_str(" target_arcsec ");
            let _ = write_fixed(&mut l, c.target_arcsec as f64, 2);
            let m = c.noise;
            for (key, v, decimals) in [
                (" arw ", m.arw_deg_rth, 7),
                (" bias_instability ", m.bias_instability_dph, 6),
                (" rrw ", m.rrw_dph_rth, 6),
                (" gm_sigma ", m.gm_sigma_dph, 6),
                (" gm_tau ", m.gm_tau_s, 2),
            ] {
                let _ = l.push_str(key);
                let _ = write_fixed(&mut l, v, decimals);
            }
            TX.send(l).await;
        }
    }
}

type Motor = StepDir<Output<'static>, Output<'static>, EmbassyClock>;
type Hw = Instrument<
    Motor,
    Spi<'static, Async, spi::mode::Master>,
    SampleQueue,
    embassy_stm32::usart::BufferedUart<'static>,
    GyroThermometer,
    EmbassyClock,
>;

#[embassy_executor::task]
async fn sequencer_task(mut hw: Hw) {
    loop {
        info!("sequencer: idle, waiting for START");
        START.wait().await;
        let cfg = CONFIG.lock(|c| c.get());
        RUNNING.store(true, Ordering::Relaxed);
        let report = run::run(&mut hw, &cfg, &mut HostSink).await;
        RUNNING.store(false, Ordering::Relaxed);
        LAST.lock(|c| c.set(Some(report)));
        TX.send(status_line()).await;
    }
}

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let p = embassy_stm32::init(board::clocks());
    info!("north finder firmware {=str}", env!("CARGO_PKG_VERSION"));
    let b = board::init(p);
    let (host_tx, host_rx) = b.host.split();
    // Infallible: the CS pin cannot fail.
    let adc_dev = ExclusiveDevice::new(b.adc_spi, b.adc_cs, Delay).unwrap();
    let hw = Instrument {
        motor: StepDir::new(b.step, b.dir, EmbassyClock, stepper::Config::default()),
        encoder: BissEncoder::new(b.encoder_spi, encoder::Config::default()),
        gyro: SampleQueue,
        inclinometer: Inclinometer::new(b.inclinometer, Default::default()),
        thermometer: b.thermometer,
        clock: EmbassyClock,
    };
    spawner.spawn(gyro_task(Ads1256::new(adc_dev, b.adc_drdy)).unwrap());
    spawner.spawn(link_tx_task(host_tx).unwrap());
    spawner.spawn(link_rx_task(host_rx).unwrap());
    spawner.spawn(sequencer_task(hw).unwrap());
}
