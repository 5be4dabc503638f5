//! Round trips: records written to memory read back as recorded (floats of the high-rate
//! channels to their quantum, the rest exactly), on every channel.

use super::raw::RawRead;
use super::recover::recover;
use super::*;
use std::io::Cursor;

fn metadata() -> SessionMetadata {
    SessionMetadata {
        format_version: FORMAT_VERSION,
        exercise: "slalom".into(),
        seed: 11,
        patient_id: "patient-7".into(),
        loop_rate_hz: 1000.0,
        config_toml: "[session]\nseed = 11\n".into(),
        regimen_toml: Some("name = \"week 3\"\n".into()),
        body: Some(BodyFacts {
            kind: raw::BodyKindName::Real,
            wheel_profile: haptic_wheel::DeviceProfile::thesis_sidewinder(),
            wheel_max_torque_nm: 1.5,
            encoder_step_rad: 0.002_253,
            arm: Some(raw::ArmFacts {
                guided: true,
                geometry: gyro_imu::arm::ArmGeometry::default(),
                swivel_rad: 0.35,
            }),
            replug_grace_ns: Some(30_000_000_000),
        }),
        difficulty: Some(DifficultyNote {
            difficulty: 0.45,
            change: -0.1,
            reason: "patient said too hard: -0.10".into(),
        }),
        clinic: Some(ClinicNote {
            patient_pseudonym: "P-0042".into(),
            clinic: "hub.clinic.example".into(),
            therapist: "t.ruiz@clinic.example".into(),
        }),
    }
}

/// A tick with every field set to something distinct (no zero that a default could fake).
pub(crate) fn tick(n: u64) -> TickRecord {
    let x = n as f64 + 0.123_456_789;
    TickRecord {
        tick: n,
        t_ns: n * 1_000_000 + 7,
        wheel: WheelSample {
            angle_rad: x,
            velocity_rad_s: -x,
            model_nm: 0.1 * x,
            road_feel_nm: 0.2 * x,
            requested_nm: 0.3 * x,
            commanded_nm: 0.4 * x,
            clipped: n.is_multiple_of(2),
            safety_scale: 0.5,
            watchdog: [
                Watchdog::Running,
                Watchdog::FaultStaleReading,
                Watchdog::Paused,
            ][n as usize % 3],
            passivity_energy_j: -1e-3 * x,
            passivity_damping_nm_s_per_rad: 1e-4,
            true_angle_rad: (n.is_multiple_of(2)).then_some(x + 1e-9),
            hand_nm: None,
            hand_est_nm: None,
            target_rad: f64::MIN_POSITIVE,
            ceiling_nm: 1.87,
            motor_rating_known: true,
            motor_updates: n / 2 + 3,
            motor_update_worst_gap_ms: (n != 1).then_some(2.0 + 1e-6 * x),
            write_failures: n / 3,
        },
        vehicle: (n != 2).then_some(VehicleSample {
            x_m: x,
            y_m: 2.0 * x,
            yaw_rad: 0.3,
            ux_m_s: 12.5,
            uy_m_s: -0.01,
            r_rad_s: 0.02,
            steer_rad: 0.04,
            front_lateral_n: 1234.5,
            s_m: 100.0 + x,
            lateral_m: -0.25,
        }),
        score: ScoreSample {
            exercise_index: 1,
            rms_lateral_m: 0.1,
            max_lateral_m: 0.4,
            pct_in_lane: 99.5,
            cone_hits: n as u32,
            dial_rms_error_deg: 3.1,
            active_s: x,
            paused: n == 3,
            strength: None,
        },
        assist: AssistSample {
            active: true,
            torque_nm: 0.3,
            reference_rad: x,
            error_rad: 1e-3,
            assistance_level: 0.75,
            saturated: n == 1,
        },
        arm: (n != 1).then_some(ArmSample {
            shoulder_elevation_rad: x,
            setup: [
                ArmSetup::HoldStill,
                ArmSetup::Tracking,
                ArmSetup::SensorLost,
            ][n as usize % 3],
            upper_orientation_wxyz: [1.0, 0.0, -0.0, 1e-300],
            range_of_motion_rad: [0.1, 0.2, 0.3, 0.4, 0.5],
            grip_m: [0.2, -0.1, x],
            fore_gyro_z_rad_s: -x,
            ..Default::default()
        }),
        timing: TimingSample {
            lateness_ns: n,
            period_ns: 1_000_000,
            work_ns: u64::MAX - n,
            dropped_records: 0,
        },
        raw: RawTick {
            wheel: RawWheelSample {
                read: [RawRead::Ok, RawRead::Silent, RawRead::Ok][n as usize % 3],
                angle_rad: x,
                reading_t_ns: n * 1_000_000 + 5,
                now_ns: n * 1_000_000 + 6,
                paused: n == 3,
                stop: n == 4,
                arm_stepped: n != 1,
                arm_lost: n == 2,
                arm_regained: n == 3,
                solver_answered: n == 3,
                solver_timed_out: n == 4,
                throttle: n as f64 / 255.0,
                brake: 0.5,
                write_failed: n == 2,
            },
            imu: [
                (n != 3).then_some(RawImuSample {
                    sensor: 0,
                    device_t_ns: 10_000_000_000 + n,
                    gyro_x_rad_s: x,
                    gyro_y_rad_s: -0.5,
                    gyro_z_rad_s: 0.25,
                    acc_x_m_s2: Some(9.81),
                    acc_y_m_s2: Some(-x),
                    acc_z_m_s2: Some(0.001),
                }),
                n.is_multiple_of(2).then_some(RawImuSample {
                    sensor: 1,
                    device_t_ns: 20_000_000_000 + n,
                    gyro_x_rad_s: -x,
                    ..Default::default()
                }),
            ],
        },
    }
}

fn record_online() -> OnlineArmCalibrationSample {
    OnlineArmCalibrationSample {
        converged_at_s: 42.0,
        shoulder_m: [-0.2, -0.3, 0.1],
        upper_arm_m: 0.31,
        forearm_m: 0.32,
        upper_arm_se_m: 0.001,
        forearm_se_m: 0.002,
        rms_residual_m: 0.004,
        samples: 1500.0,
        recursive_upper_arm_m: 0.2,
        recursive_forearm_m: 0.3,
        recursive_rms_residual_m: 0.02,
    }
}

fn calibration() -> ArmCalibrationSample {
    ArmCalibrationSample {
        shoulder_m: [-0.2, 0.35, 0.1],
        upper_arm_m: 0.31,
        forearm_m: 0.27,
        upper_arm_se_m: 0.002,
        forearm_se_m: 0.003,
        rms_residual_m: 0.004,
        condition_number: 42.0,
        samples: 1500.0,
        warnings: vec!["turn the wheel further".into()],
        online: Some(record_online()),
    }
}

/// Ticks 0..5, the score on even ticks, the calibration at the end: bytes of a finished file.
fn write_session(ticks: &[TickRecord]) -> Vec<u8> {
    let mut w = RecordWriter::new(
        Cursor::new(Vec::new()),
        1_700_000_000_000_000_000,
        &metadata(),
    )
    .unwrap();
    for t in ticks {
        w.write_tick(t, t.tick.is_multiple_of(2)).unwrap();
    }
    w.write_arm_calibration(ticks.last().unwrap(), &calibration())
        .unwrap();
    w.finish().unwrap().into_inner()
}

#[test]
fn every_channel_reads_back_as_recorded() {
    let ticks: Vec<TickRecord> = (0..5).map(tick).collect();
    let rec = Recording::from_bytes(&write_session(&ticks)).unwrap();

    assert_eq!(rec.metadata, metadata());
    let stamped = |t: &TickRecord| (t.tick, t.t_ns as f64 * 1e-9);
    let pairs = |v: Vec<(u64, f64)>| v;
    assert_eq!(
        pairs(rec.wheel.iter().map(|m| (m.tick, m.t_s)).collect()),
        ticks.iter().map(stamped).collect::<Vec<_>>()
    );
    let ticks: Vec<TickRecord> = ticks.iter().map(TickRecord::as_recorded).collect();
    let wheel: Vec<_> = rec.wheel.iter().map(|m| m.data).collect();
    assert_eq!(wheel, ticks.iter().map(|t| t.wheel).collect::<Vec<_>>());
    let vehicle: Vec<_> = rec.vehicle.iter().map(|m| m.data).collect();
    assert_eq!(
        vehicle,
        ticks.iter().filter_map(|t| t.vehicle).collect::<Vec<_>>()
    );
    let score: Vec<_> = rec.score.iter().map(|m| (m.tick, m.data)).collect();
    let even = ticks.iter().filter(|t| t.tick.is_multiple_of(2));
    assert_eq!(score, even.map(|t| (t.tick, t.score)).collect::<Vec<_>>());
    let assist: Vec<_> = rec.assist.iter().map(|m| m.data).collect();
    assert_eq!(assist, ticks.iter().map(|t| t.assist).collect::<Vec<_>>());
    let timing: Vec<_> = rec.timing.iter().map(|m| m.data).collect();
    assert_eq!(timing, ticks.iter().map(|t| t.timing).collect::<Vec<_>>());
    let arm: Vec<_> = rec.arm.iter().map(|m| (m.tick, m.data)).collect();
    let with_arm = ticks.iter().filter_map(|t| Some((t.tick, t.arm?)));
    assert_eq!(arm, with_arm.collect::<Vec<_>>());
    assert_eq!(rec.arm_calibration.len(), 1);
    assert_eq!(rec.arm_calibration[0].tick, 4);
    assert_eq!(rec.arm_calibration[0].data, calibration());
}

#[test]
fn ticks_rejoin_the_channels_with_the_latest_score() {
    let ticks: Vec<TickRecord> = (0..5).map(tick).collect();
    let rec = Recording::from_bytes(&write_session(&ticks)).unwrap();
    let expected: Vec<TickRecord> = ticks
        .iter()
        .map(|t| TickRecord {
            // The score is recorded on even ticks only: odd ticks carry the previous one.
            score: ticks[(t.tick - t.tick % 2) as usize].score,
            ..t.as_recorded()
        })
        .collect();
    assert_eq!(rec.ticks().collect::<Vec<_>>(), expected);
}

/// A `/wheel` block decodes with nothing but the file: its protobuf descriptor (schema) and
/// its columns (channel metadata), as any protobuf reader would do it.
#[test]
fn a_wheel_block_decodes_from_the_descriptor_and_columns_in_the_file() {
    let ticks: Vec<TickRecord> = (0..3).map(tick).collect();
    let bytes = write_session(&ticks);
    let wheel = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(Result::unwrap)
        .find(|m| m.channel.topic == "/wheel")
        .unwrap();
    assert_eq!(wheel.log_time, 1_700_000_000_000_000_000 + ticks[0].t_ns);
    assert_eq!(wheel.channel.message_encoding, "protobuf");
    let schema = wheel.channel.schema.as_ref().unwrap();
    assert_eq!(
        (schema.name.as_str(), schema.encoding.as_str()),
        ("telerehab.WheelBlock", "protobuf")
    );
    let pool = prost_reflect::DescriptorPool::decode(&schema.data[..]).unwrap();
    let desc = pool.get_message_by_name("telerehab.WheelBlock").unwrap();
    let msg = prost_reflect::DynamicMessage::decode(desc, &wheel.data[..]).unwrap();
    let column = |name: &str| match msg.get_field_by_name(name).unwrap().as_ref() {
        prost_reflect::Value::List(l) => l.clone(),
        other => panic!("{name} is {other:?}"),
    };
    let i64s =
        |name: &str| -> Vec<i64> { column(name).iter().map(|v| v.as_i64().unwrap()).collect() };
    // Differences from the previous tick: 0 then +1, +1; 1 ms apart.
    assert_eq!(i64s("tick"), [0, 1, 1]);
    assert_eq!(i64s("t_ns"), [7, 1_000_000, 1_000_000]);
    // angle_rad in µrad: 0.123457 rad, then +1 rad each tick.
    assert_eq!(i64s("angle_rad"), [123_457, 1_000_000, 1_000_000]);
    let watchdog: Vec<_> = column("watchdog")
        .iter()
        .map(|v| v.as_str().unwrap().to_owned())
        .collect();
    assert_eq!(watchdog, ["running", "fault-stale-reading", "paused"]);
    // hand_nm is absent on every tick; true_angle_rad on tick 1.
    assert_eq!(i64s("hand_nm"), [blocks::ABSENT, 0, 0]);
    assert_eq!(
        i64s("true_angle_rad")[1],
        blocks::ABSENT.wrapping_sub(123_457)
    );
    let columns: Vec<blocks::Column> =
        serde_json::from_str(&wheel.channel.metadata[blocks::COLUMNS_KEY]).unwrap();
    let angle = columns.iter().find(|c| c.name == "angle_rad").unwrap();
    assert_eq!(angle.quantum, Some(1e-6));
    assert!(angle.description.ends_with("rad."), "{}", angle.description);
}

#[test]
fn the_low_rate_channels_stay_json() {
    let bytes = write_session(&[tick(0)]);
    let score = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(Result::unwrap)
        .find(|m| m.channel.topic == "/score")
        .unwrap();
    let json: serde_json::Value = serde_json::from_slice(&score.data).unwrap();
    assert_eq!(
        (json["tick"].as_u64(), json["cone_hits"].as_u64()),
        (Some(0), Some(0))
    );
    assert_eq!(score.channel.message_encoding, "json");
}

#[test]
fn floats_round_to_their_quantum_and_keep_nan_infinities_and_absence() {
    use blocks::{quantise, unquantise};
    for (x, q) in [(0.123_456_789, 1e-6), (-3.5e-7, 1e-6), (1e300, 1e-9)] {
        let back = unquantise(quantise(x, q), q).unwrap();
        assert!(
            (back - x).abs() <= q / 2.0 || x.abs() > 1e12,
            "{x} → {back}"
        );
    }
    assert!(unquantise(quantise(f64::NAN, 1e-6), 1e-6).unwrap().is_nan());
    assert_eq!(
        unquantise(quantise(f64::INFINITY, 1e-6), 1e-6),
        Some(f64::INFINITY)
    );
    assert_eq!(
        unquantise(quantise(f64::NEG_INFINITY, 1e-6), 1e-6),
        Some(f64::NEG_INFINITY)
    );
    assert_eq!(unquantise(blocks::ABSENT, 1e-6), None);
    assert_eq!(blocks::quantum_of("angle_rad"), 1e-6);
    assert_eq!(blocks::quantum_of("front_lateral_n"), 1e-3);
    assert_eq!(blocks::quantum_of("upper_orientation_wxyz"), 1e-9);
}

/// Every high-rate channel's sample type flattens into a layout whose descriptor and columns
/// agree (a field type blocks cannot store fails here, not in a session).
#[test]
fn every_high_rate_channel_has_a_block_layout() {
    let mut with_blocks = 0;
    for spec in &CHANNELS {
        if let Some(layout) = spec.block_layout() {
            let layout = layout.unwrap();
            assert_eq!(layout.message_name(), format!("{}Block", spec.schema_name));
            assert!(
                layout.columns().iter().all(|c| !c.description.is_empty()),
                "{}",
                spec.topic
            );
            with_blocks += 1;
        }
    }
    assert_eq!(with_blocks, 7);
}

#[test]
fn a_message_that_does_not_decode_names_its_channel_and_index() {
    let mut w = mcap::Writer::new(Cursor::new(Vec::new())).unwrap();
    let ch = w
        .add_channel(0, "/score", "json", &Default::default())
        .unwrap();
    w.write_metadata(&mcap::records::Metadata {
        name: "session".into(),
        metadata: metadata().to_map(),
    })
    .unwrap();
    let score = serde_json::to_vec(&Stamped::at(&tick(0), tick(0).score)).unwrap();
    for (i, data) in [&score[..], &score[..], br#"{"tick": 2, "t_s": 0.002}"#]
        .iter()
        .enumerate()
    {
        let header = mcap::records::MessageHeader {
            channel_id: ch,
            sequence: i as u32,
            log_time: i as u64,
            publish_time: i as u64,
        };
        w.write_to_known_channel(&header, data).unwrap();
    }
    w.finish().unwrap();
    let bytes = w.into_inner().into_inner();
    let err = Recording::from_bytes(&bytes).unwrap_err().to_string();
    assert!(
        err.starts_with("message 2 of channel /score does not decode: missing field"),
        "{err}"
    );
}

#[test]
fn metadata_problems_are_named() {
    let mut w = RecordWriter::new(Cursor::new(Vec::new()), 0, &metadata()).unwrap();
    w.write_tick(&tick(0), true).unwrap();
    let ok = w.finish().unwrap().into_inner();
    assert!(Recording::from_bytes(&ok).is_ok());

    let mut map = metadata().to_map();
    map.insert("seed".into(), "eleven".into());
    let err = SessionMetadata::from_map(&map).unwrap_err().to_string();
    assert!(
        err.starts_with("session metadata `seed`: not a number"),
        "{err}"
    );
    map.remove("exercise");
    let err = SessionMetadata::from_map(&map).unwrap_err().to_string();
    assert_eq!(err, "session metadata `exercise`: missing");
    let err = Recording::from_bytes(b"not an mcap file").unwrap_err();
    assert!(matches!(err, ReadError::Mcap(_)), "{err}");
}

#[test]
fn the_clinic_note_round_trips_and_a_damaged_or_partial_one_does_not_stop_reading() {
    let meta = metadata();
    let back = SessionMetadata::from_map(&meta.to_map()).unwrap();
    assert_eq!(back.clinic, meta.clinic);
    let mut map = meta.to_map();
    map.insert("clinic".into(), "{not json".into());
    let back = SessionMetadata::from_map(&map).unwrap();
    assert_eq!(back.clinic, None, "damaged: left out");
    assert_eq!(back.seed, 11, "the rest read");
    // A note from a hub that did not give the pseudonym, with a field from a newer writer.
    map.insert(
        "clinic".into(),
        r#"{"clinic": "hub.example", "later": 1}"#.into(),
    );
    let note = SessionMetadata::from_map(&map).unwrap().clinic.unwrap();
    assert_eq!(
        (note.clinic.as_str(), note.patient_pseudonym.as_str()),
        ("hub.example", "")
    );
    map.remove("clinic");
    assert_eq!(SessionMetadata::from_map(&map).unwrap().clinic, None);
}

/// A sink whose bytes can be looked at while the writer still holds it: what is on disk.
#[derive(Clone, Default)]
struct Disk(std::rc::Rc<std::cell::RefCell<Cursor<Vec<u8>>>>);

impl std::io::Write for Disk {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl std::io::Seek for Disk {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        self.0.borrow_mut().seek(pos)
    }
}

#[test]
fn a_killed_recording_recovers_to_one_that_reads_back() {
    let ticks: Vec<TickRecord> = (0..5).map(tick).collect();
    let disk = Disk::default();
    let mut w = RecordWriter::new(disk.clone(), 0, &metadata()).unwrap();
    for t in &ticks[..3] {
        w.write_tick(t, false).unwrap();
    }
    w.flush().unwrap();
    for t in &ticks[3..] {
        w.write_tick(t, false).unwrap();
    }
    // Killed here: the file ends after the flushed chunk, with no summary section.
    let killed = disk.0.borrow().get_ref().clone();
    drop(w);
    assert!(!matches!(mcap::Summary::read(&killed), Ok(Some(_))));

    let (copied, out) = recover(killed.as_slice(), Cursor::new(Vec::new())).unwrap();
    // Ticks 0–2 in one block on each of wheel, vehicle, assist, timing, arm, raw wheel and
    // raw IMU (the arm's 3-D scene waits for its axes); every channel and the scene's.
    assert_eq!((copied.messages, copied.channels), (7, CHANNELS.len() + 1));
    let rec = Recording::from_bytes(&out.into_inner()).unwrap();
    assert_eq!(rec.metadata, metadata());
    let wheel: Vec<_> = rec.ticks().map(|t| t.wheel).collect();
    assert_eq!(
        wheel,
        ticks[..3]
            .iter()
            .map(|t| t.as_recorded().wheel)
            .collect::<Vec<_>>()
    );
}

/// `honest` with `record` (its 9-byte header and whatever follows) right after the header
/// record that opens every recording.
fn with_record_after_header(honest: &[u8], record: &[u8]) -> Vec<u8> {
    let header_end = 8 + 9 + u64::from_le_bytes(honest[9..17].try_into().unwrap()) as usize;
    [&honest[..header_end], record, &honest[header_end..]].concat()
}

/// A metadata record's header claiming `len` bytes, with none of them behind it.
fn metadata_claiming(len: u64) -> Vec<u8> {
    let mut head = vec![mcap::records::op::METADATA];
    head.extend(len.to_le_bytes());
    head
}

#[test]
fn a_record_over_the_one_limit_is_refused_by_name_by_every_reader() {
    let honest = write_session(&(0..300).map(tick).collect::<Vec<_>>());
    let over = MAX_RECORD_BYTES as u64 + 1;
    let forged = with_record_after_header(&honest, &metadata_claiming(over));
    let named = |e: &ReadError| {
        matches!(e, ReadError::TooLarge { what, claimed_bytes, limit_bytes }
            if what == "a record (opcode 0x0c)"
                && *claimed_bytes == over
                && *limit_bytes == MAX_RECORD_BYTES as u64)
    };
    let limits = StreamLimits::default();
    // The streaming reader (the hub's replay) refuses it while it opens, before the metadata.
    let e = TickStream::from_bytes(forged.clone(), limits, &Channel::ALL).err();
    assert!(e.as_ref().is_some_and(named), "{e:?}");
    let e = read_columns(forged.as_slice(), limits).unwrap_err();
    assert!(named(&e), "{e}");
    let e = Recording::from_bytes(&forged).unwrap_err();
    assert!(named(&e), "{e}");
    let e = compare::compare(
        &honest[..],
        &forged[..],
        limits,
        &Channel::ALL,
        &[],
        |_, _| {},
    );
    let e = e.unwrap_err();
    assert!(e.second && named(&e.source), "{e}");
    // `recover` copies up to it and says why it stopped there.
    let (copied, _) = recover(forged.as_slice(), Cursor::new(Vec::new())).unwrap();
    assert_eq!(copied.stopped_at, Some(named_error(over)));
    // One byte less is within the limit: the reader goes on to find the bytes missing.
    let at_limit = with_record_after_header(&honest, &metadata_claiming(over - 1));
    let e = read_columns(at_limit.as_slice(), limits).unwrap_err();
    assert!(!matches!(e, ReadError::TooLarge { .. }), "{e}");
}

/// The words every reader refuses a record of `len` bytes after the header with.
fn named_error(len: u64) -> String {
    format!(
        "a record (opcode 0x0c) claims {len} bytes, more than the {MAX_RECORD_BYTES} this \
         reader accepts (a damaged or hostile recording)"
    )
}
