//! The short chaos day of CI: `telerehab hub chaos` with 4 stations over a 16 s day on two hubs
//! sharing one PostgreSQL server of its own, with a hub SIGKILLed, a hub SIGTERMed, a station
//! killed and the PostgreSQL server crashed (`pg_ctl stop -m immediate`), each restarted. The
//! command itself checks every summary stored once, every recording verified, nobody stuck and
//! the audit log complete, and fails otherwise. Without PostgreSQL it prints SKIPPED.
//!
//! And the clinic network's short day (issue 45): three hubs with no shared disk behind
//! HAProxy, PostgreSQL under Patroni (primary and synchronous replica), recordings in a
//! SeaweedFS S3 store of the day's own, with every kind of fault at least once — hub SIGKILL
//! and SIGTERM, a station, the primary's machine, the store SIGKILLed and a hub partitioned
//! from the database and the store — ending with every summary stored once and every
//! recording verified from the store, and the restore drill on the cluster: pgBackRest backs up
//! whichever node leads into a store of its own, both nodes archive their WAL across the
//! failover, and the database restored at the end must hold every summary (about 2 minutes on
//! a loaded 2-core machine). The two days run one after the other (each loads the whole
//! machine).

use std::sync::Mutex;
use telerehab_tests::{chaos_day, restored_summaries};

/// One chaos day at a time.
static ONE_DAY: Mutex<()> = Mutex::new(());

#[test]
fn a_short_chaos_day_loses_and_duplicates_no_summary_and_leaves_no_station_stuck() {
    let _one = ONE_DAY
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let Some(stdout) = chaos_day(&[
        "--stations",
        "4",
        "--sessions",
        "2",
        "--seed",
        "7",
        "--day-s",
        "16",
        "--events",
        "5",
        "--deadline-s",
        "60",
    ]) else {
        return;
    };
    // The kills happened: each of the four kinds once at least (five events, the first four
    // one of each), and the stations did their sessions.
    // A kill counts only when it was carried out (`…, down N s`), not skipped.
    for kind in ["Kill hub", "Term hub", "kill station", "kill PostgreSQL"] {
        assert!(
            stdout
                .lines()
                .any(|l| l.contains(kind) && l.contains(", down ")),
            "no {kind:?} carried out in:\n{stdout}"
        );
    }
    assert!(stdout.contains("verdict: OK"), "{stdout}");
    assert!(
        stdout.contains("4 paired, 4 done"),
        "not every station finished:\n{stdout}"
    );
}

#[test]
fn three_hubs_without_a_shared_disk_lose_nothing_through_store_and_network_faults() {
    let _one = ONE_DAY
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let Some(stdout) = chaos_day(&[
        "--hubs",
        "3",
        "--patroni",
        "--s3",
        "--drill",
        "--stations",
        "12",
        "--sessions",
        "2",
        "--seed",
        "11",
        "--day-s",
        "60",
        "--events",
        "8",
        "--deadline-s",
        "150",
    ]) else {
        return;
    };
    assert!(stdout.contains("3 hubs on"), "{stdout}");
    assert!(stdout.contains("stations through HAProxy"), "{stdout}");
    // Every kind carried out at least once (eight events, the first six one of each).
    for kind in [
        "Kill hub",
        "Term hub",
        "kill station",
        "kill PostgreSQL",
        "kill the S3 store",
        "partition hub",
    ] {
        assert!(
            stdout
                .lines()
                .any(|l| l.contains(kind) && l.contains(", down ") && !l.contains("failed")),
            "no {kind:?} carried out in:\n{stdout}"
        );
    }
    assert!(stdout.contains("verdict: OK"), "{stdout}");
    assert!(
        stdout.contains("12 paired, 12 done"),
        "not every station finished:\n{stdout}"
    );
    // Recordings were checked in the store, and there were some.
    let line = stdout
        .lines()
        .find(|l| l.starts_with("recordings: "))
        .expect("a recordings line");
    assert!(line.ends_with("from the S3 store"), "{line}");
    assert!(!line.starts_with("recordings: 0 written"), "{line}");
    // The cluster restored from pgBackRest in the store, across the primary's failover.
    assert!(restored_summaries(&stdout) > 0, "{stdout}");
}
