//! Therapist side: a hub that accepts many stations, stores and acknowledges their summaries,
//! reports what happens as [`TherapistEvent`]s and can push a [`Regimen`] to a station.

use std::collections::HashMap;
use std::fmt;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde::{Deserialize, Serialize};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{Semaphore, mpsc, watch};
use tokio::task::JoinHandle;

use crate::codec::encode_to_vec;
use crate::error::NetlinkError;
use crate::frame::{
    Ack, Bye, ErrorFrame, Frame, Hello, MAX_MESSAGE_LEN, Regimen, Summary, printable,
};
use crate::store::{Appended, SessionFile, write_hello};
use crate::tls::{ServerTls, certificate_names_station};
use crate::transport::{BoxStream, FrameReader, Outgoing, spawn_writer};

/// Configuration of a [`TherapistServer`].
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TherapistConfig {
    /// Address to listen on.
    pub listen: SocketAddr,
    /// Root of the store: `DIR/<station_id>/<session_id>.jsonl` and `.hello.json`.
    pub store_dir: PathBuf,
    /// TLS settings; `None` means plaintext, allowed only on a loopback address.
    #[serde(default)]
    pub tls: Option<ServerTls>,
    /// Most simultaneous connections, in [1, 10 000]. Default 256.
    #[serde(default = "default_max_connections")]
    pub max_connections: usize,
    /// Time allowed for the TLS handshake and the station's Hello, ms, in [100, 600 000].
    /// Default 10 000.
    #[serde(default = "default_hello_timeout_ms")]
    pub hello_timeout_ms: u64,
    /// A connection silent for this long is closed, ms, in [1 000, 3 600 000]. Default 60 000
    /// (stations send a summary every 100 ms).
    #[serde(default = "default_idle_timeout_ms")]
    pub idle_timeout_ms: u64,
}

fn default_max_connections() -> usize {
    256
}
fn default_hello_timeout_ms() -> u64 {
    10_000
}
fn default_idle_timeout_ms() -> u64 {
    60_000
}

impl TherapistConfig {
    /// A configuration with the documented defaults.
    pub fn new(listen: SocketAddr, store_dir: impl Into<PathBuf>, tls: Option<ServerTls>) -> Self {
        Self {
            listen,
            store_dir: store_dir.into(),
            tls,
            max_connections: default_max_connections(),
            hello_timeout_ms: default_hello_timeout_ms(),
            idle_timeout_ms: default_idle_timeout_ms(),
        }
    }

    /// Checks every field; the error names the field and its allowed range.
    ///
    /// Plaintext (no `tls`) is refused unless `listen` is a loopback address.
    pub fn validate(&self) -> Result<(), NetlinkError> {
        let err = |m: String| Err(NetlinkError::Config(m));
        if self.tls.is_none() && !self.listen.ip().is_loopback() {
            return err(format!(
                "listen {} is not loopback and no tls is configured; plaintext is allowed only on \
                 127.0.0.1/::1",
                self.listen
            ));
        }
        if !(1..=10_000).contains(&self.max_connections) {
            return err(format!(
                "max_connections is {}, allowed [1, 10000]",
                self.max_connections
            ));
        }
        if !(100..=600_000).contains(&self.hello_timeout_ms) {
            return err(format!(
                "hello_timeout_ms is {}, allowed [100, 600000]",
                self.hello_timeout_ms
            ));
        }
        if !(1_000..=3_600_000).contains(&self.idle_timeout_ms) {
            return err(format!(
                "idle_timeout_ms is {}, allowed [1000, 3600000]",
                self.idle_timeout_ms
            ));
        }
        if self.store_dir.as_os_str().is_empty() {
            return err("store_dir is empty".into());
        }
        Ok(())
    }
}

/// Something that happened at the hub, for the CLI to print.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum TherapistEvent {
    /// A station connected and said Hello.
    Connected {
        /// Its address.
        peer: SocketAddr,
        /// Its Hello.
        hello: Hello,
    },
    /// A new (not duplicate) summary was stored.
    Summary {
        /// The station it came from.
        station_id: String,
        /// The summary.
        summary: Summary,
    },
    /// A station's connection ended.
    Disconnected {
        /// The station.
        station_id: String,
        /// Its session.
        session_id: String,
        /// Why, for humans (`bye: …` for an orderly end).
        reason: String,
    },
    /// A peer broke the protocol (or the TLS handshake); its connection was closed.
    ProtocolError {
        /// Its address.
        peer: SocketAddr,
        /// What was wrong.
        error: String,
    },
}

impl fmt::Display for TherapistEvent {
    /// One line per event, for a live console.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Connected { peer, hello } => write!(
                f,
                "[{}] connected from {peer}: patient {} session {} exercise {} ({})",
                hello.station_id,
                hello.patient_id,
                hello.session_id,
                hello.exercise,
                hello.software_version
            ),
            Self::Summary {
                station_id,
                summary: s,
            } => write!(
                f,
                "[{station_id}] t={:7.1} s seq={:<6} speed={:5.2} m/s lateral={:+.3} m \
                 rms={:.3} m max={:.3} m in-lane={:5.1} % |torque|max={:.2} N·m p99={:.0} µs",
                s.t_s,
                s.seq,
                s.speed_m_s,
                s.lateral_m,
                s.rms_lateral_m,
                s.max_lateral_m,
                s.pct_in_lane,
                s.max_abs_torque_nm,
                s.loop_p99_us
            ),
            Self::Disconnected {
                station_id,
                session_id,
                reason,
            } => write!(
                f,
                "[{station_id}] session {session_id} disconnected: {reason}"
            ),
            Self::ProtocolError { peer, error } => write!(f, "[{peer}] protocol error: {error}"),
        }
    }
}

/// Events buffered for the CLI; beyond this they are dropped (and counted), never blocking
/// the hub.
const EVENT_CAPACITY: usize = 4_096;

type SessionKey = (String, String);

struct StationRoute {
    conn_id: u64,
    out: mpsc::UnboundedSender<Outgoing>,
}

struct Hub {
    config: TherapistConfig,
    acceptor: Option<tokio_rustls::TlsAcceptor>,
    sessions: Mutex<HashMap<SessionKey, Arc<Mutex<SessionFile>>>>,
    stations: Mutex<HashMap<String, StationRoute>>,
    events: mpsc::Sender<TherapistEvent>,
    events_dropped: AtomicU64,
    next_conn_id: AtomicU64,
    connections: Arc<Semaphore>,
}

/// A running hub. Dropping it stops it too; [`Self::shutdown`] also waits for connections to
/// close and their files to be synced.
pub struct TherapistServer {
    hub: Arc<Hub>,
    local_addr: SocketAddr,
    shutdown_tx: watch::Sender<bool>,
    accept_task: JoinHandle<()>,
}

impl TherapistServer {
    /// Validates `config`, loads TLS files, binds and starts accepting (on the current runtime).
    pub async fn bind(
        config: TherapistConfig,
    ) -> Result<(Self, mpsc::Receiver<TherapistEvent>), NetlinkError> {
        config.validate()?;
        let acceptor = config.tls.as_ref().map(ServerTls::acceptor).transpose()?;
        std::fs::create_dir_all(&config.store_dir).map_err(|e| {
            NetlinkError::io(format!("creating store {}", config.store_dir.display()), e)
        })?;
        let listener = TcpListener::bind(config.listen)
            .await
            .map_err(|e| NetlinkError::io(format!("listening on {}", config.listen), e))?;
        let local_addr = listener
            .local_addr()
            .map_err(|e| NetlinkError::io("reading the listening address", e))?;
        let (events, events_rx) = mpsc::channel(EVENT_CAPACITY);
        let (shutdown_tx, shutdown_rx) = watch::channel(false);
        let hub = Arc::new(Hub {
            connections: Arc::new(Semaphore::new(config.max_connections)),
            config,
            acceptor,
            sessions: Mutex::new(HashMap::new()),
            stations: Mutex::new(HashMap::new()),
            events,
            events_dropped: AtomicU64::new(0),
            next_conn_id: AtomicU64::new(1),
        });
        tracing::info!(%local_addr, tls = hub.acceptor.is_some(), "therapist hub listening");
        let accept_task = tokio::spawn(accept_loop(hub.clone(), listener, shutdown_rx));
        Ok((
            Self {
                hub,
                local_addr,
                shutdown_tx,
                accept_task,
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

    /// Events dropped because the receiver did not keep up.
    pub fn events_dropped(&self) -> u64 {
        self.hub.events_dropped.load(Ordering::Relaxed)
    }

    /// Queues `regimen` for the connected station `station_id`.
    pub fn send_regimen(&self, station_id: &str, regimen: Regimen) -> Result<(), NetlinkError> {
        let bytes = encode_to_vec(&Frame::Regimen(regimen))?;
        let stations = lock(&self.hub.stations);
        let route = stations
            .get(station_id)
            .ok_or_else(|| NetlinkError::NotConnected(station_id.to_owned()))?;
        route
            .out
            .send(Outgoing::new(bytes.into()))
            .map_err(|_| NetlinkError::NotConnected(station_id.to_owned()))
    }

    /// Stops accepting, tells every station (Bye), syncs their files and waits up to `timeout`
    /// for the connections to close.
    pub async fn shutdown(self, timeout: Duration) {
        let _ = self.shutdown_tx.send(true);
        let _ = self.accept_task.await;
        let all = u32::try_from(self.hub.config.max_connections).unwrap_or(u32::MAX);
        if tokio::time::timeout(timeout, self.hub.connections.acquire_many(all))
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

    fn open_session(&self, hello: &Hello) -> Result<Arc<Mutex<SessionFile>>, NetlinkError> {
        let key = (hello.station_id.clone(), hello.session_id.clone());
        let mut sessions = lock(&self.sessions);
        if let Some(file) = sessions.get(&key) {
            return Ok(file.clone());
        }
        let file = SessionFile::open(&self.config.store_dir, &hello.station_id, &hello.session_id)?;
        let file = Arc::new(Mutex::new(file));
        sessions.insert(key, file.clone());
        Ok(file)
    }

    /// Forgets a session file when its last connection ends.
    fn release_session(&self, hello: &Hello, file: Arc<Mutex<SessionFile>>) {
        let key = (hello.station_id.clone(), hello.session_id.clone());
        let mut sessions = lock(&self.sessions);
        if Arc::strong_count(&file) == 2 {
            sessions.remove(&key);
        }
    }
}

async fn accept_loop(hub: Arc<Hub>, listener: TcpListener, mut shutdown: watch::Receiver<bool>) {
    loop {
        tokio::select! {
            _ = shutdown.changed() => break,
            accepted = listener.accept() => match accepted {
                Ok((tcp, peer)) => {
                    let Ok(permit) = hub.connections.clone().try_acquire_owned() else {
                        hub.emit(TherapistEvent::ProtocolError {
                            peer,
                            error: format!(
                                "refused: already {} connections (max_connections)",
                                hub.config.max_connections
                            ),
                        });
                        continue;
                    };
                    let _ = tcp.set_nodelay(true);
                    let hub = hub.clone();
                    let shutdown = shutdown.clone();
                    tokio::spawn(async move {
                        serve(hub, tcp, peer, shutdown).await;
                        drop(permit);
                    });
                }
                Err(e) => {
                    // Typically EMFILE; back off briefly instead of spinning.
                    tracing::warn!(error = %e, "therapist hub: accept failed");
                    tokio::time::sleep(Duration::from_millis(100)).await;
                }
            },
        }
    }
}

fn error_outgoing(message: &str) -> Option<Outgoing> {
    let message = printable(message, MAX_MESSAGE_LEN);
    encode_to_vec(&Frame::Error(ErrorFrame { message }))
        .ok()
        .map(|b| Outgoing::new(b.into()))
}

fn frame_outgoing(frame: &Frame) -> Option<Outgoing> {
    match encode_to_vec(frame) {
        Ok(b) => Some(Outgoing::new(b.into())),
        Err(e) => {
            tracing::error!(error = %e, "therapist hub: cannot encode {}", frame.kind());
            None
        }
    }
}

/// Serves one connection from TLS handshake to close. Never panics on peer input.
async fn serve(
    hub: Arc<Hub>,
    tcp: TcpStream,
    peer: SocketAddr,
    mut shutdown: watch::Receiver<bool>,
) {
    let hello_timeout = Duration::from_millis(hub.config.hello_timeout_ms);
    let (stream, client_cert): (BoxStream, _) = match &hub.acceptor {
        None => (Box::new(tcp), None),
        Some(acceptor) => match tokio::time::timeout(hello_timeout, acceptor.accept(tcp)).await {
            Ok(Ok(tls)) => {
                let cert = tls
                    .get_ref()
                    .1
                    .peer_certificates()
                    .and_then(|chain| chain.first())
                    .map(|leaf| leaf.clone().into_owned());
                (Box::new(tls), cert)
            }
            Ok(Err(e)) => {
                hub.emit(TherapistEvent::ProtocolError {
                    peer,
                    error: format!("TLS handshake failed: {e}"),
                });
                return;
            }
            Err(_) => {
                hub.emit(TherapistEvent::ProtocolError {
                    peer,
                    error: "TLS handshake timed out".into(),
                });
                return;
            }
        },
    };
    let (rd, wr) = tokio::io::split(stream);
    let (out, out_rx) = mpsc::unbounded_channel();
    let mut writer = spawn_writer(wr, out_rx);
    let mut reader = FrameReader::new(rd);

    let hello = match tokio::time::timeout(hello_timeout, reader.next_frame()).await {
        Ok(Ok(Some(Frame::Hello(hello)))) => Ok(hello),
        Ok(Ok(Some(other))) => Err(format!("expected Hello first, got {}", other.kind())),
        Ok(Ok(None)) => Err("connection closed before Hello".into()),
        Ok(Err(e)) => Err(e.to_string()),
        Err(_) => Err(format!("no Hello within {} ms", hello_timeout.as_millis())),
    };
    let requires_identity = hub
        .config
        .tls
        .as_ref()
        .is_some_and(|t| t.client_ca_pem_path.is_some());
    let opened = hello.and_then(|hello| {
        if requires_identity {
            let cert = client_cert
                .as_ref()
                .ok_or("no client certificate presented")?;
            certificate_names_station(cert, &hello.station_id)?;
        }
        // Hello first: if it fails, no session file has been registered yet.
        write_hello(&hub.config.store_dir, &hello)
            .map_err(|e| format!("cannot store Hello: {e}"))?;
        let file = hub
            .open_session(&hello)
            .map_err(|e| format!("cannot open the session store: {e}"))?;
        Ok((hello, file))
    });
    let (hello, file) = match opened {
        Ok(v) => v,
        Err(error) => {
            if let Some(o) = error_outgoing(&error) {
                let _ = out.send(o);
            }
            hub.emit(TherapistEvent::ProtocolError { peer, error });
            close(out, writer).await;
            return;
        }
    };

    let conn_id = hub.next_conn_id.fetch_add(1, Ordering::Relaxed);
    lock(&hub.stations).insert(
        hello.station_id.clone(),
        StationRoute {
            conn_id,
            out: out.clone(),
        },
    );
    hub.emit(TherapistEvent::Connected {
        peer,
        hello: hello.clone(),
    });
    let last_stored = lock(&file).last_seq();
    if let Some(seq) = last_stored {
        // Tell a reconnecting station what is already stored, so it need not resend it.
        let ack = Frame::Ack(Ack {
            session_id: hello.session_id.clone(),
            seq,
        });
        if let Some(o) = frame_outgoing(&ack) {
            let _ = out.send(o);
        }
    }

    let idle = Duration::from_millis(hub.config.idle_timeout_ms);
    let reason = loop {
        tokio::select! {
            _ = shutdown.changed() => {
                let bye = Frame::Bye(Bye {
                    session_id: hello.session_id.clone(),
                    reason: "therapist hub shutting down".into(),
                    final_seq: lock(&file).last_seq(),
                });
                if let Some(o) = frame_outgoing(&bye) {
                    let _ = out.send(o);
                }
                break "therapist hub shut down".to_owned();
            }
            r = &mut writer => {
                break match r {
                    Ok(Err(e)) => e.to_string(),
                    _ => "writer stopped".to_owned(),
                };
            }
            frame = tokio::time::timeout(idle, reader.next_frame()) => {
                let frame = match frame {
                    Err(_) => break format!("nothing received for {} ms", idle.as_millis()),
                    Ok(Ok(None)) => break "connection closed by station".to_owned(),
                    Ok(Ok(Some(frame))) => frame,
                    Ok(Err(e)) => {
                        let error = e.to_string();
                        if let Some(o) = error_outgoing(&error) {
                            let _ = out.send(o);
                        }
                        hub.emit(TherapistEvent::ProtocolError { peer, error: error.clone() });
                        break format!("protocol error: {error}");
                    }
                };
                match handle_frame(&hub, &hello, &file, frame).await {
                    Ok(Reply::Ack(ack)) => {
                        if let Some(o) = frame_outgoing(&ack) {
                            let _ = out.send(o);
                        }
                    }
                    Ok(Reply::Bye(bye, why)) => {
                        if let Some(o) = frame_outgoing(&bye) {
                            let _ = out.send(o);
                        }
                        break why;
                    }
                    Err(Failure::Protocol(error)) => {
                        if let Some(o) = error_outgoing(&error) {
                            let _ = out.send(o);
                        }
                        hub.emit(TherapistEvent::ProtocolError { peer, error: error.clone() });
                        break format!("protocol error: {error}");
                    }
                    Err(Failure::Closed(why)) => break why,
                }
            }
        }
    };

    {
        let mut stations = lock(&hub.stations);
        if stations
            .get(&hello.station_id)
            .is_some_and(|r| r.conn_id == conn_id)
        {
            stations.remove(&hello.station_id);
        }
    }
    if let Err(e) = sync_file(&file).await {
        tracing::error!(error = %e, "therapist hub: fsync failed");
    }
    hub.release_session(&hello, file);
    hub.emit(TherapistEvent::Disconnected {
        station_id: hello.station_id.clone(),
        session_id: hello.session_id.clone(),
        reason,
    });
    close(out, writer).await;
}

/// Lets queued frames leave (bounded), then drops the connection.
async fn close(
    out: mpsc::UnboundedSender<Outgoing>,
    mut writer: JoinHandle<Result<(), NetlinkError>>,
) {
    drop(out);
    if tokio::time::timeout(Duration::from_secs(1), &mut writer)
        .await
        .is_err()
    {
        writer.abort();
    }
}

enum Reply {
    Ack(Frame),
    Bye(Frame, String),
}

enum Failure {
    /// The station broke the protocol.
    Protocol(String),
    /// The connection ends for another reason.
    Closed(String),
}

async fn handle_frame(
    hub: &Hub,
    hello: &Hello,
    file: &Arc<Mutex<SessionFile>>,
    frame: Frame,
) -> Result<Reply, Failure> {
    match frame {
        Frame::Summary(summary) => {
            if summary.session_id != hello.session_id {
                return Err(Failure::Protocol(format!(
                    "summary for session {:?} on a connection for session {:?}",
                    summary.session_id, hello.session_id
                )));
            }
            let (appended, last) = {
                let mut f = lock(file);
                let appended = f
                    .append(&summary)
                    .map_err(|e| Failure::Closed(format!("storage failure: {e}")))?;
                (appended, f.last_seq().unwrap_or(summary.seq))
            };
            if appended == Appended::Stored {
                hub.emit(TherapistEvent::Summary {
                    station_id: hello.station_id.clone(),
                    summary,
                });
            }
            Ok(Reply::Ack(Frame::Ack(Ack {
                session_id: hello.session_id.clone(),
                seq: last,
            })))
        }
        Frame::Bye(bye) => {
            if bye.session_id != hello.session_id {
                return Err(Failure::Protocol(format!(
                    "Bye for session {:?} on a connection for session {:?}",
                    bye.session_id, hello.session_id
                )));
            }
            sync_file(file)
                .await
                .map_err(|e| Failure::Closed(format!("storage failure: {e}")))?;
            let stored = lock(file).last_seq();
            Ok(Reply::Bye(
                Frame::Bye(Bye {
                    session_id: hello.session_id.clone(),
                    reason: "stored".into(),
                    final_seq: stored,
                }),
                format!("bye: {}", bye.reason),
            ))
        }
        Frame::Error(e) => Err(Failure::Closed(format!(
            "station reported an error: {}",
            e.message
        ))),
        other => Err(Failure::Protocol(format!(
            "unexpected {} frame from a station",
            other.kind()
        ))),
    }
}

/// fsyncs a session file on the blocking pool.
async fn sync_file(file: &Arc<Mutex<SessionFile>>) -> Result<(), NetlinkError> {
    let handle = lock(file).try_clone_file()?;
    tokio::task::spawn_blocking(move || handle.sync_data())
        .await
        .map_err(|e| NetlinkError::Protocol(format!("fsync task failed: {e}")))?
        .map_err(|e| NetlinkError::io("fsync of a session file", e))
}
