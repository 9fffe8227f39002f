//! Tasks of the firmware: the gyro ADC, the host link (receive and send), and the run
//! sequencer that drives the stepper, the encoder and the inclinometer through
//! `nf-instrument`'s drivers.

use crate::board::{self, GyroThermometer};
use core::cell::RefCell;
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use defmt::{error, info, warn};
use embassy_executor::{InterruptExecutor, Spawner};
use embassy_stm32::exti::ExtiInput;
use embassy_stm32::flash::Flash;
use embassy_stm32::gpio::Output;
use embassy_stm32::interrupt::{InterruptExt, Priority};
use embassy_stm32::mode::Async;
// The PAC's `interrupt`: the handler attribute and the vector names it checks.
use crate::step_timer::Tim1Steps;
use embassy_stm32::pac::interrupt;
use embassy_stm32::peripherals::IWDG;
use embassy_stm32::spi::{self, Spi};
use embassy_stm32::usart::{RingBufferedUartRx, UartTx};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::channel::Channel;
use embassy_sync::once_lock::OnceLock;
use embassy_time::{Delay, Instant, Timer};
use embedded_hal_bus::spi::ExclusiveDevice;
use heapless::String;
use nf_instrument::adc::{self, AdcError, Ads1256};
use nf_instrument::clock::Clock;
use nf_instrument::encoder::{self, BissEncoder};
use nf_instrument::inclinometer::Inclinometer;
use nf_instrument::record::MAX_LINE;
use nf_instrument::run::{self, GyroSource, Instrument, RunConfig, Sink};
use nf_instrument::session::{Action, LineAssembler, Session};
use nf_instrument::settings;
use nf_instrument::settings_store::{SettingsStore, StoreError};
use nf_instrument::step_train::TimedStepDir;
use nf_instrument::stepper;
use static_cell::ConstStaticCell;
use {defmt_rtt as _, nf_mem as _, panic_probe as _};

// Every log line carries the time since boot.
defmt::timestamp!("{=u64:us}", Instant::now().as_micros());

type Line = String<MAX_LINE>;

/// The gyro ADC's task runs here, in an interrupt above thread mode: a conversion is read when
/// DRDY falls, whatever the run, the host link or the flash are doing.
static HIGH: InterruptExecutor = InterruptExecutor::new();

/// UART5 is unused on this board: its vector drives the high-priority executor.
#[interrupt]
unsafe fn UART5() {
    // Safety: called only from this handler, after `HIGH.start` in `main`.
    unsafe { HIGH.on_interrupt() }
}
type M = CriticalSectionRawMutex;

/// Samples (or their errors, [`adc::to_word`]) from the ADC task to the sequencer: 0.25 s of
/// buffer at 1 kHz.
static SAMPLES: Channel<M, i32, 256> = Channel::new();
/// Samples the full queue turned away.
static MISSED: AtomicU32 = AtomicU32::new(0);
/// Lines to the host (a full queue holds its sender back: none is lost).
static TX: Channel<M, Line, 4> = Channel::new();
/// START: the run's configuration as START took it. (A channel, not a signal: it starts
/// zeroed, in .bss, where a signal of a `RunConfig` takes 624 bytes of flash for its initial
/// value. The session refuses START while a run goes, so it never holds two.)
static START: Channel<M, RunConfig, 1> = Channel::new();
static ABORT: AtomicBool = AtomicBool::new(false);
/// Counts the run's signs of life (it looks for an abort every 50 ms of moving, settling and
/// dwelling); the watchdog is fed only while it grows or no run goes.
static PROGRESS: AtomicU32 = AtomicU32::new(0);
static IDLE: AtomicBool = AtomicBool::new(true);
/// The host link's settings and state, set once the saved settings are loaded. (Set at run
/// time, it starts zeroed in .bss: a constant initial session took 752 bytes of flash.)
static SESSION: OnceLock<Mutex<M, RefCell<Session>>> = OnceLock::new();
/// SAVE requests: the settings to store.
static SAVE: Channel<M, RunConfig, 1> = Channel::new();

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
        adc::from_word(SAMPLES.receive().await)
    }

    fn discard_pending(&mut self) {
        while SAMPLES.try_receive().is_ok() {}
    }

    fn take_missed(&mut self) -> u32 {
        MISSED.swap(0, Ordering::Relaxed)
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
        PROGRESS.fetch_add(1, Ordering::Relaxed);
        ABORT.load(Ordering::Relaxed)
    }
}

type AdcSpi = ExclusiveDevice<Spi<'static, Async, spi::mode::Master>, Output<'static>, Delay>;

#[embassy_executor::task]
async fn gyro_task(mut adc: Ads1256<AdcSpi, ExtiInput<'static, Async>>) {
    if let Err(e) = adc.start(&Default::default(), &mut EmbassyClock).await {
        error!("adc: start failed: {:?}", e);
    }
    loop {
        let s = adc.next_sample().await;
        // A full queue between dwells means nobody wants the sample; within a dwell it is a
        // loss, which the dwell reports (it resets the count when it starts).
        if SAMPLES.try_send(adc::to_word(s)).is_err() {
            MISSED.fetch_add(1, Ordering::Relaxed);
        }
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

/// Bytes from the host: the ring buffer keeps filling by DMA while the task works.
#[embassy_executor::task]
async fn link_rx_task(mut rx: RingBufferedUartRx<'static>) {
    // Commands wait for the saved settings (bytes wait in the ring buffer meanwhile).
    let session = SESSION.get().await;
    let mut lines = LineAssembler::default();
    let mut chunk = [0u8; 32];
    loop {
        let n = match rx.read(&mut chunk).await {
            Ok(n) => n,
            Err(e) => {
                warn!("host link: receive error {:?}, partial line dropped", e);
                lines.reset();
                continue;
            }
        };
        for &b in &chunk[..n] {
            let Some(event) = lines.push(b) else { continue };
            let (action, reply) = session.lock(|s| {
                let mut s = s.borrow_mut();
                let r = s.handle(event);
                if r.0 == Action::Start {
                    ABORT.store(false, Ordering::Relaxed);
                    if START.try_send(s.cfg).is_err() {
                        error!("host link: START while the sequencer has one pending, dropped");
                    }
                }
                r
            });
            match action {
                Action::Abort => ABORT.store(true, Ordering::Relaxed),
                Action::Save => SAVE.send(session.lock(|s| s.borrow().cfg)).await,
                // START signalled the sequencer above, under the session's lock.
                Action::Start | Action::None => {}
            }
            for l in reply {
                TX.send(l).await;
            }
        }
    }
}

type Motor = TimedStepDir<Tim1Steps, Output<'static>>;
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
        let cfg = START.receive().await;
        IDLE.store(false, Ordering::Relaxed);
        let report = run::run(&mut hw, &cfg, &mut HostSink).await;
        IDLE.store(true, Ordering::Relaxed);
        // Set before any START: the host link takes commands only once it is.
        let status = SESSION.get().await.lock(|s| {
            let mut s = s.borrow_mut();
            s.finished(report);
            s.status()
        });
        for l in status {
            TX.send(l).await;
        }
    }
}

type Store = SettingsStore<Flash<'static>>;

/// Loads the saved settings at boot, then stores them on SAVE and answers when the flash is
/// written. (Loading here rather than in `main` keeps one store future in RAM, not two.)
#[embassy_executor::task]
async fn settings_task(mut store: Store) {
    let cfg = load_settings(&mut store).await;
    if SESSION.init(Mutex::new(RefCell::new(Session::new(cfg)))).is_err() {
        // Only this task sets it, once.
        defmt::unreachable!();
    }
    loop {
        // Encoded before the flash is written: the task keeps the bytes, not the settings.
        let mut record = [0; settings::MAX_BYTES];
        let n = settings::encode(&SAVE.receive().await, &mut record);
        let ok = store.save_encoded(&record[..n]).await;
        TX.send(save_reply(ok)).await;
    }
}

/// The answer to SAVE.
fn save_reply(ok: Result<(), StoreError>) -> Line {
    let mut l = Line::new();
    match ok {
        Ok(()) => {
            info!("settings: saved");
            let _ = l.push_str("OK");
        }
        Err(e) => {
            error!("settings: not saved: {:?}", e);
            let _ = l.push_str("ERR settings not saved: flash error");
        }
    }
    l
}

/// The saved settings, or the defaults when there are none or they cannot be read.
async fn load_settings(store: &mut Store) -> RunConfig {
    match store.load().await {
        Ok(Some(cfg)) => {
            info!("settings: loaded from flash");
            cfg
        }
        Ok(None) => {
            info!("settings: none saved, defaults");
            RunConfig::DEFAULT
        }
        Err(e) => {
            error!("settings: not loaded ({:?}), defaults", e);
            RunConfig::DEFAULT
        }
    }
}

/// Feeds the watchdog while the firmware is idle or the run shows progress; a run stuck in a
/// driver stops feeding it, and the MCU resets after [`board::WATCHDOG_US`].
#[embassy_executor::task]
async fn watchdog_task(mut wdg: IndependentWatchdog<'static, IWDG>) {
    wdg.unleash();
    let mut seen = PROGRESS.load(Ordering::Relaxed);
    loop {
        Timer::after_millis(500).await;
        let now = PROGRESS.load(Ordering::Relaxed);
        if IDLE.load(Ordering::Relaxed) || now != seen {
            wdg.pet();
        } else {
            warn!("watchdog: no progress in 500 ms");
        }
        seen = now;
    }
}

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let p = embassy_stm32::init(board::clocks());
    info!(
        "north finder firmware {=str}; last reset: {=str}",
        env!("CARGO_PKG_VERSION"),
        board::reset_cause()
    );
    let b = board::init(p);
    let store = match SettingsStore::new(b.flash, board::SETTINGS_FLASH) {
        Some(s) => s,
        // The range is a constant of the board: wrong only by a programming error.
        None => defmt::panic!("settings: the flash range is not whole sectors"),
    };
    let (host_tx, host_rx) = b.host.split();
    static HOST_RX: ConstStaticCell<[u8; 256]> = ConstStaticCell::new([0; 256]);
    let host_rx = host_rx.into_ring_buffered(HOST_RX.take());
    // Infallible: the CS pin cannot fail.
    let adc_dev = ExclusiveDevice::new(b.adc_spi, b.adc_cs, Delay).unwrap();
    let hw = Instrument {
        motor: TimedStepDir::new(b.step, b.dir, stepper::Config::default()),
        encoder: BissEncoder::new(b.encoder_spi, encoder::Config::default()),
        gyro: SampleQueue,
        inclinometer: Inclinometer::new(b.inclinometer, Default::default()),
        thermometer: b.thermometer,
        clock: EmbassyClock,
    };
    interrupt::UART5.set_priority(Priority::P6);
    let high = HIGH.start(interrupt::UART5);
    high.spawn(gyro_task(Ads1256::new(adc_dev, b.adc_drdy)).unwrap());
    spawner.spawn(link_tx_task(host_tx).unwrap());
    spawner.spawn(link_rx_task(host_rx).unwrap());
    spawner.spawn(sequencer_task(hw).unwrap());
    spawner.spawn(watchdog_task(b.watchdog).unwrap());
    spawner.spawn(settings_task(store).unwrap());
}
