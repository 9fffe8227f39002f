//! Absolute encoder over BiSS-C (point-to-point, read over an SPI bus's MISO and SCK).
//!
//! Frame, MSB first: the encoder holds the line low for the acknowledge, then sends a start
//! bit (1), the CDS bit (0), the position (`bits` wide), nE and nW (active-low error and
//! warning) and a CRC-6 (polynomial `x^6 + x + 1`, sent inverted) over position, nE and nW.
//! The driver clocks [`FRAME_BYTES`] bytes, finds the start bit and checks everything.

use embedded_hal_async::spi::SpiBus;

/// Bytes clocked per read: up to 7 acknowledge bits, 2 + 32 + 2 + 6 frame bits fit.
pub const FRAME_BYTES: usize = 7;

/// Why an encoder read failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EncoderError {
    /// The SPI bus reported an error.
    Bus,
    /// No start bit: the line stays low (no encoder, no power, broken cable).
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

/// The bits an encoder sends for `counts`, after `ack_bits` acknowledge zeros.
pub fn encode_frame(counts: u32, bits: u8, error: bool, warning: bool, ack_bits: u32) -> [u8; FRAME_BYTES] {
    let data = ((counts as u64 & ((1 << bits) - 1)) << 2) | ((!error as u64) << 1) | (!warning as u64);
    let n = bits as u32 + 2;
    let crc = (!crc6(data, n)) & 0x3F;
    let frame = (0b10u64 << (n + 6)) | (data << 6) | crc as u64;
    let len = n + 8;
    let total = (FRAME_BYTES * 8) as u32;
    let shifted = (frame as u128) << (total - ack_bits - len);
    let mut out = [0u8; FRAME_BYTES];
    for (i, b) in out.iter_mut().enumerate() {
        *b = (shifted >> (8 * (FRAME_BYTES - 1 - i))) as u8;
    }
    out
}

/// Decodes a frame clocked in by [`BissEncoder::read`].
pub fn decode_frame(raw: &[u8; FRAME_BYTES], bits: u8) -> Result<u32, EncoderError> {
    let total = (FRAME_BYTES * 8) as u32;
    let word = raw.iter().fold(0u128, |w, &b| (w << 8) | b as u128);
    if word == 0 {
        return Err(EncoderError::NotResponding);
    }
    let start = 127 - word.leading_zeros(); // bit index of the start bit
    let n = bits as u32 + 2;
    if start < n + 7 || total - 1 - start > 7 {
        return Err(EncoderError::BadFrame);
    }
    if (word >> (start - 1)) & 1 != 0 {
        return Err(EncoderError::BadFrame);
    }
    let body = start - 1; // bits after the CDS bit
    let data = ((word >> (body - n)) as u64) & ((1 << n) - 1);
    let crc = ((word >> (body - n - 6)) as u8) & 0x3F;
    if (!crc6(data, n)) & 0x3F != crc {
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

    #[test]
    fn frames_round_trip_at_every_acknowledge_length() {
        for bits in [22u8, 23, 26, 32] {
            for ack in 0..=7 {
                for counts in [0u32, 1, 0x2AAAAA, ((1u64 << bits) - 1) as u32] {
                    let f = encode_frame(counts, bits, false, false, ack);
                    assert_eq!(decode_frame(&f, bits), Ok(counts), "bits {bits} ack {ack}");
                }
            }
        }
    }

    #[test]
    fn every_single_bit_error_is_caught() {
        let f = encode_frame(0x1234AB, 23, false, false, 3);
        // 3 acknowledge bits, then start, CDS, 23 position bits, nE, nW and 6 CRC bits.
        let frame_end = 3 + 2 + 23 + 2 + 6;
        for bit in 0..FRAME_BYTES * 8 {
            let mut g = f;
            g[bit / 8] ^= 0x80 >> (bit % 8);
            let r = decode_frame(&g, 23);
            if bit < frame_end {
                assert!(r.is_err(), "bit {bit}: {r:?}");
            } else {
                assert_eq!(r, Ok(0x1234AB), "bit {bit} is after the frame");
            }
        }
        assert_eq!(decode_frame(&[0; FRAME_BYTES], 23), Err(EncoderError::NotResponding));
        assert_eq!(decode_frame(&[0xFF; FRAME_BYTES], 23), Err(EncoderError::BadFrame));
        assert_eq!(
            decode_frame(&encode_frame(5, 23, true, false, 0), 23),
            Err(EncoderError::DeviceError)
        );
    }

    #[test]
    fn driver_retries_crc_errors_then_gives_up() {
        let good = encode_frame(4242, 23, false, false, 2);
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
