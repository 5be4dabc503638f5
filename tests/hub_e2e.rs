//! End-to-end: a clinic's hub and a paired station, as the README's acceptance path runs them
//! (`hub init`, `hub patient add`, `hub serve`, `pair`, `run`, `hub patient show`), plus
//! revocation, delivery after the hub was down, a station killed mid-session, and bad input.

use std::process::{Command, Stdio};
use std::time::Duration;
use telerehab_tests::clinic::{
    Hub, clinic, clinic_on, fresh_postgres_database, ok, pair, prescribe, produced, run_session,
    show, show_json, telerehab, wait_for_file,
};
use telerehab_tests::{Tmpfs, spawn_real_time_session, telerehab_bin, wait_for_first_chunk};

#[test]
fn a_clinic_pairs_a_station_that_then_streams_every_session_over_mutual_tls() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    let paired = pair(&hub, &code, &home);
    assert!(
        paired.starts_with("paired: this station is st-")
            && paired.contains("for patient P-0042 at"),
        "{paired}"
    );
    // The hub told the station the patient's pseudonym, which its recordings then carry.
    let pairing = std::fs::read_to_string(home.join("pairing/hub.toml")).unwrap();
    assert!(
        pairing.contains("patient_pseudonym = \"P-0042\""),
        "{pairing}"
    );

    let report = run_session(&home, "5");
    let n = produced(&report);
    assert!(
        report.contains(&format!("{n} sent, {n} acknowledged, 0 NOT delivered")),
        "{report}"
    );
    assert!(
        !report.contains("therapist queue"),
        "everything delivered: {report}"
    );
    let (stored, revoked) = show(&data);
    assert_eq!((stored, revoked), (vec![n], 0));
    // The session's movement measures came with its end.
    let metrics = &show_json(&data)["sessions"][0]["metrics"];
    // 5 s of exercise and the torque's fade-out at the end.
    let session_s = metrics["session_s"].as_f64().unwrap();
    assert!((5.0..5.5).contains(&session_s), "{metrics}");
    assert!(metrics["movements"].as_f64().unwrap() >= 1.0, "{metrics}");
    // Smoothness only over discrete movements (rest before and after): one, or none at all.
    let discrete = metrics["discrete_movements"].as_f64().unwrap();
    match metrics["sparc_median"].as_f64() {
        Some(sparc) => assert!(discrete >= 1.0 && sparc < 0.0, "{metrics}"),
        None => assert_eq!(discrete, 0.0, "{metrics}"),
    }
    // A paired station records every session in its home, private to its user.
    let recordings: Vec<_> = std::fs::read_dir(home.join("recordings"))
        .unwrap()
        .collect();
    assert_eq!(recordings.len(), 1);
    // The code was single use; the refusal reads as every failed code does (nothing to
    // enumerate), in words a patient can act on.
    let again = telerehab(
        &["pair", "--hub", &hub.stations, "--code", &code],
        Some(&tmp.path().join("s2")),
    );
    let err = String::from_utf8_lossy(&again.stderr);
    assert!(
        !again.status.success() && err.contains("mistyped, expired or already used"),
        "{err}"
    );
    hub.stop();
}

/// The one file with extension `ext` under `dir` (searched two levels deep), once it exists.
#[test]
fn a_recording_stopped_by_a_disk_running_low_is_finished_and_still_reaches_the_hub() {
    let Some(disk) = Tmpfs::mount_or_skip(72) else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    // The station's home, and so its recordings, on the small disk.
    let home = disk.path().join("station");
    pair(&hub, &code, &home);
    let child = spawn_real_time_session("5", |c| c.env("TELEREHAB_HOME", &home));
    let recording = wait_for_file(&home.join("recordings"), "mcap");
    wait_for_first_chunk(&recording);
    disk.fill_under_the_reserve();
    let out = child.wait_with_output().unwrap();
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(!out.status.success(), "a stopped recording fails the run");
    assert!(report.contains("recording stopped at"), "{report}");
    // Finished while there was room, so what it holds is the therapist's too.
    assert!(
        report.contains("recording upload    1 uploaded"),
        "{report}"
    );
    let stored = wait_for_file(&data.join("recordings"), "mcap");
    assert_eq!(
        std::fs::read(&stored).unwrap(),
        std::fs::read(&recording).unwrap(),
        "the hub holds the station's finished file"
    );
    hub.stop();
}

#[test]
fn a_revoked_station_is_refused_and_keeps_its_summaries_on_disk() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let pairing = std::fs::read_to_string(home.join("pairing/hub.toml")).unwrap();
    let station = pairing
        .lines()
        .find_map(|l| l.strip_prefix("station_id = "))
        .unwrap()
        .trim_matches('"')
        .to_owned();
    ok(
        &[
            "hub",
            "station",
            "revoke",
            "--data",
            data.to_str().unwrap(),
            &station,
        ],
        None,
    );
    let report = run_session(&home, "3");
    assert!(
        report.contains("has been revoked by the clinic"),
        "{report}"
    );
    assert!(report.contains("summaries kept on disk"), "{report}");
    let (stored, revoked) = show(&data);
    assert_eq!(
        (stored, revoked),
        (vec![], 1),
        "nothing stored from a revoked station"
    );
    hub.stop();
}

#[test]
fn summaries_of_a_session_run_while_the_hub_was_down_are_delivered_once_by_sync() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let port = hub.stations.rsplit(':').next().unwrap().to_owned();
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    hub.stop();

    let report = run_session(&home, "3");
    let n = produced(&report);
    assert!(
        report.contains(&format!("{n} summaries kept on disk")),
        "{report}"
    );

    // The hub comes back where the station was paired with it.
    let hub = Hub::serve(&data, &format!("127.0.0.1:{port}"));
    let synced = ok(&["sync"], Some(&home));
    assert!(
        synced.contains("1 queued sessions, 1 delivered, 0 summaries still queued"),
        "{synced}"
    );
    let again = ok(&["sync"], Some(&home));
    assert!(again.contains("0 queued sessions"), "{again}");
    assert_eq!(show(&data).0, vec![n], "every summary stored exactly once");
    let metrics = &show_json(&data)["sessions"][0]["metrics"];
    assert!(
        metrics["movements"].is_number(),
        "the measures waited in the queue for the hub: {metrics}"
    );
    hub.stop();
}

#[test]
fn a_station_killed_mid_session_delivers_what_it_queued_at_the_next_sync() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let mut station = Command::new(telerehab_bin())
        .args(["run", "--sim", "--headless", "--duration", "60"])
        .env("TELEREHAB_HOME", &home)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Let it stream for a while, then kill it without warning.
    let queue = home.join("queue");
    let queued_lines = || -> usize {
        std::fs::read_dir(&queue)
            .into_iter()
            .flatten()
            .flatten()
            .filter(|e| e.path().extension().is_some_and(|x| x == "jsonl"))
            .map(|e| {
                std::fs::read_to_string(e.path())
                    .unwrap_or_default()
                    .lines()
                    .count()
            })
            .sum()
    };
    // A liveness guard, not a timing assertion: a loaded CI machine may start slowly.
    for _ in 0..1200 {
        if queued_lines() >= 20 {
            break;
        }
        assert!(
            station.try_wait().unwrap().is_none(),
            "the station ended early"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let queued_at_kill = queued_lines();
    station.kill().unwrap();
    station.wait().unwrap();
    let queued = queued_lines() as u64;
    eprintln!("queued {queued_at_kill} lines before the kill, {queued} after");
    assert!(queued >= 20, "the queue holds what was produced: {queued}");
    let synced = ok(&["sync"], Some(&home));
    assert!(synced.contains("1 delivered"), "{synced}");
    let (stored, _) = show(&data);
    assert_eq!(stored.len(), 1);
    assert!(
        stored[0] >= queued,
        "stored {} of {queued} queued",
        stored[0]
    );
    hub.stop();
}

#[test]
fn hostile_pseudonyms_and_a_second_init_are_refused_with_the_reason() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, _) = clinic(tmp.path());
    let d = data.to_str().unwrap();
    for bad in ["../../etc", "'; DROP TABLE patients; --", ""] {
        let out = telerehab(
            &["hub", "patient", "add", "--data", d, "--pseudonym", bad],
            None,
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains("pseudonym"),
            "{bad:?}: {err}"
        );
    }
    let out = telerehab(
        &["hub", "init", "--data", d, "--admin", "bob@clinic.example"],
        None,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("already holds a clinic"),
        "{err}"
    );
    let out = telerehab(
        &["pair", "--hub", "127.0.0.1:9", "--code", "7KQ2-M9XU"],
        Some(&tmp.path().join("h")),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("never contains 'U'"),
        "{err}"
    );
}

#[test]
fn a_prescribed_regimen_reaches_the_station_and_runs_at_its_next_session() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let d = data.to_str().unwrap();
    let set = prescribe(&data, "medium");
    assert!(set.contains("regimen version 1"), "{set}");
    let bad = tmp.path().join("bad.toml");
    std::fs::write(
        &bad,
        "[[exercise]]\nkind = \"straight\"\nduration_s = -5.0\n",
    )
    .unwrap();
    let out = telerehab(
        &[
            "hub",
            "patient",
            "regimen",
            "--data",
            d,
            "P-0042",
            "--file",
            bad.to_str().unwrap(),
            "--by",
            "ana@clinic.example",
        ],
        None,
    );
    assert!(!out.status.success(), "an invalid regimen is refused");

    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    // The first session after the prescription was saved runs it: the station asks the hub
    // before it starts.
    let first = run_session(&home, "3");
    assert!(
        first.contains("-v1 from the hub, received before the start"),
        "{first}"
    );
    assert!(
        !first.contains("exercises           1 (1 run)"),
        "the regimen's exercises run: {first}"
    );
    // Kept for a session without the hub.
    hub.stop();
    let offline = run_session(&home, "3");
    assert!(
        offline.contains("prescription        kept ") && offline.contains("regimen.toml"),
        "{offline}"
    );
    assert!(
        !offline.contains("exercises           1 (1 run)"),
        "the kept regimen runs: {offline}"
    );
}

#[test]
fn each_way_a_session_ends_reaches_the_hub_as_its_end_reason() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let run = |faults: &[&str]| {
        let mut args = vec![
            "run",
            "--sim",
            "--headless",
            "--speed",
            "max",
            "--duration",
            "3",
        ];
        for f in faults {
            args.extend(["--fault", f]);
        }
        // A recording that failed fails the run (after the session and its report).
        let out = telerehab(&args, Some(&home));
        let report = String::from_utf8_lossy(&out.stdout).into_owned();
        let ended = report
            .lines()
            .find_map(|l| l.strip_prefix("ended               "))
            .unwrap_or_else(|| panic!("no end line: {report}"))
            .to_owned();
        // Newest first at the hub: this session's row.
        let stored = show_json(&data)["sessions"][0]["session"]["end_reason"]
            .as_str()
            .unwrap_or_default()
            .to_owned();
        assert_eq!(stored, ended, "the hub stores what the station said");
        stored
    };
    assert_eq!(run(&[]), "complete");
    assert_eq!(run(&["wheel-unplug@1"]), "wheel unplugged");
    let full = run(&["disk-full@1"]);
    assert!(
        full.starts_with("complete; recording stopped: disk full at "),
        "{full}"
    );
    hub.stop();
}

/// The acceptance path of a clinic that chose PostgreSQL: `hub init --db postgres://…`, then
/// every command finds the database from the clinic's directory.
#[test]
fn a_clinic_on_postgresql_pairs_streams_and_shows_the_patient() {
    let Some(url) = fresh_postgres_database() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic_on(tmp.path(), Some(&url));
    assert!(
        !data.join("hub.db").exists(),
        "no SQLite file beside PostgreSQL"
    );
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let report = run_session(&home, "3");
    let n = produced(&report);
    assert!(
        report.contains(&format!("{n} sent, {n} acknowledged, 0 NOT delivered")),
        "{report}"
    );
    let (stored, revoked) = show(&data);
    assert_eq!((stored, revoked), (vec![n], 0));
    assert!(show_json(&data)["sessions"][0]["metrics"]["movements"].is_number());
    hub.stop();
}
