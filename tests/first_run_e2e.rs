//! End-to-end: `telerehab` with no arguments, as a patient meets it — the first-run pages in
//! a real window under X (Xvfb in CI), typed into with xdotool, pairing with a clinic's hub on
//! loopback; and the plain message without a display.

use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;
use telerehab_tests::clinic::{Hub, clinic};
use telerehab_tests::logged;
use telerehab_tests::{Reaper, telerehab_bin, xdotool_in};

#[test]
fn without_a_display_telerehab_says_so_points_to_doctor_and_exits_2() {
    let home = tempfile::tempdir().unwrap();
    let out = Command::new(telerehab_bin())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env("TELEREHAB_HOME", home.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no display was found") && err.contains("telerehab doctor"),
        "{err}"
    );
}

/// xdotool on the window titled "telerehab": focus it, then `args` (e.g. `type TEXT`).
fn xdotool(args: &[&str]) {
    xdotool_in("^telerehab$", args);
}

/// Waits for a log line containing `what` (the lines come from the process's stderr).
/// Presses `key` until a log line containing `what` comes (a key sent before the window maps
/// and takes keys is lost on a loaded machine: press again).
fn press_until(lines: &mpsc::Receiver<String>, key: &str, what: &str) {
    for _ in 0..30 {
        xdotool(&["key", key]);
        while let Ok(line) = lines.recv_timeout(Duration::from_secs(2)) {
            if line.contains(what) {
                return;
            }
        }
    }
    panic!("{key} never brought a log line with {what:?}");
}

fn wait_for(lines: &mpsc::Receiver<String>, what: &str) {
    logged::wait_for(lines, &[what], Duration::from_secs(60));
}

#[test]
fn a_patient_pairs_from_the_first_run_page_by_typing_the_clinics_address_and_code_on_a_keyboard() {
    if std::env::var_os("DISPLAY").is_none() {
        eprintln!("SKIPPED: no display (run under xvfb-run to test the first-run window)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    let mut child = Command::new(telerehab_bin())
        .env("TELEREHAB_HOME", &home)
        .env("RUST_LOG", "info")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let _reaper = Reaper(child.id());
    let lines = logged::stderr_lines(&mut child);
    // The keyboard is the alternative to the wheel: Enter takes the language chosen.
    wait_for(&lines, "first-run page shown page_id=language");
    press_until(
        &lines,
        "Return",
        "first-run page shown page_id=pairing-ask-clinic",
    );
    assert!(!home.join("pairing").exists(), "not paired before the code");
    xdotool(&["type", "--delay", "20", &hub.stations]);
    xdotool(&["key", "Return"]);
    xdotool(&["type", "--delay", "20", &code]);
    xdotool(&["key", "Return"]);
    wait_for(&lines, "first-run page shown page_id=today");
    let pairing = std::fs::read_to_string(home.join("pairing/hub.toml")).unwrap();
    assert!(pairing.contains(&hub.stations), "{pairing}");
    xdotool(&["key", "Escape"]);
    let status = child.wait().unwrap();
    assert!(status.success(), "{status}");
}
