//! A small instrument for the run sequencer, on the wires its drivers expect: a motor turning a
//! shared shaft, a BiSS-C encoder frame with its CRC-6, inclinometer answers in their line
//! protocol, gyro ADC counts of the Earth rate at the shaft's angle plus deterministic noise, a
//! thermometer and a virtual clock. No allocation and no `std`, so the same file runs on the
//! emulated MCU and, through `#[path]`, in `tests/qemu.rs` on the host. The maths is called
//! through `Float` because `core` has no `cos` of its own: the same call compiles in both.

use core::cell::RefCell;
use core::convert::Infallible;
use core::fmt::Write as _;
use nf_instrument::clock::Clock;
use nf_instrument::encoder::{self, BissEncoder};
use nf_instrument::inclinometer::{self, Inclinometer};
use nf_instrument::run::{self, GyroSource, Instrument, RunConfig, RunReport, Sink, Thermometer};
use nf_instrument::stepper::{Motor, MotorError};
use nf_model::dwell::Calibration;
use nf_model::rng::Rng;
use nf_model::{EARTH_RATE_DPH, Float};

/// The run: 24 positions of 0.2 s at 1 kHz, tilt-corrected, at the paper's latitude.
const RUN: RunConfig = RunConfig {
    positions: 24,
    dwell_ms: 200,
    settle_ms: 100,
    ..RunConfig::DEFAULT
};
/// The azimuth the gyro sees.
const PSI_DEG: f64 = 65.5;
const STEPS_PER_REV: i64 = 32_000;
const ENCODER_BITS: u8 = 23;
const BIAS_DPH: f64 = -0.4;
/// White noise of one ADC sample.
const NOISE_DPH: f64 = 0.05;
/// The shaft leans this far (under the levelling limit), towards this encoder angle.
const TILT_DEG: f64 = 0.02;
const TILT_TOWARDS_DEG: f64 = 30.0;
const SEED: u64 = 7;

/// The shaft, the time and the noise: what every device shares.
struct World {
    now_us: u64,
    steps: i64,
    rng: Rng,
}

impl World {
    fn new() -> Self {
        World {
            now_us: 0,
            steps: 0,
            rng: Rng::new(SEED),
        }
    }

    fn gamma_deg(&self) -> f64 {
        self.steps.rem_euclid(STEPS_PER_REV) as f64 * 360.0 / STEPS_PER_REV as f64
    }

    /// Elevations of the inclinometer's X axis (the gyro's) and Y axis (90 deg on).
    fn tilt_deg(&self) -> (f64, f64) {
        let d = (self.gamma_deg() - TILT_TOWARDS_DEG).to_radians();
        (TILT_DEG * Float::cos(d), -TILT_DEG * Float::sin(d))
    }

    /// The Earth rate on the gyro axis: horizontal part by the azimuth, vertical part by the
    /// axis' elevation.
    fn rate_dph(&mut self) -> f64 {
        let lat = (RUN.latitude_deg as f64).to_radians();
        let horizontal = EARTH_RATE_DPH * Float::cos(lat) * Float::cos((self.gamma_deg() + PSI_DEG).to_radians());
        let vertical = EARTH_RATE_DPH * Float::sin(lat) * Float::sin(self.tilt_deg().0.to_radians());
        horizontal + vertical + BIAS_DPH + NOISE_DPH * self.rng.gauss()
    }
}

/// Virtual time: waiting advances it at once.
struct FakeClock<'a>(&'a RefCell<World>);

impl Clock for FakeClock<'_> {
    fn now_us(&self) -> u64 {
        self.0.borrow().now_us
    }

    async fn delay_us(&mut self, us: u64) {
        self.0.borrow_mut().now_us += us;
    }
}

/// Turns the shaft at once, at 250 us per step of virtual time.
struct FakeMotor<'a>(&'a RefCell<World>);

impl Motor for FakeMotor<'_> {
    async fn move_steps(&mut self, steps: i32, stop: &mut dyn FnMut() -> bool) -> Result<(), MotorError> {
        if stop() {
            return Err(MotorError::Stopped);
        }
        let mut w = self.0.borrow_mut();
        w.steps += steps as i64;
        w.now_us += 250 * steps.unsigned_abs() as u64;
        Ok(())
    }

    fn steps_per_rev(&self) -> u32 {
        STEPS_PER_REV as u32
    }
}

/// Remainder of `data * x^6` divided by `x^6 + x + 1` (0x43), `data` being `n` bits.
fn crc6(data: u64, n: u32) -> u64 {
    let mut r = data << 6;
    for i in (6..n + 6).rev() {
        if r >> i & 1 == 1 {
            r ^= 0x43 << (i - 6);
        }
    }
    r
}

/// The encoder's line as an SPI bus: a read clocks in one frame, MSB first. One idle cycle
/// (high), two of acknowledge (low), start (1), CDS (0), the position, nE and nW (high: no
/// error, no warning), the inverted CRC-6, then low.
struct FakeEncoderBus<'a>(&'a RefCell<World>);

impl embedded_hal_async::spi::ErrorType for FakeEncoderBus<'_> {
    type Error = Infallible;
}

impl embedded_hal_async::spi::SpiBus for FakeEncoderBus<'_> {
    async fn read(&mut self, words: &mut [u8]) -> Result<(), Infallible> {
        let steps = self.0.borrow().steps.rem_euclid(STEPS_PER_REV);
        let counts = (steps << ENCODER_BITS) / STEPS_PER_REV;
        let n = ENCODER_BITS as u32 + 2;
        let data = (counts as u64) << 2 | 0b11;
        let crc = !crc6(data, n) & 0x3F;
        // Idle (1), acknowledge (00), start (1) and CDS (0), then the data and the CRC.
        let frame = (((0b10010u64 << n) | data) << 6) | crc;
        let len = 5 + n + 6;
        for (k, byte) in words.iter_mut().enumerate() {
            *byte = (0..8).fold(0, |b, i| {
                let bit = 8 * k as u32 + i;
                let level = bit < len && frame >> (len - 1 - bit) & 1 == 1;
                (b << 1) | level as u8
            });
        }
        Ok(())
    }

    async fn write(&mut self, _: &[u8]) -> Result<(), Infallible> {
        Ok(())
    }

    async fn transfer(&mut self, read: &mut [u8], _: &[u8]) -> Result<(), Infallible> {
        self.read(read).await
    }

    async fn transfer_in_place(&mut self, words: &mut [u8]) -> Result<(), Infallible> {
        self.read(words).await
    }

    async fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// Bytes of one line, for formatting without allocation.
struct Line {
    buf: [u8; inclinometer::MAX_LINE],
    len: usize,
}

impl core::fmt::Write for Line {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let end = self.len + s.len();
        self.buf
            .get_mut(self.len..end)
            .ok_or(core::fmt::Error)?
            .copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

/// The inclinometer's UART: `RD\r\n` asks, `$TLT,<x>,<y>*<XOR of the body, hex>\r\n` answers.
struct FakeUart<'a> {
    world: &'a RefCell<World>,
    command: Line,
    answer: Line,
    sent: usize,
}

impl FakeUart<'_> {
    fn answer(&mut self) {
        let (x, y) = self.world.borrow().tilt_deg();
        let a = &mut self.answer;
        a.len = 0;
        self.sent = 0;
        // The body goes after the `$`; its checksum is taken before the rest is added.
        let written = write!(a, "$TLT,{x:+.5},{y:+.5}").is_ok() && {
            let sum = a.buf[1..a.len].iter().fold(0, |s, b| s ^ b);
            write!(a, "*{sum:02X}\r\n").is_ok()
        };
        if !written {
            a.len = 0;
        }
    }
}

impl embedded_io_async::ErrorType for FakeUart<'_> {
    type Error = Infallible;
}

impl embedded_io_async::Write for FakeUart<'_> {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        for &b in buf {
            let c = &mut self.command;
            if c.len < c.buf.len() {
                c.buf[c.len] = b;
                c.len += 1;
            }
            if b == b'\n' {
                if c.buf[..c.len] == *b"RD\r\n" {
                    self.answer();
                }
                self.command.len = 0;
            }
        }
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

impl embedded_io_async::Read for FakeUart<'_> {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let rest = &self.answer.buf[self.sent..self.answer.len];
        if rest.is_empty() {
            // Nothing more comes until the next request; the driver's timeout ends the wait.
            core::future::pending::<()>().await;
        }
        let n = buf.len().min(rest.len());
        buf[..n].copy_from_slice(&rest[..n]);
        self.sent += n;
        Ok(n)
    }
}

/// The gyro through the ADC at 1 kHz: each sample takes a period of virtual time.
struct FakeGyro<'a>(&'a RefCell<World>);

impl GyroSource for FakeGyro<'_> {
    async fn next_sample(&mut self) -> Result<i32, nf_instrument::adc::AdcError> {
        let mut w = self.0.borrow_mut();
        w.now_us += 1_000_000 / RUN.sample_rate_hz as u64;
        let rate = w.rate_dph();
        Ok(Float::round(Calibration::DEFAULT.counts(rate)) as i32)
    }
}

struct FakeThermometer;

impl Thermometer for FakeThermometer {
    fn read_c(&mut self) -> Option<f32> {
        Some(24.5)
    }
}

/// Counts the recording's lines.
struct Lines(u32);

impl Sink for Lines {
    async fn line(&mut self, _: &str) {
        self.0 += 1;
    }
}

/// Runs [`RUN`] on the fake instrument: the report and the recording's line count.
pub fn run() -> (RunReport, u32) {
    let world = RefCell::new(World::new());
    let mut hw = Instrument {
        motor: FakeMotor(&world),
        encoder: BissEncoder::new(
            FakeEncoderBus(&world),
            encoder::Config {
                bits: ENCODER_BITS,
                retries: 0,
            },
        ),
        gyro: FakeGyro(&world),
        inclinometer: Inclinometer::new(
            FakeUart {
                world: &world,
                command: Line {
                    buf: [0; inclinometer::MAX_LINE],
                    len: 0,
                },
                answer: Line {
                    buf: [0; inclinometer::MAX_LINE],
                    len: 0,
                },
                sent: 0,
            },
            Default::default(),
        ),
        thermometer: FakeThermometer,
        clock: FakeClock(&world),
    };
    let mut lines = Lines(0);
    let report = embassy_futures::block_on(run::run(&mut hw, &RUN, &mut lines));
    (report, lines.0)
}
