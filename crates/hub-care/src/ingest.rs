//! The station side of the hub: netlink's [`HubStore`] over the database (who may speak,
//! summaries stored exactly once) and its [`PairingAuthority`] (codes, rate limits, the
//! clinic's CA).
//!
//! A station is known by the SHA-256 of its client certificate: the TLS handshake proves it
//! holds the key, [`DbStore::admit`] that the certificate is the one issued at pairing, that the
//! station is not revoked and that it speaks for its own patient. Revocation takes effect at
//! once: the revoked set is re-read every [`REVOCATION_POLL`], and the next summary of an open
//! session of a revoked station ends its connection.

use std::collections::{HashMap, HashSet};
use std::net::{IpAddr, SocketAddr};
use std::sync::{Arc, Mutex, RwLock};
use std::time::Duration;

use tokio::sync::{mpsc, oneshot};

use netlink::pairing::{Issued, PairingAuthority, Ticket};
use netlink::pki::{ClinicCa, certificate_sha256_hex};
use netlink::store::Appended;
use netlink::{
    BoxFuture, Bye, CheckNews, Hello, HubStore, NetlinkError, Peer, Refusal, SessionStore, Summary,
};

use crate::live::unix_ms;
use crate::telemetry::{AdmissionRefusal, Telemetry};
use hub_store::HubError;
use hub_store::db::{Db, MAX_SESSIONS_PER_STATION_DAY, PairingEvent};

/// How often the set of revoked stations is re-read.
pub const REVOCATION_POLL: Duration = Duration::from_secs(1);
/// Pairing attempts one address may begin per minute.
pub const PAIRING_ATTEMPTS_PER_MINUTE: u32 = 10;
/// Failed pairing attempts one address may make per hour; beyond, it is refused for the hour.
pub const PAIRING_FAILURES_PER_HOUR: u32 = 20;

/// At most one audit entry per station and kind of refusal in this long, ms: a station held to
/// its limits refuses again at every try, and the log must not grow with it.
pub const REFUSAL_AUDIT_EVERY_MS: i64 = 60_000;

/// Most summaries one group commit takes.
pub const MAX_BATCH: usize = 1024;

/// A summary waiting for the group commit, where its result goes, and when it reached the
/// store (its acknowledgement latency is counted from there).
type Pending = (
    Summary,
    oneshot::Sender<Result<Appended, String>>,
    std::time::Instant,
);

/// The group-commit writer: takes whatever summaries are waiting (at least one, at most
/// [`MAX_BATCH`]) and stores them in one transaction. It never waits to fill a batch, so an
/// idle hub commits each summary at once and a busy one commits many per transaction.
async fn group_commit(
    db: Db,
    mut rx: mpsc::Receiver<Pending>,
    clock: clock::Clock,
    telemetry: Arc<Telemetry>,
) {
    let mut batch: Vec<Pending> = Vec::with_capacity(MAX_BATCH);
    while rx.recv_many(&mut batch, MAX_BATCH).await > 0 {
        let summaries: Vec<Summary> = batch.iter().map(|(s, _, _)| s.clone()).collect();
        match db.store_summaries(&summaries, unix_ms(&clock)).await {
            Ok(results) => {
                for ((_, reply, arrived), result) in batch.drain(..).zip(results) {
                    if let Ok(appended) = &result {
                        let duplicate = *appended != Appended::Stored;
                        telemetry.summary_stored(duplicate, arrived.elapsed().as_secs_f64());
                    }
                    let _ = reply.send(result.map_err(|e| e.to_string()));
                }
            }
            Err(e) => {
                let message = e.to_string();
                for (_, reply, _) in batch.drain(..) {
                    let _ = reply.send(Err(message.clone()));
                }
            }
        }
    }
}

/// The database as the station link's store, and the pairing authority.
pub struct DbStore {
    db: Db,
    /// Where uploaded recordings are kept (the data directory or an S3 store).
    recordings: crate::recordings::RecordingStore,
    writer: mpsc::Sender<Pending>,
    ca: ClinicCa,
    /// The name on the hub's certificate, given to paired stations.
    server_name: String,
    revoked: Arc<RwLock<HashSet<String>>>,
    /// When each station's refusal of each kind was last audited, ms (at most one entry per
    /// station and kind per [`REFUSAL_AUDIT_EVERY_MS`]).
    refusal_audits: Mutex<HashMap<(String, &'static str), i64>>,
    clock: clock::Clock,
    /// The clinic's pain settings a station's check is told ([`crate::news::for_check`]);
    /// `None`: checks get no care frame.
    care: Option<crate::care::CareConfig>,
    /// Admissions, refusals, summaries and uploads counted for `/metrics`.
    telemetry: Arc<Telemetry>,
}

impl std::fmt::Debug for DbStore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DbStore")
            .field("server_name", &self.server_name)
            .finish_non_exhaustive()
    }
}

fn refusal(e: HubError) -> Refusal {
    Refusal::new(e.to_string())
}

/// Checkpoints the SQLite database's write-ahead log every second, off the writer's path,
/// for as long as the store's writer channel lives.
async fn checkpoints(db: Db, writer: mpsc::WeakSender<Pending>) {
    let mut every = tokio::time::interval(Duration::from_secs(1));
    every.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        every.tick().await;
        if writer.upgrade().is_none() {
            return;
        }
        if let Err(e) = db.checkpoint().await {
            tracing::warn!("{e}");
        }
    }
}

impl DbStore {
    /// A store over `db` issuing certificates from `ca` for a hub named `server_name`; its
    /// group-commit writer runs on the current tokio runtime. Its counts go to a registry of
    /// its own (see [`Self::new_counted`]).
    pub fn new(
        db: Db,
        ca: ClinicCa,
        server_name: String,
        recordings: crate::recordings::RecordingStore,
        clock: clock::Clock,
    ) -> Self {
        Self::new_counted(db, ca, server_name, recordings, clock, Arc::default())
    }

    /// [`Self::new`] counting admissions, refusals, summaries and uploads in `telemetry`.
    pub fn new_counted(
        db: Db,
        ca: ClinicCa,
        server_name: String,
        recordings: crate::recordings::RecordingStore,
        clock: clock::Clock,
        telemetry: Arc<Telemetry>,
    ) -> Self {
        let (writer, rx) = mpsc::channel(4 * MAX_BATCH);
        tokio::spawn(group_commit(
            db.clone(),
            rx,
            clock.clone(),
            telemetry.clone(),
        ));
        if db.backend() == hub_store::Backend::Sqlite {
            tokio::spawn(checkpoints(db.clone(), writer.downgrade()));
        }
        Self {
            recordings,
            writer,
            db,
            ca,
            server_name,
            revoked: Arc::default(),
            refusal_audits: Mutex::default(),
            clock,
            care: None,
            telemetry,
        }
    }

    /// The store telling stations' checks the clinic's pain settings `care`.
    pub fn with_care(mut self, care: crate::care::CareConfig) -> Self {
        self.care = Some(care);
        self
    }

    fn now(&self) -> i64 {
        unix_ms(&self.clock)
    }

    /// Re-reads the revoked stations (called every [`REVOCATION_POLL`] by the hub).
    pub async fn refresh_revoked(&self) -> Result<usize, HubError> {
        let ids: Vec<String> =
            sqlx::query_scalar("SELECT station_id FROM stations WHERE revoked_at_ms IS NOT NULL")
                .fetch_all(self.db.pool())
                .await
                .map_err(HubError::db("reading revoked stations"))?;
        let n = ids.len();
        *self
            .revoked
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = ids.into_iter().collect();
        Ok(n)
    }

    /// Whether the station of `hello` may speak: its certificate is the one issued at pairing,
    /// it is not revoked, and it speaks for its own patient.
    /// Refused: why, for `/metrics`, and what the station is told.
    async fn check_admission(
        &self,
        hello: &Hello,
        peer: Peer<'_>,
    ) -> Result<(), (AdmissionRefusal, Refusal)> {
        let database = |e| (AdmissionRefusal::Database, refusal(e));
        let refused = |why, said: String| Err((why, Refusal::new(said)));
        let Some(cert) = peer.certificate else {
            return refused(
                AdmissionRefusal::NoCertificate,
                "no client certificate presented: pair first".into(),
            );
        };
        let fingerprint = certificate_sha256_hex(cert);
        let Some(station) = self.db.station(&hello.station_id).await.map_err(database)? else {
            let said = format!("unknown station {:?}", hello.station_id);
            return refused(AdmissionRefusal::UnknownStation, said);
        };
        if station.cert_fingerprint != fingerprint {
            let said = format!(
                "the certificate presented is not station {:?}'s",
                hello.station_id
            );
            return refused(AdmissionRefusal::CertificateMismatch, said);
        }
        if station.is_revoked() {
            let said = format!(
                "station {:?} has been revoked by the clinic",
                hello.station_id
            );
            return refused(AdmissionRefusal::Revoked, said);
        }
        if station.patient_id != hello.patient_id {
            let said = format!(
                "station {:?} speaks for its own patient only",
                hello.station_id
            );
            return refused(AdmissionRefusal::WrongPatient, said);
        }
        self.db
            .touch_station(&hello.station_id, self.now())
            .await
            .map_err(database)?;
        // The patient's wheel, as the station tells it: the prescribe form's bounds.
        match &hello.wheel {
            Some(wheel) => self
                .db
                .note_station_wheel(&hello.station_id, wheel, self.now())
                .await
                .map_err(database),
            None => Ok(()),
        }
    }

    /// Audits the refusal `kind` of station `hello` (`why`: what it was told), unless one of
    /// that kind was audited for it in the last [`REFUSAL_AUDIT_EVERY_MS`].
    async fn audit_station_refusal(&self, hello: &Hello, kind: &'static str, why: &str) {
        self.telemetry.station_refused(kind);
        let now = self.now();
        {
            let mut last = self
                .refusal_audits
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if last.len() > 10_000 {
                last.retain(|_, at| now - *at < REFUSAL_AUDIT_EVERY_MS);
            }
            let key = (hello.station_id.clone(), kind);
            if last
                .get(&key)
                .is_some_and(|at| now - *at < REFUSAL_AUDIT_EVERY_MS)
            {
                return;
            }
            last.insert(key, now);
        }
        let actor = format!("station:{}", hello.station_id);
        let action = format!("station_refused_{kind}");
        if let Err(e) = self
            .db
            .audit(&actor, &action, &hello.session_id, why, now)
            .await
        {
            tracing::warn!("cannot audit a station refusal: {e}");
        }
    }

    /// Refuses a new session of `hello`'s station beyond [`MAX_SESSIONS_PER_STATION_DAY`]
    /// started on the same UTC day (a session already known is always reopened).
    async fn check_sessions_of_the_day(&self, hello: &Hello) -> Result<(), Refusal> {
        if self
            .db
            .session(&hello.session_id)
            .await
            .map_err(refusal)?
            .is_some()
        {
            return Ok(());
        }
        let started = i64::try_from(hello.started_unix_ms).unwrap_or(i64::MAX);
        let n = self
            .db
            .sessions_started_on_day(&hello.station_id, started)
            .await
            .map_err(refusal)?;
        if n < MAX_SESSIONS_PER_STATION_DAY {
            return Ok(());
        }
        let why = format!(
            "station {:?} has already started {n} sessions on this day, the most the hub takes \
             ({MAX_SESSIONS_PER_STATION_DAY}; a regimen prescribes at most 4 a day)",
            hello.station_id
        );
        self.audit_station_refusal(hello, "sessions_per_day", &why)
            .await;
        Err(Refusal::new(why))
    }

    /// Counts a pairing attempt from `ip`; false beyond [`PAIRING_ATTEMPTS_PER_MINUTE`] a
    /// minute or after [`PAIRING_FAILURES_PER_HOUR`] failures within the hour. Both are counted
    /// per address (IPv6 per /64: one host holds a whole /64) in the database, shared by every
    /// hub of the clinic ([`PairingEvent`]).
    async fn pairing_allowed(&self, ip: IpAddr) -> Result<bool, HubError> {
        let now = self.now();
        let address = hub_store::db::address_key(ip);
        let failed = self
            .db
            .pairing_events(PairingEvent::Failed, &address, now)
            .await?;
        if failed >= PAIRING_FAILURES_PER_HOUR {
            return Ok(false);
        }
        let begun = self
            .db
            .count_pairing_event(PairingEvent::Begun, &address, now)
            .await?;
        Ok(begun <= PAIRING_ATTEMPTS_PER_MINUTE)
    }
}

impl HubStore for DbStore {
    fn now_ms(&self) -> u64 {
        u64::try_from(self.now()).unwrap_or(0)
    }

    fn refused<'a>(
        &'a self,
        hello: &'a Hello,
        kind: &'static str,
        why: &'a str,
    ) -> BoxFuture<'a, ()> {
        Box::pin(self.audit_station_refusal(hello, kind, why))
    }

    fn upload_bytes_on<'a>(
        &'a self,
        station_id: &'a str,
        day: u64,
    ) -> BoxFuture<'a, Result<u64, NetlinkError>> {
        Box::pin(async move {
            self.db
                .upload_bytes_on(station_id, day)
                .await
                .map_err(storage_error)
        })
    }

    fn add_upload_bytes<'a>(
        &'a self,
        station_id: &'a str,
        day: u64,
        bytes: u64,
    ) -> BoxFuture<'a, Result<Option<u64>, NetlinkError>> {
        Box::pin(async move {
            self.db
                .add_upload_bytes(station_id, day, bytes)
                .await
                .map(Some)
                .map_err(storage_error)
        })
    }

    fn recording_path(&self, hello: &Hello) -> Option<std::path::PathBuf> {
        // Identifiers were checked by the codec and admitted by `admit`: safe path components.
        // Where the upload grows on this hub's disk; the store keeps it once whole.
        Some(
            self.recordings
                .staging_path(&hello.station_id, &hello.session_id),
        )
    }

    fn recording_held<'a>(
        &'a self,
        hello: &'a Hello,
        path: &'a std::path::Path,
    ) -> BoxFuture<'a, Result<Option<(u64, String)>, NetlinkError>> {
        let _ = path;
        Box::pin(async move {
            self.recordings
                .held(&hello.station_id, &hello.session_id)
                .await
                .map_err(storage_error)
        })
    }

    fn keep_recording<'a>(
        &'a self,
        hello: &'a Hello,
        part: &'a std::path::Path,
        path: &'a std::path::Path,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        let _ = path;
        Box::pin(async move {
            self.recordings
                .keep(&hello.station_id, &hello.session_id, part)
                .await
                .map_err(storage_error)
        })
    }

    fn recording_progress<'a>(
        &'a self,
        hello: &'a Hello,
        sha256: &'a str,
        size_bytes: u64,
        received_bytes: u64,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        Box::pin(async move {
            let recording = hub_store::db::Recording {
                last_part_ms: Some(self.now()),
                ..self.recording_row(hello, sha256, size_bytes, received_bytes)
            };
            self.db
                .note_recording_progress(&recording)
                .await
                .map_err(storage_error)
        })
    }

    fn recording_stored<'a>(
        &'a self,
        hello: &'a Hello,
        sha256: &'a str,
        size_bytes: u64,
        path: &'a std::path::Path,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        // Recorded where the store keeps it (`path` is only where it grew).
        let _ = path;
        Box::pin(async move {
            let known = self
                .db
                .recording(&hello.session_id)
                .await
                .map_err(storage_error)?;
            if known.is_some_and(|r| r.complete && r.sha256 == sha256) {
                return Ok(());
            }
            // Audited first: a failure after it makes the station upload again (a second
            // entry), never a recording without its entry.
            let actor = format!("station:{}", hello.station_id);
            let detail = format!("{size_bytes} bytes, sha256 {sha256}");
            self.db
                .audit(
                    &actor,
                    "recording_uploaded",
                    &hello.session_id,
                    &detail,
                    self.now(),
                )
                .await
                .map_err(storage_error)?;
            let recording = self.recording_row(hello, sha256, size_bytes, size_bytes);
            self.db
                .put_recording(&recording)
                .await
                .map_err(storage_error)
        })
    }

    fn admit<'a>(&'a self, hello: &'a Hello, peer: Peer<'a>) -> BoxFuture<'a, Result<(), Refusal>> {
        Box::pin(async move {
            let admitted = self.check_admission(hello, peer).await;
            let admitted = match admitted {
                Ok(()) => {
                    self.telemetry.station_admitted();
                    Ok(())
                }
                Err((why, refused)) => {
                    self.telemetry.admission_refused(why);
                    Err(refused)
                }
            };
            if let Err(refused) = &admitted {
                // Audited like every refusal, at a bounded rate per address.
                let actor = format!("station:{}", hello.station_id);
                let audited = self
                    .db
                    .audit_refusal(
                        &actor,
                        "station_refused",
                        &hello.patient_id,
                        &refused.message,
                        &peer.addr.ip().to_string(),
                        self.now(),
                    )
                    .await;
                if let Err(e) = audited {
                    tracing::warn!("cannot audit a station refusal: {e}");
                }
            }
            admitted
        })
    }

    fn station_check<'a>(&'a self, hello: &'a Hello) -> BoxFuture<'a, CheckNews> {
        Box::pin(crate::news::for_check(
            &self.db,
            self.care.as_ref(),
            &hello.patient_id,
            self.now(),
        ))
    }

    fn open_session<'a>(
        &'a self,
        hello: &'a Hello,
    ) -> BoxFuture<'a, Result<Box<dyn SessionStore>, Refusal>> {
        Box::pin(async move {
            self.check_sessions_of_the_day(hello).await?;
            let last_seq = self
                .db
                .open_session(hello, self.now())
                .await
                .map_err(refusal)?;
            let last_t_s = match last_seq {
                Some(_) => self.db.last_t_s(&hello.session_id).await.map_err(refusal)?,
                None => None,
            };
            Ok(Box::new(DbSession {
                db: self.db.clone(),
                writer: self.writer.clone(),
                station_id: hello.station_id.clone(),
                last_seq,
                last_t_s,
                revoked: self.revoked.clone(),
                clock: self.clock.clone(),
            }) as Box<dyn SessionStore>)
        })
    }
}

/// The store and authority together, shared by the station link.
#[derive(Debug, Clone)]
pub struct Ingest(pub Arc<DbStore>);

impl HubStore for Ingest {
    fn now_ms(&self) -> u64 {
        self.0.now_ms()
    }

    fn refused<'a>(
        &'a self,
        hello: &'a Hello,
        kind: &'static str,
        why: &'a str,
    ) -> BoxFuture<'a, ()> {
        self.0.refused(hello, kind, why)
    }

    fn upload_bytes_on<'a>(
        &'a self,
        station_id: &'a str,
        day: u64,
    ) -> BoxFuture<'a, Result<u64, NetlinkError>> {
        self.0.upload_bytes_on(station_id, day)
    }

    fn add_upload_bytes<'a>(
        &'a self,
        station_id: &'a str,
        day: u64,
        bytes: u64,
    ) -> BoxFuture<'a, Result<Option<u64>, NetlinkError>> {
        self.0.add_upload_bytes(station_id, day, bytes)
    }

    fn admit<'a>(&'a self, hello: &'a Hello, peer: Peer<'a>) -> BoxFuture<'a, Result<(), Refusal>> {
        self.0.admit(hello, peer)
    }

    fn station_check<'a>(&'a self, hello: &'a Hello) -> BoxFuture<'a, CheckNews> {
        self.0.station_check(hello)
    }

    fn open_session<'a>(
        &'a self,
        hello: &'a Hello,
    ) -> BoxFuture<'a, Result<Box<dyn SessionStore>, Refusal>> {
        self.0.open_session(hello)
    }

    fn recording_path(&self, hello: &Hello) -> Option<std::path::PathBuf> {
        self.0.recording_path(hello)
    }

    fn recording_stored<'a>(
        &'a self,
        hello: &'a Hello,
        sha256: &'a str,
        size_bytes: u64,
        path: &'a std::path::Path,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        Box::pin(async move {
            let stored = self
                .0
                .recording_stored(hello, sha256, size_bytes, path)
                .await;
            match &stored {
                Ok(()) => self.0.telemetry.upload_completed(size_bytes),
                Err(_) => self.0.telemetry.upload_failed(),
            }
            stored
        })
    }

    fn recording_held<'a>(
        &'a self,
        hello: &'a Hello,
        path: &'a std::path::Path,
    ) -> BoxFuture<'a, Result<Option<(u64, String)>, NetlinkError>> {
        self.0.recording_held(hello, path)
    }

    fn keep_recording<'a>(
        &'a self,
        hello: &'a Hello,
        part: &'a std::path::Path,
        path: &'a std::path::Path,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        self.0.keep_recording(hello, part, path)
    }

    fn recording_progress<'a>(
        &'a self,
        hello: &'a Hello,
        sha256: &'a str,
        size_bytes: u64,
        received_bytes: u64,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        self.0
            .recording_progress(hello, sha256, size_bytes, received_bytes)
    }

    fn pairing(&self) -> Option<Arc<dyn PairingAuthority>> {
        Some(self.0.clone())
    }

    fn message_seen<'a>(
        &'a self,
        hello: &'a Hello,
        seen: &'a netlink::MessageSeen,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        self.0.message_seen(hello, seen)
    }
}

impl DbStore {
    /// The database row of `hello`'s recording holding `received_bytes` of `size_bytes`
    /// (complete when it holds them all), where the store keeps it.
    fn recording_row(
        &self,
        hello: &Hello,
        sha256: &str,
        size_bytes: u64,
        received_bytes: u64,
    ) -> hub_store::db::Recording {
        let bytes = |n: u64| i64::try_from(n).unwrap_or(i64::MAX);
        hub_store::db::Recording {
            session_id: hello.session_id.clone(),
            sha256: sha256.to_owned(),
            size_bytes: bytes(size_bytes),
            received_bytes: bytes(received_bytes),
            path: self
                .recordings
                .location(&hello.station_id, &hello.session_id),
            complete: received_bytes == size_bytes,
            last_part_ms: None,
        }
    }

    /// Records that the station of `hello` showed message `seen.id` to its patient (audited
    /// as the station); a message of another patient, or one already seen, changes nothing.
    fn message_seen<'a>(
        &'a self,
        hello: &'a Hello,
        seen: &'a netlink::MessageSeen,
    ) -> BoxFuture<'a, Result<(), NetlinkError>> {
        Box::pin(async move {
            let changed = self
                .db
                .message_seen(&hello.patient_id, &seen.id, seen.seen_unix_ms)
                .await
                .map_err(storage_error)?;
            if changed {
                let actor = format!("station:{}", hello.station_id);
                let detail = format!("message {} seen at {} ms", seen.id, seen.seen_unix_ms);
                self.db
                    .audit(
                        &actor,
                        "message_seen",
                        &hello.patient_id,
                        &detail,
                        self.now(),
                    )
                    .await
                    .map_err(storage_error)?;
            }
            Ok(())
        })
    }
}

struct DbSession {
    db: Db,
    writer: mpsc::Sender<Pending>,
    station_id: String,
    last_seq: Option<u64>,
    /// The time of the last summary stored.
    last_t_s: Option<f64>,
    revoked: Arc<RwLock<HashSet<String>>>,
    clock: clock::Clock,
}

fn storage_error(e: HubError) -> NetlinkError {
    NetlinkError::Store(e.to_string())
}

impl SessionStore for DbSession {
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
            let revoked = self
                .revoked
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .contains(&self.station_id);
            if revoked {
                return Err(NetlinkError::Protocol(format!(
                    "station {:?} has been revoked by the clinic",
                    self.station_id
                )));
            }
            let (reply, result) = oneshot::channel();
            self.writer
                .send((summary.clone(), reply, std::time::Instant::now()))
                .await
                .map_err(|_| NetlinkError::Closed)?;
            let appended = result
                .await
                .map_err(|_| NetlinkError::Closed)?
                .map_err(NetlinkError::Protocol)?;
            if appended == Appended::Stored {
                self.last_seq = Some(summary.seq);
                self.last_t_s = Some(summary.t_s);
            }
            Ok(appended)
        })
    }

    fn sync<'a>(&'a mut self, bye: Option<&'a Bye>) -> BoxFuture<'a, Result<(), NetlinkError>> {
        // Every summary was committed before it was acknowledged; a Bye closes the session.
        Box::pin(async move {
            if let Some(bye) = bye {
                self.db
                    .close_session(bye, unix_ms(&self.clock))
                    .await
                    .map_err(storage_error)?;
            }
            Ok(())
        })
    }
}

impl PairingAuthority for DbStore {
    fn begin<'a>(
        &'a self,
        code_id: &'a str,
        peer: SocketAddr,
    ) -> BoxFuture<'a, Result<Ticket, Refusal>> {
        Box::pin(async move {
            if !self.pairing_allowed(peer.ip()).await.map_err(refusal)? {
                return Err(Refusal::new(format!(
                    "too many pairing attempts from {}; try again later (each address may \
                     begin {PAIRING_ATTEMPTS_PER_MINUTE} a minute and fail \
                     {PAIRING_FAILURES_PER_HOUR} an hour)",
                    peer.ip()
                )));
            }
            let ticket = self
                .db
                .begin_pairing_attempt(code_id, &hub_store::db::address_key(peer.ip()), self.now())
                .await
                .map_err(refusal)?;
            Ok(match ticket {
                Some(t) => Ticket {
                    secret: t.secret,
                    patient_id: t.patient_id,
                },
                // Not a live code now: the exchange runs with a secret nobody knows, and
                // fails exactly as a wrong secret does.
                None => Ticket {
                    secret: netlink::pairing::PairingCode::generate()
                        .map_err(|e| Refusal::new(e.to_string()))?
                        .secret()
                        .to_owned(),
                    patient_id: String::new(),
                },
            })
        })
    }

    fn failed<'a>(&'a self, code_id: &'a str, peer: SocketAddr) -> BoxFuture<'a, ()> {
        Box::pin(async move {
            // The code's own attempt was counted when it began; here the address's.
            let now = self.now();
            let address = hub_store::db::address_key(peer.ip());
            if let Err(e) = self
                .db
                .count_pairing_event(PairingEvent::Failed, &address, now)
                .await
            {
                tracing::warn!("cannot count a failed pairing attempt: {e}");
            }
            let _ = self
                .db
                .audit(
                    "station:pairing",
                    "pairing_failed",
                    code_id,
                    &peer.to_string(),
                    now,
                )
                .await;
        })
    }

    fn complete<'a>(
        &'a self,
        code_id: &'a str,
        csr_pem: &'a str,
    ) -> BoxFuture<'a, Result<Issued, Refusal>> {
        Box::pin(async move {
            let now = self.now();
            // The certificate first (no database), then code, station and audit entry in
            // one transaction: a failure leaves the code live.
            let station_id = new_station_id().map_err(refusal)?;
            let cert_pem = self
                .ca
                .sign_station(csr_pem, &station_id)
                .map_err(|e| Refusal::new(e.to_string()))?;
            let der = netlink::pki::first_certificate_der(&cert_pem)
                .map_err(|e| Refusal::new(e.to_string()))?;
            let patient_id = match self
                .db
                .pair_station(code_id, &station_id, &certificate_sha256_hex(&der), now)
                .await
            {
                Ok(p) => p,
                Err(HubError::Pair(_)) => {
                    return Err(Refusal::new(netlink::pairing::CODE_NOT_ACCEPTED));
                }
                Err(e) => return Err(refusal(e)),
            };
            // The station names its sessions by it; a lookup that fails only leaves it out.
            let patient_pseudonym = match self.db.patient(&patient_id).await {
                Ok(p) => p.map(|p| p.pseudonym),
                Err(e) => {
                    tracing::warn!(patient = %patient_id, "pseudonym not sent at pairing: {e}");
                    None
                }
            };
            Ok(Issued {
                station_id,
                patient_id,
                ca_pem: self.ca.pem().cert_pem.clone(),
                cert_pem,
                server_name: self.server_name.clone(),
                patient_pseudonym,
            })
        })
    }
}

/// `st-` + 16 random hex digits: a DNS label, so a certificate can name it.
fn new_station_id() -> Result<String, HubError> {
    hub_store::db::new_id("st-")
}
