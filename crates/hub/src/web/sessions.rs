//! One session, its summaries and its movement metrics.

use std::collections::{BTreeMap, HashSet};
use std::sync::{Arc, Mutex};

use axum::Json;
use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use axum::http::header;
use axum::response::{IntoResponse, Response};
use netlink::Summary;
use tokio::sync::Semaphore;

use super::auth::Authed;
use super::{ApiError, AppState, check_path_id};
use crate::db::{SessionRow, Therapist};

/// The session `id` if `therapist` may see its patient; 404 otherwise.
pub(crate) async fn visible_session(
    state: &AppState,
    therapist: &Therapist,
    id: &str,
) -> Result<SessionRow, ApiError> {
    check_path_id("session id", id)?;
    let not_found = || ApiError::NotFound(format!("no session {id:?}"));
    let session = state.db.session(id).await?.ok_or_else(not_found)?;
    state
        .visible_patient(therapist, &session.patient_id)
        .await
        .map_err(|_| not_found())?;
    Ok(session)
}

pub(crate) async fn one(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<SessionRow>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    state
        .audit(&therapist.actor(), "read_session", &session.session_id, "")
        .await?;
    Ok(Json(session))
}

pub(crate) async fn summaries(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<Summary>>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    let summaries = state.db.summaries_of(&session.session_id).await?;
    state
        .audit(
            &therapist.actor(),
            "read_summaries",
            &session.session_id,
            "",
        )
        .await?;
    Ok(Json(summaries))
}

pub(crate) async fn metrics(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<BTreeMap<String, f64>>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    let metrics = state.db.metrics_of(&session.session_id).await?;
    state
        .audit(&therapist.actor(), "read_metrics", &session.session_id, "")
        .await?;
    Ok(Json(metrics))
}

/// `GET /api/sessions/{id}/exercises`: each exercise's own results, in course order.
pub(crate) async fn exercises(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<Vec<crate::db::SessionExercise>>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    let exercises = state.db.exercises_of(&session.session_id).await?;
    state
        .audit(
            &therapist.actor(),
            "read_exercises",
            &session.session_id,
            "",
        )
        .await?;
    Ok(Json(exercises))
}

/// Largest recording file the console replays by default, bytes (`hub serve --max-replay-mb`):
/// about five hours of a 1 kHz session. The replay streams the file in bounded memory, so this
/// bounds the time one replay takes, not the hub's memory.
pub const DEFAULT_MAX_REPLAY_BYTES: u64 = 2048 << 20;

/// Replays decoded (and streamed) at once by one hub; more wait their turn (up to
/// [`REPLAY_QUEUE_WAIT_S`]). Each holds a few MB for a station's recording (at most some
/// 50 MB for a hostile file within the stream's limits), and they share the CPU: eight
/// therapists opening a replay together all see its first frames at once.
pub const REPLAYS_AT_ONCE: usize = 8;

/// Longest a streamed replay waits for the console to take its next line, s: a console that
/// stops reading (a stalled or hostile client) gives its turn back instead of holding one of
/// the [`REPLAYS_AT_ONCE`] and a blocking thread for ever.
pub const REPLAY_STALL_S: u64 = 30;

/// How long a replay waits for one of the [`REPLAYS_AT_ONCE`] turns before the hub answers
/// 503, s.
pub const REPLAY_QUEUE_WAIT_S: u64 = 60;

/// The replays being decoded, and the therapists waiting for one: one replay per therapist
/// at a time (a second is answered 429), [`REPLAYS_AT_ONCE`] per hub.
#[derive(Debug)]
pub struct ReplayTurns {
    decoding: Arc<Semaphore>,
    asking: Mutex<HashSet<String>>,
}

impl Default for ReplayTurns {
    fn default() -> Self {
        Self {
            decoding: Arc::new(Semaphore::new(REPLAYS_AT_ONCE)),
            asking: Mutex::new(HashSet::new()),
        }
    }
}

/// A therapist's replay, from the request until its decoding ends.
struct Asking {
    turns: Arc<ReplayTurns>,
    therapist_id: String,
}

impl Asking {
    /// `None` if the therapist already has a replay waiting or decoding.
    fn begin(turns: &Arc<ReplayTurns>, therapist_id: &str) -> Option<Self> {
        let mut asking = turns.asking.lock().unwrap_or_else(|e| e.into_inner());
        asking.insert(therapist_id.to_owned()).then(|| Self {
            turns: Arc::clone(turns),
            therapist_id: therapist_id.to_owned(),
        })
    }
}

impl Drop for Asking {
    fn drop(&mut self) {
        let mut asking = self.turns.asking.lock().unwrap_or_else(|e| e.into_inner());
        asking.remove(&self.therapist_id);
    }
}

/// `GET /api/sessions/{id}/replay`: the session's uploaded recording as the console's replay
/// draws it, streamed as NDJSON lines while it is decoded (`record::view::replay_ndjson`), so
/// the first frames show at once and the hub holds one line of frames a replay; 404 until the whole recording has arrived, 422 for a file over the hub's limit or
/// one that cannot be read (a recording is a station's upload: untrusted), 429 while the same
/// therapist's previous replay is still being prepared, 503 when the hub's turns stay busy.
pub(crate) async fn replay(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Response, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    let recording = state
        .db
        .recording(&session.session_id)
        .await?
        .filter(|r| r.complete)
        .ok_or_else(|| {
            ApiError::NotFound(format!(
                "the recording of session {:?} has not (fully) arrived yet",
                session.session_id
            ))
        })?;
    state
        .audit(&therapist.actor(), "read_replay", &session.session_id, "")
        .await?;
    let path = std::path::PathBuf::from(&recording.path);
    // Off the async workers, and a file that cannot be read is refused, not taken as empty.
    let size = tokio::fs::metadata(&path)
        .await
        .map_err(|e| {
            tracing::warn!(session = %session.session_id, "replay file unreadable: {e}");
            ApiError::Unprocessable(format!(
                "the recording of session {:?} cannot be read on the hub",
                session.session_id
            ))
        })?
        .len();
    if size > state.replay_max_bytes {
        return Err(ApiError::Unprocessable(format!(
            "the recording of session {:?} is {} MB, more than the {} MB this hub replays \
             (hub serve --max-replay-mb)",
            session.session_id,
            size >> 20,
            state.replay_max_bytes >> 20
        )));
    }
    let Some(asking) = Asking::begin(&state.replay_turns, &therapist.id) else {
        return Err(ApiError::TooManyRequests(
            "a replay you asked for is still being prepared; ask again once it is shown".into(),
            5,
        ));
    };
    let decoding = Arc::clone(&state.replay_turns.decoding);
    let wait = std::time::Duration::from_secs(REPLAY_QUEUE_WAIT_S);
    let Ok(Ok(turn)) = tokio::time::timeout(wait, decoding.acquire_owned()).await else {
        return Err(ApiError::Unavailable(
            format!(
                "the hub is busy preparing other replays ({REPLAYS_AT_ONCE} at a time); try \
                 again in a moment"
            ),
            10,
        ));
    };
    // The file is opened (and its start checked) before the answer begins, so that a file
    // refused at once is a 422; the frames then follow as they are decoded.
    let opened = tokio::task::spawn_blocking(move || {
        record::TickStream::open_path(
            &path,
            record::StreamLimits::default(),
            &record::view::REPLAY_CHANNELS,
        )
        .map_err(|e| e.to_string())
    })
    .await
    .map_err(|_| ApiError::Internal)?
    .map_err(|e| {
        tracing::warn!(session = %session.session_id, "replay refused: {e}");
        ApiError::Unprocessable(format!(
            "the recording of session {:?} cannot be replayed: {e}",
            session.session_id
        ))
    })?;
    // A few lines in flight: a slow console holds the decoder back rather than the hub's
    // memory.
    let (tx, rx) = tokio::sync::mpsc::channel::<Result<Vec<u8>, std::io::Error>>(4);
    let id = session.session_id.clone();
    // The turn and the therapist's claim are held until the decoding ends; a console gone
    // away, or not reading for REPLAY_STALL_S, ends it at the next line.
    let runtime = tokio::runtime::Handle::current();
    let stall = std::time::Duration::from_secs(REPLAY_STALL_S);
    tokio::task::spawn_blocking(move || {
        let _held = (turn, asking);
        let sent = record::view::replay_ndjson(opened, record::view::MAX_REPLAY_FRAMES, |line| {
            matches!(
                runtime.block_on(tokio::time::timeout(stall, tx.send(Ok(line)))),
                Ok(Ok(()))
            )
        });
        if !sent {
            tracing::debug!(session = %id, "replay ended early: the console went away or stalled");
        }
    });
    let body = axum::body::Body::from_stream(tokio_stream::wrappers::ReceiverStream::new(rx));
    Ok(([(header::CONTENT_TYPE, "application/x-ndjson")], body).into_response())
}
