//! End-to-end: stations and the therapist hub on loopback.

use std::process::{Command, Stdio};
use std::time::Duration;
use telerehab_tests::{TherapistHub, by_topic, read_mcap, run_ok, stored_seqs, telerehab_bin};

#[test]
fn two_stations_deliver_every_summary_exactly_once_to_one_hub() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("store");
    let hub = TherapistHub::start(&store);
    let run_station = |id: &'static str, addr: String| {
        std::thread::spawn(move || {
            run_ok(&[
                "run",
                "--sim",
                "--headless",
                "--duration",
                "3",
                "--speed",
                "max",
                "--station-id",
                id,
                "--therapist",
                &addr,
            ])
        })
    };
    let a = run_station("station-a", hub.addr.clone());
    let b = run_station("station-b", hub.addr.clone());
    for (id, handle) in [("station-a", a), ("station-b", b)] {
        let out = handle.join().unwrap();
        let report = String::from_utf8_lossy(&out.stdout);
        assert!(
            report.contains("31 summaries: 31 sent, 31 acknowledged, 0 NOT delivered"),
            "{report}"
        );
        let sessions = stored_seqs(&store, id);
        assert_eq!(sessions.len(), 1, "{id}");
        assert_eq!(sessions[0], (0..31).collect::<Vec<u64>>(), "{id}");
    }
    hub.interrupt();
}

#[test]
fn killing_the_therapist_mid_session_leaves_the_station_running_with_an_honest_report() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("store");
    let mcap = dir.path().join("s.mcap");
    let hub = TherapistHub::start(&store);
    let station = Command::new(telerehab_bin())
        .args([
            "run",
            "--sim",
            "--headless",
            "--duration",
            "3",
            "--therapist",
            &hub.addr,
            "--record",
            mcap.to_str().unwrap(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1200));
    hub.kill();
    let out = station.wait_with_output().unwrap();
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{report}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The session ran to its end and recorded every tick.
    assert!(!report.contains("stopped early"), "{report}");
    assert_eq!(by_topic(&read_mcap(&mcap))["/wheel"].len(), 3101);
    // The report says how many summaries did not reach the therapist, and they are the ones missing.
    let line = report
        .lines()
        .find(|l| l.starts_with("therapist"))
        .expect("therapist line");
    let undelivered: u64 = line
        .split(", ")
        .find_map(|p| p.strip_suffix(" NOT delivered"))
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!(undelivered >= 10, "{line}");
    let stored: usize = stored_seqs(&store, "station-1").iter().map(Vec::len).sum();
    assert_eq!(stored as u64 + undelivered, 31, "{line}");
}
