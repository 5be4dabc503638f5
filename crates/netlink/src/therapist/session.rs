//! One station's session at the hub: frames after `Hello` are stored, acknowledged or
//! answered with `Bye`; the session file is synced to disk.

use crate::error::NetlinkError;
use crate::frame::{Ack, Bye, Frame, Hello, MAX_SEQ_STEP, max_next_seq};
use crate::store::Appended;

use super::*;

/// Holds a summary back until its station's pace (`summary_pace_per_s`, by default
/// [`station_limits::SUMMARY_PACE_PER_S`])
/// lets it through; refused when it would wait more than
/// [`station_limits::MAX_SUMMARY_WAIT`].
async fn pace_summary(hub: &Hub, hello: &Hello) -> Result<(), Failure> {
    use station_limits::{MAX_SUMMARY_WAIT, SUMMARY_BURST};
    let pace_per_s = f64::from(hub.config.summary_pace_per_s);
    let taken = hub
        .summary_pace
        .take(
            &hello.station_id,
            1.0,
            pace_per_s,
            SUMMARY_BURST,
            MAX_SUMMARY_WAIT,
        )
        .await;
    if taken {
        return Ok(());
    }
    Err(Failure::Refused(
        "summary_rate",
        format!(
            "station {:?} sends more summaries than a station produces: at most {pace_per_s} \
             a second are taken from one station over all its connections",
            hello.station_id
        ),
    ))
}

pub(super) enum Reply {
    Ack(Ack),
    /// Another answer (upload progress).
    Frame(Frame),
    Bye(Frame, String),
    /// Nothing to answer (a `MessageSeen`).
    Nothing,
}

pub(super) enum Failure {
    /// The station broke the protocol.
    Protocol(String),
    /// The connection ends for another reason.
    Closed(String),
    /// The hub cannot do it now (its store failed): the station is told why, and tries again
    /// later.
    Unavailable(String),
    /// The station is held to what a real station sends (`kind`, e.g. `summary_rate`): told
    /// why in an `Error` frame, the refusal audited by the store (at a bounded rate).
    Refused(&'static str, String),
}

pub(super) async fn handle_frame(
    hub: &Hub,
    hello: &Hello,
    file: &SessionSlot,
    upload: &mut Option<upload::Upload>,
    frame: Frame,
) -> Result<Reply, Failure> {
    match frame {
        Frame::UploadStart(start) => {
            let (state, at) = upload::start(hub, hello, start).await?;
            *upload = state;
            Ok(Reply::Frame(Frame::UploadAt(at)))
        }
        Frame::UploadChunk(chunk) => Ok(Reply::Frame(Frame::UploadAt(
            upload::chunk(hub, hello, upload, chunk).await?,
        ))),
        Frame::Summary(summary) => {
            if summary.session_id != hello.session_id {
                return Err(Failure::Protocol(format!(
                    "summary for session {:?} on a connection for session {:?}",
                    summary.session_id, hello.session_id
                )));
            }
            let ack = |seq| {
                Ok(Reply::Ack(Ack {
                    session_id: hello.session_id.clone(),
                    seq,
                }))
            };
            pace_summary(hub, hello).await?;
            let mut guard = file.lock().await;
            let Some(store) = guard.as_mut() else {
                return Err(Failure::Closed("session store is not open".into()));
            };
            let last = store.last_seq();
            let limit = max_next_seq(last);
            if summary.seq > limit {
                return Err(Failure::Protocol(format!(
                    "summary seq {} jumps too far ahead: the last stored is {last:?}, at most \
                     {limit} accepted (MAX_SEQ_STEP = {MAX_SEQ_STEP})",
                    summary.seq
                )));
            }
            if let Some(last) = last.filter(|&l| summary.seq <= l) {
                // A duplicate: answered without touching the store.
                return ack(last);
            }
            station_limits::check_summary_time(
                summary.t_s,
                store.last_t_s(),
                hello.started_unix_ms,
                hub.store.now_ms(),
            )
            .map_err(|why| Failure::Refused("summary_time", why))?;
            station_limits::check_summary_count(summary.seq, summary.t_s)
                .map_err(|why| Failure::Refused("summary_rate", why))?;
            // Holding only this session's lock; the store does its blocking work off the reactor.
            let appended = store
                .append(&summary)
                .await
                .map_err(|e| Failure::Closed(format!("storage failure: {e}")))?;
            let last = store.last_seq().unwrap_or(summary.seq);
            drop(guard);
            if appended == Appended::Stored {
                hub.emit(TherapistEvent::Summary {
                    station_id: hello.station_id.clone(),
                    patient_id: hello.patient_id.clone(),
                    summary,
                });
            }
            ack(last)
        }
        Frame::Bye(bye) => {
            if bye.session_id != hello.session_id {
                return Err(Failure::Protocol(format!(
                    "Bye for session {:?} on a connection for session {:?}",
                    bye.session_id, hello.session_id
                )));
            }
            check_final_seq(file, &bye).await?;
            sync_file(file, Some(&bye))
                .await
                .map_err(|e| Failure::Closed(format!("storage failure: {e}")))?;
            let stored = last_seq(file).await;
            Ok(Reply::Bye(
                Frame::Bye(Bye {
                    session_id: hello.session_id.clone(),
                    reason: "stored".into(),
                    final_seq: stored,
                    measures: Default::default(),
                    hub_unix_ms: Some(crate::frame::unix_ms_now()),
                    checkin: None,
                    difficulty: None,
                    exercises: Vec::new(),
                }),
                format!("bye: {}", bye.reason),
            ))
        }
        Frame::MessageSeen(seen) => {
            hub.store
                .message_seen(hello, &seen)
                .await
                .map_err(|e| Failure::Unavailable(format!("cannot store a message seen: {e}")))?;
            hub.emit(TherapistEvent::MessageSeen {
                station_id: hello.station_id.clone(),
                patient_id: hello.patient_id.clone(),
                seen,
            });
            Ok(Reply::Nothing)
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

/// Refuses a `Bye` whose final sequence number is beyond what arrived: it would claim
/// summaries never sent.
async fn check_final_seq(file: &SessionSlot, bye: &Bye) -> Result<(), Failure> {
    let received = last_seq(file).await;
    if let Some(claimed) = bye.final_seq
        && received.is_none_or(|r| claimed > r)
    {
        return Err(Failure::Refused(
            "bye_final_seq",
            format!(
                "Bye says the session's last summary is seq {claimed}, but the hub received {}; \
                 send the missing summaries first",
                received.map_or_else(|| "none".to_owned(), |r| format!("up to seq {r}"))
            ),
        ));
    }
    Ok(())
}

/// The last sequence number stored in a session, `None` if none (or the store is not open).
pub(super) async fn last_seq(file: &SessionSlot) -> Option<u64> {
    file.lock().await.as_ref().and_then(|s| s.last_seq())
}

/// Makes a session's store durable; `bye` when the station ended the session in order.
pub(super) async fn sync_file(file: &SessionSlot, bye: Option<&Bye>) -> Result<(), NetlinkError> {
    match file.lock().await.as_mut() {
        Some(store) => store.sync(bye).await,
        None => Ok(()),
    }
}
