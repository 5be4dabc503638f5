//! One clinic for the console's tests: an admin, two therapists each with a patient, and the
//! console's router over it with its clock at [`super::T0`] until a test moves it.

use std::sync::Arc;

use axum::Router;
use hub::web::{self, AppState, LiveEvent, ReplayTurns};
use hub::{Db, Patient, Role, Therapist};
use tokio::sync::broadcast;

use super::T0;
use super::api::PASSWORD;

/// The clinic and the console's router over it.
pub struct Fixture {
    pub app: Router,
    pub db: Db,
    /// Where the ingest would announce summaries (the console's live streams read it).
    pub live: broadcast::Sender<LiveEvent>,
    /// The hand of the console's clock ([`T0`] at first).
    pub clock: clock::MockClock,
    /// The replays being prepared.
    pub turns: Arc<ReplayTurns>,
    /// `root@clinic.example`, an admin.
    pub admin: Therapist,
    /// `ada@clinic.example` and `bob@clinic.example`, therapists.
    pub ada: Therapist,
    pub bob: Therapist,
    /// `p-ada-1` in ada's care and `p-bob-1` in bob's.
    pub p_ada: Patient,
    pub p_bob: Patient,
    /// The SQLite database's directory (`None` on PostgreSQL); files a test writes go here.
    pub dir: Option<tempfile::TempDir>,
}

/// The clinic on a fresh SQLite database, the console's state as [`AppState::new`] makes it.
pub async fn fixture() -> Fixture {
    Fixture::new(|s| s).await
}

impl Fixture {
    /// The clinic on a fresh SQLite database; `state` changes the console's state.
    pub async fn new(state: impl FnOnce(AppState) -> AppState) -> Self {
        let (db, dir) = super::sqlite_db().await;
        Self::on(db, Some(dir), state).await
    }

    /// The clinic on `db` (kept in `dir`, if any); `state` changes the console's state.
    pub async fn on(
        db: Db,
        dir: Option<tempfile::TempDir>,
        state: impl FnOnce(AppState) -> AppState,
    ) -> Self {
        let add = |email: &'static str, role| {
            let db = db.clone();
            async move { db.add_therapist(email, PASSWORD, role, T0).await.unwrap() }
        };
        let admin = add("root@clinic.example", Role::Admin).await;
        let ada = add("ada@clinic.example", Role::Therapist).await;
        let bob = add("bob@clinic.example", Role::Therapist).await;
        let p_ada = db.add_patient("p-ada-1", Some(&ada.id), T0).await.unwrap();
        let p_bob = db.add_patient("p-bob-1", Some(&bob.id), T0).await.unwrap();
        let (live, _) = broadcast::channel(256);
        let (now, clock) = super::clock_at(T0);
        let mut base = AppState::new(db.clone(), live.clone()).with_clock(now);
        if let Some(dir) = &dir {
            // Recordings kept as `hub serve` keeps them by default: `<dir>/recordings`.
            let store = hub::recordings::RecordingStore::local(dir.path().join("recordings"));
            base = base.with_recordings(store.unwrap());
        }
        let state = state(base);
        let turns = Arc::clone(&state.replay_turns);
        Self {
            app: web::router(state),
            db,
            live,
            clock,
            turns,
            admin,
            ada,
            bob,
            p_ada,
            p_bob,
            dir,
        }
    }
}
