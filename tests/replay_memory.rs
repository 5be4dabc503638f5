//! `telerehab replay` compares as it reads: the re-run is recorded to a temporary file and the
//! two recordings are read side by side, so replaying a session ten times longer does not take
//! ten times the memory (it took 30 MB a second of session before: 18.5 GB for 10 minutes).
//!
//! The peak is the replaying process's `VmHWM` (peak resident set), read from
//! `/proc/<pid>/status` while it runs (it only grows, so the last reading is its peak).

use std::process::{Command, Stdio};
use std::time::Duration;
use telerehab_tests::{run_ok, sim_session_args, telerehab_bin};

/// `telerehab ARGS` run to success: its peak resident set, bytes, and what it printed.
fn peak_of(args: &[&str]) -> (u64, String) {
    let mut child = Command::new(telerehab_bin())
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run telerehab");
    let status_path = format!("/proc/{}/status", child.id());
    let mut peak_kib = 0;
    let status = loop {
        if let Ok(status) = std::fs::read_to_string(&status_path)
            && let Some(kib) = status.lines().find_map(|l| {
                let v = l.strip_prefix("VmHWM:")?;
                v.trim().trim_end_matches("kB").trim().parse::<u64>().ok()
            })
        {
            peak_kib = peak_kib.max(kib);
        }
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        status.success(),
        "telerehab {args:?} failed: {stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (peak_kib * 1024, stdout)
}

#[test]
fn replaying_a_session_ten_times_longer_takes_about_the_same_peak_memory() {
    if !std::path::Path::new("/proc/self/status").exists() {
        println!("SKIPPED: no /proc/<pid>/status (not Linux?)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut peaks = Vec::new();
    for seconds in ["1", "10"] {
        let path = dir.path().join(format!("s{seconds}.mcap"));
        run_ok(&sim_session_args(seconds, &path, &["--seed", "11"]));
        let recording = path.to_str().unwrap();
        let (peak_bytes, said) = peak_of(&["replay", recording]);
        assert!(said.contains("replay: identical"), "{said}");
        println!(
            "replay of {seconds} s ({} KB file): peak RSS {} MB",
            std::fs::metadata(&path).unwrap().len() >> 10,
            peak_bytes >> 20
        );
        peaks.push(peak_bytes);
    }
    let (short, long) = (peaks[0], peaks[1]);
    // Holding both runs whole took 30 MB a second of session: 270 MB more for the long one.
    assert!(
        long * 10 < short * 13 + (16 << 20) * 10,
        "replaying 10 s peaked at {} MB, 1 s at {} MB",
        long >> 20,
        short >> 20
    );
}
