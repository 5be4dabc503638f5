//! Several hubs on one PostgreSQL database, no shared disk: the pairing limits of an address
//! hold across hubs, and what one hub tells the others ([`hub::fanout`]) reaches them — with
//! its delay measured, and again after the listening connection was lost.
//!
//! PostgreSQL only (`bash scripts/with-postgres.sh cargo test -p hub --test several_hubs`);
//! without it each test says SKIPPED. The delay figures of BENCHMARKS.md come from
//! `… --test several_hubs -- --nocapture`.

mod common;

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::time::{Duration, Instant};

use common::{PgDb, T0, clock_at};
use hub::Db;
use hub::fanout::{Fanout, Note};
use hub::ingest::{DbStore, PAIRING_ATTEMPTS_PER_MINUTE, PAIRING_FAILURES_PER_HOUR};
use hub::web::LiveEvent;
use netlink::pairing::PairingAuthority;

/// The address every attempt of these tests comes from.
const GUESSER: SocketAddr = SocketAddr::new(IpAddr::V4(Ipv4Addr::new(203, 0, 113, 9)), 4711);

/// Longest a note may take to cross in these tests (a loaded 2-core machine).
const CROSS_WITHIN: Duration = Duration::from_secs(10);

/// A hub's station store on `db` (its own pool: another hub's process).
fn hub_store(db: Db, clock: clock::Clock) -> DbStore {
    let ca = netlink::pki::ClinicCa::create("Clinic").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let recordings = hub::recordings::RecordingStore::open(dir.path(), None).unwrap();
    DbStore::new(db, ca, "localhost".into(), recordings, clock)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pairing_attempts_spread_over_two_hubs_get_one_addresss_allowance() {
    let Some(pg) = PgDb::create().await else {
        return;
    };
    let (clock, hand) = clock_at(T0);
    let a = hub_store(pg.db.clone(), clock.clone());
    let b = hub_store(Db::open(&pg.url).await.unwrap(), clock.clone());
    let hubs = [&a, &b];
    let mut begun = 0;
    for i in 0..2 * PAIRING_ATTEMPTS_PER_MINUTE {
        let hub = hubs[i as usize % 2];
        if hub.begin("ABCD", GUESSER).await.is_ok() {
            begun += 1;
        }
    }
    assert_eq!(
        begun, PAIRING_ATTEMPTS_PER_MINUTE,
        "one address's minute, spread over two hubs"
    );
    // A new minute: the failures of the hour, spread over both, close both.
    hand.set_unix_ns(common::ns(T0 + 61_000));
    for i in 0..PAIRING_FAILURES_PER_HOUR {
        hubs[i as usize % 2].failed("ABCD", GUESSER).await;
    }
    for hub in hubs {
        let refused = hub.begin("ABCD", GUESSER).await.unwrap_err();
        assert!(
            refused.message.contains("too many pairing attempts"),
            "{}",
            refused.message
        );
    }
    // Another address is not held by this one's count.
    let other = SocketAddr::new(IpAddr::V4(Ipv4Addr::new(198, 51, 100, 7)), 4711);
    assert!(b.begin("ABCD", other).await.is_ok());
    drop((a, b));
    pg.drop_db().await;
}

fn live_note(seq: u64) -> Note {
    Note::Live {
        event: LiveEvent {
            patient_id: "p-1".into(),
            session_id: "s-1".into(),
            summary: netlink::Summary {
                session_id: "s-1".into(),
                seq,
                t_s: seq as f64 * 0.1,
                exercise: "sine-road".into(),
                speed_m_s: 5.0,
                lateral_m: 0.1,
                rms_lateral_m: 0.1,
                max_lateral_m: 0.2,
                pct_in_lane: 98.0,
                max_abs_torque_nm: 1.2,
                loop_p99_us: 35.0,
                ticks: seq * 100,
                dropped_records: 0,
                extra: [("assist".to_owned(), 0.4)].into(),
            },
        },
    }
}

fn seq_of(note: &Note) -> u64 {
    match note {
        Note::Live { event } => event.summary.seq,
        other => panic!("not a summary: {other:?}"),
    }
}

/// The `q`-quantile of sorted `values`.
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let i = ((sorted.len() as f64 - 1.0) * q).round() as usize;
    sorted[i]
}

/// Sends `n` summaries from hub A at about 100 a second (ten stations' pace) while hub B
/// receives them; their delays A→B, ms, sorted. Hub B hears them in the order sent.
async fn delays_a_to_b(
    a: &Fanout,
    b: &mut tokio::sync::mpsc::Receiver<Note>,
    first: u64,
    n: u64,
) -> Vec<f64> {
    let send = async {
        let mut sent_at = Vec::with_capacity(n as usize);
        let mut pace = tokio::time::interval(Duration::from_millis(10));
        for seq in first..first + n {
            pace.tick().await;
            sent_at.push(Instant::now());
            a.publish(live_note(seq));
        }
        sent_at
    };
    let receive = async {
        let mut heard = Vec::with_capacity(n as usize);
        for _ in 0..n {
            let note = tokio::time::timeout(CROSS_WITHIN, b.recv())
                .await
                .expect("every note crosses")
                .unwrap();
            heard.push((seq_of(&note), Instant::now()));
        }
        heard
    };
    let (sent_at, heard) = tokio::join!(send, receive);
    let seqs: Vec<u64> = heard.iter().map(|(seq, _)| *seq).collect();
    assert_eq!(seqs, (first..first + n).collect::<Vec<_>>(), "in order");
    let mut delays: Vec<f64> = heard
        .iter()
        .zip(&sent_at)
        .map(|((_, at), sent)| at.duration_since(*sent).as_secs_f64() * 1e3)
        .collect();
    delays.sort_by(f64::total_cmp);
    delays
}

/// Sends summaries from `seq` on until hub B hears one (after a lost connection, notes sent
/// before B listens again are lost by design), then lets the stragglers arrive and drops
/// them: the next seq to send.
async fn heard_again(a: &Fanout, b: &mut tokio::sync::mpsc::Receiver<Note>, mut seq: u64) -> u64 {
    let began = Instant::now();
    loop {
        a.publish(live_note(seq));
        seq += 1;
        if let Ok(Some(_)) = tokio::time::timeout(Duration::from_millis(200), b.recv()).await {
            break;
        }
        assert!(
            began.elapsed() < CROSS_WITHIN,
            "hub B never heard hub A again"
        );
    }
    tokio::time::sleep(Duration::from_millis(300)).await;
    while b.try_recv().is_ok() {}
    seq
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_summary_on_one_hub_reaches_the_other_in_order_and_again_after_its_connection_is_lost() {
    let Some(pg) = PgDb::create().await else {
        return;
    };
    let db_b = Db::open(&pg.url).await.unwrap();
    let (a, mut heard_by_a) = Fanout::start(&pg.db).expect("PostgreSQL has a channel");
    let (_b, mut heard_by_b) = Fanout::start(&db_b).unwrap();
    assert_ne!(a.origin(), _b.origin());
    // Both listen before the measure starts.
    let first = heard_again(&a, &mut heard_by_b, 0).await;
    let n = 300;
    let delays = delays_a_to_b(&a, &mut heard_by_b, first, n).await;
    let (median, p99) = (quantile(&delays, 0.5), quantile(&delays, 0.99));
    println!(
        "hub A -> hub B over LISTEN/NOTIFY: {n} summaries at 100/s, median {median:.2} ms, \
         p99 {p99:.2} ms, max {:.2} ms",
        delays[delays.len() - 1]
    );
    // A hub does not hear itself: its own live views were served in-process.
    assert!(heard_by_a.try_recv().is_err());

    // B's listening connection is cut (a database restart, a proxy's idle timeout): it
    // listens again by itself and hears the next summaries.
    let cut: Vec<i32> = sqlx::query_scalar(
        "SELECT pg_terminate_backend(pid)::int FROM pg_stat_activity \
         WHERE query LIKE 'LISTEN%' AND datname = current_database()",
    )
    .fetch_all(pg.db.pool())
    .await
    .unwrap();
    assert_eq!(cut.len(), 2, "both hubs were listening");
    let again = heard_again(&a, &mut heard_by_b, first + n).await;
    let after = delays_a_to_b(&a, &mut heard_by_b, again, 50).await;
    assert_eq!(after.len(), 50);
    drop((a, _b));
    db_b.close().await;
    pg.drop_db().await;
}
