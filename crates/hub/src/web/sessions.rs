//! One session, its summaries and its movement metrics.

use std::collections::{BTreeMap, HashSet};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use axum::Json;
use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use axum::http::header;
use axum::response::{IntoResponse, Response};
use netlink::Summary;
use tokio::sync::Semaphore;

use super::Says as _;
use super::auth::Authed;
use super::{ApiError, AppState, check_path_id};
use hub_store::db::{SessionRow, Therapist};
use hub_store::refusal::{Code, Why};

/// The session `id` if `therapist` may see its patient; 404 otherwise.
pub(crate) async fn visible_session(
    state: &AppState,
    therapist: &Therapist,
    id: &str,
) -> Result<SessionRow, ApiError> {
    check_path_id("session id", id)?;
    let not_found = || super::not_found("session", format!("no session {id:?}"));
    let session = state.db.session(id).await?.ok_or_else(not_found)?;
    state
        .visible_patient(therapist, &session.patient_id)
        .await
        .map_err(|_| not_found())?;
    Ok(session)
}

/// `GET /api/sessions/{id}`: the session's row and how it ended (`end_kind`, the console's
/// words for it in any language).
#[derive(serde::Serialize)]
pub(crate) struct OneSession {
    #[serde(flatten)]
    row: SessionRow,
    end_kind: metrics::words::EndKind,
}

pub(crate) async fn one(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Json<OneSession>, ApiError> {
    let Path(id) = id?;
    let session = visible_session(&state, &therapist, &id).await?;
    state
        .audit(&therapist.actor(), "read_session", &session.session_id, "")
        .await?;
    Ok(Json(OneSession {
        end_kind: hub_store::db::end_kind_of(&session),
        row: session,
    }))
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
) -> Result<Json<Vec<hub_store::db::SessionExercise>>, ApiError> {
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

/// CPU time one replay's decoding may take, s (the CPU time of the thread decoding it): a
/// one-hour 1 kHz recording replays in some 13 s of a release build's CPU (BENCHMARKS.md,
/// "Console replay of uploaded recordings"), so the longest session a station records
/// ([`record::cost::LONGEST_SESSION_S`], 4 h) twice over. Past it the replay stops, and says
/// why.
pub const DEFAULT_REPLAY_CPU_S: f64 = 120.0;

/// The replays being decoded, and the therapists waiting for one: one replay per therapist
/// at a time (a second is answered 429), [`REPLAYS_AT_ONCE`] per hub. A replay's turn and its
/// therapist's claim are held by the work itself, so they come back when the decoding has
/// ended, not when its client goes.
#[derive(Debug)]
pub struct ReplayTurns {
    decoding: Arc<Semaphore>,
    asking: Mutex<HashSet<String>>,
    /// Replays whose decoding has not ended yet.
    working: AtomicUsize,
}

impl Default for ReplayTurns {
    fn default() -> Self {
        Self {
            decoding: Arc::new(Semaphore::new(REPLAYS_AT_ONCE)),
            asking: Mutex::new(HashSet::new()),
            working: AtomicUsize::new(0),
        }
    }
}

impl ReplayTurns {
    /// Replays whose work (reading and decoding the file) has not ended yet, clients gone or
    /// not.
    pub fn working(&self) -> usize {
        self.working.load(Ordering::SeqCst)
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

/// What a replay's work holds until it ends: the hub's turn, the therapist's claim, and its
/// place in [`ReplayTurns::working`].
struct Held {
    _turn: tokio::sync::OwnedSemaphorePermit,
    asking: Asking,
}

impl Held {
    fn new(turn: tokio::sync::OwnedSemaphorePermit, asking: Asking) -> Self {
        asking.turns.working.fetch_add(1, Ordering::SeqCst);
        Self {
            _turn: turn,
            asking,
        }
    }
}

impl Drop for Held {
    fn drop(&mut self) {
        self.asking.turns.working.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Sets its flag when dropped: the request gone (its handler or its answer's body dropped)
/// tells the work to stop.
struct CancelOnDrop(Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::SeqCst);
    }
}

/// A replay's lines, cancelling its work when the body is dropped (the console went away).
struct Lines {
    rx: tokio_stream::wrappers::ReceiverStream<Result<Vec<u8>, std::io::Error>>,
    _cancel: CancelOnDrop,
}

impl tokio_stream::Stream for Lines {
    type Item = Result<Vec<u8>, std::io::Error>;

    fn poll_next(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<Option<Self::Item>> {
        std::pin::Pin::new(&mut self.rx).poll_next(cx)
    }
}

/// The CPU time the calling thread has used, s.
fn thread_cpu_s() -> f64 {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// What a replay may cost: the survey's limits and the CPU budget.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ReplayBudget {
    pub(crate) limits: record::CostLimits,
    pub(crate) cpu_s: f64,
}

/// The stream of `path`'s ticks for a replay, once its survey is within `budget`'s limits;
/// its reading asks `stop` and the CPU budget as it goes. The reason in plain words otherwise.
fn open_replay(
    recording: (&hub_care::recordings::RecordingStore, &str, &str),
    budget: ReplayBudget,
    stop: Arc<AtomicBool>,
) -> Result<record::TickStream<std::io::BufReader<Box<dyn hub_care::recordings::ReadSeek>>>, String>
{
    use std::io::Seek;
    let started_s = thread_cpu_s();
    let (store, station, session) = recording;
    let file = store
        .open_reader(station, session)
        .map_err(|e| format!("it cannot be read: {e}"))?;
    let mut input = std::io::BufReader::with_capacity(64 << 10, file);
    let survey =
        record::survey(&mut input, budget.limits.max_records).map_err(|e| e.to_string())?;
    budget.limits.check(&survey)?;
    input
        .rewind()
        .map_err(|e| format!("it cannot be read: {e}"))?;
    let check: record::Check = Box::new(move || {
        if stop.load(Ordering::SeqCst) {
            return Some("the console went away".into());
        }
        let used_s = thread_cpu_s() - started_s;
        (used_s > budget.cpu_s).then(|| {
            format!(
                "it takes more than the {} CPU-seconds this hub gives one replay",
                budget.cpu_s
            )
        })
    });
    record::TickStream::open_checked(
        input,
        record::StreamLimits::default(),
        &record::view::REPLAY_CHANNELS,
        Some(check),
    )
    .map_err(|e| e.to_string())
}

/// `GET /api/sessions/{id}/replay`: the session's uploaded recording as the console's replay
/// draws it, streamed as NDJSON lines while it is decoded (`record::view::replay_ndjson`), so
/// the first frames show at once and the hub holds one line of frames a replay; 404 until
/// the whole recording has arrived, 422 for a file over the hub's limits (its size, or what
/// its chunks declare: `record::CostLimits`) or one that cannot be read (a recording is a
/// station's upload: untrusted), 429 while the same therapist's previous replay is still
/// being decoded, 503 when the hub's turns stay busy. The work stops when the console goes
/// away or its CPU budget ([`DEFAULT_REPLAY_CPU_S`]) is spent; its turns come back when it
/// has stopped.
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
            ApiError::NotFound(Why::new(Code::RecordingNotArrived).says(format!(
                "the recording of session {:?} has not (fully) arrived yet",
                session.session_id
            )))
        })?;
    state
        .audit(&therapist.actor(), "read_replay", &session.session_id, "")
        .await?;
    // A recording the store cannot give is refused, not taken as empty.
    let unreadable = |e: String| {
        tracing::warn!(session = %session.session_id, "replay file unreadable: {e}");
        ApiError::Unprocessable(Why::new(Code::RecordingUnreadable).says(format!(
            "the recording of session {:?} cannot be read on the hub",
            session.session_id
        )))
    };
    let store = state
        .recordings
        .clone()
        .ok_or_else(|| unreadable("this console has no recording store".into()))?;
    let size = store
        .size(&session.station_id, &session.session_id)
        .await
        .map_err(|e| unreadable(e.to_string()))?
        .ok_or_else(|| unreadable(format!("{} is not in the store", recording.path)))?;
    if size > state.replay_max_bytes {
        let why = Why::new(Code::RecordingTooLarge)
            .with("mb", size >> 20)
            .with("max_mb", state.replay_max_bytes >> 20);
        return Err(ApiError::Unprocessable(why.says(format!(
            "the recording of session {:?} is {} MB, more than the {} MB this hub replays \
             (hub serve --max-replay-mb)",
            session.session_id,
            size >> 20,
            state.replay_max_bytes >> 20
        ))));
    }
    let Some(asking) = Asking::begin(&state.replay_turns, &therapist.id) else {
        return Err(ApiError::TooManyRequests(
            Why::new(Code::ReplayPending)
                .says("a replay you asked for is still being prepared; ask again once it is shown"),
            5,
        ));
    };
    let decoding = Arc::clone(&state.replay_turns.decoding);
    let wait = std::time::Duration::from_secs(REPLAY_QUEUE_WAIT_S);
    let Ok(Ok(turn)) = tokio::time::timeout(wait, decoding.acquire_owned()).await else {
        return Err(ApiError::Unavailable(
            Why::new(Code::ReplayBusy).says(format!(
                "the hub is busy preparing other replays ({REPLAYS_AT_ONCE} at a time); try \
                 again in a moment"
            )),
            10,
        ));
    };
    let held = Held::new(turn, asking);
    let budget = state.replay_budget();
    // Set when this request goes: its handler dropped while the file is opened, or its
    // answer's body dropped while the frames are sent. The work asks it as it decodes.
    let stop = Arc::new(AtomicBool::new(false));
    let cancel = CancelOnDrop(Arc::clone(&stop));
    // A few lines in flight: a slow console holds the decoder back rather than the hub's
    // memory.
    let (tx, rx) = tokio::sync::mpsc::channel::<Result<Vec<u8>, std::io::Error>>(4);
    let (opened_tx, opened_rx) = tokio::sync::oneshot::channel::<Result<(), String>>();
    let sid = session.session_id.clone();
    let station = session.station_id.clone();
    let runtime = tokio::runtime::Handle::current();
    let stall = std::time::Duration::from_secs(REPLAY_STALL_S);
    // The turn and the therapist's claim belong to the work: they are given back when it
    // ends (the client gone or not). The file is surveyed and opened (its start checked)
    // before the answer begins, so that a file refused at once is a 422; the frames then
    // follow as they are decoded.
    tokio::task::spawn_blocking(move || {
        let started_s = thread_cpu_s();
        let stream = match open_replay((&store, &station, &sid), budget, stop) {
            Ok(stream) => stream,
            Err(reason) => {
                // The work has ended: its turns come back before the refusal is answered.
                drop(held);
                let _ = opened_tx.send(Err(reason));
                return;
            }
        };
        if opened_tx.send(Ok(())).is_err() {
            return;
        }
        let sent = record::view::replay_ndjson(stream, record::view::MAX_REPLAY_FRAMES, |line| {
            matches!(
                runtime.block_on(tokio::time::timeout(stall, tx.send(Ok(line)))),
                Ok(Ok(()))
            )
        });
        let cpu_s = thread_cpu_s() - started_s;
        drop(held);
        if sent {
            tracing::debug!(session = %sid, cpu_s, "replay sent");
        } else {
            tracing::info!(session = %sid, cpu_s, "replay ended early: the console went away or stalled");
        }
    });
    match opened_rx.await {
        Ok(Ok(())) => {}
        Ok(Err(reason)) => {
            tracing::warn!(session = %session.session_id, "replay refused: {reason}");
            return Err(ApiError::Unprocessable(
                Why::new(Code::RecordingUnreadable).says(format!(
                    "the recording of session {:?} cannot be replayed: {reason}",
                    session.session_id
                )),
            ));
        }
        Err(_) => return Err(ApiError::Internal),
    }
    let lines = Lines {
        rx: tokio_stream::wrappers::ReceiverStream::new(rx),
        _cancel: cancel,
    };
    let body = axum::body::Body::from_stream(lines);
    Ok(([(header::CONTENT_TYPE, "application/x-ndjson")], body).into_response())
}
