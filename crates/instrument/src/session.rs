//! The host link's session: bytes in, lines assembled, commands handled, replies out. The
//! firmware feeds it the bytes of its USART; the host tests feed it scenario files.

use crate::link::{self, Command};
use crate::record::{MAX_LINE, write_fixed};
use crate::run::{RunConfig, RunReport, TiltPolicy};
use core::fmt::Write;
use heapless::{String, Vec};

/// Longest command line; a longer one is discarded up to its newline.
pub const MAX_COMMAND: usize = 80;

/// What a byte completed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Assembled<'a> {
    Line(&'a str),
    /// A line longer than [`MAX_COMMAND`] ended; none of it is executed.
    TooLong,
    /// A line that is not UTF-8 ended.
    NotUtf8,
}

/// Collects bytes into command lines.
#[derive(Debug, Default)]
pub struct LineAssembler {
    buf: Vec<u8, MAX_COMMAND>,
    /// Inside a line that overflowed: skip to its end.
    discarding: bool,
    /// The last byte returned a line: clear before the next.
    done: bool,
}

impl LineAssembler {
    pub fn push(&mut self, byte: u8) -> Option<Assembled<'_>> {
        if core::mem::take(&mut self.done) {
            self.buf.clear();
        }
        if byte == b'\n' || byte == b'\r' {
            if core::mem::take(&mut self.discarding) {
                return Some(Assembled::TooLong);
            }
            if self.buf.is_empty() {
                return None;
            }
            self.done = true;
            return Some(match core::str::from_utf8(&self.buf) {
                Ok(s) => Assembled::Line(s),
                Err(_) => Assembled::NotUtf8,
            });
        }
        if !self.discarding && self.buf.push(byte).is_err() {
            self.discarding = true;
            self.buf.clear();
        }
        None
    }

    /// Forgets a partial line (after a receive error).
    pub fn reset(&mut self) {
        *self = LineAssembler::default();
    }
}

/// What the firmware must do after a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    None,
    Start,
    Abort,
    /// Store [`Session::cfg`] in flash, then answer `OK` or `ERR`.
    Save,
}

/// One reply line.
pub type ReplyLine = String<MAX_LINE>;
/// The lines a command is answered with.
pub type Reply = Vec<ReplyLine, 3>;

/// The settings, whether a run goes, and the last run's report.
#[derive(Debug, Clone)]
pub struct Session {
    pub cfg: RunConfig,
    running: bool,
    last: Option<RunReport>,
}

impl Default for Session {
    fn default() -> Self {
        Session::new(RunConfig::DEFAULT)
    }
}

impl Session {
    pub const fn new(cfg: RunConfig) -> Self {
        Session {
            cfg,
            running: false,
            last: None,
        }
    }

    pub fn running(&self) -> bool {
        self.running
    }

    /// The sequencer took the run.
    pub fn started(&mut self) {
        self.running = true;
    }

    /// The run ended: its report for STATUS.
    pub fn finished(&mut self, report: RunReport) {
        self.running = false;
        self.last = Some(report);
    }

    /// Handles what a byte completed: what to do, and the answer.
    pub fn handle(&mut self, event: Assembled<'_>) -> (Action, Reply) {
        match event {
            Assembled::Line(l) => match link::parse(l) {
                Ok(cmd) => self.command(cmd),
                Err(e) => (Action::None, line(format_args!("ERR {e}"))),
            },
            Assembled::TooLong => (
                Action::None,
                line(format_args!("ERR line too long (at most {MAX_COMMAND} bytes)")),
            ),
            Assembled::NotUtf8 => (Action::None, line(format_args!("ERR line is not text"))),
        }
    }

    fn command(&mut self, cmd: Command) -> (Action, Reply) {
        match cmd {
            Command::Set(_) | Command::Start | Command::Save | Command::Defaults if self.running => {
                (Action::None, line(format_args!("ERR a run is in progress")))
            }
            Command::Save => (Action::Save, Reply::new()),
            Command::Defaults => {
                self.cfg = RunConfig::DEFAULT;
                (Action::None, line(format_args!("OK")))
            }
            Command::Set(s) => match link::apply(&mut self.cfg, s) {
                Ok(()) => (Action::None, line(format_args!("OK"))),
                Err(e) => (Action::None, line(format_args!("ERR {e}"))),
            },
            Command::Start => {
                self.running = true;
                (Action::Start, line(format_args!("OK")))
            }
            Command::Abort if self.running => (Action::Abort, line(format_args!("OK"))),
            Command::Abort => (Action::None, line(format_args!("ERR no run to abort"))),
            Command::Status => (Action::None, self.status()),
            Command::Config => (Action::None, self.config()),
        }
    }

    /// `STATUS running|idle`, and the last run: dwells, gyro samples lost (when any), azimuth,
    /// sigma, the target.
    pub fn status(&self) -> Reply {
        let mut l = ReplyLine::new();
        let _ = write!(l, "STATUS {}", if self.running { "running" } else { "idle" });
        if let Some(r) = &self.last {
            let _ = write!(l, " last: {} dwells", r.positions);
            if r.missed_samples > 0 {
                let _ = write!(l, " missed_samples {}", r.missed_samples);
            }
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
            let _ = l.push_str(match r.result {
                Ok(()) => " ok",
                Err(e) if e.fault == crate::run::Fault::Aborted => " aborted",
                Err(_) => " failed",
            });
        }
        one(l)
    }

    /// Three lines: the run's settings, the gyro's noise model and its calibration.
    pub fn config(&self) -> Reply {
        let c = &self.cfg;
        let mut a = ReplyLine::new();
        let _ = write!(
            a,
            "CONFIG n {} order {} dwell_ms {} settle_ms {} lat ",
            c.positions,
            c.order.name(),
            c.dwell_ms,
            c.settle_ms
        );
        let _ = write_fixed(&mut a, c.latitude_deg as f64, 5);
        let _ = a.push_str(" tilt_limit ");
        let _ = write_fixed(&mut a, c.tilt_limit_deg as f64, 4);
        let policy = if c.tilt_policy == TiltPolicy::Refuse {
            "refuse"
        } else {
            "warn"
        };
        let _ = write!(a, " tilt_policy {policy} target_arcsec ");
        let _ = write_fixed(&mut a, c.target_arcsec as f64, 2);
        let mut b = ReplyLine::new();
        let _ = b.push_str("CONFIG noise");
        let m = c.noise;
        for (key, v, decimals) in [
            (" arw ", m.arw_deg_rth, 7),
            (" bias_instability ", m.bias_instability_dph, 6),
            (" rrw ", m.rrw_dph_rth, 6),
            (" gm_sigma ", m.gm_sigma_dph, 6),
            (" gm_tau ", m.gm_tau_s, 2),
        ] {
            let _ = b.push_str(key);
            let _ = write_fixed(&mut b, v, decimals);
        }
        let mut c = ReplyLine::new();
        let _ = write!(c, "CONFIG cal zero_counts ");
        let _ = write_fixed(&mut c, self.cfg.calibration.zero_counts, 1);
        let _ = c.push_str(" dph_per_count ");
        let _ = write_fixed(&mut c, self.cfg.calibration.dph_per_count, 12);
        let mut r = Reply::new();
        let _ = r.push(a);
        let _ = r.push(b);
        let _ = r.push(c);
        r
    }
}

fn one(l: ReplyLine) -> Reply {
    let mut r = Reply::new();
    let _ = r.push(l);
    r
}

fn line(args: core::fmt::Arguments<'_>) -> Reply {
    let mut l = ReplyLine::new();
    let _ = l.write_fmt(args);
    one(l)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn feed(a: &mut LineAssembler, bytes: &[u8]) -> std::vec::Vec<std::string::String> {
        let mut out = std::vec::Vec::new();
        for &b in bytes {
            match a.push(b) {
                Some(Assembled::Line(l)) => out.push(l.into()),
                Some(Assembled::TooLong) => out.push("<too long>".into()),
                Some(Assembled::NotUtf8) => out.push("<not utf8>".into()),
                None => {}
            }
        }
        out
    }

    #[test]
    fn lines_end_at_cr_or_lf_and_blank_lines_vanish() {
        let mut a = LineAssembler::default();
        assert_eq!(feed(&mut a, b"SET n 8\r\n\r\nSTART\n"), ["SET n 8", "START"]);
    }

    #[test]
    fn an_over_long_line_is_dropped_whole_and_the_next_one_runs() {
        let mut a = LineAssembler::default();
        let mut bytes = std::vec![b'x'; 100];
        bytes.extend_from_slice(b" START\nSTATUS\n");
        assert_eq!(feed(&mut a, &bytes), ["<too long>", "STATUS"]);
        assert_eq!(feed(&mut a, &[0xff, b'\n']), ["<not utf8>"]);
    }

    #[test]
    fn status_tells_the_samples_the_last_run_lost() {
        let mut session = Session::default();
        let report = |missed| RunReport {
            result: Ok(()),
            positions: 8,
            missed_samples: missed,
            levelling: None,
            azimuth: None,
            under_noise: None,
            target_reached: false,
        };
        session.finished(report(0));
        assert_eq!(session.status()[0].as_str(), "STATUS idle last: 8 dwells ok");
        session.finished(report(12));
        assert_eq!(
            session.status()[0].as_str(),
            "STATUS idle last: 8 dwells missed_samples 12 ok"
        );
    }
}
