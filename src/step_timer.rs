//! STEP pulses from TIM1 channel 1 on PE9 (`nf_instrument::step_train`): PWM mode 2 at 1 MHz
//! ticks with ARR and CCR1 preloaded; the update interrupt writes the period after next and,
//! on the last, sets one-pulse mode, so the counter stops with the pin low. No step is timed
//! by the executor: a late interrupt only has to come within one period (>= 250 us at the
//! default cruise speed).

use core::cell::Cell;
use embassy_stm32::Peri;
use embassy_stm32::gpio::OutputType;
use embassy_stm32::interrupt::{InterruptExt, Priority};
use embassy_stm32::pac::interrupt;
use embassy_stm32::peripherals::{PE9, TIM1};
use embassy_stm32::time::Hertz;
use embassy_stm32::timer::low_level::{OutputCompareMode, Timer};
use embassy_stm32::timer::simple_pwm::PwmPin;
use embassy_stm32::timer::{Ch1, Channel};
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::signal::Signal;
use embassy_time::{Duration, with_timeout};
use nf_instrument::step_train::{Period, StepTimer, Train, Update};

type M = CriticalSectionRawMutex;

/// The train the update interrupt serves (`None` when idle).
static TRAIN: Mutex<M, Cell<Option<Train>>> = Mutex::new(Cell::new(None));
/// Raised by the interrupt when a train's last pulse is out.
static DONE: Signal<M, ()> = Signal::new();

/// TIM1's registers, for the interrupt (which owns no `Timer`).
fn regs() -> embassy_stm32::pac::timer::TimAdv {
    embassy_stm32::pac::TIM1
}

fn preload(p: Period) {
    let r = regs();
    r.arr().write(|w| w.set_arr(p.arr));
    r.ccr(0).write(|w| w.set_ccr(p.ccr));
}

/// TIM1's update interrupt: one more pulse is out.
#[interrupt]
fn TIM1_UP_TIM10() {
    let r = regs();
    r.sr().modify(|w| w.set_uif(false));
    TRAIN.lock(|t| {
        let Some(mut train) = t.get() else { return };
        match train.on_update() {
            Update::Load(p) => preload(p),
            Update::Last => r.cr1().modify(|w| w.set_opm(true)),
            Update::Done => {
                t.set(None);
                DONE.signal(());
                return;
            }
        }
        t.set(Some(train));
    });
}

pub struct Tim1Steps {
    timer: Timer<'static, TIM1>,
    _pin: PwmPin<'static, TIM1, Ch1>,
}

impl Tim1Steps {
    pub fn new(tim: Peri<'static, TIM1>, pin: Peri<'static, PE9>) -> Self {
        let pin = PwmPin::new(pin, OutputType::PushPull);
        let mut timer = Timer::new(tim);
        timer.set_tick_freq(Hertz(1_000_000));
        timer.set_autoreload_preload(true);
        timer.set_output_compare_mode(Channel::Ch1, OutputCompareMode::PwmMode2);
        timer.set_output_compare_preload(Channel::Ch1, true);
        timer.enable_channel(Channel::Ch1, true);
        timer.set_moe(true);
        timer.enable_update_interrupt(true);
        interrupt::TIM1_UP_TIM10.set_priority(Priority::P5);
        // Safety: the handler above only touches TIM1 and the statics it owns.
        unsafe { interrupt::TIM1_UP_TIM10.enable() };
        Tim1Steps { timer, _pin: pin }
    }
}

impl StepTimer for Tim1Steps {
    fn start(&mut self, train: Train) {
        let s = train.start();
        let r = regs();
        DONE.reset();
        r.cr1().modify(|w| w.set_opm(s.one_pulse));
        preload(s.first);
        // Load the first period without an interrupt, then preload the second.
        self.timer.generate_update_event();
        if let Some(p) = s.second {
            preload(p);
        }
        TRAIN.lock(|t| t.set(Some(train)));
        self.timer.start();
    }

    async fn wait_end(&mut self, us: u32) -> bool {
        with_timeout(Duration::from_micros(us as u64), DONE.wait())
            .await
            .is_ok()
    }

    fn stop(&mut self) {
        self.timer.stop();
        TRAIN.lock(|t| t.set(None));
        // The counter back to 0 is below CCR1: in PWM mode 2 the pin is low.
        self.timer.reset();
        DONE.reset();
    }
}
