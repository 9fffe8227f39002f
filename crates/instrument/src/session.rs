//! The host link's session: bytes in, lines assembled, commands handled, replies out. The
//! firmware feeds it the bytes of its USART; the host tests feed it scenario files.

use crate::link::{self, Command, Key, LinkError, NoiseTerm, Setting};
use crate::record::MAX_LINE;
use crate::run::{RunConfig, RunReport, TiltPolicy};
use core::fmt::Write;
use heapless::{String, Vec};
use nf_model::dwell::Calibration;
use nf_model::text;

/// Longest command line; a longer one is discarded up to its newline.
pub const MAX_COMMAND: usize = 80;

/// What a byte completed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Assembled<'a> {
    Line(&'a str),
    /// A line longer than [`MAX_COMMAND`] ended; none of it is executed.
    TooLong,
    /// A line with a byte outside ASCII ended (the commands are ASCII).
    NotAscii,
}

/// Collects bytes into command lines.
#[derive(Debug, Default)]
pub struct LineAssembler {
    buf: String<MAX_COMMAND>,
    /// Inside a line that overflowed: skip to its end.
    discarding: bool,
    /// The line so far has a byte outside ASCII.
    not_ascii: bool,
    /// The last byte returned a line: clear before the next.
    done: bool,
}

impl LineAssembler {
    pub fn push(&mut self, byte: u8) -> Option<Assembled<'_>> {
        if core::mem::take(&mut self.done) {
            self.buf.clear();
            self.not_ascii = false;
        }
        if byte == b'\n' || byte == b'\r' {
            if core::mem::take(&mut self.discarding) {
                return Some(Assembled::TooLong);
            }
            if self.buf.is_empty() {
                return None;
            }
            self.done = true;
            return Some(if self.not_ascii {
                Assembled::NotAscii
            } else {
                Assembled::Line(&self.buf)
            });
        }
        // Leading blanks (tabs, form feeds too) are not kept: a line of them is an empty line,
        // with no reply.
        if self.discarding || (self.buf.is_empty() && link::blank(byte)) {
            return None;
        }
        // A byte outside ASCII still counts toward the length; ASCII needs no UTF-8 decoder.
        self.not_ascii |= !byte.is_ascii();
        let c = if byte.is_ascii() { byte as char } else { '?' };
        if self.buf.push(c).is_err() {
            self.discarding = true;
            self.buf.clear();
            self.not_ascii = false;
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
    /// The last `SET order` or `SET order+` was refused: a continuation would extend the list
    /// before it.
    order_refused: bool,
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
            order_refused: false,
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
                Err(e) => {
                    self.order_refused |= matches!(e, LinkError::Order(_));
                    (Action::None, error(e))
                }
            },
            Assembled::TooLong => {
                let mut l = ReplyLine::new();
                let _ = l.push_str("ERR line too long (at most ");
                let _ = text::write_u64(&mut l, MAX_COMMAND as u64);
                let _ = l.push_str(" bytes)");
                (Action::None, one(l))
            }
            Assembled::NotAscii => (Action::None, line("ERR line is not text")),
        }
    }

    fn command(&mut self, cmd: Command) -> (Action, Reply) {
        match cmd {
            Command::Set(_) | Command::Start | Command::Save | Command::Defaults if self.running => {
                (Action::None, line("ERR a run is in progress"))
            }
            // A record that makes no run would not load at boot: refused, as START refuses it.
            Command::Save | Command::Start if let Some(why) = self.no_run() => (Action::None, why),
            Command::Save => (Action::Save, Reply::new()),
            Command::Defaults => {
                self.cfg = RunConfig::DEFAULT;
                (Action::None, line("OK"))
            }
            // After a refused list, a continuation would extend the list before it.
            Command::Set(Setting::OrderMore(_)) if self.order_refused => {
                (Action::None, error(LinkError::NoListToExtend))
            }
            Command::Set(s) => {
                let order = matches!(s, Setting::Order(_));
                match link::apply(&mut self.cfg, s) {
                    Ok(()) => {
                        self.order_refused &= !order;
                        (Action::None, line("OK"))
                    }
                    Err(e) => {
                        self.order_refused |= matches!(e, LinkError::Order(_));
                        (Action::None, error(e))
                    }
                }
            }
            Command::Start => {
                self.running = true;
                (Action::Start, line("OK"))
            }
            Command::Abort if self.running => (Action::Abort, line("OK")),
            Command::Abort => (Action::None, line("ERR no run to abort")),
            Command::Status => (Action::None, self.status()),
            Command::Config => (Action::None, self.config()),
        }
    }

    /// Why the settings make no run, as the answer: an order that does not fit `n`, or the one
    /// noise model the link's numbers can set that is none.
    fn no_run(&self) -> Option<Reply> {
        match self.cfg.order.check(self.cfg.positions) {
            Err(e) => Some(error(LinkError::Order(e))),
            Ok(()) if self.cfg.noise.gm_sigma_dph > 0.0 && self.cfg.noise.gm_tau_s <= 0.0 => {
                Some(line("ERR gm_sigma needs gm_tau"))
            }
            Ok(()) => None,
        }
    }

    /// `STATUS running|idle`, and the last run: dwells, gyro samples lost (when any), azimuth,
    /// sigma, the target.
    pub fn status(&self) -> Reply {
        let mut l = ReplyLine::new();
        let _ = l.push_str(if self.running { "STATUS running" } else { "STATUS idle" });
        if let Some(r) = &self.last {
            let _ = l.push_str(" last: ");
            let _ = text::write_u64(&mut l, r.positions as u64);
            let _ = l.push_str(" dwells");
            if r.missed_samples > 0 {
                let _ = l.push_str(" missed_samples ");
                let _ = text::write_u64(&mut l, r.missed_samples as u64);
            }
            if let Some(a) = r.azimuth {
                let _ = l.push_str(" psi ");
                let _ = text::write_f32(&mut l, a.psi_deg, 5);
                let _ = l.push_str(" sigma_arcsec ");
                let _ = match a.sigma_arcsec {
                    Some(s) => text::write_f32(&mut l, s, 2),
                    // No degrees of freedom: zero would claim a perfect azimuth.
                    None => l.write_str("undefined"),
                };
            }
            if let Some(u) = r.under_noise {
                let _ = l.push_str(" under_noise_sigma_arcsec ");
                let _ = text::write_f32(&mut l, u.sigma_psi_deg * 3600.0, 2);
            }
            if r.target_reached {
                let _ = l.push_str(" target_reached");
            }
            if r.under_noise.is_some() && !r.resolved {
                let _ = l.push_str(" unresolved");
            }
            let _ = l.push_str(match r.result {
                Ok(()) => " ok",
                Err(e) if e.fault == crate::run::Fault::Aborted => " aborted",
                Err(_) => " failed",
            });
        }
        one(l)
    }

    /// Three lines: the run's settings, the gyro's noise model and its calibration, as `SET`'s
    /// keys and values: each value reads back to the same setting.
    pub fn config(&self) -> Reply {
        let c = &self.cfg;
        let mut a = ReplyLine::new();
        let _ = a.push_str("CONFIG n ");
        let _ = text::write_u64(&mut a, c.positions as u64);
        let _ = a.push_str(" order ");
        let _ = a.push_str(c.order.name());
        let _ = a.push_str(" dwell_ms ");
        let _ = text::write_u64(&mut a, c.dwell_ms as u64);
        let _ = a.push_str(" settle_ms ");
        let _ = text::write_u64(&mut a, c.settle_ms as u64);
        let _ = a.push_str(" lat ");
        let _ = Key::Latitude.write_f32(&mut a, c.latitude_deg);
        let _ = a.push_str(" tilt_limit ");
        let _ = Key::TiltLimit.write_f32(&mut a, c.tilt_limit_deg);
        let _ = a.push_str(" tilt_policy ");
        let _ = a.push_str(if c.tilt_policy == TiltPolicy::Refuse {
            "refuse"
        } else {
            "warn"
        });
        let _ = a.push_str(" target_arcsec ");
        let _ = Key::Target.write_f32(&mut a, c.target_arcsec);
        let mut b = ReplyLine::new();
        let _ = b.push_str("CONFIG noise");
        let m = c.noise;
        for (term, v) in [
            (NoiseTerm::Arw, m.arw_deg_rth),
            (NoiseTerm::BiasInstability, m.bias_instability_dph),
            (NoiseTerm::Rrw, m.rrw_dph_rth),
            (NoiseTerm::GmSigma, m.gm_sigma_dph),
            (NoiseTerm::GmTau, m.gm_tau_s),
        ] {
            let key = Key::Noise(term);
            let _ = b.push_str(" ");
            let _ = b.push_str(key.name());
            let _ = b.push_str(" ");
            let _ = key.write_f32(&mut b, v);
        }
        let mut c = ReplyLine::new();
        let _ = c.push_str("CONFIG cal cal_zero ");
        let cal = self.cfg.calibration;
        let _ = text::write_units_trimmed(&mut c, cal.zero_micro_counts, Calibration::ZERO_DECIMALS);
        let _ = c.push_str(" cal_scale ");
        let _ = text::write_units_trimmed(&mut c, cal.femto_dph_per_count, Calibration::SCALE_DECIMALS);
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

fn line(text: &str) -> Reply {
    let mut l = ReplyLine::new();
    let _ = l.push_str(text);
    one(l)
}

fn error(e: link::LinkError) -> Reply {
    let mut l = ReplyLine::new();
    let _ = l.push_str("ERR ");
    let _ = e.write_message(&mut l);
    one(l)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Xorshift draws below `m`.
    fn draws(mut state: u64) -> impl FnMut(u64) -> u64 {
        move |m| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % m
        }
    }

    fn feed(a: &mut LineAssembler, bytes: &[u8]) -> std::vec::Vec<std::string::String> {
        let mut out = std::vec::Vec::new();
        for &b in bytes {
            match a.push(b) {
                Some(Assembled::Line(l)) => out.push(l.into()),
                Some(Assembled::TooLong) => out.push("<too long>".into()),
                Some(Assembled::NotAscii) => out.push("<not ascii>".into()),
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
        assert_eq!(feed(&mut a, &[0xff, b'\n']), ["<not ascii>"]);
    }

    #[test]
    fn a_line_outside_ascii_is_refused_whole_and_the_next_one_runs() {
        let mut a = LineAssembler::default();
        let mut bytes = "SET latitude 43.8\u{b0}\nSTATUS\n".as_bytes().to_vec();
        bytes.extend_from_slice(b"STA\xffTUS\nSTATUS\n");
        assert_eq!(feed(&mut a, &bytes), ["<not ascii>", "STATUS", "<not ascii>", "STATUS"]);
        // Its bytes count toward the length: 79 x and a two-byte character are too long.
        let mut long = std::vec![b'x'; 79];
        long.extend_from_slice("\u{b0}\nSTATUS\n".as_bytes());
        assert_eq!(feed(&mut a, &long), ["<too long>", "STATUS"]);
        // Past the length, such a byte is dropped with the rest and leaves the next line alone.
        let mut long = std::vec![b'x'; 100];
        long.extend_from_slice(b"\xff\nSTATUS\n");
        assert_eq!(feed(&mut a, &long), ["<too long>", "STATUS"]);
    }

    /// The assembler's contract, written plainly: lines end at CR or LF, leading blanks are
    /// dropped and empty lines vanish, a line over [`MAX_COMMAND`] bytes is too long, else one
    /// with a byte outside ASCII is not text.
    fn model(bytes: &[u8]) -> std::vec::Vec<std::string::String> {
        bytes
            .split(|&b| b == b'\n' || b == b'\r')
            .map(|l| {
                &l[l.iter()
                    .take_while(|&&b| matches!(b, b' ' | b'\t' | 0x0b | 0x0c))
                    .count()..]
            })
            .filter(|l| !l.is_empty())
            .map(|l| match l {
                l if l.len() > MAX_COMMAND => "<too long>".into(),
                l if !l.is_ascii() => "<not ascii>".into(),
                l => l.iter().map(|&b| b as char).collect(),
            })
            .collect()
    }

    #[test]
    fn random_byte_streams_are_cut_as_the_model_cuts_them() {
        // Streams of lines of 0 to 120 bytes from an alphabet with both terminators, two
        // non-ASCII bytes and a form feed.
        let mut next = draws(0x2545_f491_4f6c_dd1d);
        let alphabet = [b'a', b'Z', b' ', b'7', b'\n', b'\r', 0xff, 0xc2, 0x0c];
        let mut a = LineAssembler::default();
        for _ in 0..2000 {
            let mut bytes = std::vec::Vec::new();
            for _ in 0..1 + next(4) {
                let len = next(121) as usize;
                // Mostly ASCII letters, so that long lines occur.
                bytes.extend((0..len).map(|_| alphabet[if next(10) == 0 { next(9) } else { next(4) } as usize]));
                bytes.push(b'\n');
            }
            assert_eq!(feed(&mut a, &bytes), model(&bytes), "{bytes:?}");
        }
    }

    #[test]
    fn a_line_of_blanks_is_answered_as_an_empty_line_is_not_at_all() {
        let (mut session, mut a) = (Session::default(), LineAssembler::default());
        for line in [&b"   \t\r\n"[..], b"\x0c\x0b \n", b"\r\n", b" STATUS \n"] {
            let mut replies = std::vec::Vec::new();
            for &b in line {
                if let Some(event) = a.push(b) {
                    replies.extend(
                        session
                            .handle(event)
                            .1
                            .iter()
                            .map(|l| std::string::String::from(l.as_str())),
                    );
                }
            }
            let want: &[&str] = if line.starts_with(b" S") { &["STATUS idle"] } else { &[] };
            assert_eq!(replies, want, "{line:?}");
        }
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
            resolved: true,
        };
        session.finished(report(0));
        assert_eq!(session.status()[0].as_str(), "STATUS idle last: 8 dwells ok");
        session.finished(report(12));
        assert_eq!(
            session.status()[0].as_str(),
            "STATUS idle last: 8 dwells missed_samples 12 ok"
        );
    }

    /// Random settings within the link's ranges, set, shown by CONFIG, and CONFIG's pairs
    /// sent back as `SET` lines to the firmware's defaults: the same configuration.
    #[test]
    fn config_shows_every_value_as_set_reads_it_back() {
        let mut next = draws(0x9e37_79b9_7f4a_7c15);
        let send = |session: &mut Session, line: &str| {
            let (_, reply) = session.handle(Assembled::Line(line));
            reply
                .iter()
                .map(|l| std::string::String::from(l.as_str()))
                .collect::<std::vec::Vec<_>>()
        };
        for _ in 0..500 {
            let mut set = Session::default();
            for (name, key) in crate::link_key::KEYS {
                let Some(r) = key.range() else { continue };
                // Short and long decimals, and the range's ends.
                let span = (r.hi - r.lo) as u64 + 1;
                let v = match next(4) {
                    0 => r.lo,
                    1 => r.hi,
                    2 => r.lo + (next(span) / crate::decimal::pow10(next(r.decimals as u64 + 1) as u32)) as i64,
                    _ => r.lo + next(span) as i64,
                };
                let mut line = std::format!("SET {name} ");
                text::write_units(&mut line, v, r.decimals).unwrap();
                // A `cal_scale` of 0 and a `gm_sigma` without `gm_tau` are refused; both fine here.
                let _ = send(&mut set, &line);
            }
            let mut back = Session::default();
            back.cfg.order = set.cfg.order;
            for l in send(&mut set, "CONFIG") {
                // "CONFIG n ...", "CONFIG noise arw ...", "CONFIG cal cal_zero ...".
                let pairs = l.strip_prefix("CONFIG ").unwrap();
                let pairs = pairs
                    .strip_prefix("noise ")
                    .or(pairs.strip_prefix("cal "))
                    .unwrap_or(pairs);
                let words: std::vec::Vec<&str> = pairs.split(' ').collect();
                for pair in words.chunks(2) {
                    if pair[0] != "order" {
                        let line = std::format!("SET {} {}", pair[0], pair[1]);
                        assert_eq!(send(&mut back, &line), ["OK"], "{line}");
                    }
                }
            }
            assert_eq!(back.cfg, set.cfg);
        }
    }
}
