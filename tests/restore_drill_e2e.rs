//! The restore drill of issue 45 in a short chaos day: `telerehab hub chaos --drill` backs the
//! day's PostgreSQL up with pgBackRest into a SeaweedFS of its own over HTTPS (a CA made at run
//! time), archives the WAL all day (a PostgreSQL crash among the kills), and at the end restores
//! into a fresh data directory, starts a second server on it and compares the counts of
//! summaries, sessions, recordings, audit rows, patients and stations and a digest of every
//! summary with the live database's: the command fails on any difference. Without PostgreSQL it
//! prints SKIPPED (as tests/hub_chaos_e2e.rs); without pgBackRest or SeaweedFS it fails
//! (scripts/setup.sh installs both).

use telerehab_tests::{chaos_day, restored_summaries};

#[test]
fn a_chaos_day_restored_from_pgbackrest_in_the_object_store_has_every_summary() {
    let Some(stdout) = chaos_day(&[
        "--drill",
        "--stations",
        "4",
        "--sessions",
        "2",
        "--seed",
        "11",
        "--day-s",
        "20",
        "--events",
        "4",
        "--kinds",
        "postgres,station,hub-kill",
        "--deadline-s",
        "90",
    ]) else {
        return;
    };
    assert!(
        stdout
            .lines()
            .any(|l| l.contains("kill PostgreSQL") && l.contains(", down ")),
        "no PostgreSQL crash during the archived day:\n{stdout}"
    );
    // The restored counts are printed and are not empty: the day's summaries came back.
    let summaries = restored_summaries(&stdout);
    assert!(summaries > 0, "the restore holds no summary:\n{stdout}");
    assert!(stdout.contains("verdict: OK"), "{stdout}");
}
