//! BiSS-C frames. On any 7 bytes and any width: `decode_frame` does not panic, and a position
//! it gives fits the width. A frame as the twin's encoder puts it on the wire (idle-high bits,
//! 1 to 7 acknowledge bits, the error and warning bits; written from the protocol, not by the
//! driver) decodes to that position, or to `DeviceError` when the error bit is set; with one
//! bit flipped after the start bit, it is refused (a flip in the idle, acknowledge or start bits
//! shifts the frame, which only the CRC can catch).
//! The driver, over a fake bus answering scripted frames, gives what the frames and its retry
//! rule say, and reads at most `retries + 1` frames.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf_fuzz::fake::SpiBus;
use nf_instrument::encoder::{BissEncoder, Config, EncoderError, FRAME_BYTES, decode_frame};
use nf_twin::biss::Frame;

/// The line as the twin's encoder drives it for `FRAME_BYTES` bytes of clock.
fn wire(counts: u32, bits: u8, error: bool, warning: bool, idle: usize, ack: usize) -> [u8; FRAME_BYTES] {
    let mut out = [0u8; FRAME_BYTES];
    Frame {
        counts: counts as u64 & mask(bits),
        bits,
        error,
        warning,
        idle,
        ack,
    }
    .clock_into(&mut out);
    out
}

fn mask(bits: u8) -> u64 {
    (1u64 << bits) - 1
}

fn run(u: &mut Unstructured) -> Result<()> {
    // Any bytes, any width.
    let raw: [u8; FRAME_BYTES] = u.arbitrary()?;
    let bits: u8 = u.arbitrary()?;
    if let Ok(v) = decode_frame(&raw, bits) {
        assert!(
            bits > 32 || v as u64 <= mask(bits),
            "{raw:02x?} at {bits} bits gives {v}"
        );
    }

    // Encoded and decoded.
    let bits: u8 = u.int_in_range(1..=32)?;
    let counts: u32 = u.arbitrary()?;
    let (error, warning): (bool, bool) = u.arbitrary()?;
    let idle: usize = u.int_in_range(0..=2)?;
    let ack: usize = u.int_in_range(1..=7)?;
    let frame = wire(counts, bits, error, warning, idle, ack);
    let want = if error {
        Err(EncoderError::DeviceError)
    } else {
        Ok((counts as u64 & mask(bits)) as u32)
    };
    assert_eq!(decode_frame(&frame, bits), want, "{frame:02x?}");
    let frame_bits = idle + ack + 2 + bits as usize + 8;
    let flip: usize = u.int_in_range(0..=FRAME_BYTES * 8 - 1)?;
    let mut bad = frame;
    bad[flip / 8] ^= 0x80 >> (flip % 8);
    let got = decode_frame(&bad, bits);
    if let Ok(v) = got {
        assert!(v as u64 <= mask(bits));
    }
    if flip <= idle + ack {
        // An idle or acknowledge bit flipped, or the start bit cleared, moves the start: the
        // frame is read shifted, and only its CRC (1 in 64 passes) can tell. A limit of the
        // protocol.
    } else if flip < frame_bits {
        // CDS, position, nE, nW or CRC: the CRC-6 catches every single-bit error.
        assert!(got.is_err(), "bit {flip} flipped in {frame:02x?}: {got:?}");
    } else {
        assert_eq!(got, want, "bit {flip} is after the frame");
    }

    // The driver.
    let retries: u8 = u.int_in_range(0..=8)?;
    let bits: u8 = u.int_in_range(1..=32)?;
    let mut reads = Vec::new();
    for _ in 0..u.int_in_range(0..=12)? {
        reads.push(match u.int_in_range(0..=3u8)? {
            0 => Err(()),
            1 => Ok(u.arbitrary::<[u8; FRAME_BYTES]>()?.to_vec()),
            _ => {
                let c: u32 = u.arbitrary()?;
                let (e, w) = (u.ratio(1, 8)?, u.arbitrary()?);
                let mut f = wire(c, bits, e, w, u.int_in_range(0..=2)?, u.int_in_range(1..=7)?);
                if u.arbitrary()? {
                    let b: usize = u.int_in_range(0..=FRAME_BYTES * 8 - 1)?;
                    f[b / 8] ^= 0x80 >> (b % 8);
                }
                Ok(f.to_vec())
            }
        });
    }
    // The model: frames in turn; a CRC error is retried `retries` times; the bus's error (or
    // the script's end) ends the read.
    let (mut want, mut frames) = (None, 0);
    for r in &reads {
        frames += 1;
        let Ok(raw) = r else {
            want = Some(Err(EncoderError::Bus));
            break;
        };
        let d = decode_frame(raw.as_slice().try_into().unwrap(), bits);
        if d == Err(EncoderError::Crc) && frames <= retries as usize {
            continue;
        }
        want = Some(d);
        break;
    }
    // The script ran out: one more read, which fails.
    let want = want.unwrap_or_else(|| {
        frames += 1;
        Err(EncoderError::Bus)
    });
    let mut bus = SpiBus {
        reads: reads.into(),
        calls: 0,
    };
    let mut enc = BissEncoder::new(&mut bus, Config { bits, retries });
    let got = embassy_futures::block_on(enc.read());
    assert_eq!(got, want);
    if let Ok(v) = got {
        assert!(v as u64 <= mask(bits));
    }
    assert_eq!(bus.calls, frames);
    assert!(bus.calls <= retries as usize + 1);
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
