//! The hub's side of a recording upload (see `UploadStart` in [`crate::frame`]): the file grows
//! as `<session>.<sha256 prefix>.part` on the receiving hub's disk (beside
//! [`super::HubStore::recording_path`]), resumes from its length on the next connection to the
//! same hub, and is handed to the store ([`super::HubStore::keep_recording`]: a rename, or a
//! copy into object storage) only when its SHA-256 is the one announced. A station that
//! reconnects to another hub starts there from byte 0; the recording is still stored once, under
//! one name, whichever hub completes it.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use base64::Engine;
use tokio::io::AsyncWriteExt;

use crate::frame::{Hello, UploadAt, UploadChunk, UploadStart};

use super::session::Failure;
use super::{Hub, station_limits};

/// One connection's upload in progress.
#[derive(Debug)]
pub(super) struct Upload {
    path: PathBuf,
    part: PathBuf,
    size: u64,
    sha256: String,
    offset: u64,
    file: tokio::fs::File,
    /// Whether a chunk of this upload has been counted against the day's bytes yet (the first
    /// one reads the shared count afresh: another hub may have taken bytes since).
    counted: bool,
    /// When its progress was last told to the store.
    noted_at: Instant,
}

/// How often the bytes a station uploaded here are added to the store's shared count while
/// it uploads (and at the end of each recording): a restarted hub loses at most this much of
/// the count, and a station spreading one day over several hubs passes the cap by at most what
/// it sends to each in this time after its last re-read.
const NOTE_DAILY_BYTES_EVERY: Duration = Duration::from_secs(1);

/// How often an upload's progress is told to the store
/// ([`super::HubStore::recording_progress`]) while chunks arrive: one small write per uploading
/// station every 5 s (a thousand stations uploading at once: 200 a second), never one per chunk.
pub const RECORDING_PROGRESS_EVERY: Duration = Duration::from_secs(5);

/// The bytes each station has uploaded today (UTC days by the store's clock), against
/// [`super::TherapistConfig::max_upload_bytes_per_station_day`]. The count is the store's,
/// shared by every hub on it: read when a station first uploads on a day and at the start of
/// each recording, and grown by adding this hub's bytes to it (never by writing this hub's
/// total over it, which would let a station alternating between hubs take the cap on each).
#[derive(Debug, Default)]
pub(super) struct DailyBytes(Mutex<HashMap<String, DayCount>>);

#[derive(Debug)]
struct DayCount {
    day: u64,
    /// The day's bytes as this hub knows them: the store's count at the last read or add,
    /// plus `pending`.
    bytes: u64,
    /// Bytes taken here and not yet added to the store's count.
    pending: u64,
    noted_at: Option<Instant>,
}

impl DailyBytes {
    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<String, DayCount>> {
        self.0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Counts `n` more bytes for `station` today, refused if that would pass `limit`; the
    /// store's count is read afresh when `refresh` (a recording's first chunk here) or on a new
    /// day, and this hub's bytes are added to it at most every [`NOTE_DAILY_BYTES_EVERY`], and
    /// at a recording's `last` chunk.
    async fn add(
        &self,
        hub: &Hub,
        station: &str,
        n: u64,
        limit: u64,
        (refresh, last): (bool, bool),
    ) -> Result<(), Failure> {
        let day = hub.store.now_ms() / 86_400_000;
        let fresh = |day| DayCount {
            day,
            bytes: 0,
            pending: 0,
            noted_at: None,
        };
        let known = self.lock().get(station).is_some_and(|c| c.day == day);
        if refresh || !known {
            let stored = hub.store.upload_bytes_on(station, day).await.map_err(|e| {
                Failure::Unavailable(format!("cannot read the day's upload count: {e}"))
            })?;
            let mut map = self.lock();
            map.retain(|_, c| c.day == day);
            let count = map.entry(station.to_owned()).or_insert_with(|| fresh(day));
            count.bytes = count.bytes.max(stored.saturating_add(count.pending));
        }
        let due = {
            let mut map = self.lock();
            let count = map.entry(station.to_owned()).or_insert_with(|| fresh(day));
            let total = count.bytes.saturating_add(n);
            if total > limit {
                return Err(Failure::Refused(
                    "upload_daily_bytes",
                    format!(
                        "station {station:?} has uploaded {} MB today, the most this hub takes \
                         from one station a day (max_upload_bytes_per_station_day = {} MB); the \
                         rest is taken tomorrow",
                        count.bytes >> 20,
                        limit >> 20
                    ),
                ));
            }
            count.bytes = total;
            count.pending = count.pending.saturating_add(n);
            let due = last
                || count
                    .noted_at
                    .is_none_or(|t| t.elapsed() >= NOTE_DAILY_BYTES_EVERY);
            if due {
                count.noted_at = Some(Instant::now());
            }
            due.then(|| std::mem::take(&mut count.pending))
        };
        if let Some(delta) = due {
            match hub.store.add_upload_bytes(station, day, delta).await {
                Ok(Some(shared)) => {
                    if let Some(count) = self.lock().get_mut(station).filter(|c| c.day == day) {
                        count.bytes = count.bytes.max(shared.saturating_add(count.pending));
                    }
                }
                Ok(None) => {}
                Err(e) => {
                    // Added again with the next note: the shared count is late, not short.
                    if let Some(count) = self.lock().get_mut(station).filter(|c| c.day == day) {
                        count.pending = count.pending.saturating_add(delta);
                    }
                    tracing::warn!(station, error = %e, "therapist hub: cannot add to the day's upload count");
                }
            }
        }
        Ok(())
    }
}

/// Removes `.part` files of the station's directory `dir` other than `keep`: those not written
/// for [`station_limits::STALE_PART_S`], then the oldest until the rest and `incoming` bytes fit in `limit`
/// (a station uploads one recording at a time; the others restart from their beginning).
async fn bound_station_parts(
    dir: &std::path::Path,
    keep: &std::path::Path,
    incoming: u64,
    limit: u64,
) {
    let Ok(mut entries) = tokio::fs::read_dir(dir).await else {
        return;
    };
    let mut parts = Vec::new();
    while let Ok(Some(entry)) = entries.next_entry().await {
        let p = entry.path();
        if p == keep || p.extension().is_none_or(|e| e != "part") {
            continue;
        }
        let Ok(meta) = entry.metadata().await else {
            continue;
        };
        let age = meta
            .modified()
            .ok()
            .and_then(|m| m.elapsed().ok())
            .unwrap_or_default();
        if age.as_secs() >= station_limits::STALE_PART_S {
            let _ = tokio::fs::remove_file(&p).await;
        } else {
            parts.push((age, meta.len(), p));
        }
    }
    // Oldest (longest unwritten) first.
    parts.sort_by_key(|p| std::cmp::Reverse(p.0));
    let mut total: u64 = parts
        .iter()
        .map(|(_, len, _)| len)
        .sum::<u64>()
        .saturating_add(incoming);
    for (_, len, p) in parts {
        if total <= limit {
            break;
        }
        if tokio::fs::remove_file(&p).await.is_ok() {
            total = total.saturating_sub(len);
        }
    }
}

fn closed(what: &str, path: &std::path::Path, e: std::io::Error) -> Failure {
    Failure::Closed(format!("recording {what} {}: {e}", path.display()))
}

/// Lowercase hex SHA-256 of a file, read in a stream (off the reactor).
pub(crate) async fn file_sha256(path: PathBuf) -> std::io::Result<(u64, String)> {
    tokio::task::spawn_blocking(move || crate::upload::file_sha256(&path))
        .await
        .map_err(std::io::Error::other)?
}

fn at(hello: &Hello, offset: u64, complete: bool) -> UploadAt {
    UploadAt {
        session_id: hello.session_id.clone(),
        offset,
        complete,
    }
}

/// Removes partial copies of other versions of this session's recording: a station (or a
/// broken one) announcing a new SHA-256 each time must not fill the hub's disk with parts.
async fn remove_other_parts(path: &std::path::Path, keep: &std::path::Path) {
    let (Some(dir), Some(stem)) = (path.parent(), path.file_stem().and_then(|s| s.to_str())) else {
        return;
    };
    let Ok(mut entries) = tokio::fs::read_dir(dir).await else {
        return;
    };
    let prefix = format!("{stem}.");
    while let Ok(Some(entry)) = entries.next_entry().await {
        let p = entry.path();
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if p != keep && name.starts_with(&prefix) && name.ends_with(".part") {
            let _ = tokio::fs::remove_file(&p).await;
        }
    }
}

/// Opens (or resumes) the upload `start` announces; the reply says where to resume.
pub(super) async fn start(
    hub: &Hub,
    hello: &Hello,
    start: UploadStart,
) -> Result<(Option<Upload>, UploadAt), Failure> {
    if start.session_id != hello.session_id {
        return Err(Failure::Protocol(format!(
            "upload for session {:?} on a connection for session {:?}",
            start.session_id, hello.session_id
        )));
    }
    pace_upload_start(hub, hello).await?;
    let limit = hub.config.max_upload_bytes_per_session;
    if start.size_bytes > limit {
        return Err(Failure::Protocol(format!(
            "the recording is {} MB, more than the {} MB this hub takes for one session \
             (max_upload_bytes_per_session); it stays on the station",
            start.size_bytes >> 20,
            limit >> 20
        )));
    }
    let path = hub
        .store
        .recording_path(hello)
        .ok_or_else(|| Failure::Protocol("this hub does not take recordings".into()))?;
    if let Some(dir) = path.parent() {
        // Health data: directories 0700, files 0600.
        let mut builder = tokio::fs::DirBuilder::new();
        builder.recursive(true);
        #[cfg(unix)]
        builder.mode(0o700);
        builder
            .create(dir)
            .await
            .map_err(|e| closed("directory", dir, e))?;
    }
    let held = hub.store.recording_held(hello, &path).await.map_err(|e| {
        Failure::Unavailable(format!(
            "cannot tell whether the recording of session {:?} is stored ({e}); upload it \
             again later",
            hello.session_id
        ))
    })?;
    if let Some((size, sha)) = held {
        if sha == start.sha256 && size == start.size_bytes {
            // Held already; recorded again if recording it failed before.
            recorded(hub, hello, &sha, size, &path).await?;
            return Ok((None, at(hello, size, true)));
        }
        return Err(Failure::Protocol(format!(
            "a different recording of session {:?} is already stored",
            hello.session_id
        )));
    }
    let part = path.with_extension(format!("{}.part", &start.sha256[..16]));
    remove_other_parts(&path, &part).await;
    if let Some(dir) = path.parent() {
        bound_station_parts(dir, &part, start.size_bytes, limit).await;
    }
    let mut options = tokio::fs::OpenOptions::new();
    options.create(true).append(true);
    #[cfg(unix)]
    options.mode(0o600);
    let file = options
        .open(&part)
        .await
        .map_err(|e| closed("file", &part, e))?;
    let mut offset = file
        .metadata()
        .await
        .map_err(|e| closed("file", &part, e))?
        .len();
    if offset > start.size_bytes {
        file.set_len(0)
            .await
            .map_err(|e| closed("file", &part, e))?;
        offset = 0;
    }
    let mut upload = Upload {
        path,
        part,
        size: start.size_bytes,
        sha256: start.sha256,
        offset,
        file,
        counted: false,
        noted_at: Instant::now(),
    };
    if offset == upload.size {
        // Whole already: an earlier attempt could not keep it (its store failed). Kept now,
        // without the station sending it again.
        return Ok((None, finish(hub, hello, upload).await?));
    }
    progress(hub, hello, &mut upload).await;
    Ok((Some(upload), at(hello, offset, false)))
}

/// Appends a chunk; at the end verifies the file and stores it. The reply says what the hub
/// holds now (a chunk at another offset is not written: the reply resynchronises).
pub(super) async fn chunk(
    hub: &Hub,
    hello: &Hello,
    upload: &mut Option<Upload>,
    chunk: UploadChunk,
) -> Result<UploadAt, Failure> {
    let Some(up) = upload.as_mut() else {
        return Err(Failure::Protocol("UploadChunk before UploadStart".into()));
    };
    if chunk.offset != up.offset {
        return Ok(at(hello, up.offset, false));
    }
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(chunk.data.as_bytes())
        .map_err(|e| Failure::Protocol(format!("upload chunk is not base64: {e}")))?;
    let end = up.offset.saturating_add(bytes.len() as u64);
    if end > up.size {
        return Err(Failure::Protocol(format!(
            "upload chunk ends at byte {end}, past the announced size {}",
            up.size
        )));
    }
    pace_upload(hub, hello, bytes.len() as u64).await?;
    let daily = hub.config.max_upload_bytes_per_station_day;
    let refresh = !std::mem::replace(&mut up.counted, true);
    hub.daily_upload_bytes
        .add(
            hub,
            &hello.station_id,
            bytes.len() as u64,
            daily,
            (refresh, end == up.size),
        )
        .await?;
    up.file
        .write_all(&bytes)
        .await
        .map_err(|e| closed("write to", &up.part, e))?;
    up.offset = end;
    if end < up.size {
        if up.noted_at.elapsed() >= RECORDING_PROGRESS_EVERY {
            progress(hub, hello, up).await;
        }
        return Ok(at(hello, end, false));
    }
    let up = upload.take().expect("checked above");
    finish(hub, hello, up).await
}

/// Holds a chunk of `n` bytes back until its station's upload pace
/// ([`super::TherapistConfig::max_upload_bytes_per_s`], over all the station's connections)
/// lets it through (the station sends its next chunk only after the answer); refused if that
/// would take more than [`station_limits::MAX_UPLOAD_WAIT`].
async fn pace_upload(hub: &Hub, hello: &Hello, n: u64) -> Result<(), Failure> {
    let rate = hub.config.max_upload_bytes_per_s as f64;
    // One chunk may come at once.
    let burst = crate::frame::MAX_CHUNK_BYTES as f64;
    let taken = hub
        .upload_pace
        .take(
            &hello.station_id,
            n as f64,
            rate,
            burst,
            station_limits::MAX_UPLOAD_WAIT,
        )
        .await;
    if taken {
        return Ok(());
    }
    Err(Failure::Refused(
        "upload_rate",
        format!(
            "station {:?} uploads on too many connections at once: this hub takes {} KB/s from \
             one station (max_upload_bytes_per_s); upload one recording at a time",
            hello.station_id,
            hub.config.max_upload_bytes_per_s / 1000
        ),
    ))
}

/// Holds an upload announcement back until its station's pace
/// ([`station_limits::UPLOAD_START_PACE_PER_S`] after [`station_limits::UPLOAD_START_BURST`],
/// over all the station's connections) lets it through; refused if that would take more than
/// [`station_limits::MAX_UPLOAD_WAIT`]. Each announcement costs a store lookup and a database
/// note, so a station repeating them cannot make the hub do either faster than this.
async fn pace_upload_start(hub: &Hub, hello: &Hello) -> Result<(), Failure> {
    use station_limits::{MAX_UPLOAD_WAIT, UPLOAD_START_BURST, UPLOAD_START_PACE_PER_S};
    let taken = hub
        .upload_start_pace
        .take(
            &hello.station_id,
            1.0,
            UPLOAD_START_PACE_PER_S,
            UPLOAD_START_BURST,
            MAX_UPLOAD_WAIT,
        )
        .await;
    if taken {
        return Ok(());
    }
    Err(Failure::Refused(
        "upload_start_rate",
        format!(
            "station {:?} announces uploads faster than a station uploads: at most \
             {UPLOAD_START_PACE_PER_S} a second are taken from one station over all its \
             connections; upload one recording at a time",
            hello.station_id
        ),
    ))
}

/// Tells the store how much of `up` this hub holds ([`super::HubStore::recording_progress`]);
/// a store that cannot note it is logged, and the upload goes on.
async fn progress(hub: &Hub, hello: &Hello, up: &mut Upload) {
    up.noted_at = Instant::now();
    if let Err(e) = hub
        .store
        .recording_progress(hello, &up.sha256, up.size, up.offset)
        .await
    {
        tracing::warn!(
            session = %hello.session_id,
            received_bytes = up.offset,
            error = %e,
            "an upload's progress was not noted; the upload goes on"
        );
    }
}

async fn finish(hub: &Hub, hello: &Hello, mut up: Upload) -> Result<UploadAt, Failure> {
    up.file
        .flush()
        .await
        .and(up.file.sync_all().await)
        .map_err(|e| closed("sync of", &up.part, e))?;
    let (size, sha) = file_sha256(up.part.clone())
        .await
        .map_err(|e| closed("check of", &up.part, e))?;
    if sha != up.sha256 || size != up.size {
        let _ = tokio::fs::remove_file(&up.part).await;
        return Err(Failure::Protocol(format!(
            "the recording's SHA-256 is {sha}, not the announced {}: discarded, upload again",
            up.sha256
        )));
    }
    // The verified part stays until the store holds the recording whole: a store that fails
    // (after its own bounded retries) leaves it for the station's next attempt.
    hub.store
        .keep_recording(hello, &up.part, &up.path)
        .await
        .map_err(|e| {
            Failure::Unavailable(format!(
                "recording of session {:?} received whole but not stored ({e}); upload it \
                 again later",
                hello.session_id
            ))
        })?;
    recorded(hub, hello, &up.sha256, up.size, &up.path).await?;
    Ok(at(hello, size, true))
}

/// Has the store record a verified recording; the station is told `complete` only after.
async fn recorded(
    hub: &Hub,
    hello: &Hello,
    sha256: &str,
    size: u64,
    path: &std::path::Path,
) -> Result<(), Failure> {
    hub.store
        .recording_stored(hello, sha256, size, path)
        .await
        .map_err(|e| {
            Failure::Unavailable(format!(
                "recording of session {:?} kept but not recorded ({e}); upload it again",
                hello.session_id
            ))
        })
}
