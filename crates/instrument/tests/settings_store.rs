//! The settings store on a mock NOR flash that enforces what the STM32F4's flash enforces
//! (aligned words, programming only clears bits, whole-page erases) and cuts the power in the
//! middle of any write or erase.

use embedded_storage_async::nor_flash::{ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash};
use nf_instrument::run::RunConfig;
use nf_instrument::settings_store::{SettingsStore, StoreError};
use nf_model::order::Order;

const WORD: usize = 4;
const PAGE: usize = 2048;
const PAGES: usize = 4;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FlashError {
    Misaligned,
    NotErased,
    OutOfBounds,
    PowerCut,
}

impl NorFlashError for FlashError {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            FlashError::Misaligned => NorFlashErrorKind::NotAligned,
            FlashError::OutOfBounds => NorFlashErrorKind::OutOfBounds,
            _ => NorFlashErrorKind::Other,
        }
    }
}

#[derive(Clone)]
struct MockFlash {
    bytes: Vec<u8>,
    /// Writes and erases left before the power goes; the one that meets zero is cut halfway.
    ops_left: Option<usize>,
    ops: usize,
    erases: usize,
}

impl MockFlash {
    fn new() -> Self {
        MockFlash {
            bytes: vec![0xFF; PAGE * PAGES],
            ops_left: None,
            ops: 0,
            erases: 0,
        }
    }

    /// Counts the operation; `Err` when the power is gone (after doing `half` of it).
    fn power(&mut self, half: impl FnOnce(&mut Self)) -> Result<(), FlashError> {
        self.ops += 1;
        match self.ops_left {
            Some(0) => Err(FlashError::PowerCut),
            Some(1) => {
                half(self);
                self.ops_left = Some(0);
                Err(FlashError::PowerCut)
            }
            Some(n) => {
                self.ops_left = Some(n - 1);
                Ok(())
            }
            None => Ok(()),
        }
    }
}

impl ErrorType for MockFlash {
    type Error = FlashError;
}

impl ReadNorFlash for MockFlash {
    const READ_SIZE: usize = 1;
    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), FlashError> {
        let from = offset as usize;
        let src = self
            .bytes
            .get(from..from + bytes.len())
            .ok_or(FlashError::OutOfBounds)?;
        bytes.copy_from_slice(src);
        Ok(())
    }
    fn capacity(&self) -> usize {
        self.bytes.len()
    }
}

impl NorFlash for MockFlash {
    const WRITE_SIZE: usize = WORD;
    const ERASE_SIZE: usize = PAGE;

    async fn erase(&mut self, from: u32, to: u32) -> Result<(), FlashError> {
        let (from, to) = (from as usize, to as usize);
        if !from.is_multiple_of(PAGE) || !to.is_multiple_of(PAGE) {
            return Err(FlashError::Misaligned);
        }
        if to > self.bytes.len() || from > to {
            return Err(FlashError::OutOfBounds);
        }
        self.erases += 1;
        self.power(|f| f.bytes[from..from + (to - from) / 2].fill(0xFF))?;
        self.bytes[from..to].fill(0xFF);
        Ok(())
    }

    async fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), FlashError> {
        let at = offset as usize;
        if !at.is_multiple_of(WORD) || !data.len().is_multiple_of(WORD) {
            return Err(FlashError::Misaligned);
        }
        let dst = self.bytes.get(at..at + data.len()).ok_or(FlashError::OutOfBounds)?;
        // No ECC on the F4: programming clears bits, and cannot set one again.
        if dst.iter().zip(data).any(|(&old, &new)| old & new != new) {
            return Err(FlashError::NotErased);
        }
        // Cut halfway: the first half of the words land, and one byte of the next.
        let half = (data.len() / WORD / 2) * WORD + 1;
        let program = |f: &mut Self, n: usize| {
            for (b, &d) in f.bytes[at..at + n].iter_mut().zip(data) {
                *b &= d;
            }
        };
        self.power(|f| program(f, half.min(data.len())))?;
        program(self, data.len());
        Ok(())
    }
}

fn block<T>(f: impl Future<Output = T>) -> T {
    embassy_futures::block_on(f)
}

fn store(flash: MockFlash) -> SettingsStore<MockFlash> {
    SettingsStore::new(flash, 0..(PAGE * PAGES) as u32).expect("whole pages")
}

fn config(k: u16) -> RunConfig {
    RunConfig {
        positions: 8 + 2 * k,
        order: if k.is_multiple_of(2) {
            Order::OppositePairs
        } else {
            Order::parse("0,1,2,3,4,5,6,7").unwrap()
        },
        dwell_ms: 1000 + k as u32,
        latitude_deg: 10.0 + k as f32 / 8.0,
        ..RunConfig::DEFAULT
    }
}

#[test]
fn nothing_saved_loads_nothing_and_a_save_loads_back() {
    let mut s = store(MockFlash::new());
    assert_eq!(block(s.load()), Ok(None));
    block(s.save(&config(3))).unwrap();
    assert_eq!(block(s.load()), Ok(Some(config(3))));
}

#[test]
fn the_newest_of_many_saves_loads_as_the_queue_wraps() {
    let mut s = store(MockFlash::new());
    for k in 0..200 {
        block(s.save(&config(k % 300))).unwrap();
        assert_eq!(block(s.load()), Ok(Some(config(k % 300))), "save {k}");
    }
}

#[test]
fn a_power_cut_at_any_point_of_a_save_leaves_the_old_or_the_new_settings() {
    let (mut cuts, mut erasing_saves) = (0, 0);
    // Histories of every length up to past the first wrap, so that some saves erase a page.
    let mut before = store(MockFlash::new());
    for k in 0..90 {
        block(before.save(&config(k))).unwrap();
        let flash = before.into_flash();
        let (old, new) = (config(k), config(k + 1));
        let (ops, erases) = {
            let mut s = store(MockFlash {
                ops: 0,
                erases: 0,
                ..flash.clone()
            });
            block(s.save(&new)).unwrap();
            let f = s.into_flash();
            (f.ops, f.erases)
        };
        erasing_saves += (erases > 0) as usize;
        for cut in 1..=ops {
            let mut s = store(MockFlash {
                ops_left: Some(cut),
                ..flash.clone()
            });
            assert_eq!(
                block(s.save(&new)),
                Err(StoreError::Flash),
                "history {k}, cut at op {cut}"
            );
            // Power back: a new boot on what the flash holds.
            let mut f = s.into_flash();
            f.ops_left = None;
            let mut s = store(f);
            let got = block(s.load()).unwrap_or_else(|e| panic!("history {k}, cut at op {cut} of {ops}: {e:?}"));
            assert!(
                got == Some(old) || got == Some(new),
                "history {k}, cut at op {cut}: {got:?}"
            );
            // And the store still takes a save.
            block(s.save(&config(200))).unwrap();
            assert_eq!(block(s.load()), Ok(Some(config(200))));
            cuts += 1;
        }
        before = store(flash);
    }
    println!("{cuts} power cuts, {erasing_saves} of 90 saves erased a page");
    assert!(erasing_saves > 0 && cuts > 90);
}
