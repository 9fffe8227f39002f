//! The ADS1256 driver over a fake SPI device and DRDY pin. `start` tries up to three times the
//! sequence of the datasheet (SDATAC and WREG of MUX, ADCON and DRATE; RREG of the same three,
//! which must read back as written; SELFCAL; DRDY low; RDATAC), each step of which may fail,
//! and reports the last attempt's error; every sample read is the 24-bit two's-complement value
//! of its bytes, within the ADC's codes, and saturation is flagged exactly at the full-scale
//! codes. A failing bus or pin is an error value, never a panic.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf_fuzz::fake::{InstantClock, Pin, SpiDevice};
use nf_instrument::adc::{AdcError, Ads1256, CODE_MAX, CODE_MIN, Config, START_TRIES, is_saturated, sample_from_bytes};

/// Where a start-up attempt fails, if it does.
#[derive(Clone, Copy, PartialEq, arbitrary::Arbitrary)]
enum Fail {
    None,
    WriteRegs,
    WriteRreg,
    ReadBack,
    Mismatch,
    WriteSelfcal,
    Drdy,
    WriteRdatac,
}

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
    // Script the attempts and, beside them, what the driver must write and return.
    let regs = vec![0x0F, 0x51, 2, cfg.mux, cfg.adcon, cfg.drate];
    let mut want_written: Vec<Vec<u8>> = Vec::new();
    let mut want = Err(AdcError::Bus);
    for _ in 0..START_TRIES {
        let f: Fail = u.arbitrary()?;
        let write_ok = |step: Fail| f != step;
        spi.fail_writes.push_back(!write_ok(Fail::WriteRegs));
        if f == Fail::WriteRegs {
            want = Err(AdcError::Bus);
            continue;
        }
        want_written.push(regs.clone());
        spi.fail_writes.push_back(!write_ok(Fail::WriteRreg));
        if f == Fail::WriteRreg {
            want = Err(AdcError::Bus);
            continue;
        }
        let read: [u8; 3] = if f == Fail::Mismatch {
            let mut r = [cfg.mux, cfg.adcon, cfg.drate];
            let k = u.int_in_range(0..=2usize)?;
            r[k] ^= u.int_in_range(1..=255u8)?;
            want = Err(AdcError::Readback {
                register: 1 + k as u8,
                wrote: [cfg.mux, cfg.adcon, cfg.drate][k],
                read: r[k],
            });
            r
        } else {
            [cfg.mux, cfg.adcon, cfg.drate]
        };
        spi.reads
            .push_back(if f == Fail::ReadBack { Err(()) } else { Ok(read) });
        if f == Fail::ReadBack {
            want = Err(AdcError::Bus);
            continue;
        }
        want_written.push(vec![0x11, 2]);
        if f == Fail::Mismatch {
            continue;
        }
        spi.fail_writes.push_back(!write_ok(Fail::WriteSelfcal));
        if f == Fail::WriteSelfcal {
            want = Err(AdcError::Bus);
            continue;
        }
        want_written.push(vec![0xF0]);
        pin.waits.push_back(f != Fail::Drdy);
        if f == Fail::Drdy {
            want = Err(AdcError::Bus);
            continue;
        }
        spi.fail_writes.push_back(!write_ok(Fail::WriteRdatac));
        if f == Fail::WriteRdatac {
            want = Err(AdcError::Bus);
            continue;
        }
        want_written.push(vec![0x03]);
        want = Ok(());
        break;
    }
    let mut samples = Vec::new();
    let first_edge = pin.waits.len();
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
    let edges: Vec<bool> = pin.waits.iter().skip(first_edge).copied().collect();
    let mut adc = Ads1256::new(&mut spi, &mut pin);
    let started = embassy_futures::block_on(adc.start(&cfg, &mut InstantClock::default()));
    let mut got = Vec::new();
    if started.is_ok() {
        for _ in 0..n {
            got.push(embassy_futures::block_on(adc.next_sample()));
        }
    }
    // A write that fails moves no byte: the model's written list holds what went out.
    assert_eq!(started, want);
    let written: Vec<Vec<u8>> = spi.written.iter().filter(|w| !w.is_empty()).cloned().collect();
    assert_eq!(
        written[..want_written.len().min(written.len())],
        want_written[..want_written.len().min(written.len())]
    );
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
