//! Therapist side: a hub that accepts many stations, stores and acknowledges their summaries,
//! reports what happens as [`TherapistEvent`]s and can push a [`Regimen`] to a station.

mod backend;
pub mod budget;
mod config;
mod connection;
mod event;
mod outgoing;
mod pairing;
mod session;
pub mod station_limits;
mod upload;

use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::net::TcpListener;
use tokio::sync::{Semaphore, mpsc, watch};
use tokio::task::JoinHandle;

use crate::codec::encode_to_vec;
use crate::error::NetlinkError;
use crate::frame::{CARE_VERSION, Care, Frame, Hello, MESSAGES_VERSION, Message, Regimen};
use crate::tls::ServerTls;
use crate::transport::{OUTBOX_CAPACITY, Outbox, OutboxStats, Outgoing};

pub use backend::{BoxFuture, CheckNews, FileStore, HubStore, Peer, Refusal, SessionStore};
use budget::{ConnectionGate, EVICTION_GRACE, GateLimits};
pub use config::{
    DEFAULT_MAX_CONNECTIONS, DEFAULT_MAX_CONNECTIONS_PER_ADDRESS, DEFAULT_MAX_UNAUTHENTICATED,
    TherapistConfig,
};
use connection::accept_loop;
pub use event::TherapistEvent;
pub use upload::RECORDING_PROGRESS_EVERY;

/// Events buffered for the CLI; beyond this they are dropped (and counted), never blocking
/// the hub.
const EVENT_CAPACITY: usize = 4_096;

type SessionKey = (String, String);

/// One session's store, `None` until it is opened; locked per session (async), never held
/// across the hub-wide table's lock.
type SessionSlot = Arc<tokio::sync::Mutex<Option<Box<dyn SessionStore>>>>;

struct StationRoute {
    conn_id: u64,
    out: Outbox,
    /// The protocol version negotiated on this connection (what frames it may be sent).
    version: u16,
}

struct Hub {
    config: TherapistConfig,
    acceptor: Option<tokio_rustls::TlsAcceptor>,
    store: Arc<dyn HubStore>,
    /// SHA-256 of the hub's own TLS certificate (DER), which pairing binds to.
    certificate_sha256: Option<[u8; 32]>,
    /// Open sessions; each has its own lock, so one session's file work never waits for another's.
    sessions: Mutex<HashMap<SessionKey, SessionSlot>>,
    stations: Mutex<HashMap<String, StationRoute>>,
    events: mpsc::Sender<TherapistEvent>,
    events_dropped: AtomicU64,
    next_conn_id: AtomicU64,
    /// Admitted stations (`max_connections`); unauthenticated ones are counted by `gate`.
    connections: Arc<Semaphore>,
    /// Connections not admitted yet, per address and in all.
    gate: Arc<ConnectionGate>,
    outbox_stats: Arc<OutboxStats>,
    /// Recording bytes taken from each station today.
    daily_upload_bytes: upload::DailyBytes,
    /// Each station's summaries, paced across its connections.
    summary_pace: station_limits::Pacer,
    /// Each station's recording bytes, paced across its connections.
    upload_pace: station_limits::Pacer,
    /// Each station's upload announcements (`UploadStart`), paced across its connections.
    upload_start_pace: station_limits::Pacer,
}

/// A running hub. Dropping it stops it too; [`Self::shutdown`] also waits for connections to
/// close and their files to be synced.
pub struct TherapistServer {
    hub: Arc<Hub>,
    local_addr: SocketAddr,
    shutdown_tx: watch::Sender<bool>,
    accept_task: JoinHandle<()>,
    /// Closed (`recv` gives `None`) once the accept loop and every connection task have ended.
    tasks_done: mpsc::Receiver<()>,
}

impl TherapistServer {
    /// Validates `config`, loads TLS files, binds and starts accepting (on the current runtime),
    /// storing into files under `config.store_dir` ([`FileStore`]).
    pub async fn bind(
        config: TherapistConfig,
    ) -> Result<(Self, mpsc::Receiver<TherapistEvent>), NetlinkError> {
        config.validate()?;
        std::fs::create_dir_all(&config.store_dir).map_err(|e| {
            NetlinkError::io(format!("creating store {}", config.store_dir.display()), e)
        })?;
        let store = Arc::new(FileStore::new(config.store_dir.clone()));
        Self::bind_with_store(config, store).await
    }

    /// As [`Self::bind`], storing into `store` (`config.store_dir` is then unused).
    pub async fn bind_with_store(
        config: TherapistConfig,
        store: Arc<dyn HubStore>,
    ) -> Result<(Self, mpsc::Receiver<TherapistEvent>), NetlinkError> {
        config.validate()?;
        let acceptor = config.tls.as_ref().map(ServerTls::acceptor).transpose()?;
        let certificate_sha256 = config
            .tls
            .as_ref()
            .map(ServerTls::leaf_sha256)
            .transpose()?;
        let listener = TcpListener::bind(config.listen)
            .await
            .map_err(|e| NetlinkError::io(format!("listening on {}", config.listen), e))?;
        let local_addr = listener
            .local_addr()
            .map_err(|e| NetlinkError::io("reading the listening address", e))?;
        let (events, events_rx) = mpsc::channel(EVENT_CAPACITY);
        let (shutdown_tx, shutdown_rx) = watch::channel(false);
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: config.max_unauthenticated,
                max_per_address: config.max_connections_per_address,
                grace: EVICTION_GRACE,
            },
            "station port",
        );
        let hub = Arc::new(Hub {
            connections: Arc::new(Semaphore::new(config.max_connections)),
            gate,
            config,
            acceptor,
            store,
            certificate_sha256,
            sessions: Mutex::new(HashMap::new()),
            stations: Mutex::new(HashMap::new()),
            events,
            events_dropped: AtomicU64::new(0),
            next_conn_id: AtomicU64::new(1),
            outbox_stats: Arc::new(OutboxStats::default()),
            daily_upload_bytes: upload::DailyBytes::default(),
            summary_pace: station_limits::Pacer::default(),
            upload_pace: station_limits::Pacer::default(),
            upload_start_pace: station_limits::Pacer::default(),
        });
        tracing::info!(%local_addr, tls = hub.acceptor.is_some(), "therapist hub listening");
        let (tasks, tasks_done) = mpsc::channel(1);
        let accept_task = tokio::spawn(accept_loop(hub.clone(), listener, shutdown_rx, tasks));
        Ok((
            Self {
                hub,
                local_addr,
                shutdown_tx,
                accept_task,
                tasks_done,
            },
            events_rx,
        ))
    }

    /// The address actually bound (useful with port 0).
    pub fn local_addr(&self) -> SocketAddr {
        self.local_addr
    }

    /// Stations connected now, sorted.
    pub fn connected_stations(&self) -> Vec<String> {
        let mut ids: Vec<String> = lock(&self.hub.stations).keys().cloned().collect();
        ids.sort();
        ids
    }

    /// Connections not admitted yet (TLS handshake, waiting for the Hello, pairing).
    pub fn unauthenticated_connections(&self) -> usize {
        self.hub.gate.waiting()
    }

    /// Events dropped because the receiver did not keep up.
    pub fn events_dropped(&self) -> u64 {
        self.hub.events_dropped.load(Ordering::Relaxed)
    }

    /// The most frames ever waiting to be written to one connection: queued frames (at most
    /// [`Self::OUTBOX_CAPACITY`]) plus the one latest Ack. Bounded whatever a station does.
    pub fn outgoing_high_water(&self) -> usize {
        self.hub.outbox_stats.high_water.load(Ordering::Relaxed)
    }

    /// Acks replaced by a newer one before they were written (a slow or non-reading station).
    pub fn acks_coalesced(&self) -> u64 {
        self.hub.outbox_stats.acks_coalesced.load(Ordering::Relaxed)
    }

    /// Frames (regimens, Bye, Error) not queued because a connection's outbox was full.
    pub fn outgoing_refused(&self) -> u64 {
        self.hub.outbox_stats.refused.load(Ordering::Relaxed)
    }

    /// Frames besides the latest Ack that may wait for one connection.
    pub const OUTBOX_CAPACITY: usize = OUTBOX_CAPACITY;

    /// Queues `regimen` for the connected station `station_id`.
    ///
    /// Fails with [`NetlinkError::NotConnected`] if the station is not connected and with
    /// [`NetlinkError::Busy`] if [`Self::OUTBOX_CAPACITY`] frames already wait for it (it is
    /// not reading): try again later.
    pub fn send_regimen(&self, station_id: &str, regimen: Regimen) -> Result<(), NetlinkError> {
        let bytes = encode_to_vec(&Frame::Regimen(regimen))?;
        let stations = lock(&self.hub.stations);
        let route = stations
            .get(station_id)
            .ok_or_else(|| NetlinkError::NotConnected(station_id.to_owned()))?;
        if route.out.send(Outgoing::new(bytes.into())) {
            Ok(())
        } else {
            Err(NetlinkError::Busy(format!(
                "{OUTBOX_CAPACITY} frames already wait for station {station_id:?} (it is not \
                 reading, or has just disconnected); regimen not queued"
            )))
        }
    }

    /// Queues the therapist's `message` for the connected station `station_id`: `Ok(true)`
    /// when queued, `Ok(false)` when the station's connection was negotiated below
    /// [`MESSAGES_VERSION`] (an older station, which must never receive the frame).
    ///
    /// Fails as [`Self::send_regimen`] does.
    pub fn send_message(&self, station_id: &str, message: Message) -> Result<bool, NetlinkError> {
        let bytes = encode_to_vec(&Frame::Message(message))?;
        let stations = lock(&self.hub.stations);
        let route = stations
            .get(station_id)
            .ok_or_else(|| NetlinkError::NotConnected(station_id.to_owned()))?;
        if route.version < MESSAGES_VERSION {
            return Ok(false);
        }
        if route.out.send(Outgoing::new(bytes.into())) {
            Ok(true)
        } else {
            Err(NetlinkError::Busy(format!(
                "{OUTBOX_CAPACITY} frames already wait for station {station_id:?}; message not \
                 queued"
            )))
        }
    }

    /// Queues the clinic's pain settings `care` for the connected station `station_id`:
    /// `Ok(true)` when queued, `Ok(false)` when the station's connection was negotiated below
    /// [`CARE_VERSION`] (an older station, which must never receive the frame).
    ///
    /// Fails as [`Self::send_regimen`] does.
    pub fn send_care(&self, station_id: &str, care: Care) -> Result<bool, NetlinkError> {
        let bytes = encode_to_vec(&Frame::Care(care))?;
        let stations = lock(&self.hub.stations);
        let route = stations
            .get(station_id)
            .ok_or_else(|| NetlinkError::NotConnected(station_id.to_owned()))?;
        if route.version < CARE_VERSION {
            return Ok(false);
        }
        if route.out.send(Outgoing::new(bytes.into())) {
            Ok(true)
        } else {
            Err(NetlinkError::Busy(format!(
                "{OUTBOX_CAPACITY} frames already wait for station {station_id:?}; pain settings \
                 not queued"
            )))
        }
    }

    /// Stops accepting, tells every station (Bye), syncs their files and waits up to `timeout`
    /// for the connections to close.
    pub async fn shutdown(mut self, timeout: Duration) {
        let _ = self.shutdown_tx.send(true);
        let _ = self.accept_task.await;
        if tokio::time::timeout(timeout, self.tasks_done.recv())
            .await
            .is_err()
        {
            tracing::warn!("therapist hub: connections still open after the shutdown timeout");
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    // A panic while holding these locks cannot leave the maps inconsistent (single inserts
    // and removes), so a poisoned lock is still usable.
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Hub {
    fn emit(&self, event: TherapistEvent) {
        if self.events.try_send(event).is_err() {
            self.events_dropped.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Reports a connection refused before admission: on its own line for the first few of
    /// an interval, then only counted in the interval's summary.
    fn refuse(&self, peer: SocketAddr, reason: &'static str, error: String) {
        if self.gate.refusals().detail(reason) {
            self.emit(TherapistEvent::ProtocolError { peer, error });
        }
    }

    /// Emits the summary of refusals not reported one by one, once per interval at most
    /// (`now`: at once, at shutdown).
    fn summarise_refusals(&self, now: bool) {
        let refusals = self.gate.refusals();
        let summary = if now {
            refusals.take_summary_now()
        } else {
            refusals.take_summary()
        };
        if let Some(s) = summary {
            tracing::warn!("therapist hub: {s}");
            self.emit(TherapistEvent::Refused {
                count: s.count,
                interval_s: s.interval_s,
                reasons: s.reasons,
            });
        }
    }

    /// The session's slot, its store opened (holding only this session's lock) if no other
    /// connection has it open. The hub-wide table is locked only to find or insert the slot,
    /// never across store work.
    async fn open_session(&self, hello: &Hello, peer: Peer<'_>) -> Result<SessionSlot, Refusal> {
        // Every connection passes the store's checks, even one joining an open session.
        self.store.admit(hello, peer).await?;
        // A start far from the hub's clock would stay at the top (or bottom) of every list.
        if let Err(why) = station_limits::check_start(hello.started_unix_ms, self.store.now_ms()) {
            self.store.refused(hello, "start_time", &why).await;
            return Err(Refusal::new(why));
        }
        let key = (hello.station_id.clone(), hello.session_id.clone());
        let slot = lock(&self.sessions).entry(key).or_default().clone();
        let opened = {
            let mut guard = slot.lock().await;
            if guard.is_none() {
                self.store
                    .open_session(hello)
                    .await
                    .map(|store| *guard = Some(store))
            } else {
                Ok(())
            }
        };
        match opened {
            Ok(()) => Ok(slot),
            Err(e) => {
                // Unless another connection waits for this slot, forget it.
                self.release_session(hello, slot);
                Err(e)
            }
        }
    }

    /// The connection writing to `out` began an upload: what the therapist pushes to the
    /// station (messages, regimens) no longer goes to it, whose purpose is the recording (a
    /// station takes them during an upload too, but its live link is where they belong; one
    /// not pushed now is pushed on the station's next connection).
    fn stop_routing_to(&self, station_id: &str, out: &Outbox) {
        let mut stations = lock(&self.stations);
        if stations
            .get(station_id)
            .is_some_and(|r| r.out.same_connection(out))
        {
            stations.remove(station_id);
        }
    }

    /// Forgets a session file when its last connection ends.
    fn release_session(&self, hello: &Hello, file: SessionSlot) {
        let key = (hello.station_id.clone(), hello.session_id.clone());
        let mut sessions = lock(&self.sessions);
        // Ours and the table's: no other connection holds or waits for this session.
        if Arc::strong_count(&file) == 2 {
            sessions.remove(&key);
        }
    }
}
