//! End-to-end: the console's replay of recordings that paired stations uploaded
//! (`GET /api/sessions/{id}/replay`) — an honest session, a decompression bomb, and eight
//! therapists replaying a long recording at once — against `telerehab hub serve` over HTTPS.
//!
//! A recording reaches the hub as a station uploads it: a session run while the hub is down
//! queues its recording; the file is replaced (a hostile or a long generated one) before
//! `telerehab sync` uploads it on the session's own connection.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use telerehab_tests::clinic::{Hub, NewClinic, after, ok, run_session};
use telerehab_tests::console::Console;

/// A clinic with one patient and its admin, a paired station, and one session run while the
/// hub was down (its summaries and recording queued on the station).
struct Clinic {
    _tmp: tempfile::TempDir,
    data: PathBuf,
    home: PathBuf,
    admin_password: String,
    stations_port: String,
}

impl Clinic {
    fn with_a_queued_session() -> Self {
        let tmp = tempfile::tempdir().unwrap();
        let NewClinic {
            data,
            code,
            admin_password,
        } = NewClinic::make(tmp.path(), None);
        let hub = Hub::serve_console(&data, "127.0.0.1:0");
        let home = tmp.path().join("station");
        ok(
            &["pair", "--hub", &hub.stations, "--code", &code],
            Some(&home),
        );
        let stations_port = hub.stations_port();
        hub.stop();
        run_session(&home, "2");
        Self {
            _tmp: tmp,
            data,
            home,
            admin_password,
            stations_port,
        }
    }

    /// The queued session's id and the recording file its upload will send.
    fn queued_upload(&self) -> (String, PathBuf) {
        let entries: Vec<PathBuf> = std::fs::read_dir(self.home.join("uploads"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "json"))
            .collect();
        let [entry] = entries.as_slice() else {
            panic!("one queued upload: {entries:?}");
        };
        let pending: serde_json::Value =
            serde_json::from_slice(&std::fs::read(entry).unwrap()).unwrap();
        (
            pending["hello"]["session_id"].as_str().unwrap().to_owned(),
            PathBuf::from(pending["path"].as_str().unwrap()),
        )
    }

    /// The hub back where the station was paired with it, the queue delivered by `sync`.
    fn serve_and_sync(&self) -> Hub {
        let hub = Hub::serve_console(&self.data, &format!("127.0.0.1:{}", self.stations_port));
        let synced = ok(&["sync", "--upload-rate", "1000000000"], Some(&self.home));
        assert!(synced.contains("1 uploaded"), "{synced}");
        hub
    }
}

/// The one `.mcap` file under `dir`, at any depth.
fn find_mcap(dir: &Path) -> PathBuf {
    let mut found = Vec::new();
    let mut dirs = vec![dir.to_owned()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|e| e == "mcap") {
                found.push(p);
            }
        }
    }
    let [one] = found.as_slice() else {
        panic!("one recording under {}: {found:?}", dir.display());
    };
    one.clone()
}

/// `recording` with a zstd chunk that declares 5 368 700 000 uncompressed bytes and holds
/// 64 MiB of zeros, right after the file's header: a few KB on disk.
fn bomb(recording: &[u8]) -> Vec<u8> {
    let mut encoder = zstd::stream::write::Encoder::new(Vec::new(), 3).unwrap();
    let mib = vec![0u8; 1 << 20];
    for _ in 0..64 {
        encoder.write_all(&mib).unwrap();
    }
    let zeros = encoder.finish().unwrap();
    let mut body = Vec::new();
    body.extend(0u64.to_le_bytes()); // message start time
    body.extend(0u64.to_le_bytes()); // message end time
    body.extend(5_368_700_000u64.to_le_bytes()); // uncompressed size
    body.extend(0u32.to_le_bytes()); // uncompressed CRC (none)
    body.extend(4u32.to_le_bytes());
    body.extend(b"zstd");
    body.extend((zeros.len() as u64).to_le_bytes());
    body.extend(&zeros);
    let header_end = 8 + 9 + u64::from_le_bytes(recording[9..17].try_into().unwrap()) as usize;
    let mut out = recording[..header_end].to_vec();
    out.push(0x06); // chunk
    out.extend((body.len() as u64).to_le_bytes());
    out.extend(body);
    out.extend(&recording[header_end..]);
    out
}

/// A replay's NDJSON lines (crates/hub/API.md) put together as the console does: `{"exercise",
/// "rate_hz", "duration_s", "columns"}`, and the number of lines of frames.
fn replay_of(body: &[u8]) -> (serde_json::Value, usize) {
    let text = std::str::from_utf8(body).unwrap();
    let mut lines = text
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap());
    let head = lines.next().expect("a first line");
    let mut answer = serde_json::json!({"exercise": head["exercise"], "rate_hz": head["rate_hz"]});
    let (mut columns, mut n, mut chunks) = (serde_json::Map::new(), 0, 0);
    for line in lines {
        if let Some(k) = line["frames"].as_u64() {
            chunks += 1;
            for (name, values) in line["columns"].as_object().unwrap() {
                let column = columns.entry(name.clone()).or_insert(serde_json::json!([]));
                let column = column.as_array_mut().unwrap();
                column.resize(n, serde_json::Value::Null);
                column.extend(values.as_array().unwrap().iter().cloned());
            }
            n += k as usize;
            for column in columns.values_mut() {
                column
                    .as_array_mut()
                    .unwrap()
                    .resize(n, serde_json::Value::Null);
            }
        } else if line["end"] == true {
            answer["rate_hz"] = line["rate_hz"].clone();
            answer["duration_s"] = line["duration_s"].clone();
            answer["complete"] = true.into();
        } else if let Some(rate) = line.get("rate_hz") {
            for column in columns.values_mut() {
                let mut i = 0;
                column.as_array_mut().unwrap().retain(|_| {
                    i += 1;
                    i % 2 == 1
                });
            }
            n = n.div_ceil(2);
            answer["rate_hz"] = rate.clone();
        } else {
            panic!("an unexpected line: {line}");
        }
    }
    assert_eq!(answer["complete"], true, "the replay ran to its end");
    answer["columns"] = serde_json::Value::Object(columns);
    (answer, chunks)
}

#[test]
fn a_paired_stations_uploaded_session_replays_at_20_frames_a_second() {
    let clinic = Clinic::with_a_queued_session();
    let (session, _) = clinic.queued_upload();
    let hub = clinic.serve_and_sync();
    let console = Console::new(&clinic.data, hub.web());
    let cookie = console.login("ana@clinic.example", &clinic.admin_password);
    let answer = console.get(&format!("/api/sessions/{session}/replay"), &cookie);
    assert_eq!(
        answer.status,
        200,
        "{}",
        String::from_utf8_lossy(&answer.body)
    );
    assert_eq!(answer.header("content-type"), Some("application/x-ndjson"));
    let (replay, chunks) = replay_of(&answer.body);
    assert!(chunks >= 2, "the first second comes on its own line");
    assert_eq!(replay["rate_hz"], 20.0);
    let duration_s = replay["duration_s"].as_f64().unwrap();
    assert!((2.0..2.6).contains(&duration_s), "{duration_s}");
    let columns = replay["columns"].as_object().unwrap();
    let frames = columns["t_s"].as_array().unwrap().len();
    assert_eq!(frames as f64, (duration_s * 20.0).round() + 1.0);
    for name in ["wheel_angle_rad", "torque_nm", "car_x_m", "pct_in_lane"] {
        assert_eq!(columns[name].as_array().unwrap().len(), frames, "{name}");
    }
    // Someone else's session is not there; the replay read is audited.
    let missing = console.get("/api/sessions/no-such-session/replay", &cookie);
    assert_eq!(missing.status, 404);
    let audit = console.get("/api/audit", &cookie).json();
    assert!(
        audit["entries"]
            .as_array()
            .unwrap()
            .iter()
            .any(|e| e["action"] == "read_replay" && e["target"] == session),
        "{audit}"
    );
    hub.stop();
}

#[test]
fn a_decompression_bomb_from_a_paired_station_is_refused_by_name_and_the_hub_keeps_serving() {
    let clinic = Clinic::with_a_queued_session();
    let (session, recording) = clinic.queued_upload();
    let honest = std::fs::read(&recording).unwrap();
    std::fs::write(&recording, bomb(&honest)).unwrap();
    let hub = clinic.serve_and_sync();
    let stored = std::fs::metadata(find_mcap(&clinic.data.join("recordings")))
        .unwrap()
        .len();
    assert!(stored < honest.len() as u64 + 64 * 1024, "{stored} bytes");
    let console = Console::new(&clinic.data, hub.web());
    let cookie = console.login("ana@clinic.example", &clinic.admin_password);
    for _ in 0..2 {
        let answer = console.get(&format!("/api/sessions/{session}/replay"), &cookie);
        assert_eq!(
            answer.status,
            422,
            "{}",
            String::from_utf8_lossy(&answer.body)
        );
        let error = answer.json()["error"].as_str().unwrap().to_owned();
        // Refused from its record headers before any chunk is decompressed: the chunk's
        // 5.4 GB against the file's size.
        assert!(
            error.contains("cannot be replayed")
                && error.contains("its chunks declare 5")
                && error.contains("expand at most 64 times"),
            "{error}"
        );
    }
    assert_eq!(console.get("/api/health", &cookie).status, 200);
    assert_eq!(console.get("/api/patients", &cookie).status, 200);
    assert!(
        hub.peak_rss_bytes() < 200 << 20,
        "hub peak {} MB",
        hub.peak_rss_bytes() >> 20
    );
    hub.stop();
}

/// Minutes of the generated recording the eight therapists replay
/// (`TELEREHAB_REPLAY_MINUTES`; the figures in BENCHMARKS.md use 60 in a release build).
fn replay_minutes() -> u64 {
    std::env::var("TELEREHAB_REPLAY_MINUTES")
        .ok()
        .and_then(|m| m.parse().ok())
        .unwrap_or(3)
}

/// A recording of `minutes` of a 1 kHz session with the station's own configuration, every
/// per-tick channel written (the raw inputs too), values from a fixed seed.
fn long_recording(path: &Path, minutes: u64, config_toml: String) {
    use record::{
        ArmSample, RawImuSample, RecordWriter, SessionMetadata, TickRecord, VehicleSample,
    };
    let meta = SessionMetadata {
        exercise: "sine-road".into(),
        seed: 42,
        loop_rate_hz: 1000.0,
        config_toml,
        ..Default::default()
    };
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut w = RecordWriter::new(file, 1_795_253_400_000_000_000, &meta).unwrap();
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut noise = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for tick in 0..minutes * 60_000 {
        let t = tick as f64 * 1e-3;
        let mut rec = TickRecord {
            tick,
            t_ns: tick * 1_000_000,
            ..Default::default()
        };
        rec.wheel.angle_rad = (0.5 * t).sin() + 0.01 * noise();
        rec.wheel.target_rad = (0.5 * t).sin();
        rec.wheel.commanded_nm = 0.3 * noise();
        rec.wheel.ceiling_nm = 1.87;
        rec.wheel.safety_scale = 1.0;
        rec.assist.torque_nm = 0.1 * noise();
        rec.timing.period_ns = 1_000_000;
        rec.raw.wheel.angle_rad = rec.wheel.angle_rad;
        rec.raw.wheel.now_ns = rec.t_ns;
        rec.score.pct_in_lane = 90.0 + 5.0 * noise();
        rec.vehicle = Some(VehicleSample {
            x_m: 12.5 * t,
            y_m: (0.5 * t).sin(),
            lateral_m: 0.2 * noise(),
            ..Default::default()
        });
        rec.arm = Some(ArmSample {
            elbow_flexion_rad: 1.0 + 0.2 * (0.5 * t).sin() + 0.01 * noise(),
            shoulder_elevation_rad: 0.4 + 0.01 * noise(),
            grip_m: [0.3, 0.1 * noise(), 0.2],
            ..Default::default()
        });
        if tick % 5 == 0 {
            for sensor in 0..2 {
                rec.raw.imu[sensor as usize] = Some(RawImuSample {
                    sensor,
                    device_t_ns: rec.t_ns,
                    gyro_x_rad_s: noise(),
                    gyro_y_rad_s: noise(),
                    gyro_z_rad_s: noise(),
                    ..Default::default()
                });
            }
        }
        w.write_tick(&rec, tick % 100 == 0).unwrap();
        if tick % 1000 == 999 {
            w.flush().unwrap();
        }
    }
    w.finish().unwrap();
}

#[test]
fn eight_therapists_replaying_a_long_recording_at_once_keep_the_hub_under_300_mb_and_sigint_stops_it_mid_replay()
 {
    let minutes = replay_minutes();
    let clinic = Clinic::with_a_queued_session();
    let (session, recording) = clinic.queued_upload();
    let config_toml = record::Recording::open(&recording)
        .unwrap()
        .metadata
        .config_toml;
    let started = std::time::Instant::now();
    long_recording(&recording, minutes, config_toml);
    let file_bytes = std::fs::metadata(&recording).unwrap().len();
    eprintln!(
        "generated {minutes} min: {:.1} MB in {:.1} s",
        file_bytes as f64 / 1e6,
        started.elapsed().as_secs_f64()
    );
    let hub = clinic.serve_and_sync();
    let d = clinic.data.to_str().unwrap();
    let console = Arc::new(Console::new(&clinic.data, hub.web()));
    let cookies: Vec<String> = (0..8)
        .map(|i| {
            let email = format!("t{i}@clinic.example");
            let added = ok(
                &[
                    "hub",
                    "therapist",
                    "add",
                    "--data",
                    d,
                    "--email",
                    &email,
                    "--admin",
                ],
                None,
            );
            console.login(&email, &after(&added, "one-time password: "))
        })
        .collect();
    let idle_bytes = hub.peak_rss_bytes();
    let started = std::time::Instant::now();
    let replays: Vec<_> = cookies
        .into_iter()
        .map(|cookie| {
            let console = Arc::clone(&console);
            let path = format!("/api/sessions/{session}/replay");
            std::thread::spawn(move || {
                let answer = console.get(&path, &cookie);
                let first_s = answer.first_frames_after.map(|d| d.as_secs_f64());
                (answer.status, answer.body.len(), answer.body, first_s)
            })
        })
        .collect();
    let answers: Vec<_> = replays.into_iter().map(|r| r.join().unwrap()).collect();
    let elapsed_s = started.elapsed().as_secs_f64();
    let peak_bytes = hub.peak_rss_bytes();
    eprintln!(
        "8 replays of {minutes} min ({:.1} MB file): {elapsed_s:.1} s, hub peak {} MB \
         (idle {} MB), answers {:?}",
        file_bytes as f64 / 1e6,
        peak_bytes >> 20,
        idle_bytes >> 20,
        answers
            .iter()
            .map(|(s, n, _, _)| (*s, *n))
            .collect::<Vec<_>>()
    );
    eprintln!(
        "first frames after (s): {:?}",
        answers
            .iter()
            .map(|a| a.3.unwrap_or(f64::NAN))
            .collect::<Vec<_>>()
    );
    for (status, _, body, _) in &answers {
        assert_eq!(*status, 200, "{}", String::from_utf8_lossy(body));
        let (replay, _) = replay_of(body);
        let frames = replay["columns"]["t_s"].as_array().unwrap().len();
        assert!(frames <= 40_000, "{frames} frames");
        let covered_s = frames as f64 / replay["rate_hz"].as_f64().unwrap();
        assert!(covered_s >= minutes as f64 * 60.0 - 1.0, "{covered_s} s");
    }
    // Before streaming, one replay took about 11 times its file; eight at once, 88 times.
    assert!(
        peak_bytes < 300 << 20,
        "hub peak {} MB for 8 replays of a {} MB file",
        peak_bytes >> 20,
        file_bytes >> 20
    );

    // Mid-replay, SIGINT still stops the hub within 5 s (issue 25: a clean stop in every state).
    let mut hub = hub;
    let path = format!("/api/sessions/{session}/replay");
    let cookie = console.login("ana@clinic.example", &clinic.admin_password);
    let in_flight = {
        let console = Arc::clone(&console);
        // The hub goes away under it: this request may fail (its thread's panic is ignored).
        std::thread::spawn(move || console.get(&path, &cookie).status)
    };
    std::thread::sleep(std::time::Duration::from_millis(200));
    let took = hub.signal_and_wait("INT", std::time::Duration::from_secs(5));
    assert!(
        took.is_some(),
        "hub serve still running 5 s after SIGINT mid-replay"
    );
    let _ = in_flight.join();
}
