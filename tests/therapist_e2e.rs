//! End-to-end: stations and the therapist hub on loopback.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;
use telerehab_tests::{by_topic, read_mcap, run_ok, telerehab_bin};

/// A running hub and the address it listens on.
struct Hub {
    child: Child,
    addr: String,
}

impl Hub {
    fn start(store: &Path) -> Hub {
        let mut child = Command::new(telerehab_bin())
            .args([
                "therapist",
                "--listen",
                "127.0.0.1:0",
                "--store",
                store.to_str().unwrap(),
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        let first = lines.next().expect("hub prints where it listens").unwrap();
        let addr = first
            .strip_prefix("listening on ")
            .and_then(|r| r.split_whitespace().next())
            .unwrap_or_else(|| panic!("unexpected first line {first:?}"))
            .to_string();
        // Keep draining the hub's live lines so it never blocks on a full pipe.
        std::thread::spawn(move || for _ in lines {});
        Hub { child, addr }
    }

    fn interrupt(mut self) {
        let _ = Command::new("kill")
            .args(["-INT", &self.child.id().to_string()])
            .status();
        let _ = self.child.wait();
    }
}

/// Stored summaries of every session under `store/station_id`: seq lists per session.
fn stored_seqs(store: &Path, station_id: &str) -> Vec<Vec<u64>> {
    let mut sessions = Vec::new();
    for entry in std::fs::read_dir(store.join(station_id)).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "jsonl") {
            let text = std::fs::read_to_string(&path).unwrap();
            let seqs = text
                .lines()
                .map(|l| {
                    serde_json::from_str::<serde_json::Value>(l).unwrap()["seq"]
                        .as_u64()
                        .unwrap()
                })
                .collect();
            sessions.push(seqs);
        }
    }
    sessions
}

#[test]
fn two_stations_deliver_every_summary_exactly_once_to_one_hub() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("store");
    let hub = Hub::start(&store);
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
    let mut hub = Hub::start(&store);
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
    hub.child.kill().unwrap();
    let _ = hub.child.wait();
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
