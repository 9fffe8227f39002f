//! A spinner for work that turns out to be long: shown on standard error (on a terminal
//! only) once the work has taken a second, whatever the machine and the input.

use std::sync::mpsc::{RecvTimeoutError, channel};
use std::time::Duration;

/// How long work runs before the spinner shows.
const QUIET: Duration = Duration::from_secs(1);

/// `job`'s result; after [`QUIET`] a spinner says `message` until the job ends.
pub(crate) fn spinning<T>(message: String, job: impl FnOnce() -> T) -> T {
    let (done, wait) = channel::<()>();
    std::thread::scope(move |s| {
        s.spawn(move || {
            if wait.recv_timeout(QUIET) == Err(RecvTimeoutError::Timeout) {
                let bar = indicatif::ProgressBar::new_spinner();
                bar.set_message(message);
                bar.enable_steady_tick(Duration::from_millis(120));
                // Returns when `done` is dropped, the job ended (or panicked).
                let _ = wait.recv();
                bar.finish_and_clear();
            }
        });
        let out = job();
        drop(done);
        out
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_jobs_result_comes_back_whether_it_is_quick_or_outlasts_the_quiet_second() {
        assert_eq!(spinning("quick".into(), || 7), 7);
        let slow = spinning("slow".into(), || {
            std::thread::sleep(QUIET + Duration::from_millis(200));
            "done"
        });
        assert_eq!(slow, "done");
    }
}
