//! Time, as the run logic sees it: embassy-time on the MCU, virtual time in the twin.

use embassy_futures::select::{Either, select};

/// A monotonic clock that can wait.
pub trait Clock {
    /// Microseconds since an arbitrary origin.
    fn now_us(&self) -> u64;
    /// Waits `us` microseconds.
    async fn delay_us(&mut self, us: u64);
}

/// Runs `fut`, or gives up after `us` microseconds.
pub async fn with_timeout<C: Clock, T>(clock: &mut C, us: u64, fut: impl Future<Output = T>) -> Option<T> {
    match select(fut, clock.delay_us(us)).await {
        Either::First(v) => Some(v),
        Either::Second(()) => None,
    }
}

/// Time that moves only when waited on: the host tests' clock.
#[cfg(test)]
pub(crate) struct Count(pub u64);

#[cfg(test)]
impl Clock for Count {
    fn now_us(&self) -> u64 {
        self.0
    }
    async fn delay_us(&mut self, us: u64) {
        self.0 += us;
    }
}
