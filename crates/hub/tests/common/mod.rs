//! Databases for the hub's tests: a SQLite file in a temp dir, and a fresh PostgreSQL
//! database on the server named by `TELEREHAB_TEST_PG_URL` (`scripts/with-postgres.sh`).

#![allow(dead_code, missing_docs)]

pub mod api;
pub mod fixture;
pub mod link;
pub mod s3;

use hub::Db;
use sqlx::Connection;

/// The tests' "now": 2026-11-21 09:30 UTC, ms since the Unix epoch.
pub const T0: i64 = 1_795_253_400_000;

/// A mock clock whose wall clock reads `unix_ms` (ms since the Unix epoch) until its hand
/// moves it ([`clock::MockClock::set_unix_ns`] with [`ns`], or `advance`).
pub fn clock_at(unix_ms: i64) -> (clock::Clock, clock::MockClock) {
    clock::Clock::mock_at_unix_ns(ns(unix_ms))
}

/// `unix_ms` (ms since the Unix epoch) in ns.
pub fn ns(unix_ms: i64) -> u64 {
    u64::try_from(unix_ms).expect("a date after 1970") * 1_000_000
}

/// A station's `Hello` opening session `session_id` of a sine road at [`T0`].
pub fn hello(station_id: &str, patient_id: &str, session_id: &str) -> netlink::Hello {
    netlink::Hello {
        protocol_version: netlink::PROTOCOL_VERSION,
        station_id: station_id.to_owned(),
        patient_id: patient_id.to_owned(),
        session_id: session_id.to_owned(),
        exercise: "sine-road".to_owned(),
        started_unix_ms: T0 as u64,
        software_version: "telerehab 0.1.0".to_owned(),
        min_protocol_version: None,
        wheel: None,
    }
}

/// The environment variable naming the PostgreSQL server for tests.
pub const PG_ENV: &str = "TELEREHAB_TEST_PG_URL";

/// A fresh SQLite database; keep the temp dir alive as long as the database.
pub async fn sqlite_db() -> (Db, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("temp dir");
    let db = Db::open_sqlite(&dir.path().join("hub.db"))
        .await
        .expect("open sqlite");
    (db, dir)
}

/// A fresh database `t_<random>` on the test PostgreSQL server, dropped by [`PgDb::drop_db`].
pub struct PgDb {
    pub db: Db,
    pub url: String,
    admin_url: String,
    name: String,
}

fn random_suffix() -> String {
    let mut bytes = [0u8; 8];
    getrandom::fill(&mut bytes).expect("random");
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

impl PgDb {
    /// `None` (after printing why) when `TELEREHAB_TEST_PG_URL` is not set.
    pub async fn create() -> Option<Self> {
        let Ok(admin_url) = std::env::var(PG_ENV) else {
            println!("SKIPPED: {PG_ENV} is not set (scripts/with-postgres.sh starts a server)");
            return None;
        };
        sqlx::any::install_default_drivers();
        let name = format!("t_{}", random_suffix());
        let mut conn = sqlx::AnyConnection::connect(&admin_url)
            .await
            .expect("connect to the test PostgreSQL server");
        sqlx::raw_sql(sqlx::AssertSqlSafe(format!("CREATE DATABASE {name}")))
            .execute(&mut conn)
            .await
            .expect("create test database");
        conn.close().await.ok();
        let base = admin_url
            .rsplit_once('/')
            .map_or(admin_url.as_str(), |(base, _)| base);
        let url = format!("{base}/{name}");
        let db = Db::open(&url).await.expect("open postgres");
        Some(Self {
            db,
            url,
            admin_url,
            name,
        })
    }

    /// Closes the pool and drops the database.
    pub async fn drop_db(self) {
        self.db.close().await;
        let mut conn = sqlx::AnyConnection::connect(&self.admin_url)
            .await
            .expect("connect to the test PostgreSQL server");
        sqlx::raw_sql(sqlx::AssertSqlSafe(format!(
            "DROP DATABASE IF EXISTS {} WITH (FORCE)",
            self.name
        )))
        .execute(&mut conn)
        .await
        .expect("drop test database");
        conn.close().await.ok();
    }
}

/// Runs each named `async fn(Db)` on SQLite and on PostgreSQL: tests `<name>::sqlite` and
/// `<name>::postgres`.
#[macro_export]
macro_rules! on_both_backends {
    ($($name:ident),* $(,)?) => {$(
        mod $name {
            #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
            async fn sqlite() {
                let (db, _dir) = $crate::common::sqlite_db().await;
                super::$name(db).await;
            }

            #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
            async fn postgres() {
                let Some(pg) = $crate::common::PgDb::create().await else {
                    return;
                };
                super::$name(pg.db.clone()).await;
                pg.drop_db().await;
            }
        }
    )*};
}

/// A station's recording of `seconds` at 1 kHz (a sine on the wheel's angle, a chunk a
/// second), as the recorder writes one.
pub fn honest_recording(seconds: u64) -> Vec<u8> {
    let meta = record::SessionMetadata {
        loop_rate_hz: 1000.0,
        exercise: "sine-road".into(),
        ..Default::default()
    };
    let mut w = record::RecordWriter::new(std::io::Cursor::new(Vec::new()), 0, &meta).unwrap();
    for tick in 0..seconds * 1000 {
        let mut rec = record::TickRecord {
            tick,
            t_ns: tick * 1_000_000,
            ..Default::default()
        };
        rec.wheel.angle_rad = (tick as f64 * 1e-3).sin();
        w.write_tick(&rec, tick % 100 == 0).unwrap();
        if tick % 1000 == 999 {
            w.flush().unwrap();
        }
    }
    w.finish().unwrap().into_inner()
}
