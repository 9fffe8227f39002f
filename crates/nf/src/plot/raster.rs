//! A small rasterizer (lines, dots, rectangles, a 5x7 bitmap font) and a PNG encoder
//! (stored deflate blocks, CRC-32, Adler-32).

use super::{Anchor, Rgb, Surface};

pub struct Raster {
    w: usize,
    h: usize,
    px: Vec<Rgb>,
}

/// 5x7 glyphs, one byte a row (low 5 bits, MSB on the left), for ' ' to '~'.
const FONT: [[u8; 7]; 95] = [
    [0, 0, 0, 0, 0, 0, 0],
    [4, 4, 4, 4, 4, 0, 4],
    [10, 10, 10, 0, 0, 0, 0],
    [10, 10, 31, 10, 31, 10, 10],
    [4, 15, 20, 14, 5, 30, 4],
    [24, 25, 2, 4, 8, 19, 3],
    [12, 18, 20, 8, 21, 18, 13],
    [12, 4, 8, 0, 0, 0, 0],
    [2, 4, 8, 8, 8, 4, 2],
    [8, 4, 2, 2, 2, 4, 8],
    [0, 4, 21, 14, 21, 4, 0],
    [0, 4, 4, 31, 4, 4, 0],
    [0, 0, 0, 0, 12, 4, 8],
    [0, 0, 0, 31, 0, 0, 0],
    [0, 0, 0, 0, 0, 12, 12],
    [0, 1, 2, 4, 8, 16, 0],
    [14, 17, 19, 21, 25, 17, 14],
    [4, 12, 4, 4, 4, 4, 14],
    [14, 17, 1, 2, 4, 8, 31],
    [31, 2, 4, 2, 1, 17, 14],
    [2, 6, 10, 18, 31, 2, 2],
    [31, 16, 30, 1, 1, 17, 14],
    [6, 8, 16, 30, 17, 17, 14],
    [31, 1, 2, 4, 8, 8, 8],
    [14, 17, 17, 14, 17, 17, 14],
    [14, 17, 17, 15, 1, 2, 12],
    [0, 12, 12, 0, 12, 12, 0],
    [0, 12, 12, 0, 12, 4, 8],
    [2, 4, 8, 16, 8, 4, 2],
    [0, 0, 31, 0, 31, 0, 0],
    [8, 4, 2, 1, 2, 4, 8],
    [14, 17, 1, 2, 4, 0, 4],
    [14, 17, 1, 13, 21, 21, 14],
    [14, 17, 17, 17, 31, 17, 17],
    [30, 17, 17, 30, 17, 17, 30],
    [14, 17, 16, 16, 16, 17, 14],
    [28, 18, 17, 17, 17, 18, 28],
    [31, 16, 16, 30, 16, 16, 31],
    [31, 16, 16, 30, 16, 16, 16],
    [14, 17, 16, 23, 17, 17, 15],
    [17, 17, 17, 31, 17, 17, 17],
    [14, 4, 4, 4, 4, 4, 14],
    [7, 2, 2, 2, 2, 18, 12],
    [17, 18, 20, 24, 20, 18, 17],
    [16, 16, 16, 16, 16, 16, 31],
    [17, 27, 21, 21, 17, 17, 17],
    [17, 17, 25, 21, 19, 17, 17],
    [14, 17, 17, 17, 17, 17, 14],
    [30, 17, 17, 30, 16, 16, 16],
    [14, 17, 17, 17, 21, 18, 13],
    [30, 17, 17, 30, 20, 18, 17],
    [15, 16, 16, 14, 1, 1, 30],
    [31, 4, 4, 4, 4, 4, 4],
    [17, 17, 17, 17, 17, 17, 14],
    [17, 17, 17, 17, 17, 10, 4],
    [17, 17, 17, 21, 21, 21, 10],
    [17, 17, 10, 4, 10, 17, 17],
    [17, 17, 17, 10, 4, 4, 4],
    [31, 1, 2, 4, 8, 16, 31],
    [14, 8, 8, 8, 8, 8, 14],
    [0, 16, 8, 4, 2, 1, 0],
    [14, 2, 2, 2, 2, 2, 14],
    [4, 10, 17, 0, 0, 0, 0],
    [0, 0, 0, 0, 0, 0, 31],
    [8, 4, 2, 0, 0, 0, 0],
    [0, 0, 14, 1, 15, 17, 15],
    [16, 16, 22, 25, 17, 17, 30],
    [0, 0, 14, 16, 16, 17, 14],
    [1, 1, 13, 19, 17, 17, 15],
    [0, 0, 14, 17, 31, 16, 14],
    [6, 9, 8, 28, 8, 8, 8],
    [0, 15, 17, 17, 15, 1, 14],
    [16, 16, 22, 25, 17, 17, 17],
    [4, 0, 12, 4, 4, 4, 14],
    [2, 0, 6, 2, 2, 18, 12],
    [16, 16, 18, 20, 24, 20, 18],
    [12, 4, 4, 4, 4, 4, 14],
    [0, 0, 26, 21, 21, 17, 17],
    [0, 0, 22, 25, 17, 17, 17],
    [0, 0, 14, 17, 17, 17, 14],
    [0, 0, 30, 17, 30, 16, 16],
    [0, 0, 13, 19, 15, 1, 1],
    [0, 0, 22, 25, 16, 16, 16],
    [0, 0, 14, 16, 14, 1, 30],
    [8, 8, 28, 8, 8, 9, 6],
    [0, 0, 17, 17, 17, 19, 13],
    [0, 0, 17, 17, 17, 10, 4],
    [0, 0, 17, 17, 21, 21, 10],
    [0, 0, 17, 10, 4, 10, 17],
    [0, 0, 17, 17, 15, 1, 14],
    [0, 0, 31, 2, 4, 8, 31],
    [2, 4, 4, 8, 4, 4, 2],
    [4, 4, 4, 4, 4, 4, 4],
    [8, 4, 4, 2, 4, 4, 8],
    [0, 0, 8, 21, 2, 0, 0],
];

impl Raster {
    pub fn new(w: usize, h: usize) -> Self {
        Raster {
            w,
            h,
            px: vec![[255; 3]; w * h],
        }
    }

    fn set(&mut self, x: i64, y: i64, c: Rgb) {
        if x >= 0 && y >= 0 && (x as usize) < self.w && (y as usize) < self.h {
            self.px[y as usize * self.w + x as usize] = c;
        }
    }

    fn glyph(&mut self, x: i64, y: i64, scale: i64, vertical: bool, ch: char, c: Rgb) {
        let g = FONT[(ch as usize).wrapping_sub(32).min(94)];
        let g = if (' '..='~').contains(&ch) { g } else { FONT[31] };
        for (row, bits) in g.iter().enumerate() {
            for col in 0..5 {
                if bits & (16 >> col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let (u, v) = (col * scale + dx, row as i64 * scale + dy);
                        if vertical {
                            self.set(x + v, y - u, c)
                        } else {
                            self.set(x + u, y + v, c)
                        }
                    }
                }
            }
        }
    }

    /// The image as a PNG file: 8-bit RGB, no filter, stored deflate blocks.
    pub fn png(&self) -> Vec<u8> {
        let mut raw = Vec::with_capacity(self.h * (1 + 3 * self.w));
        for row in self.px.chunks(self.w) {
            raw.push(0);
            raw.extend(row.iter().flatten());
        }
        let mut z = vec![0x78, 0x01];
        let chunks: Vec<&[u8]> = raw.chunks(65_535).collect();
        for (i, c) in chunks.iter().enumerate() {
            z.push((i + 1 == chunks.len()) as u8);
            z.extend((c.len() as u16).to_le_bytes());
            z.extend((!(c.len() as u16)).to_le_bytes());
            z.extend_from_slice(c);
        }
        z.extend(adler32(&raw).to_be_bytes());
        let mut ihdr = Vec::new();
        ihdr.extend((self.w as u32).to_be_bytes());
        ihdr.extend((self.h as u32).to_be_bytes());
        ihdr.extend([8, 2, 0, 0, 0]);
        let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
        for (kind, data) in [(b"IHDR", &ihdr[..]), (b"IDAT", &z[..]), (b"IEND", &[][..])] {
            out.extend((data.len() as u32).to_be_bytes());
            let start = out.len();
            out.extend(kind);
            out.extend(data);
            let crc = crc32(&out[start..]);
            out.extend(crc.to_be_bytes());
        }
        out
    }
}

fn crc32(data: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in data {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

fn adler32(data: &[u8]) -> u32 {
    let (mut a, mut b) = (1u32, 0u32);
    for &x in data {
        a = (a + x as u32) % 65_521;
        b = (b + a) % 65_521;
    }
    (b << 16) | a
}

/// The pixel nearest a coordinate, held to a range where the offsets added to it cannot
/// overflow: a tick of a degenerate axis can sit at 1e19 (and NaN gives 0). All of it is
/// outside the image, which draws nothing there.
fn pixel(v: f64) -> i64 {
    v.clamp(-1e9, 1e9).round() as i64
}

impl Surface for Raster {
    fn line(&mut self, a: (f64, f64), b: (f64, f64), c: Rgb) {
        let n = (b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil().max(1.0) as i64;
        for i in 0..=n {
            let t = i as f64 / n as f64;
            self.set(
                (a.0 + t * (b.0 - a.0)).round() as i64,
                (a.1 + t * (b.1 - a.1)).round() as i64,
                c,
            );
        }
    }

    fn polyline(&mut self, pts: &[(f64, f64)], c: Rgb) {
        for w in pts.windows(2) {
            self.line(w[0], w[1], c);
            self.line((w[0].0, w[0].1 + 1.0), (w[1].0, w[1].1 + 1.0), c);
        }
    }

    fn dot(&mut self, p: (f64, f64), c: Rgb) {
        let (x, y) = (pixel(p.0), pixel(p.1));
        for dy in -2..=2i64 {
            for dx in -2..=2i64 {
                if dx * dx + dy * dy <= 5 {
                    self.set(x + dx, y + dy, c);
                }
            }
        }
    }

    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, c: Rgb, filled: bool) {
        if filled {
            for yy in y.round() as i64..(y + h).round() as i64 {
                self.line((x, yy as f64), (x + w, yy as f64), c);
            }
        } else {
            self.line((x, y), (x + w, y), c);
            self.line((x + w, y), (x + w, y + h), c);
            self.line((x + w, y + h), (x, y + h), c);
            self.line((x, y + h), (x, y), c);
        }
    }

    fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, vertical: bool, s: &str) {
        let scale = if size >= 13.0 { 2 } else { 1 };
        let adv = 6 * scale;
        let len = s.chars().count() as i64 * adv;
        let shift = match anchor {
            Anchor::Start => 0,
            Anchor::Middle => len / 2,
            Anchor::End => len,
        };
        let (x, y) = (pixel(x), pixel(y));
        for (i, ch) in s.chars().enumerate() {
            let o = i as i64 * adv - shift;
            if vertical {
                self.glyph(x - 7 * scale, y - o, scale, true, ch, super::INK);
            } else {
                self.glyph(x + o, y - 7 * scale, scale, false, ch, super::INK);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksums_of_known_strings() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(adler32(b"Wikipedia"), 0x11E6_0398);
    }

    #[test]
    fn text_and_dots_far_outside_the_image_draw_nothing() {
        // `x.round() as i64` saturates at 1e19; adding the glyph offsets then overflowed (a
        // panic in debug builds). Found by the `plot` fuzz target.
        let mut r = Raster::new(20, 20);
        for v in [1e19, -1e19, f64::INFINITY, f64::NEG_INFINITY, f64::MAX] {
            for anchor in [Anchor::Start, Anchor::Middle, Anchor::End] {
                r.text(v, 5.0, 11.0, anchor, false, "12");
                r.text(5.0, v, 14.0, anchor, true, "12");
            }
            r.dot((v, -v), [0; 3]);
        }
        r.text(f64::NAN, f64::NAN, 11.0, Anchor::Middle, false, "");
        assert!(r.px.iter().all(|&p| p == [255; 3]));
    }

    #[test]
    fn stored_blocks_split_large_images() {
        let png = Raster::new(300, 300).png();
        // 300 rows of 901 bytes need five stored blocks.
        assert!(png.len() > 300 * 901);
    }
}
