//! A real-device session replays bit for bit from its recorded raw inputs (issue 15): a
//! real-time session on the kernel force-feedback backend over an in-memory device, on the
//! wall clock, with a person turning the wheel as the clock goes, a pause and a stop from
//! another thread — everything a second run could not repeat — re-run by `telerehab replay`
//! from `/raw/wheel`, every recorded output compared.

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Duration;

use clock::Clock;
use haptic_wheel::evdev_wheel::EvdevWheel;
use haptic_wheel::evdev_wheel::fake::FakeFfDevice;
use station::commands::replay::replay;
use station::config::StationConfig;
use station::record::Recording;
use station::record::raw::{BodyKindName, RawRead};
use station::session::haptic::Pacing;
use station::session::plant::Body;
use station::session::{self, BodyKind, Controls, SessionOptions};

/// The thesis SideWinder's USB id (built-in profile, 1.87 N·m).
const SIDEWINDER: (u16, u16) = (0x045e, 0x0034);

/// How a recorded session ends early.
#[derive(Clone, Copy, PartialEq)]
enum End {
    /// The patient stops it.
    Stop,
    /// The wheel is unplugged (a real one ends the session at once).
    Unplug,
}

/// Record a real-time session of `exercise` on a fake SideWinder to `path`: the rim turned by
/// a script on the wall clock and giving way under the motor, the exercise paused at 0.8 s
/// for 0.3 s, the session ended as `end` says at 2.0 s (of its 3 s).
fn record_real_session(path: &Path, exercise: &str, end: End) -> session::SessionReport {
    let mut config = StationConfig::default();
    config.session.duration_s = 3.0;
    config.session.exercise = exercise.into();
    let clock = Clock::real();
    let dev = FakeFfDevice::wheel("fake wheel", SIDEWINDER, 1.87, clock.clone());
    let fake = dev.handle();
    let start_ns = clock.now_ns();
    fake.set_script(Some(Box::new(move |t_ns| {
        let t = t_ns.saturating_sub(start_ns) as f64 * 1e-9;
        32_768 + (9_000.0 * (std::f64::consts::TAU * 0.7 * t).sin()) as i32
    })));
    fake.set_compliance(1500.0);
    let wheel = EvdevWheel::with_device(dev, "fake", config.wheel.clone(), clock.clone()).unwrap();
    let body = Body::real_wheel(Box::new(wheel), None, clock.clone());
    let opts = SessionOptions {
        config,
        pacing: Pacing::RealTime,
        record: Some(path.to_path_buf()),
        body: BodyKind::RealWheel,
        regimen: None,
        isolate_core: false,
        clock,
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
        assert!(outcome.compared["/wheel"] > 1500, "{:?}", outcome.compared);
        assert_eq!(outcome.compared["/metrics"], 1);
    }
}

#[test]
fn a_real_wheel_session_ended_by_an_unplug_replays_bit_for_bit_from_its_raw_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), "sine-road", End::Unplug);
    let rec = Recording::open(&path).unwrap();
    let unplugged = rec
        .raw_wheel
        .iter()
        .position(|w| w.data.read == RawRead::Unplugged)
        .expect("the unplug was recorded");
    // Ended at once (no replug grace for a real wheel): the fade-out, not 30 s.
    assert!(rec.raw_wheel.len() - unplugged < 3000, "{unplugged}");
    let outcome = replay(&path).unwrap();
    assert!(outcome.from_raw);
    assert_eq!(outcome.first_difference, None);
}
