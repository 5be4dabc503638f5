//! The station's on-disk queue of summaries: every summary is appended to
//! `queue/<session_id>.jsonl` (with `queue/<session_id>.hello.json`) before the link sends it,
//! so a session's summaries survive the station's own crash as well as a dropped link. A
//! session's files are removed once the hub has acknowledged everything; what remains is
//! delivered at the next run or by `telerehab sync` (the hub stores each summary once).

use crate::home::{private_dir, write_private};
use anyhow::Context;
use netlink::{ClientTls, Hello, StationLink, StationLinkConfig, Summary};
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Write};
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// One session's queue file, open for appending.
#[derive(Debug)]
pub struct QueueFile {
    summaries: PathBuf,
    hello: PathBuf,
    file: File,
    /// The first write error, after which the queue stops (the link still sends).
    pub error: Option<String>,
}

fn paths(dir: &Path, session_id: &str) -> (PathBuf, PathBuf) {
    (
        dir.join(format!("{session_id}.jsonl")),
        dir.join(format!("{session_id}.hello.json")),
    )
}

impl QueueFile {
    /// Starts the queue of the session `hello` opens, in `dir` (0700; files 0600).
    pub fn create(dir: &Path, hello: &Hello) -> anyhow::Result<Self> {
        private_dir(dir)?;
        let (summaries, hello_path) = paths(dir, &hello.session_id);
        let json = serde_json::to_vec(hello).context("cannot encode the session's Hello")?;
        write_private(&hello_path, &json)?;
        let file = OpenOptions::new()
            .append(true)
            .create(true)
            .mode(0o600)
            .open(&summaries)
            .with_context(|| format!("cannot create {}", summaries.display()))?;
        Ok(Self {
            summaries,
            hello: hello_path,
            file,
            error: None,
        })
    }

    /// Appends one summary as a line, handed to the OS at once (survives a station crash).
    pub fn push(&mut self, summary: &Summary) {
        if self.error.is_some() {
            return;
        }
        let mut line = match serde_json::to_vec(summary) {
            Ok(l) => l,
            Err(e) => {
                self.error = Some(format!("cannot encode summary {}: {e}", summary.seq));
                return;
            }
        };
        line.push(b'\n');
        if let Err(e) = self.file.write_all(&line) {
            self.error = Some(format!("{}: {e}", self.summaries.display()));
        }
    }

    /// Removes the session's files: the hub has everything.
    pub fn delivered(self) {
        for p in [&self.summaries, &self.hello] {
            if let Err(e) = std::fs::remove_file(p) {
                tracing::warn!(path = %p.display(), "cannot remove a delivered queue file: {e}");
            }
        }
    }
}

/// A session waiting in the queue.
#[derive(Debug, Clone, PartialEq)]
pub struct Queued {
    /// Its Hello.
    pub hello: Hello,
    /// Its summaries, in order (a partial last line, from a crash mid-write, is left out).
    pub summaries: Vec<Summary>,
}

/// The sessions waiting in `dir`, oldest first (by session id).
pub fn pending(dir: &Path) -> anyhow::Result<Vec<Queued>> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e).with_context(|| format!("cannot read {}", dir.display())),
    };
    let mut hellos: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.to_string_lossy().ends_with(".hello.json"))
        .collect();
    hellos.sort();
    let mut out = Vec::with_capacity(hellos.len());
    for hello_path in hellos {
        let text = std::fs::read(&hello_path)
            .with_context(|| format!("cannot read {}", hello_path.display()))?;
        let hello: Hello = serde_json::from_slice(&text)
            .with_context(|| format!("{} is not a session's Hello", hello_path.display()))?;
        let (summaries_path, _) = paths(dir, &hello.session_id);
        let mut summaries = Vec::new();
        if let Ok(f) = File::open(&summaries_path) {
            for line in BufReader::new(f).lines() {
                let Ok(line) = line else { break };
                // A partial last line (crash mid-write) does not parse: it was never sent.
                match serde_json::from_str::<Summary>(&line) {
                    Ok(s) => summaries.push(s),
                    Err(_) => break,
                }
            }
        }
        out.push(Queued { hello, summaries });
    }
    Ok(out)
}

/// What delivering the queue did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SyncReport {
    /// Sessions found in the queue.
    pub sessions: usize,
    /// Sessions now wholly acknowledged (their files removed).
    pub delivered: usize,
    /// Summaries still waiting.
    pub remaining: u64,
    /// The last error, if any session stays.
    pub last_error: Option<String>,
}

/// Sends every queued session to `address` (each within `timeout`), removing what the hub has
/// acknowledged. Sessions go as their own Hello said; the hub keeps each summary once.
pub async fn deliver(
    dir: &Path,
    address: &str,
    tls: Option<ClientTls>,
    timeout: Duration,
) -> anyhow::Result<SyncReport> {
    deliver_sessions(pending(dir)?, dir, address, tls, timeout).await
}

/// As [`deliver`], for the sessions `queued` (read from `dir` before a new session's queue
/// file was created there, so a running session is never taken for a queued one).
pub async fn deliver_sessions(
    queued: Vec<Queued>,
    dir: &Path,
    address: &str,
    tls: Option<ClientTls>,
    timeout: Duration,
) -> anyhow::Result<SyncReport> {
    let mut report = SyncReport {
        sessions: queued.len(),
        ..SyncReport::default()
    };
    let handle = tokio::runtime::Handle::current();
    for q in queued {
        let n = q.summaries.len() as u64;
        let session_id = q.hello.session_id.clone();
        let config = StationLinkConfig::new(address, tls.clone(), q.hello);
        let (sender, link) = StationLink::spawn(&handle, config)
            .with_context(|| format!("queued session {session_id}"))?;
        for s in q.summaries {
            if let Err(e) = sender.send(s) {
                tracing::warn!(session = %session_id, "queued summary not sent: {e}");
            }
        }
        let stats = link.finish(timeout).await;
        // The hub's Bye answer says it has synced everything it acknowledged.
        if stats.pending == 0 && stats.bye_acknowledged {
            let (a, b) = paths(dir, &session_id);
            let _ = std::fs::remove_file(a);
            let _ = std::fs::remove_file(b);
            report.delivered += 1;
        } else {
            report.remaining += if stats.pending > 0 { stats.pending } else { n };
            report.last_error = stats.last_error.or(report.last_error);
        }
    }
    Ok(report)
}
