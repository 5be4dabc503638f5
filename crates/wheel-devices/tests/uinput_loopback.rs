//! Loopback test of the evdev backend against a virtual force-feedback wheel made through
//! `/dev/uinput`. This test plays the wheel's firmware: it answers effect uploads and
//! erasures and records every upload, play and gain/autocentre event, then checks what the
//! backend sent. Skips (passes with a printed SKIP line) where `/dev/uinput` is missing or
//! not writable, as in containers and CI.

#![cfg(all(target_os = "linux", feature = "evdev"))]

use std::collections::BTreeSet;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use evdev::uinput::VirtualDevice;
use evdev::{
    AbsInfo, AbsoluteAxisCode, AttributeSet, BusType, EventSummary, EventType, FFEffectCode,
    FFEffectData, FFEffectKind, InputEvent, InputId, UInputCode, UinputAbsSetup,
};
use haptic_wheel::WheelConfig;
use haptic_wheel::{Condition, ConditionKind, DeviceProfile, Wheel};
use wheel_devices::evdev_wheel::EvdevWheel;

/// What the virtual firmware saw.
#[derive(Debug)]
enum Seen {
    Upload { id: i16, data: FFEffectData },
    Erase,
    Play { id: u16, count: i32 },
    Gain(i32),
    Autocenter(i32),
}

fn uinput_usable() -> Result<(), String> {
    std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/uinput")
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// The firmware loop: answer uploads/erasures until every uploaded effect is erased.
fn firmware(mut dev: VirtualDevice, tx: mpsc::Sender<Seen>) -> std::io::Result<()> {
    let mut live = BTreeSet::new();
    let mut uploads = 0;
    loop {
        let events: Vec<InputEvent> = dev.fetch_events()?.collect();
        for ev in events {
            match ev.destructure() {
                EventSummary::UInput(ev, UInputCode::UI_FF_UPLOAD, ..) => {
                    let mut up = dev.process_ff_upload(ev)?;
                    up.set_retval(0);
                    live.insert(up.effect_id() as u32);
                    uploads += 1;
                    let _ = tx.send(Seen::Upload {
                        id: up.effect_id(),
                        data: up.effect(),
                    });
                }
                EventSummary::UInput(ev, UInputCode::UI_FF_ERASE, ..) => {
                    let er = dev.process_ff_erase(ev)?;
                    live.remove(&er.effect_id());
                    let _ = tx.send(Seen::Erase);
                    if live.is_empty() && uploads > 0 {
                        return Ok(());
                    }
                }
                EventSummary::ForceFeedback(_, FFEffectCode::FF_GAIN, v) => {
                    let _ = tx.send(Seen::Gain(v));
                }
                EventSummary::ForceFeedback(_, FFEffectCode::FF_AUTOCENTER, v) => {
                    let _ = tx.send(Seen::Autocenter(v));
                }
                EventSummary::ForceFeedback(_, FFEffectCode(id), count) => {
                    let _ = tx.send(Seen::Play { id, count });
                }
                _ => {}
            }
        }
    }
}

/// A virtual Logitech G29 (its profile's rate policy is 500 Hz) turned to a quarter of its
/// axis, its event node, and until when the node's permissions may take to settle.
fn virtual_g29() -> (VirtualDevice, std::path::PathBuf, Instant) {
    let ff = AttributeSet::from_iter([
        FFEffectCode::FF_CONSTANT,
        FFEffectCode::FF_SPRING,
        FFEffectCode::FF_FRICTION,
        FFEffectCode::FF_GAIN,
        FFEffectCode::FF_AUTOCENTER,
    ]);
    let mut dev = VirtualDevice::builder()
        .unwrap()
        .name("telerehab loopback wheel")
        .input_id(InputId::new(BusType::BUS_USB, 0x046d, 0xc24f, 0x0111))
        .with_absolute_axis(&UinputAbsSetup::new(
            AbsoluteAxisCode::ABS_X,
            AbsInfo::new(0, -32768, 32767, 0, 0, 0),
        ))
        .unwrap()
        .with_ff(&ff)
        .unwrap()
        .with_ff_effects_max(16)
        .build()
        .unwrap();
    dev.emit(&[InputEvent::new(
        EventType::ABSOLUTE.0,
        AbsoluteAxisCode::ABS_X.0,
        16384,
    )])
    .unwrap();
    // The event node appears shortly after the device is created.
    let deadline = Instant::now() + Duration::from_secs(5);
    let node = loop {
        let found = dev
            .enumerate_dev_nodes_blocking()
            .ok()
            .and_then(|mut nodes| nodes.find_map(Result::ok));
        match found {
            Some(p) => break p,
            None if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(20)),
            None => panic!("the virtual wheel got no /dev/input/event node within 5 s"),
        }
    };
    (dev, node, deadline)
}

#[test]
fn backend_streams_constant_force_and_uploads_conditions_to_a_virtual_wheel() {
    if let Err(e) = uinput_usable() {
        println!(
            "SKIPPED: backend_streams_constant_force_and_uploads_conditions_to_a_virtual_wheel: \
             /dev/uinput is not usable here ({e}); the evdev loopback test needs the uinput \
             module and write access to /dev/uinput"
        );
        return;
    }
    let (dev, node, deadline) = virtual_g29();
    let (tx, rx) = mpsc::channel();
    let fw = std::thread::spawn(move || firmware(dev, tx));

    // The node's permissions may take a moment to settle (udev).
    let mut wheel = loop {
        match EvdevWheel::open(&node, WheelConfig::default(), clock::Clock::real()) {
            Ok(w) => break w,
            Err(e) if Instant::now() < deadline => {
                let _ = e;
                std::thread::sleep(Duration::from_millis(20));
            }
            Err(e) => panic!("could not open {}: {e}", node.display()),
        }
    };
    let g29 = DeviceProfile::logitech_g29();
    assert_eq!(wheel.min_update_interval_ns(), 2_000_000);

    // Angle: G29 sign convention (device right = negative), 900° over the axis range.
    let r = wheel.read().unwrap();
    let expected = g29.angle_sign * 2.0 * g29.half_range_rad / 65535.0 * (16384.0 + 0.5);
    assert!(
        (r.angle_rad - expected).abs() < 1e-9,
        "{} vs {expected}",
        r.angle_rad
    );

    // Stream 1 kHz commands for 200 ms; the backend throttles to 500 Hz.
    let start = Instant::now();
    for k in 0..200 {
        wheel.command_torque(0.5 * (k as f64 * 0.05).sin()).unwrap();
        std::thread::sleep(Duration::from_millis(1));
    }
    let streamed = start.elapsed();
    std::thread::sleep(Duration::from_millis(5));
    let half_nm = 0.5 * g29.max_torque_nm;
    wheel.command_torque(half_nm).unwrap(); // half of the G29's rated torque
    let half_level = wheel.sent_level();
    let spring = Condition::symmetric(ConditionKind::Spring, 1.0, 5.0);
    let budget = wheel.upload_condition(&spring, 0.5).unwrap();
    assert_eq!(budget, 0.5, "saturation capped to the budget");
    assert!(
        wheel
            .upload_condition(&Condition::symmetric(ConditionKind::Damper, 1.0, 1.0), 0.5)
            .is_err()
    );
    drop(wheel);
    fw.join().unwrap().unwrap();
    let seen: Vec<Seen> = rx.try_iter().collect();

    // Truncated towards zero: the motor never gives more than asked.
    assert_eq!(
        half_level, 16383,
        "half the rated torque is half of full scale"
    );
    the_firmware_saw_streamed_torque_one_spring_and_a_clean_exit(&seen, streamed);
}

/// What the virtual wheel's firmware saw of a session that streamed torque for `streamed`
/// (at most the G29's 500 Hz), uploaded one spring and dropped the wheel.
fn the_firmware_saw_streamed_torque_one_spring_and_a_clean_exit(seen: &[Seen], streamed: Duration) {
    let constants: Vec<(i16, i16, u16)> = seen
        .iter()
        .filter_map(|s| match s {
            Seen::Upload {
                id,
                data:
                    FFEffectData {
                        kind: FFEffectKind::Constant { level, .. },
                        replay,
                        ..
                    },
            } => Some((*id, *level, replay.length)),
            _ => None,
        })
        .collect();
    assert!(
        constants.len() > 10,
        "torque was streamed: {}",
        constants.len()
    );
    let id = constants[0].0;
    assert!(
        constants.iter().all(|c| c.0 == id),
        "one effect id, re-uploaded"
    );
    assert!(constants.iter().all(|c| c.2 == 100), "short replay length");
    let max_updates = (streamed.as_secs_f64() / 0.002).ceil() as usize + 4;
    assert!(
        constants.len() <= max_updates,
        "{} updates in {streamed:?} exceeds the 500 Hz policy",
        constants.len()
    );
    assert_eq!(constants.last().unwrap().1, 0, "zero torque sent on drop");
    let springs = seen
        .iter()
        .filter(|s| {
            matches!(
                s,
                Seen::Upload {
                    data: FFEffectData {
                        kind: FFEffectKind::Spring { .. },
                        ..
                    },
                    ..
                }
            )
        })
        .count();
    assert_eq!(springs, 1);
    assert!(
        seen.iter()
            .any(|s| matches!(s, Seen::Play { id: p, count: 1 } if *p as i16 == id)),
        "constant force is played (re-armed)"
    );
    let gains: Vec<i32> = seen
        .iter()
        .filter_map(|s| match s {
            Seen::Gain(g) => Some(*g),
            _ => None,
        })
        .collect();
    assert_eq!(gains.first(), Some(&0xffff));
    assert_eq!(gains.last(), Some(&0xffff), "gain restored on exit");
    assert!(seen.iter().any(|s| matches!(s, Seen::Autocenter(0))));
    assert!(seen.iter().any(|s| matches!(s, Seen::Erase)));
}
