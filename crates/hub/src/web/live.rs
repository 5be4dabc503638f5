//! Server-Sent Events of a patient's running session. A stream lives only as long as the
//! login that opened it: its login and the patient's assignment are checked again every
//! [`LIVE_RECHECK_MS`], and at most [`MAX_LIVE_STREAMS_PER_LOGIN`] are open per login and
//! [`MAX_LIVE_STREAMS_PER_ACCOUNT`] per therapist across all their logins.

use std::collections::HashMap;
use std::convert::Infallible;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use axum::http::HeaderMap;
use axum::response::sse::{Event, KeepAlive, Sse};
use tokio::sync::broadcast::error::RecvError;
use tokio::sync::mpsc::error::TrySendError;
use tokio_stream::Stream;
use tokio_stream::StreamExt as _;
use tokio_stream::wrappers::ReceiverStream;

use super::Says as _;
use super::auth::{Authed, token_of};
use super::{ApiError, AppState, LiveEvent};
use hub_store::db::sha256_hex;
use hub_store::refusal::{Code, Why};

/// How often a live stream checks again that its login is valid and its patient still
/// visible, ms; a logout, expiry, password change, revocation or reassignment ends it within
/// twice that.
pub const LIVE_RECHECK_MS: u64 = 500;

/// Most live streams open at once per login (one console tab needs one); more are answered
/// 429.
pub const MAX_LIVE_STREAMS_PER_LOGIN: usize = 4;

/// Most live streams open at once per therapist across all their logins (two browsers with a
/// few tabs each); more are answered 429, so many logins of one account cannot multiply
/// [`MAX_LIVE_STREAMS_PER_LOGIN`].
pub const MAX_LIVE_STREAMS_PER_ACCOUNT: usize = 8;

/// Events a stream buffers for a slow client before it skips some (and says `lagged`).
const STREAM_BUFFER: usize = 64;

/// A running session's live data is *delayed* when nothing of it has arrived for this long,
/// or when a summary arrives this much later than the station produced it, ms (twenty
/// summary periods at 10 Hz): a home link that is down, flapping or catching up after an
/// outage. The stream then says so (`delayed`, `late_ms`) instead of showing the last
/// summary as if it were now.
pub const LIVE_DELAYED_MS: i64 = 2_000;

/// A `summary` event's data: the summary as the ingest broadcast it and how late it reached
/// the hub.
#[derive(serde::Serialize)]
struct LiveSummary<'a> {
    #[serde(flatten)]
    event: &'a LiveEvent,
    /// The hub's clock when it broadcast the summary minus the station's time of it (its
    /// session's start plus its `t_s`), ms; `None` when the session's start is unknown. Off
    /// by the two clocks' difference (`telerehab doctor --hub` shows it).
    late_ms: Option<i64>,
}

/// A `delayed` event's data: nothing of the running session `session_id` has arrived for
/// `silent_ms`.
#[derive(serde::Serialize)]
struct Delayed<'a> {
    session_id: &'a str,
    silent_ms: i64,
}

/// The session a stream last forwarded a summary of.
struct Watched {
    session_id: String,
    /// Its start by the station's clock, ms since the Unix epoch, if the hub has the session.
    started_unix_ms: Option<i64>,
    /// The hub's clock at its last summary, ms since the Unix epoch.
    last_ms: i64,
    /// The station said `Bye`: its silence is its end, not a delay.
    closed: bool,
}

/// Live streams open per login (keyed `login:` + the token's hash) and per therapist (keyed
/// `account:` + their id).
#[derive(Debug, Clone, Default)]
pub struct StreamCounts(Arc<Mutex<HashMap<String, usize>>>);

/// Why a stream was refused a place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Full {
    Login,
    Account,
}

/// One open stream's places in [`StreamCounts`] (its login's and its account's), given back
/// when dropped.
struct StreamSlot {
    counts: StreamCounts,
    keys: [String; 2],
}

impl StreamCounts {
    /// A place for one more stream of the login with token hash `login` of the therapist
    /// `account`, taken on both counts at once (or on neither).
    fn take(&self, login: &str, account: &str) -> Result<StreamSlot, Full> {
        let keys = [format!("login:{login}"), format!("account:{account}")];
        let mut map = self.0.lock().map_err(|_| Full::Login)?;
        let count = |map: &HashMap<String, usize>, k: &str| map.get(k).copied().unwrap_or(0);
        if count(&map, &keys[0]) >= MAX_LIVE_STREAMS_PER_LOGIN {
            return Err(Full::Login);
        }
        if count(&map, &keys[1]) >= MAX_LIVE_STREAMS_PER_ACCOUNT {
            return Err(Full::Account);
        }
        for k in &keys {
            *map.entry(k.clone()).or_insert(0) += 1;
        }
        Ok(StreamSlot {
            counts: self.clone(),
            keys,
        })
    }
}

impl Drop for StreamSlot {
    fn drop(&mut self) {
        if let Ok(mut map) = self.counts.0.lock() {
            for key in &self.keys {
                if let Some(n) = map.get_mut(key) {
                    *n = n.saturating_sub(1);
                    if *n == 0 {
                        map.remove(key);
                    }
                }
            }
        }
    }
}

/// `GET /api/patients/{id}/live`: events `summary` (data: a [`LiveEvent`] as JSON with its
/// `late_ms`) for this patient only, `delayed` (data: the session and how long it has been
/// silent) while a running session sends nothing for [`LIVE_DELAYED_MS`] or more, `lagged`
/// (data: how many were skipped) when the client is too slow, and a last `ended` (data: why)
/// when the login or the patient's assignment ends.
pub(crate) async fn live(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    headers: HeaderMap,
    id: Result<Path<String>, PathRejection>,
) -> Result<Sse<impl Stream<Item = Result<Event, Infallible>>>, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let token = token_of(&headers).ok_or(ApiError::Internal)?;
    let slot = state
        .live_streams
        .take(&sha256_hex(token.as_bytes()), &therapist.id)
        .map_err(|full| {
            let (max, message) = match full {
                Full::Login => (
                    MAX_LIVE_STREAMS_PER_LOGIN,
                    format!(
                        "at most {MAX_LIVE_STREAMS_PER_LOGIN} live streams per login; close one \
                         first"
                    ),
                ),
                Full::Account => (
                    MAX_LIVE_STREAMS_PER_ACCOUNT,
                    format!(
                        "at most {MAX_LIVE_STREAMS_PER_ACCOUNT} live streams per therapist \
                         across all your logins; close one first"
                    ),
                ),
            };
            ApiError::TooManyRequests(
                Why::new(Code::LiveStreams).with("max", max).says(message),
                1,
            )
        })?;
    // Subscribe before answering, so nothing broadcast after the answer is missed.
    let receiver = state.live.subscribe();
    state
        .audit(&therapist.actor(), "watch_live", &patient.id, "")
        .await?;
    let (tx, rx) = tokio::sync::mpsc::channel(STREAM_BUFFER);
    let watch = Watch {
        state,
        token,
        actor: therapist.actor(),
        patient_id: patient.id,
    };
    tokio::spawn(watch.forward(receiver, tx, slot));
    Ok(Sse::new(ReceiverStream::new(rx).map(Ok)).keep_alive(KeepAlive::default()))
}

/// What a live stream forwards and re-checks.
struct Watch {
    state: AppState,
    token: String,
    actor: String,
    patient_id: String,
}

impl Watch {
    /// Why the stream must end now, if it must.
    async fn ended(&self) -> Option<Stopped> {
        let now = self.state.now();
        let therapist = match self.state.db.web_session(&self.token, now).await {
            Ok(Some(t)) => t,
            Ok(None) => return Some(Stopped::LoginEnded),
            Err(e) => {
                tracing::warn!("a live stream cannot re-check its login: {e}");
                return Some(Stopped::LoginUnchecked);
            }
        };
        match self
            .state
            .visible_patient(&therapist, &self.patient_id)
            .await
        {
            Ok(_) => None,
            Err(_) => Some(Stopped::NotYourPatient),
        }
    }

    /// Notes `event` as the watched session's latest summary; how late it arrived, ms.
    async fn late_ms(&self, watched: &mut Option<Watched>, event: &LiveEvent) -> Option<i64> {
        let now = self.state.now();
        let same = watched
            .as_ref()
            .is_some_and(|w| w.session_id == event.session_id);
        if !same {
            let started_unix_ms = match self.state.db.session(&event.session_id).await {
                Ok(row) => row.map(|r| r.started_unix_ms),
                Err(e) => {
                    tracing::warn!("a live stream cannot read its session's start: {e}");
                    None
                }
            };
            *watched = Some(Watched {
                session_id: event.session_id.clone(),
                started_unix_ms,
                last_ms: now,
                closed: false,
            });
        }
        let w = watched.as_mut()?;
        w.last_ms = now;
        w.closed = false;
        // The summary's time on the station, ms (a finite t_s: the ingest checked it).
        #[allow(clippy::cast_possible_truncation)]
        // Saturating: a station's clock or t_s far off must not overflow the stream's task.
        let at_ms = w
            .started_unix_ms?
            .saturating_add((event.summary.t_s * 1000.0).round() as i64);
        Some(now.saturating_sub(at_ms).max(0))
    }

    /// A `delayed` event if the watched session is still running (no `Bye`) and has sent
    /// nothing for [`LIVE_DELAYED_MS`] or more.
    async fn silence(&self, watched: Option<&mut Watched>) -> Option<Event> {
        let w = watched?;
        let silent_ms = self.state.now() - w.last_ms;
        if w.closed || silent_ms < LIVE_DELAYED_MS {
            return None;
        }
        match self.state.db.session(&w.session_id).await {
            Ok(Some(row)) if row.closed_at_ms.is_some() => {
                w.closed = true;
                return None;
            }
            Ok(_) => {}
            Err(e) => tracing::warn!("a live stream cannot check its session's end: {e}"),
        }
        let data = Delayed {
            session_id: &w.session_id,
            silent_ms,
        };
        Some(match Event::default().event("delayed").json_data(data) {
            Ok(e) => e,
            Err(e) => Event::default().event("error").data(e.to_string()),
        })
    }

    /// Forwards this patient's summaries to the client until it goes away or [`Watch::ended`]
    /// says the stream must end.
    async fn forward(
        self,
        mut receiver: tokio::sync::broadcast::Receiver<LiveEvent>,
        tx: tokio::sync::mpsc::Sender<Event>,
        slot: StreamSlot,
    ) {
        let _slot = slot;
        let mut check = tokio::time::interval(Duration::from_millis(LIVE_RECHECK_MS));
        check.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
        let mut skipped: u64 = 0;
        let mut watched: Option<Watched> = None;
        loop {
            let event = tokio::select! {
                biased;
                () = tx.closed() => return,
                _ = check.tick() => {
                    if let Some(stopped) = self.ended().await {
                        let _ = tx.try_send(Event::default().event("ended").data(stopped.code()));
                        if let Err(e) = self.state.audit(&self.actor, "live_ended", &self.patient_id, stopped.english()).await {
                            tracing::error!("cannot audit the end of a live stream: {e:?}");
                        }
                        return;
                    }
                    match self.silence(watched.as_mut()).await {
                        Some(delayed) => delayed,
                        None => continue,
                    }
                }
                message = receiver.recv() => match message {
                    Ok(event) if event.patient_id == self.patient_id => {
                        let late_ms = self.late_ms(&mut watched, &event).await;
                        match Event::default().event("summary").json_data(LiveSummary { event: &event, late_ms }) {
                            Ok(e) => e,
                            Err(e) => Event::default().event("error").data(e.to_string()),
                        }
                    }
                    Ok(_) => continue,
                    Err(RecvError::Lagged(n)) => {
                        skipped += n;
                        continue;
                    }
                    Err(RecvError::Closed) => return,
                },
            };
            if skipped > 0 {
                let lagged = Event::default().event("lagged").data(skipped.to_string());
                if tx.try_send(lagged).is_ok() {
                    skipped = 0;
                }
            }
            match tx.try_send(event) {
                Ok(()) => {}
                Err(TrySendError::Full(_)) => skipped += 1,
                Err(TrySendError::Closed(_)) => return,
            }
        }
    }
}

/// Why the hub stopped a live stream: the `ended` event's data is its code, which the console
/// words as `live-stopped-<code>`; the audit log keeps the English.
#[derive(Debug, Clone, Copy)]
enum Stopped {
    LoginEnded,
    LoginUnchecked,
    NotYourPatient,
}

impl Stopped {
    fn code(self) -> &'static str {
        match self {
            Self::LoginEnded => "login-ended",
            Self::LoginUnchecked => "login-unchecked",
            Self::NotYourPatient => "not-your-patient",
        }
    }

    fn english(self) -> &'static str {
        match self {
            Self::LoginEnded => "your login ended (logout, expiry or password change)",
            Self::LoginUnchecked => "the hub cannot check your login right now",
            Self::NotYourPatient => "this patient is no longer assigned to you",
        }
    }
}
