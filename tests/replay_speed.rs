//! `telerehab replay` re-runs a session and compares it as the re-run is written (issue 47):
//! the comparison runs beside the re-run instead of after it, and compares the two files'
//! block messages as bytes, decoding only where they differ. So a replay takes little more
//! than the re-run alone, which is what `telerehab run --speed max --record` of the same
//! session takes: the ratio of the two, measured in one run, is what this test keeps (never an
//! absolute time). Before issue 47 the replay ran the re-run and then decoded both files whole,
//! one after the other — see BENCHMARKS.md.

use std::time::{Duration, Instant};
use telerehab_tests::{run_ok, sim_session_args};

/// The wall time of `f`.
fn timed(f: impl FnOnce()) -> Duration {
    let start = Instant::now();
    f();
    start.elapsed()
}

#[test]
fn a_replay_takes_little_more_than_recording_the_session_at_full_speed() {
    let dir = tempfile::tempdir().unwrap();
    let seconds = "20";
    let recording = dir.path().join("session.mcap");
    run_ok(&sim_session_args(
        seconds,
        &recording,
        &["--exercise", "sine-road", "--seed", "3"],
    ));
    let recording = recording.to_str().unwrap();
    let mut rerun = 0;
    let mut a_run = || {
        let path = dir.path().join(format!("again{rerun}.mcap"));
        rerun += 1;
        run_ok(&sim_session_args(
            seconds,
            &path,
            &["--exercise", "sine-road", "--seed", "3"],
        ));
        std::fs::remove_file(&path).unwrap();
    };
    // Alternated, so that a stretch of load elsewhere falls on both; the fastest of each is
    // the one least disturbed by the machine's other work.
    let (mut run, mut replay) = (Duration::MAX, Duration::MAX);
    for _ in 0..3 {
        run = run.min(timed(&mut a_run));
        replay = replay.min(timed(|| {
            let out = run_ok(&["replay", recording]);
            let said = String::from_utf8_lossy(&out.stdout);
            assert!(said.contains("replay: identical"), "{said}");
        }));
    }
    let ratio = replay.as_secs_f64() / run.as_secs_f64();
    println!(
        "{seconds} s of session: recorded at full speed in {:.2} s, replayed in {:.2} s: {ratio:.2}×",
        run.as_secs_f64(),
        replay.as_secs_f64()
    );
    // Measured 0.93× (debug build) and 0.81× (release) on a loaded 2-core machine: the
    // comparison beside the re-run costs it nothing to speak of. A comparison that fell
    // behind the re-run, or ran after it, adds its own time to the ratio.
    assert!(
        ratio < 1.8,
        "a replay took {ratio:.2}× a recorded run of the same session (expected < 1.8×)"
    );
}
