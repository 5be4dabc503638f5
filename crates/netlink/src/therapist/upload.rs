//! The hub's side of a recording upload (see `UploadStart` in [`crate::frame`]): the file grows
//! as `<session>.<sha256 prefix>.part` beside where the store keeps recordings, resumes from
//! its length on the next connection, and becomes `<session>.mcap` only when its SHA-256 is the
//! one announced.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use base64::Engine;
use tokio::io::AsyncWriteExt;

use crate::frame::{Hello, UploadAt, UploadChunk, UploadStart};

use super::Hub;
use super::session::Failure;

/// One connection's upload in progress.
#[derive(Debug)]
pub(super) struct Upload {
    path: PathBuf,
    part: PathBuf,
    size: u64,
    sha256: String,
    offset: u64,
    file: tokio::fs::File,
    /// When this connection's upload began, and the bytes it has written since (the hub's
    /// rate limit paces on them).
    began: Instant,
    written: u64,
}

/// Longest a chunk's answer is held back by the rate limit, s (a station's reply timeout is
/// far longer).
const MAX_PACING_WAIT: Duration = Duration::from_secs(5);

/// The bytes each station has uploaded today (UTC days), against
/// [`super::TherapistConfig::max_upload_bytes_per_station_day`]. Kept in memory: a restarted
/// hub starts the day's count again (the per-session cap and the rate still hold).
#[derive(Debug, Default)]
pub(super) struct DailyBytes(Mutex<HashMap<String, (u64, u64)>>);

impl DailyBytes {
    /// Counts `n` more bytes for `station` today; `Err(total)` if that would pass `limit`.
    fn add(&self, station: &str, n: u64, limit: u64) -> Result<(), u64> {
        let day = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs() / 86_400);
        let mut map = self
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        map.retain(|_, (d, _)| *d == day);
        let entry = map.entry(station.to_owned()).or_insert((day, 0));
        let total = entry.1.saturating_add(n);
        if total > limit {
            return Err(entry.1);
        }
        entry.1 = total;
        Ok(())
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
        tokio::fs::DirBuilder::new()
            .recursive(true)
            .mode(0o700)
            .create(dir)
            .await
            .map_err(|e| closed("directory", dir, e))?;
    }
    if tokio::fs::try_exists(&path).await.unwrap_or(false) {
        let (size, sha) = file_sha256(path.clone())
            .await
            .map_err(|e| closed("check of", &path, e))?;
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
    let file = tokio::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .mode(0o600)
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
    let upload = Upload {
        path,
        part,
        size: start.size_bytes,
        sha256: start.sha256,
        offset,
        file,
        began: Instant::now(),
        written: 0,
    };
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
    let daily = hub.config.max_upload_bytes_per_station_day;
    if let Err(today) = hub
        .daily_upload_bytes
        .add(&hello.station_id, bytes.len() as u64, daily)
    {
        return Err(Failure::Protocol(format!(
            "station {:?} has uploaded {} MB today, the most this hub takes from one station a \
             day (max_upload_bytes_per_station_day = {} MB); the rest is taken tomorrow",
            hello.station_id,
            today >> 20,
            daily >> 20
        )));
    }
    up.file
        .write_all(&bytes)
        .await
        .map_err(|e| closed("write to", &up.part, e))?;
    up.offset = end;
    up.written += bytes.len() as u64;
    pace(up.began, up.written, hub.config.max_upload_bytes_per_s).await;
    if end < up.size {
        return Ok(at(hello, end, false));
    }
    let up = upload.take().expect("checked above");
    finish(hub, hello, up).await
}

/// Holds the answer back until `written` bytes since `began` are within `bytes_per_s` (the
/// station sends its next chunk only after the answer, so this is the hub's own rate limit).
async fn pace(began: Instant, written: u64, bytes_per_s: u64) {
    let due = Duration::from_secs_f64(written as f64 / bytes_per_s.max(1) as f64);
    if let Some(wait) = due.checked_sub(began.elapsed()) {
        tokio::time::sleep(wait.min(MAX_PACING_WAIT)).await;
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
    tokio::fs::rename(&up.part, &up.path)
        .await
        .map_err(|e| closed("rename of", &up.part, e))?;
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
