//! The link's counters, shared between the station's handles and the link task.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

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
    /// Summaries refused by [`SummarySender::send`](super::SummarySender::send) as invalid.
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
    /// Set when the hub answered that it cannot serve any protocol version this station
    /// speaks (the hub's message). The link has stopped reconnecting for this session: show
    /// the patient that the software needs an update. Summaries keep being queued and are
    /// reported undelivered at the end.
    pub update_required: Option<String>,
}

#[derive(Debug, Default)]
pub(super) struct Shared {
    pub(super) connected: AtomicBool,
    pub(super) sent: AtomicU64,
    pub(super) acked: AtomicU64,
    pub(super) resent: AtomicU64,
    pub(super) pending: AtomicU64,
    pub(super) dropped: AtomicU64,
    pub(super) rejected: AtomicU64,
    pub(super) connect_failures: AtomicU64,
    pub(super) connections: AtomicU64,
    pub(super) regimens_received: AtomicU64,
    pub(super) bye_acknowledged: AtomicBool,
    pub(super) last_error: Mutex<Option<String>>,
    pub(super) update_required: Mutex<Option<String>>,
    /// The clinic's pain settings the hub last sent, not yet taken.
    pub(super) care: Mutex<Option<crate::frame::Care>>,
}

impl Shared {
    pub(super) fn bump(counter: &AtomicU64) {
        counter.fetch_add(1, Ordering::Relaxed);
    }

    pub(super) fn set_error(&self, message: String) {
        tracing::warn!(error = %message, "therapist link");
        if let Ok(mut slot) = self.last_error.lock() {
            *slot = Some(message);
        }
    }

    pub(super) fn snapshot(&self) -> LinkStats {
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
            update_required: self.update_required.lock().ok().and_then(|e| e.clone()),
        }
    }
}
