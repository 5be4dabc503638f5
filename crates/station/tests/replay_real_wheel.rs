//! A real-device session replays bit for bit from its recorded raw inputs (issue 15): a
//! real-time session on the kernel force-feedback backend over an in-memory device, on the
//! wall clock, with a person turning the wheel as the clock goes, a pause and a stop from
//! another thread — everything a second run could not repeat — re-run by `telerehab replay`
//! from `/raw/wheel`, every recorded output compared. Also a real wheel unplugged and plugged
//! back in (issue 17): the session pauses at zero torque, re-opens the wheel by its identity,
//! resumes with a soft start, says so in its report, and replays bit for bit.
#![cfg(target_os = "linux")]

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use clock::Clock;
use record::Recording;
use record::raw::{BodyKindName, RawRead};
use record::types::Watchdog;
use session::config::StationConfig;
use session::haptic::Pacing;
use session::plant::Body;
use session::{self, BodyKind, Controls, SessionOptions};
use station::commands::replay::replay;
use wheel_devices::evdev_wheel::EvdevWheel;
use wheel_devices::evdev_wheel::fake::{FakeFfDevice, FakeHandle};

/// The thesis SideWinder's USB id (built-in profile, 1.87 N·m).
const SIDEWINDER: (u16, u16) = (0x045e, 0x0034);

/// How a recorded session ends early.
#[derive(Clone, Copy, PartialEq)]
enum End {
    /// The patient stops it.
    Stop,
    /// The wheel is unplugged and not plugged back in: the session ends when the 1 s replug
    /// grace runs out.
    Unplug,
    /// The wheel is unplugged, plugged back in 0.5 s later (a new device node on the same
    /// port), and the patient stops the session 1 s after that.
    Replug,
}

/// The USB port the fake wheel sits on.
const PORT: &str = "usb-0000:00:14.0-2/input0";

/// A fake SideWinder on `PORT` turned by a person (a script on the wall clock from
/// `start_ns`), its rim giving way under the motor.
fn turned_wheel(clock: &Clock, start_ns: u64) -> FakeFfDevice {
    let dev =
        FakeFfDevice::wheel("fake wheel", SIDEWINDER, 1.87, clock.clone()).at(Some(PORT), None);
    let fake = dev.handle();
    fake.set_script(Some(Box::new(move |t_ns| {
        let t = t_ns.saturating_sub(start_ns) as f64 * 1e-9;
        32_768 + (9_000.0 * (std::f64::consts::TAU * 0.7 * t).sin()) as i32
    })));
    fake.set_compliance(1500.0);
    dev
}

/// What the devices showed in a session with a replug.
#[derive(Default)]
struct Motors {
    /// The unplugged device's motor torque just before the wheel was plugged back in, N·m.
    old_away_nm: f64,
    /// The device plugged back in.
    new: Option<FakeHandle>,
}

/// Record a real-time session of `exercise` on a fake SideWinder to `path`: the rim turned by
/// a script on the wall clock and giving way under the motor, the exercise paused at 0.8 s
/// for 0.3 s, the wheel re-opened by its identity when plugged back in (1 s replug grace),
/// the session ended as `end` says from 2.0 s on (of its 3 s).
fn record_real_session(path: &Path, exercise: &str, end: End) -> session::SessionReport {
    record_real_session_with(path, exercise, end, &mut Motors::default())
}

fn record_real_session_with(
    path: &Path,
    exercise: &str,
    end: End,
    motors: &mut Motors,
) -> session::SessionReport {
    let mut config = StationConfig::default();
    config.session.duration_s = 3.0;
    config.session.exercise = exercise.into();
    config.haptic.replug_grace_s = 1.0;
    let clock = Clock::real();
    let start_ns = clock.now_ns();
    let dev = turned_wheel(&clock, start_ns);
    let fake = dev.handle();
    // The devices plugged in: each one taken by the first scan that sees it.
    let bus: Arc<Mutex<Vec<(String, FakeFfDevice)>>> = Arc::default();
    let finder = {
        let bus = bus.clone();
        move || std::mem::take(&mut *bus.lock().unwrap())
    };
    let wheel = EvdevWheel::with_device(dev, "fake", config.wheel.clone(), clock.clone())
        .unwrap()
        .reopen_with(finder, Duration::from_millis(20))
        .unwrap();
    let body = Body::real_wheel(Box::new(wheel), None, clock.clone());
    let opts = SessionOptions {
        config,
        pacing: Pacing::RealTime,
        record: Some(path.to_path_buf()),
        body: BodyKind::RealWheel,
        regimen: None,
        isolate_core: false,
        difficulty: None,
        clock: clock.clone(),
    };
    let controls = Controls::default();
    std::thread::scope(|s| {
        s.spawn(|| {
            std::thread::sleep(Duration::from_millis(800));
            controls.pause.store(true, Ordering::Relaxed);
            std::thread::sleep(Duration::from_millis(300));
            controls.pause.store(false, Ordering::Relaxed);
            std::thread::sleep(Duration::from_millis(900));
            match end {
                End::Stop => controls.stop.store(true, Ordering::Relaxed),
                End::Unplug => fake.set_unplugged(true),
                End::Replug => {
                    fake.set_unplugged(true);
                    std::thread::sleep(Duration::from_millis(500));
                    motors.old_away_nm = fake.motor_torque_nm();
                    let new = turned_wheel(&clock, start_ns);
                    motors.new = Some(new.handle());
                    bus.lock().unwrap().push(("/dev/input/event9".into(), new));
                    std::thread::sleep(Duration::from_millis(1000));
                    controls.stop.store(true, Ordering::Relaxed);
                }
            }
        });
        session::run_with_body(&opts, &controls, &mut (), body, None).unwrap()
    })
}

fn recording(dir: &Path, exercise: &str, end: End) -> PathBuf {
    let path = dir.join(format!("{exercise}.mcap"));
    let report = record_real_session(&path, exercise, end);
    assert!(report.haptic.stopped_early, "the end came from outside");
    assert_eq!(
        report.haptic.wheel_fault.is_some(),
        end == End::Unplug,
        "{:?}",
        report.haptic.wheel_fault
    );
    assert_eq!(report.recorder.error, None);
    path
}

#[test]
fn a_real_wheel_session_with_a_pause_and_a_stop_replays_bit_for_bit_from_its_raw_inputs() {
    let dir = tempfile::tempdir().unwrap();
    for exercise in ["sine-road", "dial-sine"] {
        let path = recording(dir.path(), exercise, End::Stop);
        let rec = Recording::open(&path).unwrap();
        let body = rec.metadata.body.as_ref().expect("the body's facts");
        assert_eq!(body.kind, BodyKindName::Real);
        assert_eq!(body.wheel_profile.max_torque_nm, 1.87);
        assert!(rec.wheel.iter().all(|w| w.data.true_angle_rad.is_none()));
        assert!(
            rec.score.iter().any(|s| s.data.paused),
            "the pause was recorded"
        );
        assert_eq!(
            rec.raw_wheel.len(),
            rec.wheel.len(),
            "raw inputs on every tick"
        );
        // The wall clock's jitter is in the inputs: the periods the chain measured differ.
        let periods: std::collections::BTreeSet<u64> = rec
            .raw_wheel
            .windows(2)
            .map(|w| w[1].data.now_ns - w[0].data.now_ns)
            .collect();
        assert!(periods.len() > 1, "{periods:?}");
        let turned = rec.raw_wheel.iter().map(|w| w.data.angle_rad.abs());
        assert!(turned.fold(0.0, f64::max) > 0.2, "the rim was turned");

        let outcome = replay(&path).unwrap();
        assert!(outcome.from_raw);
        assert_eq!(outcome.first_difference, None, "{exercise}");
        assert!(outcome.caveats.is_empty(), "{:?}", outcome.caveats);
        assert_eq!(outcome.compared["/raw/wheel"], rec.raw_wheel.len());
        assert!(outcome.compared["/wheel"] > 1000, "{:?}", outcome.compared);
        assert_eq!(outcome.compared["/metrics"], 1);
    }
}

#[test]
fn a_real_wheel_session_ended_by_an_unplug_replays_bit_for_bit_from_its_raw_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), "sine-road", End::Unplug);
    let rec = Recording::open(&path).unwrap();
    let body = rec.metadata.body.as_ref().unwrap();
    assert_eq!(body.replug_grace_ns, Some(1_000_000_000));
    let unplugged = rec
        .raw_wheel
        .iter()
        .position(|w| w.data.read == RawRead::Unplugged)
        .expect("the unplug was recorded");
    // Ended when the 1 s grace ran out (then at most the fade-out), not at once nor after
    // 30 s, on the body's clock (a loaded machine skips missed ticks, so ticks would not
    // count the time); the replay waits exactly as long.
    let now_s = |w: &record::Stamped<record::RawWheelSample>| w.data.now_ns as f64 * 1e-9;
    let away_s = now_s(rec.raw_wheel.last().unwrap()) - now_s(&rec.raw_wheel[unplugged]);
    assert!(
        (1.0..1.3).contains(&away_s),
        "{away_s} s from the unplug to the end"
    );
    let outcome = replay(&path).unwrap();
    assert!(outcome.from_raw);
    assert_eq!(outcome.first_difference, None);
}

#[test]
fn a_real_wheel_unplugged_and_plugged_back_in_pauses_resumes_says_so_and_replays_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("replug.mcap");
    let mut motors = Motors::default();
    let report = record_real_session_with(&path, "sine-road", End::Replug, &mut motors);
    assert_eq!(
        report.haptic.wheel_fault, None,
        "it came back within the grace"
    );
    assert_eq!(report.haptic.wheel_replugs, 1);
    let text = report::terminal::render(&report, None);
    assert!(
        text.contains("unplugged and plugged back 1 time(s)"),
        "{text}"
    );
    assert_eq!(report.recorder.error, None);

    let rec = Recording::open(&path).unwrap();
    let reads: Vec<RawRead> = rec.raw_wheel.iter().map(|w| w.data.read).collect();
    let gone = reads.iter().position(|r| *r == RawRead::Unplugged).unwrap();
    let back = gone
        + reads[gone..]
            .iter()
            .position(|r| *r == RawRead::Ok)
            .unwrap();
    assert!(back - gone > 300, "away {} ticks", back - gone);
    assert!(reads[back..].iter().all(|r| *r == RawRead::Ok));
    // Away: the torque faded to zero and stayed there, the exercise paused; the unplugged
    // device's motor was free.
    let fade = gone + 260;
    assert!(
        rec.wheel[fade..back]
            .iter()
            .all(|w| w.data.commanded_nm == 0.0)
    );
    let scores = |from: usize, to: usize| {
        rec.score
            .iter()
            .filter(move |s| (from as u64..to as u64).contains(&s.tick))
    };
    assert!(scores(gone + 1, back).count() >= 3);
    assert!(scores(gone + 1, back).all(|s| s.data.paused));
    assert_eq!(motors.old_away_nm, 0.0);
    // Back: from zero, soft-started, the exercise running again.
    assert_eq!(rec.wheel[back].data.commanded_nm, 0.0);
    let resumed = back
        + rec.wheel[back..]
            .iter()
            .position(|w| w.data.watchdog == Watchdog::SoftStart)
            .expect("a soft start after the replug");
    assert_eq!(rec.wheel[resumed - 1].data.commanded_nm, 0.0);
    assert!(
        rec.wheel[resumed..]
            .iter()
            .any(|w| w.data.commanded_nm.abs() > 0.01)
    );
    assert!(scores(resumed, rec.wheel.len()).any(|s| !s.data.paused));
    let new = motors.new.expect("plugged back in");
    assert_eq!(
        new.first_constant_levels()[..2],
        [0, 0],
        "the first levels sent"
    );
    assert!(new.peak_motor_torque_nm() > 0.0, "torque again");
    assert!(new.peak_motor_torque_nm() <= 1.87 + 1e-9);

    let outcome = replay(&path).unwrap();
    assert!(outcome.from_raw);
    assert_eq!(outcome.first_difference, None);
}
