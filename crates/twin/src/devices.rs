//! The twin's side of each wire: what the firmware's drivers talk to.

use crate::biss::Frame;
use crate::step_timer::TwinStepTimer;
use crate::world::{InclinometerFault, TwinConfig, World};
use core::convert::Infallible;
use embedded_hal::spi::Operation;
use nf_instrument::adc::Ads1256;
use nf_instrument::clock::Clock;
use nf_instrument::encoder::{self, BissEncoder};
use nf_instrument::inclinometer::Inclinometer;
use nf_instrument::run::{Instrument, RunConfig, Thermometer};
use nf_instrument::step_train::TimedStepDir;
use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

type Shared = Rc<RefCell<World>>;

/// Virtual time: waiting advances it at once.
#[derive(Clone)]
pub struct TwinClock(Shared);

impl Clock for TwinClock {
    fn now_us(&self) -> u64 {
        self.0.borrow().now_us
    }

    async fn delay_us(&mut self, us: u64) {
        self.0.borrow_mut().advance(us);
    }
}

/// The direction pin (high: counter-clockwise).
pub struct DirPin(Shared);

impl embedded_hal::digital::ErrorType for DirPin {
    type Error = Infallible;
}

impl embedded_hal::digital::OutputPin for DirPin {
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.0.borrow_mut().set_dir(true);
        Ok(())
    }

    fn set_low(&mut self) -> Result<(), Infallible> {
        self.0.borrow_mut().set_dir(false);
        Ok(())
    }
}

/// The inclinometer's answer, `$TLT,<x>,<y>*<XOR of the body in hex>`, from its manual's format.
fn tilt_line(x_deg: f64, y_deg: f64) -> String {
    let body = format!("TLT,{x_deg:+.5},{y_deg:+.5}");
    let sum = body.bytes().fold(0u8, |a, b| a ^ b);
    format!("${body}*{sum:02X}\r\n")
}

/// The encoder's BiSS-C line as an SPI bus: every read clocks in one frame.
pub struct EncoderBus(Shared);

impl embedded_hal_async::spi::ErrorType for EncoderBus {
    type Error = Infallible;
}

impl embedded_hal_async::spi::SpiBus for EncoderBus {
    async fn read(&mut self, words: &mut [u8]) -> Result<(), Infallible> {
        let mut w = self.0.borrow_mut();
        let bits = w.cfg.encoder_bits;
        match w.encoder_counts() {
            // No encoder: nothing pulls the line, it reads low.
            None => words.fill(0),
            Some(c) => {
                let (idle, ack) = (1 + (w.rng.next_u64() % 2) as usize, 1 + (w.rng.next_u64() % 4) as usize);
                let frame = Frame {
                    counts: c as u64,
                    bits,
                    error: false,
                    warning: false,
                    idle,
                    ack,
                };
                frame.clock_into(words);
                if w.encoder_frame_corrupt() {
                    // A bit of the start, CDS, position, status or CRC.
                    let bit = idle + ack + (w.rng.next_u64() % (bits as u64 + 10)) as usize;
                    if let Some(b) = words.get_mut(bit / 8) {
                        *b ^= 0x80 >> (bit % 8);
                    }
                }
            }
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

/// The ADC's SPI side: a 3-byte read returns the conversion of the current time, or after an
/// RREG command the registers.
pub struct AdcSpi {
    world: Shared,
    /// The ADS1256's 11 registers as written.
    regs: [u8; 11],
    /// An RREG waits for its read: the first register.
    readback: Option<usize>,
}
/// The ADC's DRDY line: waiting for it advances to the next conversion.
pub struct Drdy(Shared);

impl embedded_hal_async::spi::ErrorType for AdcSpi {
    type Error = Infallible;
}

impl AdcSpi {
    /// Takes command bytes as the ADS1256 datasheet lists them: WREG and RREG carry a register
    /// and a count; SDATAC, SELFCAL and RDATAC need nothing from the twin.
    fn command(&mut self, bytes: &[u8]) {
        let mut i = 0;
        while i < bytes.len() {
            let (op, reg) = (bytes[i] & 0xF0, (bytes[i] & 0x0F) as usize);
            let count = bytes.get(i + 1).map_or(0, |&c| c as usize + 1);
            match op {
                0x50 => {
                    for (k, &v) in bytes.iter().skip(i + 2).take(count).enumerate() {
                        if let Some(r) = self.regs.get_mut(reg + k) {
                            *r = v;
                        }
                    }
                    i += 2 + count;
                }
                0x10 => {
                    self.readback = Some(reg);
                    i += 2;
                }
                _ => i += 1,
            }
        }
    }
}

impl embedded_hal_async::spi::SpiDevice for AdcSpi {
    async fn transaction(&mut self, ops: &mut [Operation<'_, u8>]) -> Result<(), Infallible> {
        for op in ops {
            match op {
                Operation::Write(bytes) => self.command(bytes),
                Operation::Read(buf) => match self.readback.take() {
                    Some(reg) => {
                        for (k, b) in buf.iter_mut().enumerate() {
                            *b = self.regs.get(reg + k).copied().unwrap_or(0);
                        }
                    }
                    None => {
                        let s = self.world.borrow_mut().adc_sample();
                        let b = s.to_be_bytes();
                        buf.copy_from_slice(&b[1..1 + buf.len().min(3)]);
                    }
                },
                _ => {}
            }
        }
        Ok(())
    }
}

impl embedded_hal::digital::ErrorType for Drdy {
    type Error = Infallible;
}

impl Drdy {
    async fn conversion(&mut self) -> Result<(), Infallible> {
        let ready = self.0.borrow_mut().wait_conversion();
        if ready.is_none() {
            // A dead ADC never pulls DRDY low again.
            core::future::pending::<()>().await;
        }
        Ok(())
    }
}

impl embedded_hal_async::digital::Wait for Drdy {
    async fn wait_for_high(&mut self) -> Result<(), Infallible> {
        self.conversion().await
    }
    async fn wait_for_low(&mut self) -> Result<(), Infallible> {
        self.conversion().await
    }
    async fn wait_for_rising_edge(&mut self) -> Result<(), Infallible> {
        self.conversion().await
    }
    async fn wait_for_falling_edge(&mut self) -> Result<(), Infallible> {
        self.conversion().await
    }
    async fn wait_for_any_edge(&mut self) -> Result<(), Infallible> {
        self.conversion().await
    }
}

/// The inclinometer's UART.
pub struct InclUart {
    world: Shared,
    command: Vec<u8>,
    out: VecDeque<u8>,
}

impl embedded_io_async::ErrorType for InclUart {
    type Error = Infallible;
}

impl embedded_io_async::Write for InclUart {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        for &b in buf {
            self.command.push(b);
            if b != b'\n' {
                continue;
            }
            let cmd = std::mem::take(&mut self.command);
            let mut w = self.world.borrow_mut();
            match (cmd.as_slice(), w.inclinometer_fault()) {
                (b"RD\r\n", InclinometerFault::None) => {
                    // 5 ms to measure and send.
                    w.advance(5_000);
                    let (x, y) = w.inclinometer();
                    self.out.extend(tilt_line(x, y).as_bytes());
                }
                (_, InclinometerFault::Garbage) => {
                    w.advance(5_000);
                    for _ in 0..40 {
                        let b = match w.rng.next_u64() % 20 {
                            0 => b'$',
                            1 => b'\n',
                            r => b"0123456789,.+-*TLXA"[r as usize % 19],
                        };
                        self.out.push_back(b);
                    }
                }
                _ => {}
            }
        }
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

impl embedded_io_async::Read for InclUart {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        if self.out.is_empty() {
            // Nothing more will come until the next request.
            core::future::pending::<()>().await;
        }
        let n = buf.len().min(self.out.len());
        for (d, s) in buf.iter_mut().zip(self.out.drain(..n)) {
            *d = s;
        }
        Ok(n)
    }
}

/// The gyro temperature sensor.
pub struct Thermo(Shared);

impl Thermometer for Thermo {
    fn read_c(&mut self) -> Option<f32> {
        Some(self.0.borrow().temperature_c() as f32)
    }
}

/// The firmware's drivers on the twin's wires.
pub type TwinInstrument =
    Instrument<TimedStepDir<TwinStepTimer, DirPin>, EncoderBus, Ads1256<AdcSpi, Drdy>, InclUart, Thermo, TwinClock>;

/// Builds the twin and the firmware's drivers on it, the ADC started as the firmware does at
/// boot.
pub fn instrument(cfg: &TwinConfig, run: &RunConfig) -> (TwinInstrument, Shared) {
    let mut twin = cfg.clone();
    twin.sample_rate_hz = run.sample_rate_hz;
    let world = Rc::new(RefCell::new(World::new(twin)));
    let clock = TwinClock(world.clone());
    let spi = AdcSpi {
        world: world.clone(),
        regs: [0; 11],
        readback: None,
    };
    let mut adc = Ads1256::new(spi, Drdy(world.clone()));
    // The twin's ADC answers its registers; a dead ADC shows as missing samples later.
    embassy_futures::block_on(adc.start(&Default::default(), &mut clock.clone()))
        .expect("the twin's ADC reads its registers back");
    let hw = Instrument {
        motor: TimedStepDir::new(TwinStepTimer::new(world.clone()), DirPin(world.clone()), cfg.motor),
        encoder: BissEncoder::new(
            EncoderBus(world.clone()),
            encoder::Config {
                bits: cfg.encoder_bits,
                retries: 3,
            },
        ),
        gyro: adc,
        inclinometer: Inclinometer::new(
            InclUart {
                world: world.clone(),
                command: Vec::new(),
                out: VecDeque::new(),
            },
            Default::default(),
        ),
        thermometer: Thermo(world.clone()),
        clock,
    };
    (hw, world)
}
