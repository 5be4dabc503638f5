//! Every recording format this product has written stays readable: the golden recordings in
//! `tests/golden/` (written by the old code at its commit; see `tests/golden/README.md`) are
//! opened by `replay`, `report`, `recover`, the hub's replay view and the record crate's
//! readers (Python opens them in `tests/python/test_golden.py`).

use std::path::{Path, PathBuf};
use std::process::Command;
use telerehab_tests::{run_ok, sim_session_args, telerehab_bin};

/// The golden recordings, oldest format first, with the format each one is.
const GOLDEN: [(&str, u32); 3] = [
    ("v1-json-regimen.mcap", 1),
    ("v2-compact.mcap", 2),
    ("v3-raw-inputs.mcap", 3),
];

fn golden(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("golden")
        .join(name)
}

#[test]
fn every_golden_recording_opens_in_the_whole_file_and_streaming_readers() {
    for (name, format) in GOLDEN {
        let path = golden(name);
        let whole = record::Recording::open(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(
            whole.metadata.format_version,
            record::types::UNVERSIONED_FORMAT,
            "{name}: formats 1–3 carry no version"
        );
        let ticks = whole.ticks().count();
        assert!(ticks >= 900, "{name}: {ticks} ticks (format {format})");
        let stream = record::TickStream::open_path(&path, record::StreamLimits::default(), &[])
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let streamed = stream
            .map(|t| t.map(|t| t.tick))
            .collect::<Result<Vec<_>, _>>();
        let streamed = streamed.unwrap_or_else(|e| panic!("{name}: {e}"));
        let whole_ticks: Vec<u64> = whole.ticks().map(|t| t.tick).collect();
        assert_eq!(
            streamed, whole_ticks,
            "{name}: both readers see the same ticks"
        );
    }
}

/// The `record` crate's ticks of a golden recording.
fn ticks_of(name: &str) -> Vec<record::TickRecord> {
    record::Recording::open(golden(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .ticks()
        .collect()
}

/// `x` on the compact formats' grid for N·m, rad and m (`record::blocks::quantum_of`: 1e-6).
fn micro(x: f64) -> f64 {
    (x * 1e6).round() * 1e-6
}

fn assert_close(what: &str, got: f64, want: f64) {
    assert!((got - want).abs() < 1e-9, "{what}: {got}, pinned {want}");
}

/// A handful of columns at known ticks, pinned once from what each format documents, so a
/// reader that decodes zeros, shifts a column or loses a tick fails. Format 1 stores JSON:
/// its values are read here a second way, as JSON by the `mcap` crate, not the `record`
/// crate. Formats 2 and 3 store quantised delta-coded columns (1e-6 for N·m, rad and m): the
/// seed-7 simulated patient's first hand torque and elbow angle are format 1's on that grid,
/// and the car drives at its exercise's speed (12 m/s on the sine road, 7 m/s on the slalom),
/// `x_m` growing by it every 1 ms tick from one tick's travel.
#[test]
fn every_golden_recording_decodes_its_pinned_values() {
    let ticks_ms = |ticks: &[record::TickRecord]| {
        for k in [0, 250, 500, ticks.len() - 1] {
            assert_eq!(ticks[k].tick, k as u64);
            assert_eq!(ticks[k].t_ns, k as u64 * 1_000_000, "tick {k}");
        }
    };
    let v1 = ticks_of("v1-json-regimen.mcap");
    assert_eq!(v1.len(), 1101);
    ticks_ms(&v1);
    let w = &v1[250].wheel;
    assert_close("v1 angle_rad at 250", w.angle_rad, 0.056325);
    assert_close(
        "v1 commanded_nm at 250",
        w.commanded_nm,
        -0.038_052_071_743_230_04,
    );
    assert_close("v1 ceiling_nm", w.ceiling_nm, 1.87);
    let hand0 = v1[0].wheel.hand_nm.unwrap();
    assert_close("v1 hand_nm at 0", hand0, -0.015_507_438_664_355_942);
    let elbow0 = v1[0].arm.as_ref().unwrap().elbow_flexion_rad;
    assert_close("v1 elbow at 0", elbow0, 1.362_732_721_250_863_5);
    // The same values as JSON, read without the record crate.
    let bytes = std::fs::read(golden("v1-json-regimen.mcap")).unwrap();
    let wheel_json: Vec<serde_json::Value> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .filter(|m| m.channel.topic == "/wheel")
        .map(|m| serde_json::from_slice(&m.data).unwrap())
        .collect();
    assert_eq!(wheel_json.len(), v1.len());
    for k in [0, 250, 500, 1100] {
        for (column, decoded) in [
            ("angle_rad", v1[k].wheel.angle_rad),
            ("commanded_nm", v1[k].wheel.commanded_nm),
            ("requested_nm", v1[k].wheel.requested_nm),
        ] {
            let json = wheel_json[k][column].as_f64().unwrap();
            assert_eq!(decoded, json, "v1 {column} at tick {k}");
        }
    }

    for (name, speed_m_s) in [("v2-compact.mcap", 12.0), ("v3-raw-inputs.mcap", 7.0)] {
        let t = ticks_of(name);
        assert_eq!(t.len(), 1100, "{name}");
        ticks_ms(&t);
        assert_close(
            &format!("{name} hand_nm at 0"),
            t[0].wheel.hand_nm.unwrap(),
            micro(hand0),
        );
        let elbow = t[0].arm.as_ref().unwrap().elbow_flexion_rad;
        assert_close(&format!("{name} elbow at 0"), elbow, micro(elbow0));
        for (k, hand) in [(250, -0.01085), (500, 0.016155), (1099, 0.003354)] {
            assert_close(
                &format!("{name} hand_nm at {k}"),
                t[k].wheel.hand_nm.unwrap(),
                hand,
            );
        }
        for k in [0, 250, 500, 1099] {
            let car = t[k].vehicle.as_ref().unwrap();
            assert_close(&format!("{name} ux at {k}"), car.ux_m_s, speed_m_s);
            let x = speed_m_s * (k + 1) as f64 * 1e-3;
            assert_close(&format!("{name} x_m at {k}"), car.x_m, micro(x));
        }
        assert_close(
            &format!("{name} ceiling_nm"),
            t[0].wheel.ceiling_nm,
            micro(1.87),
        );
        assert_eq!(t[500].score.pct_in_lane, 100.0, "{name}");
    }
    // Format 3's raw inputs: the body clock the chain ran at, each tick.
    let v3 = ticks_of("v3-raw-inputs.mcap");
    for k in [250, 500, 1099] {
        assert_eq!(
            v3[k].raw.wheel.now_ns,
            k as u64 * 1_000_000,
            "v3 raw now_ns at {k}"
        );
    }
}

/// Each golden recording replayed from its seed by today's code: the first difference, named
/// exactly, and why that format cannot replay bit for bit; format 3 replays identically from
/// its raw inputs.
#[test]
fn every_golden_recording_replays_or_names_its_first_difference() {
    const FIRST_DIFFERENCE: [(&str, &str); 3] = [
        // Format 1 stored every value as JSON, unquantised; a replay compares today's
        // recording, whose columns are on the 1e-6 grid: the ceiling 1.87 lands on the grid's
        // nearest double.
        (
            "v1-json-regimen.mcap",
            "replay differs: first at /wheel sample 0: tick 0, t = 0.0 s: ceiling_nm recorded \
             1.87, replayed 1.8699999999999999",
        ),
        // Formats 2 and 3 were written before the simulated patient's hand model changed: a
        // seed replay re-runs today's patient, whose hand pushes differently from the first
        // tick (format 3 carries what the body delivered, so it replays from its raw inputs).
        (
            "v2-compact.mcap",
            "replay differs: first at /wheel sample 0: tick 0, t = 0.0 s: hand_nm recorded \
             -0.015507, replayed -0.004784",
        ),
        (
            "v3-raw-inputs.mcap",
            "replay differs: first at /wheel sample 0: tick 0, t = 0.0 s: hand_nm recorded \
             -0.015507, replayed -0.004784",
        ),
    ];
    for (name, first) in FIRST_DIFFERENCE {
        let path = golden(name);
        let out = Command::new(telerehab_bin())
            .args(["replay", path.to_str().unwrap()])
            .output()
            .unwrap();
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            text.contains(first),
            "{name}: expected {first:?} in\n{text}"
        );
    }
    // The newest unversioned format replays bit for bit from its raw inputs.
    let raw = golden("v3-raw-inputs.mcap");
    let out = run_ok(&["replay", "--from-raw", raw.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("replay: identical"), "{stdout}");
}

#[test]
fn every_golden_recording_reports_and_recovers() {
    let dir = tempfile::tempdir().unwrap();
    for (name, _) in GOLDEN {
        let path = golden(name);
        let html = dir.path().join(format!("{name}.html"));
        run_ok(&[
            "report",
            "--out",
            html.to_str().unwrap(),
            path.to_str().unwrap(),
        ]);
        let page = std::fs::read_to_string(&html).unwrap();
        // What the report says of each: its exercises in the patient's words, when it ran,
        // and that formats 1–3 recorded no end reason.
        let (exercises, when) = match name {
            "v1-json-regimen.mcap" => (
                "Dial sine, then Straight road, then Sine road",
                "27 Nov 2026, 13:06 UTC",
            ),
            "v2-compact.mcap" => ("Sine road", "27 Nov 2026, 13:14 UTC"),
            _ => ("Slalom", "27 Nov 2026, 13:06 UTC"),
        };
        for said in [exercises, when, "How it ended is not recorded"] {
            assert!(page.contains(said), "{name}: the report lacks {said:?}");
        }
        let recovered = dir.path().join(format!("recovered-{name}"));
        run_ok(&[
            "recover",
            "--out",
            recovered.to_str().unwrap(),
            path.to_str().unwrap(),
        ]);
        let again = record::Recording::open(&recovered).unwrap();
        let original = record::Recording::open(&path).unwrap();
        assert_eq!(again.ticks().count(), original.ticks().count(), "{name}");
    }
}

#[test]
fn every_golden_recording_draws_in_the_hubs_replay_view() {
    use record::view::{MAX_REPLAY_FRAMES, REPLAY_CHANNELS, replay_ndjson};
    for (name, _) in GOLDEN {
        let stream = record::TickStream::open_path(
            &golden(name),
            record::StreamLimits::default(),
            &REPLAY_CHANNELS,
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut lines: Vec<serde_json::Value> = Vec::new();
        let done = replay_ndjson(stream, MAX_REPLAY_FRAMES, |line| {
            lines.push(serde_json::from_slice(&line).unwrap());
            true
        });
        assert!(done, "{name}");
        let frames: u64 = lines.iter().filter_map(|l| l["frames"].as_u64()).sum();
        assert!(frames >= 18, "{name}: {frames} frames for a second at 20/s");
        assert!(
            lines
                .iter()
                .any(|l| l["columns"]["wheel_angle_rad"].is_array()),
            "{name}"
        );
        let last = lines.last().unwrap();
        assert_eq!(last["end"], true, "{name}: {last}");
    }
}

#[test]
fn this_builds_recordings_say_their_format_version() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("now.mcap");
    run_ok(&sim_session_args("0.3", &mcap, &["--seed", "3"]));
    let meta = record::Recording::open(&mcap).unwrap().metadata;
    assert_eq!(meta.format_version, record::FORMAT_VERSION);
    assert_eq!(meta.format_note(), None);
    let version = run_ok(&["--version"]);
    let text = String::from_utf8_lossy(&version.stdout);
    assert!(
        text.contains(&format!("recording format {}", record::FORMAT_VERSION))
            && text.contains("protocol"),
        "{text}"
    );
}
