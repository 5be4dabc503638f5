//! Where a hub keeps what stations send, and who may send it: the [`HubStore`] seam.
//!
//! The hub's protocol logic (sequence bounds, duplicates, Acks, per-session locks) lives in
//! [`super::TherapistServer`]; a store only admits sessions and persists summaries. Two stores
//! exist: [`FileStore`] (one JSON-lines file per session under a directory, for
//! `telerehab therapist --store DIR`) and the clinic hub's database (crate `hub`).

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use rustls::pki_types::CertificateDer;

use crate::error::NetlinkError;
use crate::frame::{Bye, Care, Frame, Hello, Message, MessageSeen, Regimen, Summary};
use crate::pairing::PairingAuthority;
use crate::store::{Appended, SessionFile, write_hello};

pub use crate::answer::{BoxFuture, Refusal};

/// What the hub knows of the connecting station before it trusts its `Hello`.
#[derive(Debug, Clone, Copy)]
pub struct Peer<'a> {
    /// Remote address.
    pub addr: SocketAddr,
    /// The client certificate the station presented in the TLS handshake, leaf only (already
    /// verified to chain to the hub's client CA), if any.
    pub certificate: Option<&'a CertificateDer<'static>>,
}

/// What a hub tells a station's check besides its clock (protocol version
/// [`crate::frame::CHECK_NEWS_VERSION`] and above): the patient's news as the hub knows it now,
/// so that today's page is current without a session.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CheckNews {
    /// The clinic's pain settings with the patient's clearance.
    pub care: Option<Care>,
    /// The therapist's messages the patient has not seen, oldest first.
    pub messages: Vec<Message>,
    /// The patient's current regimen.
    pub regimen: Option<Regimen>,
}

impl CheckNews {
    /// The frames, in the order a session's connection gets them: care, messages, regimen.
    pub fn into_frames(self) -> Vec<Frame> {
        let care = self.care.map(Frame::Care);
        let messages = self.messages.into_iter().map(Frame::Message);
        let regimen = self.regimen.map(Frame::Regimen);
        care.into_iter().chain(messages).chain(regimen).collect()
    }
}

/// The hub's persistence and admission policy.
pub trait HubStore: Send + Sync + 'static {
    /// Admits a connection whose `Hello` is well formed, before anything is stored: where the
    /// store knows stations, that the certificate is the station's, that it is not revoked and
    /// that it speaks for its own patient. Called for every connection. The default admits.
    fn admit<'a>(&'a self, hello: &'a Hello, peer: Peer<'a>) -> BoxFuture<'a, Result<(), Refusal>> {
        let _ = (hello, peer);
        Box::pin(async { Ok(()) })
    }

    /// The patient's news for a station's check of `hello` (already admitted by
    /// [`Self::admit`]): what a session's connection would be sent before its first summary.
    /// Read only, it opens no session. The default (a store that keeps no patients) has none.
    fn station_check<'a>(&'a self, hello: &'a Hello) -> BoxFuture<'a, CheckNews> {
        let _ = hello;
        Box::pin(async { CheckNews::default() })
    }

    /// Records the `Hello` and opens its session for appending (only when no other connection
    /// of the session has it open).
    fn open_session<'a>(
        &'a self,
        hello: &'a Hello,
    ) -> BoxFuture<'a, Result<Box<dyn SessionStore>, Refusal>>;

    /// The authority that pairs new stations, if this hub pairs (the file store does not).
    fn pairing(&self) -> Option<Arc<dyn PairingAuthority>> {
        None
    }

    /// Where the recording of `hello`'s session is kept once uploaded; `None`: this hub takes
    /// no recordings.
    fn recording_path(&self, hello: &Hello) -> Option<PathBuf> {
        let _ = hello;
        None
    }

    /// The size and SHA-256 of the recording of `hello`'s session this hub already stores
    /// ([`Self::recording_path`] is `path`), `None` when it stores none. Asked before an upload
    /// begins, so a recording stored once is never taken twice. The default reads the file at
    /// `path`; a hub keeping recordings elsewhere (object storage) asks its store.
    fn recording_held<'a>(
        &'a self,
        hello: &'a Hello,
        path: &'a std::path::Path,
    ) -> BoxFuture<'a, Result<Option<(u64, String)>, NetlinkError>> {
        let _ = hello;
        Box::pin(async move {
            let io = |e| NetlinkError::Io {
                context: format!("recording check of {}", path.display()),
                source: e,
            };
            if !tokio::fs::try_exists(path).await.map_err(io)? {
                return Ok(None);
            }
            super::upload::file_sha256(path.to_owned())
                .await
                .map(Some)
                .map_err(io)
        })
    }

    /// Keeps the verified upload `part` (whole, its SHA-256 the announced one) as the
    /// recording of `hello`'s session; `path` is [`Self::recording_path`]. It is stored whole or
    /// not at all: after an error nothing of it may be listed as stored, and `part` must be
    /// left in place so that the station's next attempt completes it. The default renames
    /// `part` to `path`; a hub keeping recordings in object storage copies it there.
    fn keep_recording<'a>(
        &'a self,
        hello: &'a Hello,
        part: &'a std::path::Path,
        path: &'a std::path::Path,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        let _ = hello;
        Box::pin(async move {
            tokio::fs::rename(part, path)
                .await
                .map_err(|e| NetlinkError::Io {
                    context: format!("rename of {}", part.display()),
                    source: e,
                })
        })
    }

    /// A recording arrived whole and verified at `path` (also called again when a station
    /// uploads a recording the hub already holds, so a record that failed before is made
    /// then). The station is told `complete` only after this succeeds; an error makes it
    /// upload again later.
    fn recording_stored<'a>(
        &'a self,
        hello: &'a Hello,
        sha256: &'a str,
        size_bytes: u64,
        path: &'a std::path::Path,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        let _ = (hello, sha256, size_bytes, path);
        Box::pin(async { Ok(()) })
    }

    /// An upload of `hello`'s recording (`size_bytes` long, SHA-256 `sha256`) holds
    /// `received_bytes` on this hub: said when it begins or resumes and every
    /// [`super::RECORDING_PROGRESS_EVERY`] after, so the clinic sees a recording on its way
    /// rather than none. Never called for a recording stored whole ([`Self::recording_stored`]
    /// says that). Informative only: an error is logged and the upload goes on. The default
    /// keeps nothing.
    fn recording_progress<'a>(
        &'a self,
        hello: &'a Hello,
        sha256: &'a str,
        size_bytes: u64,
        received_bytes: u64,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        let _ = (hello, sha256, size_bytes, received_bytes);
        Box::pin(async { Ok(()) })
    }

    /// The hub's clock, ms since the Unix epoch, that a station's times are checked against
    /// (session starts, summary times, the day of the daily upload count). The default is the
    /// system clock.
    fn now_ms(&self) -> u64 {
        crate::frame::unix_ms_now()
    }

    /// The hub refused something of the station of `hello` (`kind`: a short name such as
    /// `summary_rate`, `why`: what the station was told in its `Error` frame). A store that
    /// keeps an audit log records it, at a bounded rate. The default keeps nothing.
    fn refused<'a>(
        &'a self,
        hello: &'a Hello,
        kind: &'static str,
        why: &'a str,
    ) -> BoxFuture<'a, ()> {
        let _ = (hello, kind, why);
        Box::pin(async {})
    }

    /// Recording bytes taken from `station_id` on UTC day `day` (days since the Unix epoch) by
    /// every hub on this store, as added with [`Self::add_upload_bytes`]; read when a hub first
    /// counts the station's bytes on that day and at the start of each recording, so a
    /// restarted hub goes on counting and hubs sharing the store share the count. The default
    /// keeps nothing (0).
    fn upload_bytes_on<'a>(
        &'a self,
        station_id: &'a str,
        day: u64,
    ) -> BoxFuture<'a, Result<u64, NetlinkError>> {
        let _ = (station_id, day);
        Box::pin(async { Ok(0) })
    }

    /// Adds `bytes` more recording bytes taken from `station_id` on UTC day `day` to the count
    /// every hub on this store shares (one atomic addition: two hubs adding at once both
    /// count), and answers the day's count after it; `None` from a store that keeps no count
    /// (the default).
    fn add_upload_bytes<'a>(
        &'a self,
        station_id: &'a str,
        day: u64,
        bytes: u64,
    ) -> BoxFuture<'a, Result<Option<u64>, NetlinkError>> {
        let _ = (station_id, day, bytes);
        Box::pin(async { Ok(None) })
    }

    /// The station of `hello` showed the therapist's message `seen.id` to its patient. A
    /// store that keeps messages records when (an id it does not know for that patient is
    /// ignored); an error makes the station say it again later. The default keeps nothing.
    fn message_seen<'a>(
        &'a self,
        hello: &'a Hello,
        seen: &'a MessageSeen,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        let _ = (hello, seen);
        Box::pin(async { Ok(()) })
    }
}

/// One open session in a [`HubStore`]. The hub calls it under the session's own lock, so
/// calls never overlap; it asks for the last stored sequence number once, at open.
pub trait SessionStore: Send {
    /// The highest sequence number stored in this session, `None` if none.
    fn last_seq(&self) -> Option<u64>;

    /// The time (`t_s`) of the last summary stored in this session, `None` if none or not
    /// known; the hub refuses a summary whose time goes back before it.
    fn last_t_s(&self) -> Option<f64> {
        None
    }

    /// Stores `summary` unless one with this or a higher sequence number is stored; durable
    /// against a hub crash when it returns `Stored` (the hub acknowledges it next).
    fn append<'a>(
        &'a mut self,
        summary: &'a Summary,
    ) -> BoxFuture<'a, Result<Appended, NetlinkError>>;

    /// Makes everything appended durable against power loss; `bye` is the station's, when the
    /// session ended in order (`None` at a disconnect).
    fn sync<'a>(&'a mut self, bye: Option<&'a Bye>) -> BoxFuture<'a, Result<(), NetlinkError>>;
}

/// The directory store: `DIR/<station_id>/<session_id>.jsonl` and `.hello.json` (see
/// [`crate::store`]). It knows no stations, so it admits every well-formed `Hello` (the hub
/// has already checked a client certificate against the station id when it requires one).
#[derive(Debug, Clone)]
pub struct FileStore {
    dir: PathBuf,
}

impl FileStore {
    /// A store rooted at `dir` (created when the hub binds).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Self { dir: dir.into() }
    }
}

/// Runs blocking file work on tokio's blocking pool.
async fn blocking<T: Send + 'static>(
    what: &'static str,
    work: impl FnOnce() -> Result<T, NetlinkError> + Send + 'static,
) -> Result<T, NetlinkError> {
    tokio::task::spawn_blocking(work)
        .await
        .map_err(|e| NetlinkError::Protocol(format!("{what} task failed: {e}")))?
}

impl HubStore for FileStore {
    fn recording_path(&self, hello: &Hello) -> Option<PathBuf> {
        // Identifiers were checked by the codec: safe path components.
        Some(
            self.dir
                .join(&hello.station_id)
                .join(format!("{}.mcap", hello.session_id)),
        )
    }

    fn open_session<'a>(
        &'a self,
        hello: &'a Hello,
    ) -> BoxFuture<'a, Result<Box<dyn SessionStore>, Refusal>> {
        Box::pin(async move {
            let (dir, owned) = (self.dir.clone(), hello.clone());
            let file = blocking("session open", move || {
                write_hello(&dir, &owned)?;
                SessionFile::open(&dir, &owned.station_id, &owned.session_id)
            })
            .await
            .map_err(|e| Refusal::new(format!("cannot open the session store: {e}")))?;
            let last_seq = file.last_seq();
            Ok(Box::new(FileSession {
                file: Arc::new(Mutex::new(file)),
                last_seq,
                last_t_s: None,
                dir: self.dir.clone(),
                station_id: hello.station_id.clone(),
            }) as Box<dyn SessionStore>)
        })
    }
}

struct FileSession {
    file: Arc<Mutex<SessionFile>>,
    last_seq: Option<u64>,
    /// The time of the last summary appended since the session was opened.
    last_t_s: Option<f64>,
    /// The store's directory and the session's station, for the measures a `Bye` brings.
    dir: PathBuf,
    station_id: String,
}

fn lock_file(file: &Mutex<SessionFile>) -> std::sync::MutexGuard<'_, SessionFile> {
    // Only this session's calls (never overlapping) take it; a panic mid-append leaves at worst
    // a partial line, which the next open cuts off.
    file.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl SessionStore for FileSession {
    fn last_seq(&self) -> Option<u64> {
        self.last_seq
    }

    fn last_t_s(&self) -> Option<f64> {
        self.last_t_s
    }

    fn append<'a>(
        &'a mut self,
        summary: &'a Summary,
    ) -> BoxFuture<'a, Result<Appended, NetlinkError>> {
        Box::pin(async move {
            let t_s = summary.t_s;
            let (file, summary) = (self.file.clone(), summary.clone());
            let (appended, last) = blocking("storage", move || {
                let mut f = lock_file(&file);
                let appended = f.append(&summary)?;
                Ok((appended, f.last_seq()))
            })
            .await?;
            self.last_seq = last;
            if appended == Appended::Stored {
                self.last_t_s = Some(t_s);
            }
            Ok(appended)
        })
    }

    fn sync<'a>(&'a mut self, bye: Option<&'a Bye>) -> BoxFuture<'a, Result<(), NetlinkError>> {
        Box::pin(async move {
            if let Some(bye) = bye.filter(|b| !b.measures.is_empty()) {
                let (dir, station, bye) = (self.dir.clone(), self.station_id.clone(), bye.clone());
                blocking("measures", move || {
                    crate::store::write_measures(&dir, &station, &bye)
                })
                .await?;
            }
            let handle = lock_file(&self.file).try_clone_file()?;
            blocking("fsync", move || {
                handle
                    .sync_data()
                    .map_err(|e| NetlinkError::io("fsync of a session file", e))
            })
            .await
        })
    }
}
