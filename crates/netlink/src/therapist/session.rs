//! One station's session at the hub: frames after `Hello` are stored, acknowledged or
//! answered with `Bye`; the session file is synced to disk.

use std::sync::{Arc, Mutex};

use crate::error::NetlinkError;
use crate::frame::{Ack, Bye, Frame, Hello, MAX_SEQ_STEP, max_next_seq};
use crate::store::{Appended, SessionFile};

use super::*;

pub(super) enum Reply {
    Ack(Ack),
    Bye(Frame, String),
}

pub(super) enum Failure {
    /// The station broke the protocol.
    Protocol(String),
    /// The connection ends for another reason.
    Closed(String),
}

pub(super) async fn handle_frame(
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
                let limit = max_next_seq(f.last_seq());
                if summary.seq > limit {
                    return Err(Failure::Protocol(format!(
                        "summary seq {} jumps too far ahead: the last stored is {:?}, at most {limit} \
                         accepted (MAX_SEQ_STEP = {MAX_SEQ_STEP})",
                        summary.seq,
                        f.last_seq()
                    )));
                }
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
            Ok(Reply::Ack(Ack {
                session_id: hello.session_id.clone(),
                seq: last,
            }))
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
pub(super) async fn sync_file(file: &Arc<Mutex<SessionFile>>) -> Result<(), NetlinkError> {
    let handle = lock(file).try_clone_file()?;
    tokio::task::spawn_blocking(move || handle.sync_data())
        .await
        .map_err(|e| NetlinkError::Protocol(format!("fsync task failed: {e}")))?
        .map_err(|e| NetlinkError::io("fsync of a session file", e))
}
