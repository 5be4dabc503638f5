//! Recordings waiting to go to the clinic's hub (`HOME/uploads/<session>.json`): a paired
//! station queues its session's recording at the end of the session and uploads it right away
//! for a while (bandwidth-capped); what is not done resumes at the next run or `telerehab sync`
//! (the hub keeps the bytes it has and verifies the whole file's SHA-256).

use crate::home::private_dir;
use anyhow::Context;
use netlink::{ClientTls, Hello};
use serde::{Deserialize, Serialize};
use session::files::write_private;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The upload's bandwidth cap, bytes/s (a home uplink is often 10–20 Mbit/s; this leaves room
/// for the live link and the family's video call).
pub const UPLOAD_BYTES_PER_S: u64 = 1_000_000;

/// One recording to upload.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PendingUpload {
    /// The session's Hello (the upload goes on a connection of that session).
    pub hello: Hello,
    /// The MCAP file.
    pub path: PathBuf,
}

/// Queues `path`, the recording of `hello`'s session.
pub fn enqueue(dir: &Path, hello: &Hello, path: &Path) -> anyhow::Result<()> {
    private_dir(dir)?;
    let pending = PendingUpload {
        hello: hello.clone(),
        path: std::fs::canonicalize(path).unwrap_or_else(|_| path.to_owned()),
    };
    let json = serde_json::to_vec_pretty(&pending).context("cannot encode an upload")?;
    write_private(&dir.join(format!("{}.json", hello.session_id)), &json)
}

/// What uploading did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct UploadReport {
    /// Recordings now stored at the hub (their queue entries removed).
    pub uploaded: usize,
    /// Recordings still queued.
    pub remaining: usize,
    /// Bytes sent.
    pub sent_bytes: u64,
    /// The last error, if a recording stays.
    pub last_error: Option<String>,
    /// What the hub pushed on the uploads' connections (the therapist's messages, the newest
    /// regimen): the caller keeps them as its live link's.
    pub pushed: netlink::upload::Pushed,
}

/// Uploads every queued recording to `address` until `within` has passed; a recording whose
/// file is gone is dropped from the queue (with a warning). The therapist's messages and
/// regimen the hub pushes on the way are in the report's `pushed`.
pub async fn upload_all(
    dir: &Path,
    address: &str,
    tls: Option<&ClientTls>,
    bytes_per_s: u64,
    within: Duration,
) -> UploadReport {
    let mut report = UploadReport::default();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return report;
    };
    let mut queued: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    queued.sort();
    let deadline = Instant::now() + within;
    for entry in queued {
        let pending: PendingUpload = match std::fs::read(&entry)
            .map_err(anyhow::Error::from)
            .and_then(|b| serde_json::from_slice(&b).map_err(anyhow::Error::from))
        {
            Ok(p) => p,
            Err(e) => {
                tracing::warn!(path = %entry.display(), "unreadable upload entry: {e}");
                report.remaining += 1;
                continue;
            }
        };
        if !pending.path.exists() {
            tracing::warn!(path = %pending.path.display(), "queued recording is gone; dropped");
            let _ = std::fs::remove_file(&entry);
            continue;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        let mut pushed = netlink::upload::Pushed::default();
        let attempt = netlink::upload::upload_recording_keeping(
            address,
            tls,
            pending.hello.clone(),
            &pending.path,
            bytes_per_s,
            &mut pushed,
        );
        let outcome = tokio::time::timeout(left, attempt).await;
        report.pushed.append(pushed);
        match outcome {
            Ok(Ok(done)) => {
                report.uploaded += 1;
                report.sent_bytes += done.sent_bytes;
                let _ = std::fs::remove_file(&entry);
            }
            Ok(Err(e)) => {
                report.remaining += 1;
                report.last_error = Some(e.to_string());
            }
            Err(_) => {
                report.remaining += 1;
                report.last_error = Some("time up; it resumes where it stopped".into());
            }
        }
    }
    report
}

impl UploadReport {
    /// One line for the session report or `sync`.
    pub fn describe(&self) -> String {
        let mut s = format!(
            "{} uploaded ({:.2} MB sent), {} still queued",
            self.uploaded,
            self.sent_bytes as f64 / 1e6,
            self.remaining
        );
        if let Some(e) = &self.last_error {
            s.push_str(&format!(" ({e})"));
        }
        s
    }
}
