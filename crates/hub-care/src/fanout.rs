//! What one hub tells the other hubs of its clinic, through PostgreSQL's LISTEN/NOTIFY on the
//! one database they share: several hubs behind a load balancer, no shared disk.
//!
//! A station is connected to one hub, a therapist's browser to any: the summaries of a running
//! session ([`Note::Live`], for live views open on another hub), a regimen just prescribed and
//! a pain alert just cleared (for a station connected to another hub) cross on the channel
//! [`CHANNEL`]. Each note names the hub it comes from ([`Fanout::origin`]); a hub ignores its
//! own, which it already handled in-process.
//!
//! **Payloads stay small.** PostgreSQL refuses a NOTIFY payload of 8000 bytes or more. A note
//! is a few hundred bytes of JSON; a summary whose note would reach [`MAX_PAYLOAD_BYTES`]
//! (many `extra` metrics) is sent as a reference instead ([`Note::LiveStored`]: session and
//! sequence number), and the hub that receives it reads the stored summary
//! ([`hub_store::Db::summary`]).
//!
//! **Best effort, like the live view itself.** Notes are not stored: a hub that was not
//! listening (its database connection was lost) misses what was said meanwhile. The listener
//! reconnects by itself, with a growing wait ([`RECONNECT_MAX`]); what is missed is only live
//! display — every summary is in the database, a regimen reaches a station at its next
//! connection, pain news at its next check.
//!
//! On SQLite there is one hub and nothing to tell: [`Fanout::start`] returns `None`.

use std::time::Duration;

use serde::{Deserialize, Serialize};
use sqlx::postgres::PgListener;
use tokio::sync::mpsc;

use crate::live::LiveEvent;
use hub_store::db::Db;

/// The PostgreSQL notification channel the hubs of a clinic share.
pub const CHANNEL: &str = "telerehab_hubs";

/// Largest note sent whole, bytes: PostgreSQL refuses a payload of 8000 bytes or more
/// (`pg_notify`'s documented limit, in the default configuration); a margin below it.
pub const MAX_PAYLOAD_BYTES: usize = 7_900;

/// Notes waiting to be sent before more are dropped (counted in the log): the live view is
/// best effort, and a database that stalls must not hold the station link.
pub const PUBLISH_QUEUE: usize = 4_096;

/// Most notes sent by one statement (`SELECT pg_notify(…), pg_notify(…), …`).
const PUBLISH_BATCH: usize = 64;

/// Longest wait between two attempts to listen again after the connection was lost.
pub const RECONNECT_MAX: Duration = Duration::from_secs(5);

/// One thing a hub tells the others.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Note {
    /// A summary of a running session, whole.
    Live {
        /// The patient exercising, their session and the summary just stored.
        event: LiveEvent,
    },
    /// A summary too large for a note: the receiving hub reads it from the database.
    LiveStored {
        /// The patient exercising.
        patient_id: String,
        /// Their session.
        session_id: String,
        /// The summary's sequence number.
        seq: u64,
    },
    /// A regimen was prescribed for this patient: a hub holding one of their stations pushes
    /// the latest.
    Regimen {
        /// The patient.
        patient_id: String,
    },
    /// A pain alert of this patient was cleared: a hub holding one of their stations tells it.
    PainCleared {
        /// The patient.
        patient_id: String,
    },
}

/// A note on the wire: who sent it, and what.
#[derive(Debug, Serialize, Deserialize)]
struct Envelope {
    /// The sending hub's [`Fanout::origin`].
    from: String,
    #[serde(flatten)]
    note: Note,
}

/// `note` from `origin` as a payload for the channel: whole, or as a reference to the stored
/// summary when too large; `None` when even that is too large (a note is never cut).
fn payload_of(origin: &str, note: &Note) -> Option<String> {
    let text = serde_json::to_string(&Envelope {
        from: origin.to_owned(),
        note: note.clone(),
    })
    .ok()?;
    if text.len() < MAX_PAYLOAD_BYTES {
        return Some(text);
    }
    let Note::Live { event } = note else {
        return None;
    };
    let reference = Note::LiveStored {
        patient_id: event.patient_id.clone(),
        session_id: event.session_id.clone(),
        seq: event.summary.seq,
    };
    let text = serde_json::to_string(&Envelope {
        from: origin.to_owned(),
        note: reference,
    })
    .ok()?;
    (text.len() < MAX_PAYLOAD_BYTES).then_some(text)
}

/// This hub's side of the channel: [`Fanout::publish`] tells the other hubs; the receiver
/// [`Fanout::start`] returns gives what they told this one.
#[derive(Debug, Clone)]
pub struct Fanout {
    origin: String,
    queue: mpsc::Sender<Note>,
}

impl Fanout {
    /// Starts listening on [`CHANNEL`] and the task that sends this hub's notes, on the
    /// current tokio runtime; the other hubs' notes arrive on the receiver. `None` on SQLite.
    pub fn start(db: &Db) -> Option<(Self, mpsc::Receiver<Note>)> {
        let url = db.postgres_url()?.to_owned();
        let origin = hub_store::db::new_id("hub-").ok()?;
        let (queue, outgoing) = mpsc::channel(PUBLISH_QUEUE);
        let (incoming, received) = mpsc::channel(PUBLISH_QUEUE);
        tokio::spawn(send_notes(db.clone(), origin.clone(), outgoing));
        tokio::spawn(listen(url, origin.clone(), incoming));
        Some((Self { origin, queue }, received))
    }

    /// This hub's name on the channel (random, for this process).
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// Tells the other hubs `note`, without waiting; dropped (and logged) when the queue is
    /// full.
    pub fn publish(&self, note: Note) {
        if let Err(e) = self.queue.try_send(note) {
            tracing::warn!("a note to the other hubs was dropped: {e}");
        }
    }
}

/// Sends the queued notes, up to [`PUBLISH_BATCH`] in one statement, until every [`Fanout`]
/// is dropped.
async fn send_notes(db: Db, origin: String, mut outgoing: mpsc::Receiver<Note>) {
    let mut notes = Vec::with_capacity(PUBLISH_BATCH);
    while outgoing.recv_many(&mut notes, PUBLISH_BATCH).await > 0 {
        let payloads: Vec<String> = notes
            .drain(..)
            .filter_map(|n| {
                let payload = payload_of(&origin, &n);
                if payload.is_none() {
                    tracing::warn!("a note too large for the other hubs was not sent: {n:?}");
                }
                payload
            })
            .collect();
        if payloads.is_empty() {
            continue;
        }
        let calls: Vec<String> = (2..payloads.len() + 2)
            .map(|i| format!("pg_notify($1, ${i})"))
            .collect();
        let sql = format!("SELECT {}", calls.join(", "));
        let mut query = sqlx::query(sqlx::AssertSqlSafe(sql)).bind(CHANNEL);
        for p in payloads {
            query = query.bind(p);
        }
        if let Err(e) = query.execute(db.pool()).await {
            tracing::warn!("cannot tell the other hubs: {e}");
        }
    }
}

/// Listens on [`CHANNEL`] for as long as `incoming` has a receiver, passing on the other
/// hubs' notes; connects again after a lost connection or a failed attempt, waiting twice as
/// long each time up to [`RECONNECT_MAX`].
async fn listen(url: String, origin: String, incoming: mpsc::Sender<Note>) {
    let mut wait = Duration::from_millis(100);
    while !incoming.is_closed() {
        match listen_once(&url, &origin, &incoming).await {
            Ok(()) => return,
            Err(e) => {
                tracing::warn!(
                    wait_ms = wait.as_millis(),
                    "the other hubs' channel was lost: {e}"
                );
                tokio::time::sleep(wait).await;
                wait = (wait * 2).min(RECONNECT_MAX);
            }
        }
    }
}

/// One connection's worth of [`listen`]: `Ok` once nobody receives any more.
async fn listen_once(
    url: &str,
    origin: &str,
    incoming: &mpsc::Sender<Note>,
) -> Result<(), sqlx::Error> {
    let mut listener = PgListener::connect(url).await?;
    listener.listen(CHANNEL).await?;
    tracing::info!("listening to the other hubs");
    loop {
        // `None`: the connection was lost (and notes with it); the next call connects again.
        let Some(notification) = listener.try_recv().await? else {
            return Err(sqlx::Error::Protocol("connection lost".into()));
        };
        let envelope: Envelope = match serde_json::from_str(notification.payload()) {
            Ok(e) => e,
            Err(e) => {
                tracing::warn!("an unreadable note from another hub: {e}");
                continue;
            }
        };
        if envelope.from == origin {
            continue;
        }
        if incoming.send(envelope.note).await.is_err() {
            return Ok(());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary(extra: usize) -> netlink::Summary {
        netlink::Summary {
            session_id: "s-1".into(),
            seq: 7,
            t_s: 0.7,
            exercise: "sine-road".into(),
            speed_m_s: 5.0,
            lateral_m: 0.1,
            rms_lateral_m: 0.1,
            max_lateral_m: 0.2,
            pct_in_lane: 99.0,
            max_abs_torque_nm: 1.5,
            loop_p99_us: 40.0,
            ticks: 700,
            dropped_records: 0,
            extra: (0..extra)
                .map(|i| (format!("metric_{i:04}"), 1.0))
                .collect(),
        }
    }

    fn live(extra: usize) -> Note {
        Note::Live {
            event: LiveEvent {
                patient_id: "p-1".into(),
                session_id: "s-1".into(),
                summary: summary(extra),
            },
        }
    }

    #[test]
    fn a_usual_summary_crosses_whole_and_reads_back_the_same() {
        let note = live(3);
        let text = payload_of("hub-a", &note).unwrap();
        assert!(text.len() < 1_000, "{} bytes", text.len());
        let back: Envelope = serde_json::from_str(&text).unwrap();
        assert_eq!((back.from.as_str(), back.note), ("hub-a", note));
    }

    #[test]
    fn a_summary_too_large_for_a_notify_crosses_as_its_session_and_sequence_number() {
        let text = payload_of("hub-a", &live(600)).unwrap();
        assert!(text.len() < MAX_PAYLOAD_BYTES);
        let back: Envelope = serde_json::from_str(&text).unwrap();
        assert_eq!(
            back.note,
            Note::LiveStored {
                patient_id: "p-1".into(),
                session_id: "s-1".into(),
                seq: 7
            }
        );
    }
}
