//! Absolute encoder over BiSS-C (point-to-point, read over an SPI bus's MISO and SCK).
//!
//! Frame, MSB first: the line idles high (the encoder is ready), the encoder pulls it low for
//! the acknowledge, then sends a start bit (1), the CDS bit (0), the position (`bits` wide), nE
//! and nW (active-low error and warning) and a CRC-6 (polynomial `x^6 + x + 1`, 0x43, sent
//! inverted) over position, nE and nW, then holds the line low until its timeout. The clock
//! idles high and the encoder changes its output on rising edges: SPI mode 2 (CPOL 1, CPHA 0).
//! The driver clocks [`FRAME_BYTES`] bytes, skips the idle and acknowledge bits and checks
//! everything.

use embedded_hal_async::spi::SpiBus;

/// Bytes clocked per read: up to 7 acknowledge bits, 2 + 32 + 2 + 6 frame bits fit.
pub const FRAME_BYTES: usize = 7;

/// Why an encoder read failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EncoderError {
    /// The SPI bus reported an error.
    Bus,
    /// No acknowledge or no start bit: the line stays high or low (no encoder, no power,
    /// broken cable).
    NotResponding,
    /// A start bit without the CDS bit after it, or a frame cut short.
    BadFrame,
    /// Every retry had a CRC error.
    Crc,
    /// The encoder flagged an error (nE low): dirty disc, over-speed, internal fault.
    DeviceError,
}

/// Driver settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// Position bits per turn.
    pub bits: u8,
    /// Reads tried after a CRC error before giving up.
    pub retries: u8,
}

impl Default for Config {
    fn default() -> Self {
        Config { bits: 23, retries: 3 }
    }
}

/// The CRC-6 of BiSS-C over the `n` low bits of `data` (not yet inverted).
pub fn crc6(data: u64, n: u32) -> u8 {
    let mut crc: u8 = 0;
    for i in (0..n).rev() {
        let bit = ((data >> i) & 1) as u8;
        let fb = ((crc >> 5) & 1) ^ bit;
        crc = (crc << 1) & 0x3F;
        if fb != 0 {
            crc ^= 0x03;
        }
    }
    crc
}

/// Decodes a frame clocked in by [`BissEncoder::read`].
pub fn decode_frame(raw: &[u8; FRAME_BYTES], bits: u8) -> Result<u32, EncoderError> {
    let total = FRAME_BYTES * 8;
    let bit = |i: usize| (raw[i / 8] >> (7 - i % 8)) & 1;
    // Idle (high), then the acknowledge (low), then the start bit.
    let idle = (0..total).find(|&i| bit(i) == 0).ok_or(EncoderError::NotResponding)?;
    let start = (idle..total)
        .find(|&i| bit(i) == 1)
        .ok_or(EncoderError::NotResponding)?;
    let n = bits as usize + 2;
    if start + 2 + n + 6 > total || bit(start + 1) != 0 {
        return Err(EncoderError::BadFrame);
    }
    let field = |from: usize, len: usize| (from..from + len).fold(0u64, |w, i| (w << 1) | bit(i) as u64);
    let data = field(start + 2, n);
    let crc = field(start + 2 + n, 6) as u8;
    if (!crc6(data, n as u32)) & 0x3F != crc {
        return Err(EncoderError::Crc);
    }
    if data & 0b10 == 0 {
        return Err(EncoderError::DeviceError);
    }
    Ok((data >> 2) as u32)
}

/// A BiSS-C absolute encoder on an SPI bus.
pub struct BissEncoder<SPI> {
    spi: SPI,
    cfg: Config,
}

impl<SPI: SpiBus> BissEncoder<SPI> {
    pub fn new(spi: SPI, cfg: Config) -> Self {
        BissEncoder { spi, cfg }
    }

    pub fn config(&self) -> &Config {
        &self.cfg
    }

    /// Counts per turn (up to 2^32 for a 32-bit encoder).
    pub fn counts_per_turn(&self) -> u64 {
        1u64 << self.cfg.bits.min(32)
    }

    /// Reads the position in counts, retrying after CRC errors.
    pub async fn read(&mut self) -> Result<u32, EncoderError> {
        let mut tries = 0;
        loop {
            let mut raw = [0u8; FRAME_BYTES];
            self.spi.read(&mut raw).await.map_err(|_| EncoderError::Bus)?;
            match decode_frame(&raw, self.cfg.bits) {
                Err(EncoderError::Crc) if tries < self.cfg.retries => {
                    tries += 1;
                    warn!("encoder: CRC error, retry {}", tries);
                }
                r => return r,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_hal_mock::eh1::spi::{Mock, Transaction};

    #[test]
    fn crc6_known_value() {
        // x^6 + x + 1 over a single 1 bit: the polynomial's low bits.
        assert_eq!(crc6(1, 1), 0x03);
        assert_eq!(crc6(0, 24), 0);
    }

    /// Frames as an encoder sends them, made by polynomial long division in Python (not by
    /// this driver): (counts, bits, idle bits, acknowledge bits, nE, frame).
    const VECTORS: [(u32, u8, usize, usize, bool, [u8; FRAME_BYTES]); 6] = [
        (0x1234AB, 23, 2, 3, true, [0xC4, 0x48, 0xD2, 0xAF, 0x64, 0x00, 0x00]),
        (0, 23, 1, 1, true, [0xA0, 0x00, 0x00, 0x1F, 0x40, 0x00, 0x00]),
        (0x7FFFFF, 23, 2, 5, true, [0xC1, 0x7F, 0xFF, 0xFF, 0xDC, 0x00, 0x00]),
        (4242, 23, 2, 2, true, [0xC8, 0x00, 0x84, 0x97, 0x98, 0x00, 0x00]),
        (5, 23, 2, 1, false, [0xD0, 0x00, 0x00, 0x54, 0x00, 0x00, 0x00]),
        (0xABCDEF01, 32, 1, 1, true, [0xAA, 0xBC, 0xDE, 0xF0, 0x1F, 0x10, 0x00]),
    ];

    #[test]
    fn independent_frames_decode() {
        for (counts, bits, _, _, ok, f) in VECTORS {
            let want = if ok { Ok(counts) } else { Err(EncoderError::DeviceError) };
            assert_eq!(decode_frame(&f, bits), want, "{counts:#x}");
        }
    }

    #[test]
    fn every_single_bit_error_is_caught() {
        let (counts, bits, idle, ack, _, f) = VECTORS[0];
        let frame_end = idle + ack + 2 + bits as usize + 2 + 6;
        for bit in 0..FRAME_BYTES * 8 {
            let mut g = f;
            g[bit / 8] ^= 0x80 >> (bit % 8);
            let r = decode_frame(&g, bits);
            if bit < idle + ack {
                // An idle or acknowledge bit flipped is a different latency, or no frame.
                assert!(matches!(r, Ok(c) if c == counts) || r.is_err(), "bit {bit}: {r:?}");
            } else if bit < frame_end {
                assert!(r.is_err(), "bit {bit}: {r:?}");
            } else {
                assert_eq!(r, Ok(counts), "bit {bit} is after the frame");
            }
        }
        assert_eq!(decode_frame(&[0; FRAME_BYTES], 23), Err(EncoderError::NotResponding));
        assert_eq!(decode_frame(&[0xFF; FRAME_BYTES], 23), Err(EncoderError::NotResponding));
        let cut = [0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xA0, 0x00];
        assert_eq!(decode_frame(&cut, 23), Err(EncoderError::BadFrame));
    }

    #[test]
    fn driver_retries_crc_errors_then_gives_up() {
        let good = VECTORS[3].5;
        let mut bad = good;
        bad[3] ^= 0x10;
        let mut spi = Mock::new(&[
            Transaction::read_vec(bad.to_vec()),
            Transaction::read_vec(good.to_vec()),
        ]);
        let mut enc = BissEncoder::new(spi.clone(), Config { bits: 23, retries: 3 });
        assert_eq!(embassy_futures::block_on(enc.read()), Ok(4242));
        spi.done();
        let mut spi = Mock::new(&[Transaction::read_vec(bad.to_vec()), Transaction::read_vec(bad.to_vec())]);
        let mut enc = BissEncoder::new(spi.clone(), Config { bits: 23, retries: 1 });
        assert_eq!(embassy_futures::block_on(enc.read()), Err(EncoderError::Crc));
        spi.done();
    }
}
