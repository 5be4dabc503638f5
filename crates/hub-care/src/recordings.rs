//! Where the hub keeps stations' recordings: one interface ([`RecordingStore`]) over the
//! `object_store` crate, with the data directory (`DATA/recordings/<station>/<session>.mcap`,
//! the embedded default) or any S3-compatible store (`[recordings]` in `hub.toml`,
//! [`RecordingsConfig`]) behind it. Every reader and writer of a recording goes through it:
//! an upload's completion ([`RecordingStore::keep`]), the console's replay
//! ([`RecordingStore::open_reader`]), a patient's export and erasure
//! ([`RecordingStore::station_files`], [`RecordingStore::erase_station`]) and the backup
//! ([`RecordingStore::finished`]).
//!
//! A partial upload always grows on the receiving hub's own disk
//! (`DATA/recordings/<station>/<session>.<sha256 prefix>.part`, netlink's upload) and reaches
//! the store only whole and verified: on S3 as one multipart upload, completed (visible) or
//! aborted, never half-listed. A station that reconnects to another hub uploads from byte 0
//! there; whichever hub completes it writes the same object under the same key, so the
//! recording is stored once.

use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use futures_util::StreamExt;
use object_store::path::Path as Key;
use object_store::{ObjectStore, ObjectStoreExt, WriteMultipart};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use hub_store::HubError;

mod config;

pub use config::RecordingsConfig;

/// Bytes of one S3 multipart part (S3's minimum part is 5 MiB, but the last).
pub const PART_BYTES: usize = 8 << 20;
/// Parts in flight at once for one upload: what an upload holds is at most about
/// `PART_BYTES × (PARTS_IN_FLIGHT + 1)`.
pub const PARTS_IN_FLIGHT: usize = 2;
/// Bytes one ranged read of a reader fetches from S3 (replay, export, backup): a reader holds
/// one such block.
pub const READ_BLOCK_BYTES: u64 = 4 << 20;

/// Where the recordings are.
#[derive(Debug, Clone)]
enum Place {
    /// The data directory's `recordings/`.
    Local,
    /// An S3-compatible store; `s3://bucket/prefix`.
    S3 { url: String },
}

/// The runtime an S3 store's requests run on: its own, so a blocking reader (replay, tar
/// writing) can wait for a request from any thread, a runtime's worker included.
#[derive(Debug)]
struct IoRuntime(Option<tokio::runtime::Runtime>);

impl Drop for IoRuntime {
    fn drop(&mut self) {
        if let Some(rt) = self.0.take() {
            // Dropping a runtime may happen inside another one: never block there.
            rt.shutdown_background();
        }
    }
}

/// The key [`RecordingStore::answers`] asks the store for: no station is named so (a station's
/// recordings are under its own name), so the answer is "not found" from a working store.
pub const READINESS_KEY: &str = ".readyz";

/// The hub's recordings (see the module's documentation).
#[derive(Debug, Clone)]
pub struct RecordingStore {
    objects: Arc<dyn ObjectStore>,
    /// `DATA/recordings`: partial uploads; on [`Place::Local`] also the stored recordings.
    staging: PathBuf,
    place: Place,
    io: Option<Arc<IoRuntime>>,
}

/// A file the store holds for a station: a stored recording or a partial upload.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StoredFile {
    /// `<station>/<file>`.
    pub name: String,
    /// Its bytes.
    pub size: u64,
    source: Source,
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum Source {
    Disk(PathBuf),
    Object(Key),
}

fn store_error(what: String) -> impl FnOnce(object_store::Error) -> HubError {
    move |e| HubError::Io {
        context: format!("recording store: {what}"),
        source: std::io::Error::other(e),
    }
}

fn disk_error(what: &str, path: &Path) -> impl FnOnce(std::io::Error) -> HubError + use<> {
    HubError::io_at(what, path)
}

/// `dir` and its missing parents, each new one 0700 (health data).
fn create_private_dir(dir: &Path) -> Result<(), HubError> {
    use std::os::unix::fs::DirBuilderExt;
    std::fs::DirBuilder::new()
        .recursive(true)
        .mode(0o700)
        .create(dir)
        .map_err(disk_error("creating", dir))
}

impl RecordingStore {
    /// The embedded default: recordings under `dir` (`DATA/recordings`), made if missing.
    pub fn local(dir: impl Into<PathBuf>) -> Result<Self, HubError> {
        let staging = dir.into();
        create_private_dir(&staging)?;
        let objects = object_store::local::LocalFileSystem::new_with_prefix(&staging)
            .map_err(store_error(format!("opening {}", staging.display())))?;
        Ok(Self {
            objects: Arc::new(objects),
            staging,
            place: Place::Local,
            io: None,
        })
    }

    /// The store `hub.toml` configures for the clinic whose data directory is `data`: its
    /// `[recordings]` (an S3-compatible store), else the local directory. A bad or missing
    /// setting is an error naming it.
    pub fn open(data: &Path, config: Option<&RecordingsConfig>) -> Result<Self, HubError> {
        let staging = data.join("recordings");
        match config {
            None => Self::local(staging),
            Some(c) if c.is_local() => Self::local(staging),
            Some(c) => {
                create_private_dir(&staging)?;
                let (objects, url) = c.s3_store()?;
                let rt = tokio::runtime::Builder::new_multi_thread()
                    .worker_threads(1)
                    .thread_name("recording-store")
                    .enable_all()
                    .build()
                    .map_err(|e| HubError::io("starting the recording store's runtime", e))?;
                Ok(Self {
                    objects,
                    staging,
                    place: Place::S3 { url },
                    io: Some(Arc::new(IoRuntime(Some(rt)))),
                })
            }
        }
    }

    /// `DATA/recordings`: where partial uploads grow (and, on the local default, where the
    /// recordings are kept).
    pub fn staging_dir(&self) -> &Path {
        &self.staging
    }

    /// Where the upload of a session's recording grows, beside its `.part` files:
    /// `DATA/recordings/<station>/<session>.mcap` (the recording itself on the local default).
    pub fn staging_path(&self, station: &str, session: &str) -> PathBuf {
        self.staging.join(station).join(format!("{session}.mcap"))
    }

    fn key(station: &str, session: &str) -> Key {
        Key::from_iter([station, &format!("{session}.mcap")])
    }

    /// What the hub's records say of where a recording is: its path on the local default,
    /// `s3://bucket/prefix/<station>/<session>.mcap` on S3.
    pub fn location(&self, station: &str, session: &str) -> String {
        match &self.place {
            Place::Local => self.staging_path(station, session).display().to_string(),
            Place::S3 { url } => format!("{url}/{}", Self::key(station, session)),
        }
    }

    /// True when the recordings are kept in an S3-compatible store.
    pub fn is_s3(&self) -> bool {
        matches!(self.place, Place::S3 { .. })
    }

    /// Runs `work` on the store's own runtime (S3), or here (local).
    async fn run<T: Send + 'static>(
        &self,
        work: impl Future<Output = T> + Send + 'static,
    ) -> Result<T, HubError> {
        match &self.io {
            None => Ok(work.await),
            Some(io) => {
                let rt = io.0.as_ref().expect("taken only on drop");
                rt.spawn(work)
                    .await
                    .map_err(|e| HubError::io("recording store task", std::io::Error::other(e)))
            }
        }
    }

    /// Whether the store answers now, for the hub's readiness (`/readyz`): on S3 one `HEAD` of
    /// a key no recording has ([`READINESS_KEY`]; "not found" is an answer) within `within`;
    /// the local default always answers (its directory is checked for new files by the
    /// caller). The error names what went wrong, in the operator's words.
    pub async fn answers(&self, within: Duration) -> Result<(), String> {
        if !self.is_s3() {
            return Ok(());
        }
        let objects = Arc::clone(&self.objects);
        let head = self.run(async move { objects.head(&Key::from(READINESS_KEY)).await });
        match tokio::time::timeout(within, head).await {
            Err(_) => Err(format!(
                "the store gave no answer within {} ms",
                within.as_millis()
            )),
            Ok(Err(e)) => Err(e.to_string()),
            Ok(Ok(Ok(_) | Err(object_store::Error::NotFound { .. }))) => Ok(()),
            Ok(Ok(Err(e))) => Err(format!("the store answered with an error: {e}")),
        }
    }

    /// Keeps the verified upload `part` as the recording of `session`: on the local default
    /// a rename (same disk), on S3 one multipart upload (completed, or aborted on any error),
    /// after which `part` is removed. After an error nothing is stored and `part` is left for
    /// the next attempt.
    pub async fn keep(&self, station: &str, session: &str, part: &Path) -> Result<(), HubError> {
        if !self.is_s3() {
            let to = self.staging_path(station, session);
            return tokio::fs::rename(part, &to)
                .await
                .map_err(disk_error("renaming", part));
        }
        let key = Self::key(station, session);
        let (objects, from) = (Arc::clone(&self.objects), part.to_owned());
        self.run(put_file(objects, key, from)).await??;
        tokio::fs::remove_file(part)
            .await
            .map_err(disk_error("removing", part))
    }

    /// The size and SHA-256 of the recording of `session` if the store holds it (read as a
    /// stream, in bounded memory), `None` if not.
    pub async fn held(
        &self,
        station: &str,
        session: &str,
    ) -> Result<Option<(u64, String)>, HubError> {
        let (objects, key) = (Arc::clone(&self.objects), Self::key(station, session));
        self.run(async move {
            let what = format!("reading {key}");
            let got = match objects.get(&key).await {
                Ok(got) => got,
                Err(object_store::Error::NotFound { .. }) => return Ok(None),
                Err(e) => return Err(store_error(what)(e)),
            };
            let mut stream = got.into_stream();
            let (mut hasher, mut size) = (Sha256::new(), 0u64);
            while let Some(bytes) = stream.next().await {
                let bytes = bytes.map_err(store_error(what.clone()))?;
                size += bytes.len() as u64;
                hasher.update(&bytes);
            }
            Ok(Some((size, hub_store::db::hex(&hasher.finalize()))))
        })
        .await?
    }

    /// The size of the stored recording of `session`, `None` if the store holds none.
    pub async fn size(&self, station: &str, session: &str) -> Result<Option<u64>, HubError> {
        let (objects, key) = (Arc::clone(&self.objects), Self::key(station, session));
        self.run(async move {
            match objects.head(&key).await {
                Ok(meta) => Ok(Some(meta.size)),
                Err(object_store::Error::NotFound { .. }) => Ok(None),
                Err(e) => Err(store_error(format!("reading {key}"))(e)),
            }
        })
        .await?
    }

    /// A blocking reader of the stored recording of `session` (to be used off the async
    /// workers): the file itself on the local default, ranged reads of
    /// [`READ_BLOCK_BYTES`] on S3, so a replay holds one block whatever the recording's size.
    pub fn open_reader(&self, station: &str, session: &str) -> Result<Box<dyn ReadSeek>, HubError> {
        match &self.place {
            Place::Local => {
                let path = self.staging_path(station, session);
                let file = std::fs::File::open(&path).map_err(disk_error("reading", &path))?;
                Ok(Box::new(file))
            }
            Place::S3 { .. } => {
                let key = Self::key(station, session);
                let size = self
                    .blocking(head_size(Arc::clone(&self.objects), key.clone()))
                    .and_then(|r| r)?;
                Ok(Box::new(ObjectReader::new(self.clone(), key, size)))
            }
        }
    }

    /// Waits, blocking this thread, for `work` run on the store's runtime (S3 only).
    fn blocking<T: Send + 'static>(
        &self,
        work: impl Future<Output = T> + Send + 'static,
    ) -> Result<T, HubError> {
        let io = self.io.as_ref().expect("S3 stores have their runtime");
        let rt = io.0.as_ref().expect("taken only on drop");
        let (tx, rx) = std::sync::mpsc::sync_channel(1);
        rt.spawn(async move {
            let _ = tx.send(work.await);
        });
        rx.recv().map_err(|e| {
            HubError::io(
                "recording store task ended",
                std::io::Error::other(e.to_string()),
            )
        })
    }

    /// Every file held for `station`: its stored recordings and its partial uploads, sorted by
    /// name.
    pub async fn station_files(&self, station: &str) -> Result<Vec<StoredFile>, HubError> {
        let mut files = disk_files(&self.staging, station, true)?;
        if self.is_s3() {
            files.extend(self.objects_under(Some(station)).await?);
        }
        files.sort_by(|a, b| a.name.cmp(&b.name));
        Ok(files)
    }

    /// Every stored recording (partial uploads left out), sorted by name.
    pub async fn finished(&self) -> Result<Vec<StoredFile>, HubError> {
        let mut files = Vec::new();
        if self.is_s3() {
            files = self.objects_under(None).await?;
        } else {
            let stations = match std::fs::read_dir(&self.staging) {
                Ok(s) => s,
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(files),
                Err(e) => return Err(disk_error("listing", &self.staging)(e)),
            };
            for entry in stations {
                let entry = entry.map_err(disk_error("listing", &self.staging))?;
                if !entry.path().is_dir() {
                    continue;
                }
                let name = entry.file_name();
                let station = name.to_str().ok_or_else(|| {
                    HubError::Corrupt(format!("{} is not UTF-8", entry.path().display()))
                })?;
                files.extend(disk_files(&self.staging, station, false)?);
            }
        }
        files.sort_by(|a, b| a.name.cmp(&b.name));
        Ok(files)
    }

    async fn objects_under(&self, station: Option<&str>) -> Result<Vec<StoredFile>, HubError> {
        let objects = Arc::clone(&self.objects);
        let prefix = station.map(|s| Key::from_iter([s]));
        self.run(async move {
            let mut found = Vec::new();
            let mut list = objects.list(prefix.as_ref());
            while let Some(meta) = list.next().await {
                let meta = meta.map_err(store_error("listing recordings".into()))?;
                found.push(StoredFile {
                    name: meta.location.to_string(),
                    size: meta.size,
                    source: Source::Object(meta.location),
                });
            }
            Ok(found)
        })
        .await?
    }

    /// A blocking reader of `file` (one [`Self::station_files`] or [`Self::finished`] listed).
    pub fn read(&self, file: &StoredFile) -> Result<Box<dyn ReadSeek>, HubError> {
        match &file.source {
            Source::Disk(path) => Ok(Box::new(
                std::fs::File::open(path).map_err(disk_error("reading", path))?,
            )),
            Source::Object(key) => Ok(Box::new(ObjectReader::new(
                self.clone(),
                key.clone(),
                file.size,
            ))),
        }
    }

    /// Removes everything held for `station`: its objects in the store and its directory of
    /// partial uploads (the local default's recordings with it).
    pub async fn erase_station(&self, station: &str) -> Result<(), HubError> {
        if self.is_s3() {
            for file in self.objects_under(Some(station)).await? {
                let Source::Object(key) = file.source else {
                    continue;
                };
                let objects = Arc::clone(&self.objects);
                self.run(async move {
                    objects
                        .delete(&key)
                        .await
                        .map_err(store_error(format!("deleting {key}")))
                })
                .await??;
            }
        }
        let dir = self.staging.join(station);
        match tokio::fs::remove_dir_all(&dir).await {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                Err(disk_error("removing", &dir)(e))
            }
            _ => Ok(()),
        }
    }
}

/// A reader that also seeks (what a replay's survey needs), and can move between threads.
pub trait ReadSeek: Read + Seek + Send {}
impl<T: Read + Seek + Send> ReadSeek for T {}

/// The files of `DATA/recordings/<station>/` (with `.part` files when `partial`).
fn disk_files(staging: &Path, station: &str, partial: bool) -> Result<Vec<StoredFile>, HubError> {
    let dir = staging.join(station);
    let entries = match std::fs::read_dir(&dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(disk_error("listing", &dir)(e)),
    };
    let mut files = Vec::new();
    for entry in entries {
        let path = entry.map_err(disk_error("listing", &dir))?.path();
        let is_part = path.extension().is_some_and(|e| e == "part");
        if !path.is_file() || (is_part && !partial) {
            continue;
        }
        let file = path
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or_else(|| HubError::Corrupt(format!("{} is not UTF-8", path.display())))?;
        let size = std::fs::metadata(&path)
            .map_err(disk_error("reading", &path))?
            .len();
        files.push(StoredFile {
            name: format!("{station}/{file}"),
            size,
            source: Source::Disk(path),
        });
    }
    Ok(files)
}

async fn head_size(objects: Arc<dyn ObjectStore>, key: Key) -> Result<u64, HubError> {
    objects
        .head(&key)
        .await
        .map(|m| m.size)
        .map_err(store_error(format!("reading {key}")))
}

/// Streams the file `from` into the object `key` as one multipart upload: completed whole, or
/// aborted (nothing listed) on any error.
async fn put_file(objects: Arc<dyn ObjectStore>, key: Key, from: PathBuf) -> Result<(), HubError> {
    use tokio::io::AsyncReadExt;
    let what = format!("storing {key}");
    let mut file = tokio::fs::File::open(&from)
        .await
        .map_err(disk_error("reading", &from))?;
    let upload = objects
        .put_multipart(&key)
        .await
        .map_err(store_error(what.clone()))?;
    let mut writer = WriteMultipart::new_with_chunk_size(upload, PART_BYTES);
    let mut buf = vec![0u8; 1 << 20];
    let copied: Result<(), HubError> = async {
        loop {
            let n = file
                .read(&mut buf)
                .await
                .map_err(disk_error("reading", &from))?;
            if n == 0 {
                return Ok(());
            }
            writer
                .wait_for_capacity(PARTS_IN_FLIGHT)
                .await
                .map_err(store_error(what.clone()))?;
            writer.write(&buf[..n]);
        }
    }
    .await;
    match copied {
        Ok(()) => writer.finish().await.map(drop).map_err(store_error(what)),
        Err(e) => {
            if let Err(abort) = writer.abort().await {
                tracing::warn!(%key, "cannot abort an incomplete recording upload: {abort}");
            }
            Err(e)
        }
    }
}

/// A blocking, seekable reader of one S3 object by ranged reads of [`READ_BLOCK_BYTES`].
struct ObjectReader {
    store: RecordingStore,
    key: Key,
    size: u64,
    pos: u64,
    block: Block,
}

/// The block of the object a reader holds: its bytes and where they start.
#[derive(Debug, Default)]
struct Block {
    start: u64,
    bytes: Vec<u8>,
}

impl Block {
    /// The held bytes from `pos` on, if `pos` is inside the block.
    fn from(&self, pos: u64) -> Option<&[u8]> {
        let off = usize::try_from(pos.checked_sub(self.start)?).ok()?;
        (off < self.bytes.len()).then(|| &self.bytes[off..])
    }
}

impl ObjectReader {
    fn new(store: RecordingStore, key: Key, size: u64) -> Self {
        Self {
            store,
            key,
            size,
            pos: 0,
            block: Block::default(),
        }
    }

    fn fetch(&mut self) -> std::io::Result<()> {
        let end = self.size.min(self.pos.saturating_add(READ_BLOCK_BYTES));
        let (objects, key, start) = (Arc::clone(&self.store.objects), self.key.clone(), self.pos);
        let got = self
            .store
            .blocking(async move { objects.get_range(&key, start..end).await })
            .map_err(std::io::Error::other)?
            .map_err(std::io::Error::other)?;
        self.block = Block {
            start,
            bytes: got.to_vec(),
        };
        Ok(())
    }
}

impl Read for ObjectReader {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.pos >= self.size || buf.is_empty() {
            return Ok(0);
        }
        if self.block.from(self.pos).is_none() {
            self.fetch()?;
        }
        let held = self.block.from(self.pos).unwrap_or(&[]);
        let n = held.len().min(buf.len());
        buf[..n].copy_from_slice(&held[..n]);
        self.pos += n as u64;
        Ok(n)
    }
}

impl Seek for ObjectReader {
    fn seek(&mut self, to: SeekFrom) -> std::io::Result<u64> {
        let pos = match to {
            SeekFrom::Start(p) => Some(p),
            SeekFrom::End(d) => self.size.checked_add_signed(d),
            SeekFrom::Current(d) => self.pos.checked_add_signed(d),
        };
        self.pos = pos.ok_or_else(|| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "seek before the recording's start",
            )
        })?;
        Ok(self.pos)
    }
}

/// The request deadlines and retries of an S3 store, from `hub.toml` (documented defaults).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StoreTimeouts {
    /// Retries of a failed request (5xx, timeouts, connection errors).
    pub max_retries: usize,
    /// No retry starts later than this after the first attempt, s.
    pub retry_timeout_s: u64,
    /// One request's deadline, s.
    pub request_timeout_s: u64,
    /// Connecting's deadline, s.
    pub connect_timeout_s: u64,
}

impl Default for StoreTimeouts {
    fn default() -> Self {
        Self {
            max_retries: 3,
            retry_timeout_s: 30,
            request_timeout_s: 60,
            connect_timeout_s: 5,
        }
    }
}

impl StoreTimeouts {
    fn retry(&self) -> object_store::RetryConfig {
        object_store::RetryConfig {
            backoff: object_store::BackoffConfig::default(),
            max_retries: self.max_retries,
            retry_timeout: Duration::from_secs(self.retry_timeout_s),
        }
    }
}
