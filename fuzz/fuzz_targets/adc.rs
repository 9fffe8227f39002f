//! The ADS1256 driver over a fake SPI device and DRDY pin. `start` writes the register
//! sequence of the datasheet (SDATAC, WREG of MUX, ADCON and DRATE, SELFCAL, RDATAC) or reports
//! the bus error; every sample read is the 24-bit two's-complement value of its bytes, within
//! the ADC's codes, and saturation is flagged exactly at the full-scale codes. A failing bus or
//! pin is an error value, never a panic.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf_fuzz::fake::{Pin, SpiDevice};
use nf_instrument::adc::{AdcError, Ads1256, CODE_MAX, CODE_MIN, Config, is_saturated, sample_from_bytes};

/// Two's complement of 24 bits, by arithmetic.
fn model(b: [u8; 3]) -> i32 {
    let u = (b[0] as i32) * 65_536 + (b[1] as i32) * 256 + b[2] as i32;
    if u >= 0x80_0000 { u - 0x100_0000 } else { u }
}

fn run(u: &mut Unstructured) -> Result<()> {
    let b: [u8; 3] = u.arbitrary()?;
    let s = sample_from_bytes(b);
    assert_eq!(s, model(b), "{b:02x?}");
    assert!((CODE_MIN..=CODE_MAX).contains(&s));
    assert_eq!(is_saturated(s), s == CODE_MIN || s == CODE_MAX);

    let cfg = Config {
        mux: u.arbitrary()?,
        adcon: u.arbitrary()?,
        drate: u.arbitrary()?,
    };
    let n = u.int_in_range(0..=64usize)?;
    let mut spi = SpiDevice::default();
    let mut pin = Pin {
        waits: Default::default(),
    };
    // The start: three writes and a wait for DRDY low, each of which may fail.
    let fails: [bool; 4] = [u.ratio(1, 16)?, u.ratio(1, 16)?, u.ratio(1, 16)?, u.ratio(1, 16)?];
    spi.fail_writes.extend([fails[0], fails[1], fails[3]]);
    pin.waits.push_back(!fails[2]);
    let mut samples = Vec::new();
    for _ in 0..n {
        pin.waits.push_back(!u.ratio(1, 32)?);
        let r = if u.ratio(1, 32)? {
            Err(())
        } else {
            Ok(u.arbitrary::<[u8; 3]>()?)
        };
        spi.reads.push_back(r);
        samples.push(r);
    }
    let edges: Vec<bool> = pin.waits.iter().skip(1).copied().collect();
    let mut adc = Ads1256::new(&mut spi, &mut pin);
    let started = embassy_futures::block_on(adc.start(&cfg));
    let mut got = Vec::new();
    if started.is_ok() {
        for _ in 0..n {
            got.push(embassy_futures::block_on(adc.next_sample()));
        }
    }
    // The model.
    let steps = fails.iter().position(|&f| f);
    assert_eq!(started, if steps.is_some() { Err(AdcError::Bus) } else { Ok(()) });
    let regs = vec![0x0F, 0x51, 2, cfg.mux, cfg.adcon, cfg.drate];
    let want_written: Vec<Vec<u8>> = match steps {
        None => vec![regs, vec![0xF0], vec![0x03]],
        Some(0) => vec![],
        Some(1) => vec![regs],
        Some(_) => vec![regs, vec![0xF0]],
    };
    assert_eq!(spi.written[..want_written.len()], want_written[..]);
    if started.is_err() {
        return Ok(());
    }
    // Each sample: the edge, then the read. A failed edge consumes no read.
    let mut reads = samples.iter();
    for (g, edge) in got.iter().zip(&edges) {
        let want = if !edge {
            Err(AdcError::Bus)
        } else {
            match reads.next() {
                Some(Ok(b)) => Ok(model(*b)),
                _ => Err(AdcError::Bus),
            }
        };
        assert_eq!(*g, want);
        if let Ok(s) = g {
            assert!((CODE_MIN..=CODE_MAX).contains(s));
        }
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
