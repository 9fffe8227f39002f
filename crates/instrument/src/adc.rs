//! The gyro's rebalance-loop output through an ADS1256-class 24-bit ADC on SPI, with its
//! data-ready line on an EXTI pin. The ADC runs in continuous-read mode (RDATAC): after each
//! falling edge of DRDY the driver clocks out one 24-bit two's-complement sample.

use crate::clock::{Clock, with_timeout};
use embedded_hal::spi::Operation;
use embedded_hal_async::digital::Wait;
use embedded_hal_async::spi::SpiDevice;

/// Full-scale positive and negative codes: a sample at either is clipped.
pub const CODE_MAX: i32 = 0x7F_FFFF;
pub const CODE_MIN: i32 = -0x80_0000;

mod cmd {
    pub const WREG: u8 = 0x50;
    pub const RREG: u8 = 0x10;
    pub const SELFCAL: u8 = 0xF0;
    pub const RDATAC: u8 = 0x03;
    pub const SDATAC: u8 = 0x0F;
}

/// Why the ADC could not be used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum AdcError {
    /// The SPI bus or the DRDY pin reported an error.
    Bus,
    /// The registers read back differ from those written (no ADC, or a broken bus): the
    /// first register that differs, as written and as read.
    Readback { register: u8, wrote: u8, read: u8 },
    /// DRDY did not go low after the self-calibration.
    DrdyTimeout,
}

/// Start-up attempts before the ADC counts as faulty.
pub const START_TRIES: u8 = 3;
/// The longest self-calibration (at 2.5 samples/s it takes about 1.2 s).
const SELFCAL_TIMEOUT_US: u64 = 2_000_000;
/// From the RREG command to the first data bit: 50 periods of the 7.68 MHz clock.
const T6_NS: u32 = 6_600;
/// First register written: MUX (then ADCON and DRATE).
const REG_MUX: u8 = 0x01;

/// Register settings written at start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// MUX register: positive and negative input (default AIN0 - AIN1, the X axis).
    pub mux: u8,
    /// ADCON register: clock out off, sensor detect off, PGA gain code.
    pub adcon: u8,
    /// DRATE register (0xA1: 1000 samples/s).
    pub drate: u8,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            mux: 0x01,
            adcon: 0x00,
            drate: 0xA1,
        }
    }
}

impl Config {
    /// Samples per second of the DRATE code, for the codes this project uses.
    pub fn sample_rate_hz(&self) -> Option<u32> {
        match self.drate {
            0xF0 => Some(30_000),
            0xC0 => Some(3_750),
            0xA1 => Some(1_000),
            0x92 => Some(500),
            0x82 => Some(100),
            _ => None,
        }
    }
}

/// An ADS1256-class ADC.
pub struct Ads1256<SPI, DRDY> {
    spi: SPI,
    drdy: DRDY,
}

/// Sign-extends a 24-bit two's-complement sample.
pub fn sample_from_bytes(b: [u8; 3]) -> i32 {
    ((b[0] as i32) << 24 | (b[1] as i32) << 16 | (b[2] as i32) << 8) >> 8
}

/// Whether a sample sits at a full-scale code (the input is clipped).
pub fn is_saturated(sample: i32) -> bool {
    sample >= CODE_MAX || sample <= CODE_MIN
}

/// Errors in a sample word: below every 24-bit code.
const WORD_BUS: i32 = i32::MIN;
const WORD_DRDY_TIMEOUT: i32 = i32::MIN + 1;
/// Plus `register << 16 | wrote << 8 | read`.
const WORD_READBACK: i32 = i32::MIN + (1 << 24);

/// A sample or its error in one word, for a queue between an ADC task and the run: half the
/// RAM of a `Result<i32, AdcError>`. Samples are 24-bit codes (one beyond them is clamped to
/// full scale, which still reads as saturated); errors take words below `-2^24`.
pub fn to_word(sample: Result<i32, AdcError>) -> i32 {
    match sample {
        Ok(s) => s.clamp(CODE_MIN, CODE_MAX),
        Err(AdcError::Bus) => WORD_BUS,
        Err(AdcError::DrdyTimeout) => WORD_DRDY_TIMEOUT,
        Err(AdcError::Readback { register, wrote, read }) => {
            WORD_READBACK + ((register as i32) << 16 | (wrote as i32) << 8 | read as i32)
        }
    }
}

/// The sample or error that [`to_word`] made `word` of; a word it cannot make is a bus error.
pub fn from_word(word: i32) -> Result<i32, AdcError> {
    match word {
        CODE_MIN..=CODE_MAX => Ok(word),
        WORD_DRDY_TIMEOUT => Err(AdcError::DrdyTimeout),
        w if (WORD_READBACK..WORD_READBACK + (1 << 24)).contains(&w) => {
            let b = (w - WORD_READBACK).to_be_bytes();
            Err(AdcError::Readback {
                register: b[1],
                wrote: b[2],
                read: b[3],
            })
        }
        _ => Err(AdcError::Bus),
    }
}

impl<SPI: SpiDevice, DRDY: Wait> Ads1256<SPI, DRDY> {
    pub fn new(spi: SPI, drdy: DRDY) -> Self {
        Ads1256 { spi, drdy }
    }

    /// Stops continuous reading, writes the registers and reads them back, self-calibrates and
    /// starts continuous reading; tries [`START_TRIES`] times before reporting the fault.
    pub async fn start<C: Clock>(&mut self, cfg: &Config, clock: &mut C) -> Result<(), AdcError> {
        let mut last = AdcError::Bus;
        for attempt in 1..=START_TRIES {
            match self.try_start(cfg, clock).await {
                Ok(()) => {
                    info!(
                        "adc: registers verified, continuous read started, mux {} drate {}",
                        cfg.mux, cfg.drate
                    );
                    return Ok(());
                }
                Err(e) => {
                    warn!("adc: start-up attempt {} failed: {:?}", attempt, e);
                    last = e;
                }
            }
        }
        error!("adc: not started after {} attempts", START_TRIES);
        Err(last)
    }

    async fn try_start<C: Clock>(&mut self, cfg: &Config, clock: &mut C) -> Result<(), AdcError> {
        let wrote = [cfg.mux, cfg.adcon, cfg.drate];
        let regs = [cmd::SDATAC, cmd::WREG | REG_MUX, 2, wrote[0], wrote[1], wrote[2]];
        self.spi.write(&regs).await.map_err(|_| AdcError::Bus)?;
        let mut read = [0u8; 3];
        self.spi
            .transaction(&mut [
                Operation::Write(&[cmd::RREG | REG_MUX, 2]),
                Operation::DelayNs(T6_NS),
                Operation::Read(&mut read),
            ])
            .await
            .map_err(|_| AdcError::Bus)?;
        if let Some(k) = (0..3).find(|&k| read[k] != wrote[k]) {
            return Err(AdcError::Readback {
                register: REG_MUX + k as u8,
                wrote: wrote[k],
                read: read[k],
            });
        }
        self.spi.write(&[cmd::SELFCAL]).await.map_err(|_| AdcError::Bus)?;
        with_timeout(clock, SELFCAL_TIMEOUT_US, self.drdy.wait_for_low())
            .await
            .ok_or(AdcError::DrdyTimeout)?
            .map_err(|_| AdcError::Bus)?;
        self.spi.write(&[cmd::RDATAC]).await.map_err(|_| AdcError::Bus)
    }

    /// Waits for the next conversion and reads it.
    pub async fn next_sample(&mut self) -> Result<i32, AdcError> {
        self.drdy.wait_for_falling_edge().await.map_err(|_| AdcError::Bus)?;
        let mut b = [0u8; 3];
        self.spi
            .transaction(&mut [Operation::Read(&mut b)])
            .await
            .map_err(|_| AdcError::Bus)?;
        Ok(sample_from_bytes(b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::Count;
    use embedded_hal_mock::eh1::digital::{Edge, Mock as Pin, State, Transaction as PinT};
    use embedded_hal_mock::eh1::spi::{Mock as Spi, Transaction as SpiT};
    use std::vec;

    #[test]
    fn samples_and_errors_travel_in_one_word() {
        let all = [
            Ok(0),
            Ok(-1),
            Ok(CODE_MAX),
            Ok(CODE_MIN),
            Ok(0x123456),
            Err(AdcError::Bus),
            Err(AdcError::DrdyTimeout),
            Err(AdcError::Readback {
                register: 1,
                wrote: 1,
                read: 255,
            }),
            Err(AdcError::Readback {
                register: 255,
                wrote: 0,
                read: 0,
            }),
        ];
        for s in all {
            assert_eq!(from_word(to_word(s)), s, "{s:?}");
        }
        // Beyond 24 bits: full scale, saturated as the run sees it.
        assert_eq!(from_word(to_word(Ok(1 << 24))), Ok(CODE_MAX));
        assert_eq!(from_word(to_word(Ok(-(1 << 30)))), Ok(CODE_MIN));
        // Words no sample or error makes: a bus error, not a sample.
        for w in [CODE_MIN - 1, CODE_MAX + 1, i32::MAX, -(1 << 24) - 5] {
            assert_eq!(from_word(w), Err(AdcError::Bus), "{w}");
        }
    }

    #[test]
    fn sign_extension_and_saturation() {
        assert_eq!(sample_from_bytes([0x7F, 0xFF, 0xFF]), CODE_MAX);
        assert_eq!(sample_from_bytes([0x80, 0x00, 0x00]), CODE_MIN);
        assert_eq!(sample_from_bytes([0xFF, 0xFF, 0xFF]), -1);
        assert_eq!(sample_from_bytes([0x00, 0x01, 0x00]), 256);
        assert!(is_saturated(CODE_MAX) && is_saturated(CODE_MIN) && !is_saturated(CODE_MAX - 1));
    }

    #[test]
    fn start_then_read_two_samples() {
        let spi = [
            SpiT::transaction_start(),
            SpiT::write_vec(vec![0x0F, 0x51, 2, 0x01, 0x00, 0xA1]),
            SpiT::transaction_end(),
            SpiT::transaction_start(),
            SpiT::write_vec(vec![0x11, 2]),
            SpiT::delay(6_600),
            SpiT::read_vec(vec![0x01, 0x00, 0xA1]),
            SpiT::transaction_end(),
            SpiT::transaction_start(),
            SpiT::write_vec(vec![0xF0]),
            SpiT::transaction_end(),
            SpiT::transaction_start(),
            SpiT::write_vec(vec![0x03]),
            SpiT::transaction_end(),
            SpiT::transaction_start(),
            SpiT::read_vec(vec![0x12, 0x34, 0x56]),
            SpiT::transaction_end(),
            SpiT::transaction_start(),
            SpiT::read_vec(vec![0xFF, 0xFF, 0xFE]),
            SpiT::transaction_end(),
        ];
        let pin = [
            PinT::wait_for_state(State::Low),
            PinT::wait_for_edge(Edge::Falling),
            PinT::wait_for_edge(Edge::Falling),
        ];
        let (mut s, mut p) = (Spi::new(&spi), Pin::new(&pin));
        let mut adc = Ads1256::new(s.clone(), p.clone());
        embassy_futures::block_on(async {
            adc.start(&Config::default(), &mut Count(0)).await.unwrap();
            assert_eq!(adc.next_sample().await, Ok(0x123456));
            assert_eq!(adc.next_sample().await, Ok(-2));
        });
        s.done();
        p.done();
        assert_eq!(Config::default().sample_rate_hz(), Some(1000));
    }

    #[test]
    fn no_adc_on_the_bus_is_a_readback_fault_after_every_try() {
        let attempt = [
            SpiT::transaction_start(),
            SpiT::write_vec(vec![0x0F, 0x51, 2, 0x01, 0x00, 0xA1]),
            SpiT::transaction_end(),
            SpiT::transaction_start(),
            SpiT::write_vec(vec![0x11, 2]),
            SpiT::delay(6_600),
            // MISO pulled up: every byte reads 0xFF.
            SpiT::read_vec(vec![0xFF, 0xFF, 0xFF]),
            SpiT::transaction_end(),
        ];
        let spi: std::vec::Vec<_> = attempt
            .iter()
            .cycle()
            .take(attempt.len() * START_TRIES as usize)
            .cloned()
            .collect();
        let (mut s, mut p) = (Spi::new(&spi), Pin::new(&[]));
        let mut adc = Ads1256::new(s.clone(), p.clone());
        let r = embassy_futures::block_on(adc.start(&Config::default(), &mut Count(0)));
        assert_eq!(
            r,
            Err(AdcError::Readback {
                register: 1,
                wrote: 0x01,
                read: 0xFF
            })
        );
        s.done();
        p.done();
    }
}
