//! Station side: a store-and-forward link that never blocks the caller.
//!
//! The station hands summaries to a [`SummarySender`] (a bounded channel, `try_send`). A task on
//! the station's tokio runtime moves them into a queue of unacknowledged summaries, (re)connects
//! with exponential backoff, sends `Hello` and then everything unacknowledged, and drops
//! summaries from the queue only when the hub's cumulative `Ack` covers them. After a
//! reconnect everything unacknowledged is sent again; the hub drops what it already stored, so
//! the store holds each summary exactly once.

use std::collections::VecDeque;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde::{Deserialize, Serialize};
use tokio::net::TcpStream;
use tokio::sync::{mpsc, oneshot};
use tokio::task::JoinHandle;
use tokio::time::Instant;

use crate::codec::encode_to_vec;
use crate::error::NetlinkError;
use crate::frame::{Bye, ErrorFrame, Frame, Hello, Regimen, Summary};
use crate::tls::ClientTls;
use crate::transport::{BoxStream, FrameReader, Outgoing, spawn_writer};

/// Reconnection backoff: the delay starts at `initial_ms` and doubles after each failed
/// attempt up to `max_ms`; it resets once a connection gets an acknowledgement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Backoff {
    /// First delay, ms, in [1, 60 000].
    pub initial_ms: u64,
    /// Largest delay, ms, in [`initial_ms`, 600 000].
    pub max_ms: u64,
}

impl Default for Backoff {
    fn default() -> Self {
        Self {
            initial_ms: 200,
            max_ms: 5_000,
        }
    }
}

/// Configuration of a [`StationLink`].
#[derive(Debug, Clone, PartialEq)]
pub struct StationLinkConfig {
    /// The therapist hub's address.
    pub addr: SocketAddr,
    /// TLS settings; `None` means plaintext, allowed only to a loopback address.
    pub tls: Option<ClientTls>,
    /// Sent first on every connection; its `session_id` is the session of every summary.
    pub hello: Hello,
    /// Most unacknowledged summaries kept, in [1, 10 000 000]; beyond it new ones are dropped
    /// and counted. Default 100 000 (2.8 h at 10 Hz, about 40 MB).
    pub max_pending: usize,
    /// Capacity of the channel from [`SummarySender`] to the link task, in [1, 1 000 000].
    /// Default 4 096 (almost 7 minutes at 10 Hz, should the task ever be starved).
    pub channel_capacity: usize,
    /// Reconnection backoff.
    pub reconnect: Backoff,
    /// Limit on a TCP connect plus TLS handshake, ms, in [100, 60 000]. Default 5 000.
    pub connect_timeout_ms: u64,
    /// A connection with unacknowledged summaries and nothing heard from the hub for this
    /// long is considered dead and re-established, ms, in [1 000, 600 000]. Default 15 000.
    pub ack_timeout_ms: u64,
}

impl StationLinkConfig {
    /// A configuration with the documented defaults.
    pub fn new(addr: SocketAddr, tls: Option<ClientTls>, hello: Hello) -> Self {
        Self {
            addr,
            tls,
            hello,
            max_pending: 100_000,
            channel_capacity: 4_096,
            reconnect: Backoff::default(),
            connect_timeout_ms: 5_000,
            ack_timeout_ms: 15_000,
        }
    }

    /// Checks every field; the error names the field and its allowed range.
    ///
    /// Plaintext (no `tls`) is refused unless `addr` is a loopback address: summaries are
    /// health data and must be encrypted in transit.
    pub fn validate(&self) -> Result<(), NetlinkError> {
        let err = |m: String| Err(NetlinkError::Config(m));
        self.hello
            .validate()
            .map_err(|m| NetlinkError::Config(format!("hello: {m}")))?;
        if self.tls.is_none() && !self.addr.ip().is_loopback() {
            return err(format!(
                "addr {} is not loopback and no tls is configured; plaintext is allowed only to \
                 127.0.0.1/::1",
                self.addr
            ));
        }
        if !(1..=10_000_000).contains(&self.max_pending) {
            return err(format!(
                "max_pending is {}, allowed [1, 10000000]",
                self.max_pending
            ));
        }
        if !(1..=1_000_000).contains(&self.channel_capacity) {
            return err(format!(
                "channel_capacity is {}, allowed [1, 1000000]",
                self.channel_capacity
            ));
        }
        let b = self.reconnect;
        if !(1..=60_000).contains(&b.initial_ms) {
            return err(format!(
                "reconnect.initial_ms is {}, allowed [1, 60000]",
                b.initial_ms
            ));
        }
        if !(b.initial_ms..=600_000).contains(&b.max_ms) {
            return err(format!(
                "reconnect.max_ms is {}, allowed [reconnect.initial_ms = {}, 600000]",
                b.max_ms, b.initial_ms
            ));
        }
        if !(100..=60_000).contains(&self.connect_timeout_ms) {
            return err(format!(
                "connect_timeout_ms is {}, allowed [100, 60000]",
                self.connect_timeout_ms
            ));
        }
        if !(1_000..=600_000).contains(&self.ack_timeout_ms) {
            return err(format!(
                "ack_timeout_ms is {}, allowed [1000, 600000]",
                self.ack_timeout_ms
            ));
        }
        Ok(())
    }
}

/// A snapshot of the link's counters.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LinkStats {
    /// A connection to the hub is established (TCP and TLS up, Hello queued first).
    pub connected: bool,
    /// Summaries written to a connection for the first time.
    pub sent: u64,
    /// Summaries acknowledged by the hub (stored there).
    pub acked: u64,
    /// Summaries written again after a reconnect.
    pub resent: u64,
    /// Summaries queued but not yet acknowledged. After `finish`: not delivered.
    pub pending: u64,
    /// Summaries dropped before queuing (channel or queue full, link finished).
    pub dropped: u64,
    /// Summaries refused by [`SummarySender::send`] as invalid.
    pub rejected: u64,
    /// Failed connection attempts (TCP connect or TLS handshake).
    pub connect_failures: u64,
    /// Connections established.
    pub connections: u64,
    /// Regimens received from the hub.
    pub regimens_received: u64,
    /// The hub confirmed the end of the session (Bye answered, file synced).
    pub bye_acknowledged: bool,
    /// The most recent error, for humans.
    pub last_error: Option<String>,
}

#[derive(Debug, Default)]
struct Shared {
    connected: AtomicBool,
    sent: AtomicU64,
    acked: AtomicU64,
    resent: AtomicU64,
    pending: AtomicU64,
    dropped: AtomicU64,
    rejected: AtomicU64,
    connect_failures: AtomicU64,
    connections: AtomicU64,
    regimens_received: AtomicU64,
    bye_acknowledged: AtomicBool,
    last_error: Mutex<Option<String>>,
}

impl Shared {
    fn bump(counter: &AtomicU64) {
        counter.fetch_add(1, Ordering::Relaxed);
    }

    fn set_error(&self, message: String) {
        tracing::warn!(error = %message, "therapist link");
        if let Ok(mut slot) = self.last_error.lock() {
            *slot = Some(message);
        }
    }

    fn snapshot(&self) -> LinkStats {
        let get = |c: &AtomicU64| c.load(Ordering::Relaxed);
        LinkStats {
            connected: self.connected.load(Ordering::Relaxed),
            sent: get(&self.sent),
            acked: get(&self.acked),
            resent: get(&self.resent),
            pending: get(&self.pending),
            dropped: get(&self.dropped),
            rejected: get(&self.rejected),
            connect_failures: get(&self.connect_failures),
            connections: get(&self.connections),
            regimens_received: get(&self.regimens_received),
            bye_acknowledged: self.bye_acknowledged.load(Ordering::Relaxed),
            last_error: self.last_error.lock().ok().and_then(|e| e.clone()),
        }
    }
}

/// Why [`SummarySender::send`] did not queue a summary.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SendError {
    /// A field is invalid (the message names it); counted in [`LinkStats::rejected`].
    #[error("summary rejected: {0}")]
    Invalid(String),
    /// The summary belongs to another session than the link's Hello.
    #[error("summary session_id {found:?} is not the link's session {expected:?}")]
    WrongSession {
        /// The link's session.
        expected: String,
        /// The summary's session.
        found: String,
    },
    /// Sequence numbers must strictly increase.
    #[error("summary seq {seq} is not above the previous seq {previous}")]
    SeqNotIncreasing {
        /// The refused sequence number.
        seq: u64,
        /// The previous one.
        previous: u64,
    },
    /// The channel to the link task is full; counted in [`LinkStats::dropped`].
    #[error("link channel full; summary dropped")]
    Full,
    /// The link has finished; counted in [`LinkStats::dropped`].
    #[error("link finished; summary dropped")]
    Closed,
}

/// An encoded summary on its way to the link task.
struct Queued {
    seq: u64,
    bytes: Arc<[u8]>,
}

/// The station's handle for submitting summaries. Never waits on the network.
///
/// `Sync`: it may be shared (e.g. in an `Arc`) and used through `&self`.
pub struct SummarySender {
    tx: mpsc::Sender<Queued>,
    shared: Arc<Shared>,
    session_id: String,
    /// Last accepted seq. Held while queuing, so concurrent callers cannot queue out of order
    /// (the lock is uncontended in the intended one-thread use and never held across I/O).
    previous_seq: Mutex<Option<u64>>,
}

impl SummarySender {
    /// Validates, encodes and queues `summary` without waiting.
    ///
    /// Summaries must belong to the link's session and have strictly increasing `seq`.
    pub fn send(&self, summary: Summary) -> Result<(), SendError> {
        if summary.session_id != self.session_id {
            Shared::bump(&self.shared.rejected);
            return Err(SendError::WrongSession {
                expected: self.session_id.clone(),
                found: summary.session_id,
            });
        }
        let seq = summary.seq;
        let bytes = encode_to_vec(&Frame::Summary(summary)).map_err(|e| {
            Shared::bump(&self.shared.rejected);
            SendError::Invalid(e.to_string())
        })?;
        let mut previous_seq = self
            .previous_seq
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(previous) = previous_seq.filter(|&p| seq <= p) {
            Shared::bump(&self.shared.rejected);
            return Err(SendError::SeqNotIncreasing { seq, previous });
        }
        *previous_seq = Some(seq);
        let queued = Queued {
            seq,
            bytes: bytes.into(),
        };
        self.tx.try_send(queued).map_err(|e| {
            Shared::bump(&self.shared.dropped);
            match e {
                mpsc::error::TrySendError::Full(_) => {
                    self.shared
                        .set_error(format!("link channel full; summary {seq} dropped"));
                    SendError::Full
                }
                mpsc::error::TrySendError::Closed(_) => SendError::Closed,
            }
        })
    }

    /// Counters of the link (same as [`StationLink::stats`]).
    pub fn stats(&self) -> LinkStats {
        self.shared.snapshot()
    }
}

struct Finish {
    reason: String,
    deadline: Instant,
}

/// The running link; poll it for regimens, read its stats, finish it at the end of a session.
pub struct StationLink {
    shared: Arc<Shared>,
    finish_tx: Option<oneshot::Sender<Finish>>,
    task: JoinHandle<()>,
    regimens: mpsc::Receiver<Regimen>,
}

/// Regimens buffered between the link task and the station's poll.
const REGIMEN_CAPACITY: usize = 16;

impl StationLink {
    /// Validates `config`, loads the TLS files and starts the link task on `handle`.
    pub fn spawn(
        handle: &tokio::runtime::Handle,
        config: StationLinkConfig,
    ) -> Result<(SummarySender, StationLink), NetlinkError> {
        config.validate()?;
        let tls = config.tls.as_ref().map(ClientTls::connector).transpose()?;
        let hello_bytes: Arc<[u8]> = encode_to_vec(&Frame::Hello(config.hello.clone()))?.into();
        let shared = Arc::new(Shared::default());
        let (tx, rx) = mpsc::channel(config.channel_capacity);
        let (finish_tx, finish_rx) = oneshot::channel();
        let (regimen_tx, regimens) = mpsc::channel(REGIMEN_CAPACITY);
        let sender = SummarySender {
            tx,
            shared: shared.clone(),
            session_id: config.hello.session_id.clone(),
            previous_seq: Mutex::new(None),
        };
        let task = LinkTask {
            tls,
            hello_bytes,
            shared: shared.clone(),
            rx,
            rx_open: true,
            finish_rx,
            finish_rx_open: true,
            finishing: None,
            pending: VecDeque::new(),
            last_produced_seq: None,
            regimen_tx,
            config,
        };
        let task = handle.spawn(task.run());
        Ok((
            sender,
            StationLink {
                shared,
                finish_tx: Some(finish_tx),
                task,
                regimens,
            },
        ))
    }

    /// Counters of the link; cheap (atomics and one short lock), safe from any thread.
    pub fn stats(&self) -> LinkStats {
        self.shared.snapshot()
    }

    /// A regimen received from the therapist, if any. The station must validate it.
    pub fn try_recv_regimen(&mut self) -> Option<Regimen> {
        self.regimens.try_recv().ok()
    }

    /// Ends the session: delivers what is pending, sends `Bye` and waits for the hub's reply,
    /// giving up after `timeout`. The returned stats say honestly what was not delivered
    /// ([`LinkStats::pending`]) and whether the hub confirmed ([`LinkStats::bye_acknowledged`]).
    pub async fn finish(self, timeout: Duration) -> LinkStats {
        self.finish_with_reason("session complete", timeout).await
    }

    /// [`Self::finish`] with the reason sent in `Bye` (control characters become spaces, cut
    /// to 256 bytes).
    pub async fn finish_with_reason(mut self, reason: &str, timeout: Duration) -> LinkStats {
        let deadline = Instant::now() + timeout;
        if let Some(tx) = self.finish_tx.take() {
            let _ = tx.send(Finish {
                reason: crate::frame::printable(reason, crate::frame::MAX_TEXT_LEN),
                deadline,
            });
        }
        // The task honours the deadline itself; the grace only covers its last bookkeeping.
        let grace = Duration::from_millis(200);
        if tokio::time::timeout_at(deadline + grace, &mut self.task)
            .await
            .is_err()
        {
            self.task.abort();
            self.shared
                .set_error("link task did not stop by the finish deadline; aborted".into());
        }
        self.shared.connected.store(false, Ordering::Relaxed);
        self.shared.snapshot()
    }

    /// [`Self::finish`] for a thread outside the runtime (it blocks on `handle`; calling it
    /// from a runtime thread panics, as `Handle::block_on` does).
    pub fn finish_blocking(self, handle: &tokio::runtime::Handle, timeout: Duration) -> LinkStats {
        handle.block_on(self.finish(timeout))
    }
}

struct Pending {
    seq: u64,
    bytes: Arc<[u8]>,
    written: Arc<AtomicBool>,
}

/// How a connection ended.
enum ConnEnd {
    /// The session is over (Bye answered, deadline reached or link dropped).
    Done,
    /// The connection broke; `progress` is true if an Ack arrived on it.
    Lost { error: NetlinkError, progress: bool },
}

struct LinkTask {
    config: StationLinkConfig,
    tls: Option<(
        tokio_rustls::TlsConnector,
        rustls::pki_types::ServerName<'static>,
    )>,
    hello_bytes: Arc<[u8]>,
    shared: Arc<Shared>,
    rx: mpsc::Receiver<Queued>,
    rx_open: bool,
    finish_rx: oneshot::Receiver<Finish>,
    finish_rx_open: bool,
    finishing: Option<Finish>,
    pending: VecDeque<Pending>,
    last_produced_seq: Option<u64>,
    regimen_tx: mpsc::Sender<Regimen>,
}

/// A pause in [delay/2, delay], spread by a hash of the station id and attempt number, so
/// that many stations reconnecting to a restarted hub do not retry in lock-step. Deterministic
/// (no clock, no random source) so a given station's behaviour is reproducible.
fn jittered(delay: Duration, station_id: &str, attempt: u64) -> Duration {
    use std::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    (station_id, attempt).hash(&mut hasher);
    let fraction = (hasher.finish() >> 11) as f64 / (1u64 << 53) as f64;
    delay.mul_f64(0.5 + 0.5 * fraction)
}

/// An instant far enough away to stand for "never".
fn far_future() -> Instant {
    Instant::now() + Duration::from_secs(86_400 * 365)
}

impl LinkTask {
    async fn run(mut self) {
        let initial = Duration::from_millis(self.config.reconnect.initial_ms);
        let max = Duration::from_millis(self.config.reconnect.max_ms);
        let mut delay = initial;
        let mut attempt = 0u64;
        while !self.should_stop() {
            match self.connect().await {
                Some(Ok(stream)) => {
                    Shared::bump(&self.shared.connections);
                    let end = self.run_connection(stream).await;
                    if let ConnEnd::Lost { error, progress } = &end {
                        self.shared.set_error(error.to_string());
                        if *progress {
                            delay = initial;
                        }
                    }
                    self.shared.connected.store(false, Ordering::Relaxed);
                    if let ConnEnd::Done = end {
                        break;
                    }
                }
                Some(Err(error)) => {
                    Shared::bump(&self.shared.connect_failures);
                    self.shared.set_error(error.to_string());
                }
                None => break,
            }
            attempt += 1;
            let pause = jittered(delay, &self.config.hello.station_id, attempt);
            if self.should_stop() || !self.wait(pause).await {
                break;
            }
            delay = (delay * 2).min(max);
        }
        self.drain_channel();
        self.update_pending();
        if !self.pending.is_empty() {
            let cause = self
                .shared
                .snapshot()
                .last_error
                .map_or_else(String::new, |e| format!("; last error: {e}"));
            self.shared.set_error(format!(
                "{} summaries not delivered to the therapist (oldest seq {}){cause}",
                self.pending.len(),
                self.pending.front().map_or(0, |p| p.seq)
            ));
        }
    }

    /// True once the link was dropped or the finish deadline has passed.
    fn should_stop(&self) -> bool {
        (!self.finish_rx_open && self.finishing.is_none())
            || self
                .finishing
                .as_ref()
                .is_some_and(|f| Instant::now() >= f.deadline)
    }

    fn deadline(&self) -> Instant {
        self.finishing
            .as_ref()
            .map_or_else(far_future, |f| f.deadline)
    }

    fn update_pending(&self) {
        self.shared
            .pending
            .store(self.pending.len() as u64, Ordering::Relaxed);
    }

    /// Moves a summary from the channel into the queue. Returns true if the queue was empty.
    fn on_queued(&mut self, queued: Option<Queued>) -> bool {
        let Some(q) = queued else {
            // Every SummarySender is gone; nothing more will come.
            self.rx_open = false;
            return false;
        };
        self.last_produced_seq = Some(q.seq);
        if self.pending.len() >= self.config.max_pending {
            Shared::bump(&self.shared.dropped);
            self.shared.set_error(format!(
                "store-and-forward queue full ({} summaries); summary {} dropped",
                self.pending.len(),
                q.seq
            ));
            return false;
        }
        let was_empty = self.pending.is_empty();
        self.pending.push_back(Pending {
            seq: q.seq,
            bytes: q.bytes,
            written: Arc::new(AtomicBool::new(false)),
        });
        self.update_pending();
        was_empty
    }

    fn drain_channel(&mut self) {
        while let Ok(q) = self.rx.try_recv() {
            self.on_queued(Some(q));
        }
    }

    /// Handles the finish command (or the link being dropped: `Err`).
    fn on_finish(&mut self, finish: Result<Finish, oneshot::error::RecvError>) {
        self.finish_rx_open = false;
        if let Ok(f) = finish {
            // Everything sent before finish is in the channel; later sends fail as Closed.
            self.rx.close();
            self.drain_channel();
            self.rx_open = false;
            self.finishing = Some(f);
        }
    }

    /// Waits `delay` while still accepting summaries. False if the link should stop.
    async fn wait(&mut self, delay: Duration) -> bool {
        let until = Instant::now() + delay;
        loop {
            let wake = until.min(self.deadline());
            tokio::select! {
                () = tokio::time::sleep_until(wake) => return !self.should_stop(),
                q = self.rx.recv(), if self.rx_open => { self.on_queued(q); }
                f = &mut self.finish_rx, if self.finish_rx_open => {
                    self.on_finish(f);
                    if self.should_stop() {
                        return false;
                    }
                }
            }
        }
    }

    /// Connects (TCP, then TLS if configured) within the connect timeout and the finish
    /// deadline. `None` if the link should stop.
    async fn connect(&mut self) -> Option<Result<BoxStream, NetlinkError>> {
        let addr = self.config.addr;
        let limit = Duration::from_millis(self.config.connect_timeout_ms);
        let tls = self.tls.clone();
        let attempt = tokio::time::timeout(limit, async move {
            let tcp = TcpStream::connect(addr)
                .await
                .map_err(|e| NetlinkError::io(format!("connecting to {addr}"), e))?;
            let _ = tcp.set_nodelay(true);
            let stream: BoxStream = match tls {
                None => Box::new(tcp),
                Some((connector, name)) => Box::new(
                    connector
                        .connect(name, tcp)
                        .await
                        .map_err(|e| NetlinkError::io(format!("TLS handshake with {addr}"), e))?,
                ),
            };
            Ok(stream)
        });
        tokio::pin!(attempt);
        loop {
            let deadline = self.deadline();
            tokio::select! {
                r = &mut attempt => {
                    return Some(r.unwrap_or_else(|_| Err(NetlinkError::io(
                        format!("connecting to {addr}"),
                        std::io::Error::new(std::io::ErrorKind::TimedOut, format!("no connection within {} ms", limit.as_millis())),
                    ))));
                }
                q = self.rx.recv(), if self.rx_open => { self.on_queued(q); }
                f = &mut self.finish_rx, if self.finish_rx_open => self.on_finish(f),
                () = tokio::time::sleep_until(deadline) => return None,
            }
            if self.should_stop() {
                return None;
            }
        }
    }

    fn outgoing(&self, p: &Pending) -> Outgoing {
        let shared = self.shared.clone();
        let written = p.written.clone();
        Outgoing {
            bytes: p.bytes.clone(),
            on_written: Some(Box::new(move || {
                if written.swap(true, Ordering::Relaxed) {
                    Shared::bump(&shared.resent);
                } else {
                    Shared::bump(&shared.sent);
                }
            })),
        }
    }

    async fn run_connection(&mut self, stream: BoxStream) -> ConnEnd {
        let (rd, wr) = tokio::io::split(stream);
        let (out_tx, out_rx) = mpsc::unbounded_channel();
        let mut writer = spawn_writer(wr, out_rx);
        let mut reader = FrameReader::new(rd);
        let _ = out_tx.send(Outgoing::new(self.hello_bytes.clone()));
        self.shared.connected.store(true, Ordering::Relaxed);
        let ack_timeout = Duration::from_millis(self.config.ack_timeout_ms);
        let mut liveness = tokio::time::interval(Duration::from_millis(500));
        let mut enqueued_upto: Option<u64> = None;
        let mut bye_sent = false;
        let mut last_heard = Instant::now();
        let mut progress = false;
        let mut writer_done = false;
        let session_id = self.config.hello.session_id.clone();
        let lost = |error, progress| ConnEnd::Lost { error, progress };
        let end = loop {
            let start = self
                .pending
                .partition_point(|p| enqueued_upto.is_some_and(|u| p.seq <= u));
            for p in self.pending.range(start..) {
                let _ = out_tx.send(self.outgoing(p));
                enqueued_upto = Some(p.seq);
            }
            if let Some(f) = self.finishing.as_ref().filter(|_| !bye_sent) {
                let bye = Frame::Bye(Bye {
                    session_id: session_id.clone(),
                    reason: f.reason.clone(),
                    final_seq: self.last_produced_seq,
                });
                match encode_to_vec(&bye) {
                    Ok(bytes) => {
                        let _ = out_tx.send(Outgoing::new(bytes.into()));
                    }
                    Err(e) => self.shared.set_error(format!("cannot encode Bye: {e}")),
                }
                bye_sent = true;
            }
            let deadline = self.deadline();
            tokio::select! {
                r = &mut writer => {
                    writer_done = true;
                    let error = match r {
                        Ok(Ok(())) => NetlinkError::Closed,
                        Ok(Err(e)) => e,
                        Err(e) => NetlinkError::Protocol(format!("writer task failed: {e}")),
                    };
                    break lost(error, progress);
                }
                frame = reader.next_frame() => {
                    last_heard = Instant::now();
                    match frame {
                        Ok(Some(Frame::Ack(ack))) => {
                            if ack.session_id != session_id {
                                break lost(NetlinkError::Protocol(format!(
                                    "Ack for session {:?}, expected {session_id:?}", ack.session_id
                                )), progress);
                            }
                            let mut n = 0;
                            while self.pending.front().is_some_and(|p| p.seq <= ack.seq) {
                                self.pending.pop_front();
                                n += 1;
                            }
                            if n > 0 {
                                progress = true;
                                self.shared.acked.fetch_add(n, Ordering::Relaxed);
                                self.update_pending();
                            }
                        }
                        Ok(Some(Frame::Regimen(r))) => {
                            Shared::bump(&self.shared.regimens_received);
                            tracing::info!(id = %r.id, "regimen received from therapist");
                            if self.regimen_tx.try_send(r).is_err() {
                                self.shared.set_error(format!(
                                    "regimen dropped: {REGIMEN_CAPACITY} unread regimens waiting"
                                ));
                            }
                        }
                        Ok(Some(Frame::Bye(b))) if bye_sent && self.pending.is_empty() => {
                            tracing::info!(final_seq = ?b.final_seq, "therapist confirmed end of session");
                            self.shared.bye_acknowledged.store(true, Ordering::Relaxed);
                            break ConnEnd::Done;
                        }
                        Ok(Some(Frame::Bye(b))) => {
                            break lost(NetlinkError::Protocol(format!(
                                "therapist ended the connection: {} ({} summaries unacknowledged)",
                                b.reason, self.pending.len()
                            )), progress);
                        }
                        Ok(Some(Frame::Error(e))) => {
                            break lost(NetlinkError::Protocol(format!(
                                "therapist reported an error: {}", e.message
                            )), progress);
                        }
                        Ok(Some(other)) => {
                            let error = NetlinkError::Protocol(format!(
                                "unexpected {} frame from the therapist", other.kind()
                            ));
                            send_error_frame(&out_tx, &error);
                            break lost(error, progress);
                        }
                        Ok(None) => {
                            break lost(NetlinkError::Protocol(
                                "therapist closed the connection".into()
                            ), progress);
                        }
                        Err(error) => {
                            send_error_frame(&out_tx, &error);
                            break lost(error, progress);
                        }
                    }
                }
                q = self.rx.recv(), if self.rx_open => {
                    if self.on_queued(q) {
                        last_heard = Instant::now();
                    }
                }
                f = &mut self.finish_rx, if self.finish_rx_open => {
                    self.on_finish(f);
                    if self.finishing.is_none() {
                        break ConnEnd::Done;
                    }
                }
                () = tokio::time::sleep_until(deadline) => break ConnEnd::Done,
                _ = liveness.tick() => {
                    if !self.pending.is_empty() && last_heard.elapsed() > ack_timeout {
                        break lost(NetlinkError::Protocol(format!(
                            "no acknowledgement from the therapist for {} ms; reconnecting",
                            ack_timeout.as_millis()
                        )), progress);
                    }
                }
            }
        };
        // Let the writer send what is queued (a Bye or an Error frame) and close the stream,
        // but not past the deadline, and only briefly for a broken connection.
        drop(out_tx);
        if !writer_done {
            let limit = match end {
                ConnEnd::Done => self.deadline(),
                ConnEnd::Lost { .. } => {
                    (Instant::now() + Duration::from_millis(100)).min(self.deadline())
                }
            };
            if tokio::time::timeout_at(limit, &mut writer).await.is_err() {
                writer.abort();
            }
        }
        end
    }
}

fn send_error_frame(out_tx: &mpsc::UnboundedSender<Outgoing>, error: &NetlinkError) {
    let message = crate::frame::printable(&error.to_string(), crate::frame::MAX_MESSAGE_LEN);
    if let Ok(bytes) = encode_to_vec(&Frame::Error(ErrorFrame { message })) {
        let _ = out_tx.send(Outgoing::new(bytes.into()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jittered_backoff_stays_within_half_to_full_delay_and_differs_between_stations() {
        let delay = Duration::from_millis(1_000);
        let mut pauses = Vec::new();
        for station in ["st-1", "st-2", "st-3", "st-4"] {
            let pause = jittered(delay, station, 1);
            assert!(pause >= delay / 2 && pause <= delay, "{pause:?}");
            assert_eq!(pause, jittered(delay, station, 1), "not deterministic");
            pauses.push(pause);
        }
        pauses.sort();
        pauses.dedup();
        assert!(
            pauses.len() > 1,
            "all stations would retry in step: {pauses:?}"
        );
    }
}
