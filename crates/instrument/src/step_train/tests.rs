use super::*;
use embedded_hal_mock::eh1::digital::{Mock, State, Transaction as T};
use std::vec::Vec;

/// A model of an STM32 advanced timer in PWM mode 2 with ARR and CCR preloaded, written from
/// the reference manual's rules, not from `Train`: the preload registers move to the active
/// ones at each update event; one-pulse mode stops the counter at the next update; the
/// update interrupt runs after the event, within the new period.
struct ModelTimer {
    active: Period,
    preload: Period,
    one_pulse: bool,
    running: bool,
    now: u64,
    /// Rising edges of the pin, and the pulse widths, in ticks.
    rises: Vec<u64>,
    widths: Vec<u64>,
}

impl ModelTimer {
    fn run(mut train: Train) -> ModelTimer {
        let s = train.start();
        // The first period is written, loaded by a software update event, then the second
        // preloaded before the counter is enabled.
        let mut m = ModelTimer {
            active: s.first,
            preload: s.second.unwrap_or(s.first),
            one_pulse: s.one_pulse,
            running: true,
            now: 0,
            rises: Vec::new(),
            widths: Vec::new(),
        };
        let mut guard = 0;
        while m.running {
            let (arr, ccr) = (m.active.arr as u64, m.active.ccr as u64);
            m.rises.push(m.now + ccr);
            m.widths.push(arr + 1 - ccr);
            m.now += arr + 1;
            // Update event.
            m.active = m.preload;
            if m.one_pulse {
                m.running = false;
            }
            match train.on_update() {
                Update::Load(p) => m.preload = p,
                Update::Last => m.one_pulse = true,
                Update::Done => assert!(!m.running, "done while the counter runs"),
            }
            guard += 1;
            assert!(guard <= train.steps() + 1, "the counter never stopped");
        }
        assert_eq!(train.pulses(), train.steps());
        m
    }
}

#[test]
fn each_step_is_one_pulse_spaced_by_the_profile() {
    let cfg = Config::default();
    for steps in [1u32, 2, 3, 7, 444, 5000] {
        let m = ModelTimer::run(Train::new(cfg, steps));
        assert_eq!(m.rises.len(), steps as usize, "{steps}");
        assert!(m.widths.iter().all(|&w| w == cfg.pulse_us as u64));
        for k in 0..steps as usize - 1 {
            assert_eq!(
                m.rises[k + 1] - m.rises[k],
                cfg.interval_us(k as u32, steps) as u64,
                "{steps} at {k}"
            );
        }
        // The first step comes after the direction's setup time.
        assert_eq!(m.rises[0], DIR_SETUP_US as u64);
    }
}

#[test]
fn periods_stay_within_the_16_bit_counter() {
    let slow = Config {
        start_sps: 1.0,
        max_sps: 2.0,
        ..Config::default()
    };
    let t = Train::new(slow, 3);
    assert_eq!(t.period(1).arr, u16::MAX);
    let p = Train::new(
        Config {
            pulse_us: 0,
            ..Config::default()
        },
        3,
    )
    .period(2);
    assert_eq!(p.arr + 1 - p.ccr, 1, "a zero-width pulse is one tick");
}

/// A timer in virtual time: a train lasts the sum of its periods.
#[derive(Default)]
struct FakeTimer {
    left_us: u64,
    started: Vec<u32>,
    stopped: bool,
}

impl StepTimer for FakeTimer {
    fn start(&mut self, train: Train) {
        self.started.push(train.steps());
        self.left_us = (0..train.steps()).map(|k| train.period(k).arr as u64 + 1).sum();
    }

    async fn wait_end(&mut self, us: u32) -> bool {
        self.left_us = self.left_us.saturating_sub(us as u64);
        self.left_us == 0
    }

    fn stop(&mut self) {
        self.stopped = true;
    }
}

#[test]
fn a_move_sets_the_direction_runs_the_train_and_stops_on_request() {
    let dir = Mock::new(&[T::set(State::Low), T::set(State::High), T::set(State::High)]);
    let mut m = TimedStepDir::new(FakeTimer::default(), dir, Config::default());
    embassy_futures::block_on(m.move_steps(-444, &mut || false)).unwrap();
    assert_eq!(m.timer.started, [444]);
    let mut asked = 0;
    let r = embassy_futures::block_on(m.move_steps(30_000, &mut || {
        asked += 1;
        asked > 3
    }));
    assert_eq!(r, Err(MotorError::Stopped));
    assert!(m.timer.stopped);
    embassy_futures::block_on(m.move_steps(0, &mut || false)).unwrap();
    assert_eq!(m.timer.started, [444, 30_000]);
    m.dir.done();
}
