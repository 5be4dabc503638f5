//! The station's on-disk queue of summaries: every summary is appended to
//! `queue/<session_id>.jsonl` (with `queue/<session_id>.hello.json`) before the link sends it,
//! so a session's summaries survive the station's own crash as well as a dropped link; the
//! session's movement measures, computed at its end, wait in `queue/<session_id>.measures.json`
//! and go in its `Bye`, as does why it ended (`queue/<session_id>.end.txt`; a session without
//! one ended with the station, and its `Bye` says so). A session's files are removed once the hub has acknowledged everything
//! and confirmed the `Bye`; what remains is delivered at the next run or by `telerehab sync`
//! (the hub stores each summary once).

use crate::home::private_dir;
use anyhow::Context;
use netlink::{ClientTls, Hello, StationLink, StationLinkConfig, Summary};
use session::files::write_private;
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// One session's queue file, open for appending.
#[derive(Debug)]
pub struct QueueFile {
    dir: PathBuf,
    session_id: String,
    summaries: PathBuf,
    measures: PathBuf,
    end: PathBuf,
    file: File,
    /// The first write error, after which the queue stops (the link still sends).
    pub error: Option<String>,
}

/// A session's queue files: its summaries, its Hello, its measures, why it ended.
fn paths(dir: &Path, session_id: &str) -> [PathBuf; 4] {
    [
        dir.join(format!("{session_id}.jsonl")),
        dir.join(format!("{session_id}.hello.json")),
        dir.join(format!("{session_id}.measures.json")),
        dir.join(format!("{session_id}.end.txt")),
    ]
}

/// A session's check-in answers, for its `Bye` (beside its measures).
fn checkin_path(dir: &Path, session_id: &str) -> PathBuf {
    dir.join(format!("{session_id}.checkin.json"))
}

/// A session's difficulty and its change, for its `Bye` (beside its check-in).
fn difficulty_path(dir: &Path, session_id: &str) -> PathBuf {
    dir.join(format!("{session_id}.difficulty.json"))
}

/// A session's exercise results, for its `Bye` (beside its measures).
fn exercises_path(dir: &Path, session_id: &str) -> PathBuf {
    dir.join(format!("{session_id}.exercises.json"))
}

/// What a queued session's `Bye` says when the station stopped before the session's end
/// (its reason was never written).
pub const ENDED_WITH_THE_STATION: &str =
    "ended with the station (it stopped before the session's end)";

/// Removes a delivered session's queue files (those that exist).
fn remove_session(dir: &Path, session_id: &str) {
    for p in paths(dir, session_id).into_iter().chain([
        checkin_path(dir, session_id),
        difficulty_path(dir, session_id),
        exercises_path(dir, session_id),
    ]) {
        match std::fs::remove_file(&p) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => {
                tracing::warn!(path = %p.display(), "cannot remove a delivered queue file: {e}")
            }
        }
    }
}

impl QueueFile {
    /// Starts the queue of the session `hello` opens, in `dir` (0700; files 0600).
    pub fn create(dir: &Path, hello: &Hello) -> anyhow::Result<Self> {
        private_dir(dir)?;
        let [summaries, hello_path, measures, end] = paths(dir, &hello.session_id);
        let json = serde_json::to_vec(hello).context("cannot encode the session's Hello")?;
        write_private(&hello_path, &json)?;
        let file = session::platform::owner_only(OpenOptions::new().append(true).create(true))
            .open(&summaries)
            .with_context(|| format!("cannot create {}", summaries.display()))?;
        Ok(Self {
            dir: dir.to_owned(),
            session_id: hello.session_id.clone(),
            summaries,
            measures,
            end,
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

    /// Keeps the session's movement measures for its `Bye` (written before the link says
    /// it, so a crash or a dropped link leaves them for the next delivery).
    pub fn set_measures(&mut self, measures: &BTreeMap<String, f64>) {
        if self.error.is_some() || measures.is_empty() {
            return;
        }
        let written = serde_json::to_vec(measures)
            .map_err(|e| e.to_string())
            .and_then(|json| write_private(&self.measures, &json).map_err(|e| format!("{e:#}")));
        if let Err(e) = written {
            self.error = Some(format!("{}: {e}", self.measures.display()));
        }
    }

    /// Keeps the patient's end-screen answers for the session's `Bye`, as the measures.
    pub fn set_checkin(&mut self, checkin: &netlink::CheckIn) {
        if self.error.is_some() || checkin.is_empty() {
            return;
        }
        let path = checkin_path(&self.dir, &self.session_id);
        let written = serde_json::to_vec(checkin)
            .map_err(|e| e.to_string())
            .and_then(|json| write_private(&path, &json).map_err(|e| format!("{e:#}")));
        if let Err(e) = written {
            self.error = Some(format!("{}: {e}", path.display()));
        }
    }

    /// Keeps the session's difficulty for its `Bye`, as the check-in.
    pub fn set_difficulty(&mut self, difficulty: &netlink::DifficultyChange) {
        if self.error.is_some() {
            return;
        }
        let path = difficulty_path(&self.dir, &self.session_id);
        let written = serde_json::to_vec(difficulty)
            .map_err(|e| e.to_string())
            .and_then(|json| write_private(&path, &json).map_err(|e| format!("{e:#}")));
        if let Err(e) = written {
            self.error = Some(format!("{}: {e}", path.display()));
        }
    }

    /// Keeps each exercise's results for the session's `Bye`, as the measures.
    pub fn set_exercises(&mut self, exercises: &[netlink::ExerciseResult]) {
        if self.error.is_some() || exercises.is_empty() {
            return;
        }
        let path = exercises_path(&self.dir, &self.session_id);
        let written = serde_json::to_vec(exercises)
            .map_err(|e| e.to_string())
            .and_then(|json| write_private(&path, &json).map_err(|e| format!("{e:#}")));
        if let Err(e) = written {
            self.error = Some(format!("{}: {e}", path.display()));
        }
    }

    /// Keeps why the session ended for its `Bye`, like its measures.
    pub fn set_end_reason(&mut self, reason: &str) {
        if self.error.is_some() {
            return;
        }
        if let Err(e) = write_private(&self.end, reason.as_bytes()) {
            self.error = Some(format!("{}: {e:#}", self.end.display()));
        }
    }

    /// Removes the session's files: the hub has everything.
    pub fn delivered(self) {
        remove_session(&self.dir, &self.session_id);
    }
}

/// A session waiting in the queue.
#[derive(Debug, Clone, PartialEq)]
pub struct Queued {
    /// Its Hello.
    pub hello: Hello,
    /// Its summaries, in order (a partial last line, from a crash mid-write, is left out).
    pub summaries: Vec<Summary>,
    /// Its movement measures, for its `Bye` (empty if the session did not end in order).
    pub measures: BTreeMap<String, f64>,
    /// The patient's end-screen answers, for its `Bye`, if any.
    pub checkin: Option<netlink::CheckIn>,
    /// The session's difficulty and its change, for its `Bye`, if it adapted.
    pub difficulty: Option<netlink::DifficultyChange>,
    /// Each exercise's results, for its `Bye` (empty if the session did not end in order).
    pub exercises: Vec<netlink::ExerciseResult>,
    /// Why it ended, for its `Bye` (`None` if the session did not end in order).
    pub end_reason: Option<String>,
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
        let [summaries_path, _, measures_path, end_path] = paths(dir, &hello.session_id);
        // A partial last line (crash mid-write) was never sent; the summaries stop at the first
        // complete line that does not read.
        let summaries: Vec<Summary> = File::open(&summaries_path)
            .map(|f| {
                netlink::ndjson::read_lines(std::io::BufReader::new(f))
                    .map_while(|(_, line)| netlink::ndjson::parse(&line).ok())
                    .collect()
            })
            .unwrap_or_default();
        // Unreadable measures are not worth holding the summaries back for.
        let measures = std::fs::read(&measures_path)
            .ok()
            .and_then(|json| serde_json::from_slice(&json).ok())
            .unwrap_or_default();
        let checkin = std::fs::read(checkin_path(dir, &hello.session_id))
            .ok()
            .and_then(|json| serde_json::from_slice(&json).ok());
        let difficulty = std::fs::read(difficulty_path(dir, &hello.session_id))
            .ok()
            .and_then(|json| serde_json::from_slice(&json).ok());
        let exercises = std::fs::read(exercises_path(dir, &hello.session_id))
            .ok()
            .and_then(|json| serde_json::from_slice(&json).ok())
            .unwrap_or_default();
        let end_reason = std::fs::read_to_string(&end_path).ok();
        out.push(Queued {
            hello,
            summaries,
            measures,
            checkin,
            difficulty,
            exercises,
            end_reason,
        });
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
    /// Connections that broke and were re-established, over all sessions (0 when every
    /// session went on one connection).
    pub reconnects: u64,
    /// The therapist's messages the hub sent on the sessions' connections, for the home's
    /// message store (each once, by id).
    pub messages: Vec<netlink::Message>,
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

/// The largest channel a link accepts (`StationLinkConfig::channel_capacity`).
const MAX_LINK_CHANNEL: usize = 1_000_000;

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
        let mut config = StationLinkConfig::new(address, tls.clone(), q.hello);
        // The whole session is handed over at once, without an await between sends: the
        // link's channel must hold it all (a long session once overflowed the default 4 096
        // and lost the rest when the queue file was then removed).
        // (At most the link's own limit of a million, 28 h at 10 Hz; beyond, the summaries
        // not taken keep the session queued below.)
        config.channel_capacity = config
            .channel_capacity
            .max(q.summaries.len() + 1)
            .min(MAX_LINK_CHANNEL);
        // The hub may hold part of the session already and acknowledge it at once, before
        // the replay below has handed that far: the link takes an Ack up to the session's
        // last seq (and sends none of what it covers), and refuses one above it.
        config.replay_last_seq = q.summaries.iter().map(|s| s.seq).max();
        let (sender, mut link) = StationLink::spawn(&handle, config)
            .with_context(|| format!("queued session {session_id}"))?;
        if let Some(c) = q.checkin {
            link.set_checkin(c);
        }
        if let Some(d) = q.difficulty {
            link.set_difficulty(d);
        }
        if !q.exercises.is_empty() {
            link.set_exercises(q.exercises);
        }
        // Read at the end, not lost: the hub sends the therapist's messages here too.
        let mut messages = link.take_messages();
        let mut unsent = 0_u64;
        for s in q.summaries {
            if let Err(e) = sender.send(s) {
                unsent += 1;
                tracing::warn!(session = %session_id, "queued summary not sent: {e}");
            }
        }
        let stats = link
            .finish_with_measures(
                q.end_reason.as_deref().unwrap_or(ENDED_WITH_THE_STATION),
                q.measures,
                timeout,
            )
            .await;
        report.reconnects += stats.connections.saturating_sub(1);
        while let Ok(m) = messages.try_recv() {
            if !report.messages.iter().any(|k| k.id == m.id) {
                report.messages.push(m);
            }
        }
        // The hub's Bye answer says it has synced everything it acknowledged; a summary the
        // link never took keeps the session queued.
        if stats.pending == 0 && stats.bye_acknowledged && unsent == 0 {
            remove_session(dir, &session_id);
            report.delivered += 1;
        } else {
            report.remaining += if stats.pending > 0 { stats.pending } else { n };
            report.last_error = stats.last_error.or(report.last_error);
        }
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use netlink::{PROTOCOL_VERSION, TherapistConfig, TherapistServer};

    fn hello() -> Hello {
        Hello {
            protocol_version: PROTOCOL_VERSION,
            station_id: "station-1".into(),
            patient_id: "p-1".into(),
            session_id: "s-long".into(),
            exercise: "sine-road".into(),
            started_unix_ms: 1_795_253_400_000,
            software_version: "telerehab-test".into(),
            min_protocol_version: None,
            wheel: None,
        }
    }

    /// A queued session longer than the link's default channel (4 096 summaries, about 7 min
    /// at 10 Hz) is delivered whole on a one-thread runtime, as `sync` runs it; once it held
    /// the first 4 096, dropped the rest and removed the queue anyway.
    #[test]
    fn a_queued_session_longer_than_the_links_channel_is_delivered_whole() {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let tmp = tempfile::tempdir().unwrap();
        let queue = tmp.path().join("queue");
        let mut file = QueueFile::create(&queue, &hello()).unwrap();
        let n = 6_000;
        for seq in 0..n {
            file.push(&Summary::example("s-long", seq));
        }
        assert!(file.error.is_none());
        drop(file);
        let store = tmp.path().join("store");
        let report = runtime.block_on(async {
            let config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), &store, None);
            let (server, _events) = TherapistServer::bind(config).await.unwrap();
            let addr = server.local_addr().to_string();
            let report = deliver(&queue, &addr, None, Duration::from_secs(60))
                .await
                .unwrap();
            server.shutdown(Duration::from_secs(5)).await;
            report
        });
        assert_eq!((report.delivered, report.remaining), (1, 0), "{report:?}");
        let stored = std::fs::read_to_string(store.join("station-1/s-long.jsonl")).unwrap();
        assert_eq!(stored.lines().count() as u64, n);
        assert!(pending(&queue).unwrap().is_empty());
    }

    /// A queued session resent to a hub that already stores most of it (an earlier `sync`
    /// or run got that far), on a runtime shaped as `sync`'s: the hub acknowledges what it
    /// holds while the replay is still handing the summaries over. That Ack once counted as
    /// impossible: a protocol error and a reconnect per session (and a 15 s wait).
    #[test]
    fn a_queued_session_the_hub_partly_holds_is_resent_on_one_connection_and_stored_once() {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .unwrap();
        let tmp = tempfile::tempdir().unwrap();
        let queue = tmp.path().join("queue");
        let store = tmp.path().join("store");
        let (n, held) = (4_000, 3_000);
        let queue_up_to = |last: u64| {
            let mut file = QueueFile::create(&queue, &hello()).unwrap();
            for seq in 0..last {
                file.push(&Summary::example("s-long", seq));
            }
            assert!(file.error.is_none());
        };
        let (first, resent) = runtime.block_on(async {
            let config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), &store, None);
            let (server, _events) = TherapistServer::bind(config).await.unwrap();
            let addr = server.local_addr().to_string();
            queue_up_to(held);
            let timeout = Duration::from_secs(60);
            let first = deliver(&queue, &addr, None, timeout).await.unwrap();
            queue_up_to(n);
            let resent = deliver(&queue, &addr, None, timeout).await.unwrap();
            server.shutdown(Duration::from_secs(5)).await;
            (first, resent)
        });
        assert_eq!((first.delivered, first.reconnects), (1, 0), "{first:?}");
        assert_eq!(
            (resent.delivered, resent.remaining, resent.reconnects),
            (1, 0, 0),
            "{resent:?}"
        );
        let stored = std::fs::read_to_string(store.join("station-1/s-long.jsonl")).unwrap();
        let seqs: Vec<u64> = stored
            .lines()
            .map(|l| serde_json::from_str::<Summary>(l).unwrap().seq)
            .collect();
        assert_eq!(seqs, (0..n).collect::<Vec<_>>());
        assert!(pending(&queue).unwrap().is_empty());
    }
}
