//! PostgreSQL that fails over, end to end: `telerehab hub chaos --patroni` starts three etcd
//! members, two Patroni nodes (a primary and a synchronous replica) and HAProxy in front of them
//! (checking each node's `GET /primary`), two hubs whose database URL is the balancer, and four
//! stations sending sessions; mid-session the primary's machine goes (its Patroni, its
//! postmaster and its etcd member SIGKILLed), the replica is promoted by the two etcd members
//! left, the hubs' pools reconnect through the balancer by
//! themselves and the killed node rejoins as the replica. The command then counts every
//! summary the stations' own ledgers say a hub acknowledged against the database: each stored
//! exactly once — what synchronous replication buys. Prints the failover time (primary killed →
//! first write accepted on the new primary) and the test's. Without patroni, etcd, haproxy or
//! PostgreSQL installed (scripts/setup.sh installs them) it prints SKIPPED.

use std::process::Command;
use std::time::Instant;
use telerehab_tests::telerehab_bin;

#[test]
fn a_primary_killed_mid_session_fails_over_and_loses_and_duplicates_no_summary() {
    let began = Instant::now();
    let out = Command::new(telerehab_bin())
        .args(["hub", "chaos", "--patroni", "--kinds", "postgres"])
        .args(["--stations", "4", "--sessions", "2"])
        .args(["--seed", "7", "--day-s", "20", "--events", "1"])
        .args(["--deadline-s", "60"])
        .output()
        .expect("run telerehab hub chaos --patroni");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let missing = [
        "on the PATH",
        "/usr/lib/postgresql",
        "no `postgres` OS user",
    ];
    if !out.status.success()
        && stderr.contains("Patroni unavailable")
        && missing.iter().any(|m| stderr.contains(m))
    {
        println!("SKIPPED: {}", stderr.trim());
        return;
    }
    assert!(
        out.status.success(),
        "the day with a primary kill failed:\n{stdout}\n{stderr}"
    );
    let kill = stdout
        .lines()
        .find(|l| l.contains("kill PostgreSQL primary") && l.contains("failover "))
        .unwrap_or_else(|| panic!("no primary killed and failed over in:\n{stdout}"));
    assert!(kill.contains("back as synchronous replica"), "{kill}");
    let failover = stdout
        .lines()
        .find(|l| l.starts_with("failover: 1 primary kills"))
        .unwrap_or_else(|| panic!("no failover time in:\n{stdout}"));
    // The hubs reconnected by themselves: neither exited (their supervisor would have restarted
    // it, which would hide a pool that never recovers).
    assert!(
        stdout.contains("hub starts 2, hub exits on their own 0"),
        "a hub did not survive the failover:\n{stdout}"
    );
    assert!(
        stdout.contains("4 paired, 4 done"),
        "not every station finished:\n{stdout}"
    );
    assert!(stdout.contains(", 0 missing, 0 extra"), "{stdout}");
    assert!(stdout.contains("verdict: OK"), "{stdout}");
    println!("{failover}");
    println!(
        "failover_e2e: whole test {:.1} s",
        began.elapsed().as_secs_f64()
    );
}
