//! Tiny in-memory buses for the drivers: each answers from a script drawn from the fuzz input
//! and records what the driver sent. A script that runs out answers with an error (or, for
//! the UART, with what [`UartEnd`] says), so that every driver call ends.

use arbitrary::{Arbitrary, Unstructured};
use nf_instrument::clock::Clock;
use std::collections::VecDeque;

/// The error every fake reports.
pub type SpiErr = embedded_hal::spi::ErrorKind;
pub type PinErr = embedded_hal::digital::ErrorKind;
pub type IoErr = embedded_io_async::ErrorKind;

/// An SPI bus that answers reads with scripted bytes (the BiSS-C encoder's wires).
pub struct SpiBus {
    pub reads: VecDeque<Result<Vec<u8>, ()>>,
    /// Reads the driver made.
    pub calls: usize,
}

impl embedded_hal_async::spi::ErrorType for SpiBus {
    type Error = SpiErr;
}

impl embedded_hal_async::spi::SpiBus for SpiBus {
    async fn read(&mut self, words: &mut [u8]) -> Result<(), SpiErr> {
        self.calls += 1;
        let r = self.reads.pop_front().unwrap_or(Err(()));
        let bytes = r.map_err(|_| SpiErr::Other)?;
        for (i, w) in words.iter_mut().enumerate() {
            *w = bytes.get(i).copied().unwrap_or(0);
        }
        Ok(())
    }

    async fn write(&mut self, _words: &[u8]) -> Result<(), SpiErr> {
        Ok(())
    }

    async fn transfer(&mut self, read: &mut [u8], _write: &[u8]) -> Result<(), SpiErr> {
        self.read(read).await
    }

    async fn transfer_in_place(&mut self, words: &mut [u8]) -> Result<(), SpiErr> {
        self.read(words).await
    }

    async fn flush(&mut self) -> Result<(), SpiErr> {
        Ok(())
    }
}

/// An SPI device (chip select handled) that records writes and answers reads from a script
/// (the ADS1256).
#[derive(Default)]
pub struct SpiDevice {
    pub reads: VecDeque<Result<[u8; 3], ()>>,
    /// Transactions that fail before any byte moves.
    pub fail_writes: VecDeque<bool>,
    /// Every byte written, one entry a transaction.
    pub written: Vec<Vec<u8>>,
}

impl embedded_hal_async::spi::ErrorType for SpiDevice {
    type Error = SpiErr;
}

impl embedded_hal_async::spi::SpiDevice for SpiDevice {
    async fn transaction(&mut self, ops: &mut [embedded_hal::spi::Operation<'_, u8>]) -> Result<(), SpiErr> {
        use embedded_hal::spi::Operation;
        let mut sent = Vec::new();
        for op in ops.iter_mut() {
            match op {
                Operation::Write(w) => {
                    if self.fail_writes.pop_front().unwrap_or(false) {
                        return Err(SpiErr::Other);
                    }
                    sent.extend_from_slice(w);
                }
                Operation::Read(r) => {
                    let b = self.reads.pop_front().unwrap_or(Err(())).map_err(|_| SpiErr::Other)?;
                    for (i, x) in r.iter_mut().enumerate() {
                        *x = b.get(i).copied().unwrap_or(0);
                    }
                }
                Operation::Transfer(r, w) => {
                    sent.extend_from_slice(w);
                    r.fill(0);
                }
                Operation::TransferInPlace(x) => {
                    sent.extend_from_slice(x);
                    x.fill(0);
                }
                Operation::DelayNs(_) => {}
            }
        }
        self.written.push(sent);
        Ok(())
    }
}

/// A data-ready pin whose waits succeed or fail as scripted.
pub struct Pin {
    pub waits: VecDeque<bool>,
}

impl Pin {
    fn next(&mut self) -> Result<(), PinErr> {
        if self.waits.pop_front().unwrap_or(false) {
            Ok(())
        } else {
            Err(PinErr::Other)
        }
    }
}

impl embedded_hal::digital::ErrorType for Pin {
    type Error = PinErr;
}

impl embedded_hal_async::digital::Wait for Pin {
    async fn wait_for_high(&mut self) -> Result<(), PinErr> {
        self.next()
    }
    async fn wait_for_low(&mut self) -> Result<(), PinErr> {
        self.next()
    }
    async fn wait_for_rising_edge(&mut self) -> Result<(), PinErr> {
        self.next()
    }
    async fn wait_for_falling_edge(&mut self) -> Result<(), PinErr> {
        self.next()
    }
    async fn wait_for_any_edge(&mut self) -> Result<(), PinErr> {
        self.next()
    }
}

/// What a UART read gives once its script is spent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Arbitrary)]
pub enum UartEnd {
    /// Nothing more ever arrives (a silent device): the read waits for ever.
    Silent,
    /// `Ok(0)`: end of file, which `embedded-io` allows a reader to report.
    Eof,
    /// The UART reports an error.
    Error,
}

/// One read of the UART.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum UartRead {
    Bytes(Vec<u8>),
    Error,
}

/// A UART that answers reads from a script (the inclinometer's wires).
pub struct Uart {
    pub reads: VecDeque<UartRead>,
    pub end: UartEnd,
    pub fail_write: bool,
    pub written: Vec<u8>,
    /// Reads the driver made.
    pub calls: u64,
}

/// A driver that reads this often has stopped making progress.
pub const SPIN_LIMIT: u64 = 1_000_000;

impl embedded_io_async::ErrorType for Uart {
    type Error = IoErr;
}

impl embedded_io_async::Read for Uart {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, IoErr> {
        self.calls += 1;
        assert!(
            self.calls < SPIN_LIMIT,
            "the driver read the UART {SPIN_LIMIT} times: it spins without giving the timeout a chance"
        );
        if buf.is_empty() {
            return Ok(0);
        }
        match self.reads.pop_front() {
            Some(UartRead::Bytes(mut b)) => {
                let n = b.len().min(buf.len());
                buf[..n].copy_from_slice(&b[..n]);
                if n < b.len() {
                    self.reads.push_front(UartRead::Bytes(b.split_off(n)));
                }
                Ok(n)
            }
            Some(UartRead::Error) => Err(IoErr::Other),
            None => match self.end {
                UartEnd::Silent => core::future::pending().await,
                UartEnd::Eof => Ok(0),
                UartEnd::Error => Err(IoErr::Other),
            },
        }
    }
}

impl embedded_io_async::Write for Uart {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, IoErr> {
        if self.fail_write {
            return Err(IoErr::Other);
        }
        self.written.extend_from_slice(buf);
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), IoErr> {
        Ok(())
    }
}

/// A clock whose waits end at once (virtual time).
#[derive(Default)]
pub struct InstantClock {
    pub now_us: u64,
}

impl Clock for InstantClock {
    fn now_us(&self) -> u64 {
        self.now_us
    }

    async fn delay_us(&mut self, us: u64) {
        self.now_us = self.now_us.saturating_add(us);
    }
}

/// Splits `bytes` into chunks whose lengths come from `u` (1 to 24 bytes each).
pub fn chunks(u: &mut Unstructured<'_>, bytes: &[u8]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut rest = bytes;
    while !rest.is_empty() {
        let n = (u.int_in_range(1..=24usize).unwrap_or(16)).min(rest.len());
        out.push(rest[..n].to_vec());
        rest = &rest[n..];
    }
    out
}
