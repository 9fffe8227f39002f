//! The twin's BiSS-C encoder on the wire, written from the protocol, not from the driver: the
//! line idles high, the acknowledge pulls it low, then start (1), CDS (0), the position, nE, nW
//! and the inverted CRC-6 (x^6 + x + 1) by long division, then low until the timeout.

/// The line's levels for as many clock cycles as `out` holds, MSB first.
pub struct Frame {
    pub counts: u64,
    pub bits: u8,
    pub error: bool,
    pub warning: bool,
    /// Clock cycles before the encoder answers (the line stays high).
    pub idle: usize,
    /// Clock cycles of the acknowledge (low).
    pub ack: usize,
}

impl Frame {
    /// The levels, one per clock cycle; cycles past the frame read low (timeout).
    pub fn levels(&self) -> Vec<bool> {
        let mut data: Vec<bool> = (0..self.bits).rev().map(|i| (self.counts >> i) & 1 == 1).collect();
        data.push(!self.error);
        data.push(!self.warning);
        let mut line = vec![true; self.idle];
        line.extend(std::iter::repeat_n(false, self.ack));
        line.extend([true, false]);
        line.extend(&data);
        line.extend(crc6_by_division(&data).iter().map(|b| !b));
        line
    }

    /// Clocks `out.len()` bytes of the line.
    pub fn clock_into(&self, out: &mut [u8]) {
        let levels = self.levels();
        for (k, byte) in out.iter_mut().enumerate() {
            *byte = (0..8).fold(0, |b, i| {
                (b << 1) | levels.get(8 * k + i).copied().unwrap_or(false) as u8
            });
        }
    }
}

/// Remainder of `data * x^6` divided by `x^6 + x + 1`.
fn crc6_by_division(data: &[bool]) -> [bool; 6] {
    const POLY: [bool; 7] = [true, false, false, false, false, true, true];
    let mut r: Vec<bool> = data.to_vec();
    r.extend([false; 6]);
    for i in 0..data.len() {
        if r[i] {
            for (j, p) in POLY.iter().enumerate() {
                r[i + j] ^= p;
            }
        }
    }
    core::array::from_fn(|k| r[data.len() + k])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_has_the_protocols_fields_in_order() {
        let f = Frame {
            counts: 0b101,
            bits: 3,
            error: false,
            warning: true,
            idle: 2,
            ack: 1,
        };
        let l: String = f.levels().iter().map(|&b| if b { '1' } else { '0' }).collect();
        // idle, ack, start, CDS, position, nE, nW, inverted CRC of 10110.
        let crc: String = crc6_by_division(&[true, false, true, true, false])
            .iter()
            .map(|&b| if b { '0' } else { '1' })
            .collect();
        assert_eq!(l, format!("11 0 1 0 101 1 0 {crc}").replace(' ', ""));
    }
}
