//! The link task: the store-and-forward queue of unacknowledged summaries and the
//! reconnect loop with backoff around each connection.

use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use tokio::sync::{mpsc, oneshot};
use tokio::time::Instant;

use crate::frame::{Message, Regimen};

use super::*;

/// How a connection ended.
pub(super) enum ConnEnd {
    /// The session is over (Bye answered, deadline reached or link dropped).
    Done,
    /// The connection broke; `progress` is true if an Ack arrived on it.
    Lost { error: NetlinkError, progress: bool },
    /// The hub cannot serve any protocol version this station speaks: do not retry.
    UpdateRequired(String),
}

pub(super) struct Pending {
    pub(super) seq: u64,
    pub(super) bytes: Arc<[u8]>,
    pub(super) written: Arc<AtomicBool>,
}

pub(super) struct LinkTask {
    pub(super) config: StationLinkConfig,
    pub(super) tls: Option<(
        tokio_rustls::TlsConnector,
        rustls::pki_types::ServerName<'static>,
    )>,
    pub(super) hello_bytes: Arc<[u8]>,
    pub(super) shared: Arc<Shared>,
    pub(super) rx: mpsc::Receiver<Queued>,
    pub(super) rx_open: bool,
    pub(super) finish_rx: oneshot::Receiver<Finish>,
    pub(super) finish_rx_open: bool,
    pub(super) finishing: Option<Finish>,
    pub(super) pending: VecDeque<Pending>,
    pub(super) last_produced_seq: Option<u64>,
    /// The highest `seq` the hub has acknowledged: a summary handed over later at or below it
    /// is already stored there and is not queued (a resent queued session).
    pub(super) acked_upto: Option<u64>,
    pub(super) regimen_tx: mpsc::Sender<Regimen>,
    /// The therapist's messages received, for the station to keep and show.
    pub(super) message_tx: mpsc::Sender<Message>,
    /// Encoded `MessageSeen` frames from [`StationLink::report_seen`], not yet taken.
    pub(super) seen_rx: mpsc::UnboundedReceiver<Arc<[u8]>>,
    /// Every `MessageSeen` reported: said on each connection, since only the hub's `Bye`
    /// confirms a connection's frames were handled.
    pub(super) seen: Vec<Arc<[u8]>>,
}

/// A pause in [delay/2, delay], spread by a hash of the station id and attempt number, so
/// that many stations reconnecting to a restarted hub do not retry in lock-step. Deterministic
/// (no clock, no random source) so a given station's behaviour is reproducible.
pub(super) fn jittered(delay: Duration, station_id: &str, attempt: u64) -> Duration {
    use std::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    (station_id, attempt).hash(&mut hasher);
    let fraction = (hasher.finish() >> 11) as f64 / (1u64 << 53) as f64;
    delay.mul_f64(0.5 + 0.5 * fraction)
}

/// An instant far enough away to stand for "never".
pub(super) fn far_future() -> Instant {
    Instant::now() + Duration::from_secs(86_400 * 365)
}

impl LinkTask {
    pub(super) async fn run(mut self) {
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
                    if let ConnEnd::UpdateRequired(message) = end {
                        // Not retriable: keep queuing (nothing recorded is lost; the MCAP
                        // file has it all) until the session finishes, without reconnecting.
                        self.shared.set_error(format!("therapist hub: {message}"));
                        if let Ok(mut slot) = self.shared.update_required.lock() {
                            *slot = Some(message);
                        }
                        while self.wait(Duration::from_secs(3_600)).await {}
                        break;
                    }
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
    pub(super) fn should_stop(&self) -> bool {
        (!self.finish_rx_open && self.finishing.is_none())
            || self
                .finishing
                .as_ref()
                .is_some_and(|f| Instant::now() >= f.deadline)
    }

    pub(super) fn deadline(&self) -> Instant {
        self.finishing
            .as_ref()
            .map_or_else(far_future, |f| f.deadline)
    }

    pub(super) fn update_pending(&self) {
        self.shared
            .pending
            .store(self.pending.len() as u64, Ordering::Relaxed);
    }

    /// Moves a summary from the channel into the queue. Returns true if the queue was empty.
    pub(super) fn on_queued(&mut self, queued: Option<Queued>) -> bool {
        let Some(q) = queued else {
            // Every SummarySender is gone; nothing more will come.
            self.rx_open = false;
            return false;
        };
        self.last_produced_seq = Some(q.seq);
        if self.acked_upto.is_some_and(|a| q.seq <= a) {
            // The hub acknowledged it before it was handed over (only possible up to
            // `replay_last_seq`): it is stored there, and sending it again would be waste.
            Shared::bump(&self.shared.acked);
            return false;
        }
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

    pub(super) fn drain_channel(&mut self) {
        while let Ok(q) = self.rx.try_recv() {
            self.on_queued(Some(q));
        }
    }

    /// Handles the finish command (or the link being dropped: `Err`).
    pub(super) fn on_finish(&mut self, finish: Result<Finish, oneshot::error::RecvError>) {
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
    pub(super) async fn wait(&mut self, delay: Duration) -> bool {
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
