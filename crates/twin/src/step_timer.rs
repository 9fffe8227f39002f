//! The twin's TIM1, modelled from the reference manual's rules: each period runs from the
//! active ARR and CCR1, its pulse (PWM mode 2) rises at CCR1 and steps the motor, the update
//! event at its end moves the preload registers to the active ones and stops the counter in
//! one-pulse mode, and then the update interrupt runs the firmware's `Train::on_update`.

use crate::world::World;
use nf_instrument::step_train::{Period, StepTimer, Train, Update};
use std::cell::RefCell;
use std::rc::Rc;

struct Running {
    train: Train,
    active: Period,
    preload: Period,
    one_pulse: bool,
    /// When the active period began, us.
    began_us: u64,
    /// Whether its pulse has risen.
    pulsed: bool,
}

pub struct TwinStepTimer {
    world: Rc<RefCell<World>>,
    running: Option<Running>,
}

impl TwinStepTimer {
    pub fn new(world: Rc<RefCell<World>>) -> Self {
        TwinStepTimer { world, running: None }
    }
}

/// Advances the world to `t_us`.
fn until(world: &RefCell<World>, t_us: u64) {
    let mut w = world.borrow_mut();
    let now = w.now_us;
    w.advance(t_us.saturating_sub(now));
}

impl StepTimer for TwinStepTimer {
    fn start(&mut self, train: Train) {
        let s = train.start();
        self.running = Some(Running {
            train,
            active: s.first,
            preload: s.second.unwrap_or(s.first),
            one_pulse: s.one_pulse,
            began_us: self.world.borrow().now_us,
            pulsed: false,
        });
    }

    async fn wait_end(&mut self, us: u32) -> bool {
        let deadline = self.world.borrow().now_us + us as u64;
        while let Some(r) = &mut self.running {
            let (rise, end) = (r.began_us + r.active.ccr as u64, r.began_us + r.active.arr as u64 + 1);
            if !r.pulsed {
                if rise > deadline {
                    break;
                }
                r.pulsed = true;
                until(&self.world, rise);
                self.world.borrow_mut().step();
            }
            if end > deadline {
                break;
            }
            until(&self.world, end);
            let stops = r.one_pulse;
            (r.active, r.began_us, r.pulsed) = (r.preload, end, false);
            match r.train.on_update() {
                Update::Load(p) => r.preload = p,
                Update::Last => r.one_pulse = true,
                Update::Done => {}
            }
            if stops {
                self.running = None;
            }
        }
        if self.running.is_some() {
            until(&self.world, deadline);
            return false;
        }
        true
    }

    fn stop(&mut self) {
        self.running = None;
    }
}
