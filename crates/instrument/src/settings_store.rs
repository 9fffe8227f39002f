//! The settings in flash, power-loss safe: each SAVE appends a record to a
//! `sequential-storage` queue (old records are overwritten when it is full) and the newest
//! valid record is loaded at boot. An interrupted write leaves the record before it.

use crate::run::RunConfig;
use crate::settings::{self, MAX_BYTES, SettingsError};
use core::ops::Range;
use embedded_storage_async::nor_flash::NorFlash;
use sequential_storage::Error as StorageError;
use sequential_storage::cache::{Cache, Uncached};
use sequential_storage::queue::{QueueConfig, QueueStorage};

type NoCache = Cache<Uncached, Uncached, Uncached, ()>;

/// Why the settings could not be stored or loaded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StoreError {
    /// The flash failed, or what it holds is beyond repair (erase it with `DEFAULTS` and `SAVE`).
    Flash,
    /// The newest record could not be read back as settings.
    Record(SettingsError),
}

/// Settings records in `range` of the flash `S` (two erase pages at least).
pub struct SettingsStore<S: NorFlash> {
    queue: QueueStorage<S, NoCache>,
}

/// Room for one record and the flash's word alignment.
type Buffer = [u8; MAX_BYTES + 16];

impl<S: NorFlash> SettingsStore<S> {
    /// `None` when `range` is not whole pages, or fewer than two.
    pub fn new(flash: S, range: Range<u32>) -> Option<Self> {
        let config = QueueConfig::try_new(range).ok()?;
        Some(SettingsStore {
            queue: QueueStorage::new(flash, config, Cache::new_uncached()),
        })
    }

    /// Appends `cfg` as the newest record.
    pub async fn save(&mut self, cfg: &RunConfig) -> Result<(), StoreError> {
        let mut bytes = [0; MAX_BYTES];
        let n = settings::encode(cfg, &mut bytes);
        self.save_encoded(&bytes[..n]).await
    }

    /// Appends a record that [`settings::encode`] wrote: the caller need not keep the
    /// `RunConfig` while the flash is written.
    pub async fn save_encoded(&mut self, record: &[u8]) -> Result<(), StoreError> {
        self.queue.push(record, true).await.map_err(flash)
    }

    /// The newest record, or `None` when nothing was saved.
    pub async fn load(&mut self) -> Result<Option<RunConfig>, StoreError> {
        let mut buf: Buffer = [0; MAX_BYTES + 16];
        // The newest entry and its length, copied in place (the firmware runs this in a task
        // whose RAM is fixed at build time).
        let mut bytes = [0; MAX_BYTES];
        let mut newest: Option<usize> = None;
        let mut it = self.queue.iter().await.map_err(flash)?;
        while let Some(entry) = it.next(&mut buf).await.map_err(flash)? {
            let n = entry.len().min(MAX_BYTES);
            bytes[..n].copy_from_slice(&entry[..n]);
            newest = Some(entry.len());
        }
        match newest {
            None => Ok(None),
            Some(n) if n <= MAX_BYTES => settings::decode(&bytes[..n]).map(Some).map_err(StoreError::Record),
            Some(_) => Err(StoreError::Record(SettingsError::Length)),
        }
    }

    /// The flash back (to hand it on, or, in tests, to power it off and on).
    pub fn into_flash(self) -> S {
        self.queue.destroy().0
    }

    /// Forgets every record (the next boot takes the defaults).
    pub async fn erase(&mut self) -> Result<(), StoreError> {
        self.queue.erase_all().await.map_err(flash)
    }
}

fn flash<E>(_: StorageError<E>) -> StoreError {
    StoreError::Flash
}
