//! Station side: a store-and-forward link that never blocks the caller.
//!
//! The station hands summaries to a [`SummarySender`] (a bounded channel, `try_send`). A task on
//! the station's tokio runtime moves them into a queue of unacknowledged summaries, (re)connects
//! with exponential backoff, sends `Hello` and then everything unacknowledged, and drops
//! summaries from the queue only when the hub's cumulative `Ack` covers them. After a
//! reconnect everything unacknowledged is sent again; the hub drops what it already stored, so
//! the store holds each summary exactly once.

mod config;
mod connection;
mod stats;
mod task;

use std::collections::{BTreeMap, VecDeque};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::{mpsc, oneshot};
use tokio::task::JoinHandle;
use tokio::time::Instant;

use crate::codec::encode_to_vec;
use crate::error::NetlinkError;
use crate::frame::{Frame, Message, MessageSeen, Regimen, Summary};
use crate::tls::ClientTls;

pub use config::{Backoff, HubAddress, StationLinkConfig};
pub use stats::LinkStats;
use stats::Shared;
use task::LinkTask;

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
    /// The sequence number jumps further ahead than the protocol allows
    /// ([`MAX_SEQ_STEP`](crate::frame::MAX_SEQ_STEP)); the hub would refuse it.
    #[error(
        "summary seq {seq} jumps too far ahead of the previous seq {previous:?} (at most {limit})"
    )]
    SeqJump {
        /// The refused sequence number.
        seq: u64,
        /// The previous one, `None` for the first summary.
        previous: Option<u64>,
        /// The highest sequence number allowed here.
        limit: u64,
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
        let limit = crate::frame::max_next_seq(*previous_seq);
        if seq > limit {
            Shared::bump(&self.shared.rejected);
            return Err(SendError::SeqJump {
                seq,
                previous: *previous_seq,
                limit,
            });
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
    measures: BTreeMap<String, f64>,
    deadline: Instant,
    /// The patient's check-in answers, if the session asked ([`StationLink::set_checkin`]).
    checkin: Option<crate::frame::CheckIn>,
    /// The session's difficulty and its change ([`StationLink::set_difficulty`]).
    difficulty: Option<crate::frame::DifficultyChange>,
    /// Each exercise's results ([`StationLink::set_exercises`]).
    exercises: Vec<crate::frame::ExerciseResult>,
}

/// Most bytes of JSON a `Bye`'s exercise results may take: the rest of the frame (measures,
/// check-in, reason) stays well within [`crate::codec::MAX_PAYLOAD_LEN`].
pub const MAX_EXERCISES_JSON_BYTES: usize = 48 * 1024;

/// The running link; poll it for regimens, read its stats, finish it at the end of a session.
pub struct StationLink {
    shared: Arc<Shared>,
    finish_tx: Option<oneshot::Sender<Finish>>,
    task: JoinHandle<()>,
    regimens: mpsc::Receiver<Regimen>,
    messages: mpsc::Receiver<Message>,
    seen_tx: mpsc::UnboundedSender<Arc<[u8]>>,
    /// The check-in answers the `Bye` will carry ([`Self::set_checkin`]).
    checkin: Option<crate::frame::CheckIn>,
    /// The difficulty the `Bye` will carry ([`Self::set_difficulty`]).
    difficulty: Option<crate::frame::DifficultyChange>,
    /// The exercise results the `Bye` will carry ([`Self::set_exercises`]).
    exercises: Vec<crate::frame::ExerciseResult>,
}

/// Regimens buffered between the link task and the station's poll.
const REGIMEN_CAPACITY: usize = 16;

/// The therapist's messages buffered between the link task and the station's poll.
pub(super) const MESSAGE_CAPACITY: usize = 64;

impl StationLink {
    /// Validates `config`, loads the TLS files and starts the link task on `handle`.
    pub fn spawn(
        handle: &tokio::runtime::Handle,
        config: StationLinkConfig,
    ) -> Result<(SummarySender, StationLink), NetlinkError> {
        let mut config = config;
        if config.hello.min_protocol_version.is_none() {
            // The link speaks the wire protocol: it announces every version it can.
            config.hello.min_protocol_version = Some(crate::frame::MIN_PROTOCOL_VERSION);
        }
        config.validate()?;
        let tls = config.tls.as_ref().map(ClientTls::connector).transpose()?;
        let hello_bytes: Arc<[u8]> = encode_to_vec(&Frame::Hello(config.hello.clone()))?.into();
        let shared = Arc::new(Shared::default());
        let (tx, rx) = mpsc::channel(config.channel_capacity);
        let (finish_tx, finish_rx) = oneshot::channel();
        let (regimen_tx, regimens) = mpsc::channel(REGIMEN_CAPACITY);
        let (message_tx, messages) = mpsc::channel(MESSAGE_CAPACITY);
        let (seen_tx, seen_rx) = mpsc::unbounded_channel();
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
            acked_upto: None,
            regimen_tx,
            message_tx,
            seen_rx,
            seen: Vec::new(),
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
                messages,
                seen_tx,
                checkin: None,
                difficulty: None,
                exercises: Vec::new(),
            },
        ))
    }

    /// The patient's end-screen answers, sent in the session's `Bye`. Answers the protocol
    /// would refuse (out of range) are not sent: the error is kept in
    /// [`LinkStats::last_error`]. An empty check-in (every question skipped) is not sent.
    pub fn set_checkin(&mut self, checkin: crate::frame::CheckIn) {
        if checkin.is_empty() {
            return;
        }
        match checkin.validate() {
            Ok(()) => self.checkin = Some(checkin),
            Err(e) => self
                .shared
                .set_error(format!("check-in answers not sent: {e}")),
        }
    }

    /// The difficulty the session ran at and why, sent in the session's `Bye`. A value the
    /// protocol would refuse is not sent: the error is kept in [`LinkStats::last_error`].
    pub fn set_difficulty(&mut self, difficulty: crate::frame::DifficultyChange) {
        match difficulty.validate() {
            Ok(()) => self.difficulty = Some(difficulty),
            Err(e) => self
                .shared
                .set_error(format!("the session's difficulty not sent: {e}")),
        }
    }

    /// Each exercise's results, sent in the session's `Bye`. Results the protocol would refuse
    /// are not sent (the error is kept in [`LinkStats::last_error`]); when their JSON is over
    /// [`MAX_EXERCISES_JSON_BYTES`] the last exercises are left out, and the error says so.
    pub fn set_exercises(&mut self, mut exercises: Vec<crate::frame::ExerciseResult>) {
        if let Err(e) = crate::frame::check_exercise_results(&exercises) {
            self.shared
                .set_error(format!("exercise results not sent: {e}"));
            return;
        }
        let all = exercises.len();
        while serde_json::to_vec(&exercises).map_or(usize::MAX, |j| j.len())
            > MAX_EXERCISES_JSON_BYTES
        {
            exercises.pop();
        }
        if exercises.len() < all {
            self.shared.set_error(format!(
                "exercise results: only the first {} of {all} sent (the rest would not fit \
                 in one Bye)",
                exercises.len()
            ));
        }
        self.exercises = exercises;
    }

    /// Counters of the link; cheap (atomics and one short lock), safe from any thread.
    pub fn stats(&self) -> LinkStats {
        self.shared.snapshot()
    }

    /// A regimen received from the therapist, if any. The station must validate it.
    pub fn try_recv_regimen(&mut self) -> Option<Regimen> {
        self.regimens.try_recv().ok()
    }

    /// Takes the regimen queue, so regimens arriving until the link is finished (a hub pushes
    /// one right after `Hello`) can still be read afterwards; this link then receives none.
    pub fn take_regimens(&mut self) -> mpsc::Receiver<Regimen> {
        let (_, closed) = mpsc::channel(1);
        std::mem::replace(&mut self.regimens, closed)
    }

    /// The clinic's pain settings the hub sent since the last call, if any (the newest).
    pub fn take_care(&self) -> Option<crate::frame::Care> {
        self.shared.care.lock().ok().and_then(|mut c| c.take())
    }

    /// Takes the message queue, so messages arriving until the link is finished can still be
    /// read afterwards (a link delivering a queued session is read only at its end); this link
    /// then receives none.
    pub fn take_messages(&mut self) -> mpsc::Receiver<Message> {
        let (_, closed) = mpsc::channel(1);
        std::mem::replace(&mut self.messages, closed)
    }

    /// A message from the therapist received, if any (each arrives on every connection until
    /// the station reports it seen: keep each once, by id).
    pub fn try_recv_message(&mut self) -> Option<Message> {
        self.messages.try_recv().ok()
    }

    /// Tells the hub that message `seen.id` was shown to the patient: sent now if connected
    /// and again on every later connection of this link (the hub records it once). Delivered
    /// once [`LinkStats::bye_acknowledged`]; until then the station keeps it and reports it
    /// again on its next link. An invalid id is not sent (kept in [`LinkStats::last_error`]).
    pub fn report_seen(&self, seen: MessageSeen) {
        match encode_to_vec(&Frame::MessageSeen(seen)) {
            Ok(bytes) => {
                let _ = self.seen_tx.send(bytes.into());
            }
            Err(e) => self.shared.set_error(format!("message seen not sent: {e}")),
        }
    }

    /// Ends the session: delivers what is pending, sends `Bye` and waits for the hub's reply,
    /// giving up after `timeout`. The returned stats say honestly what was not delivered
    /// ([`LinkStats::pending`]) and whether the hub confirmed ([`LinkStats::bye_acknowledged`]).
    pub async fn finish(self, timeout: Duration) -> LinkStats {
        self.finish_with_reason("session complete", timeout).await
    }

    /// [`Self::finish`] with the reason sent in `Bye` (control characters become spaces, cut
    /// to 256 bytes).
    pub async fn finish_with_reason(self, reason: &str, timeout: Duration) -> LinkStats {
        self.finish_with_measures(reason, BTreeMap::new(), timeout)
            .await
    }

    /// [`Self::finish_with_reason`], the `Bye` carrying the session's movement `measures`
    /// (name → finite value). Measures the protocol would refuse (a non-finite value, a bad
    /// name, too many) are not sent: the error is kept in [`LinkStats::last_error`] and the
    /// session still ends in order.
    pub async fn finish_with_measures(
        mut self,
        reason: &str,
        measures: BTreeMap<String, f64>,
        timeout: Duration,
    ) -> LinkStats {
        let deadline = Instant::now() + timeout;
        let measures = match crate::frame::check_named_values("measures", &measures) {
            Ok(()) => measures,
            Err(e) => {
                self.shared
                    .set_error(format!("session measures not sent: {e}"));
                BTreeMap::new()
            }
        };
        if let Some(tx) = self.finish_tx.take() {
            let _ = tx.send(Finish {
                reason: crate::frame::printable(reason, crate::frame::MAX_TEXT_LEN),
                measures,
                deadline,
                checkin: self.checkin.take(),
                difficulty: self.difficulty.take(),
                exercises: std::mem::take(&mut self.exercises),
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
