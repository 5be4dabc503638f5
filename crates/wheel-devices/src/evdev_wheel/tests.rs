//! The evdev backend against an in-memory device, what is its own: the kernel-level mapping,
//! event time stamps, silence and bad readings, the firmware-effect lifecycle, throttling and
//! re-arming. The safety tests every backend passes (the ceiling in N·m at the motor on every
//! profile, unplug and replug, rates) are in `crate::backend_tests`.

use super::fake::{FakeFfDevice, FakeHandle};
use super::*;
use clock::MockClock;

const MS: u64 = 1_000_000;
/// An id no built-in profile claims.
const UNKNOWN_ID: (u16, u16) = (0x1d50, 0x6015);
/// The thesis SideWinder's id (a built-in profile, 1.87 N·m, hid-pidff at 1 kHz).
const SIDEWINDER_ID: (u16, u16) = (0x045e, 0x0034);

fn wheel_with(
    usb_id: (u16, u16),
    motor_nm: f64,
    config: WheelConfig,
) -> (EvdevWheel<FakeFfDevice>, FakeHandle, MockClock) {
    let (clock, mock) = Clock::mock();
    let dev = FakeFfDevice::wheel("test wheel", usb_id, motor_nm, clock.clone());
    let handle = dev.handle();
    let wheel = EvdevWheel::with_device(dev, "/dev/input/event99", config, clock).unwrap();
    (wheel, handle, mock)
}

#[test]
fn level_mapping_truncates_towards_zero_and_rejects_nonsense() {
    assert_eq!(level_for(1.0, 2.0, 2.0, 1.0, 1.0), 16_383);
    assert_eq!(level_for(-1.0, 2.0, 2.0, 1.0, 1.0), -16_383);
    assert_eq!(level_for(1.0, 2.0, 2.0, 1.0, -1.0), -16_383);
    assert_eq!(level_for(50.0, 2.0, 2.0, 1.0, 1.0), 32_767);
    assert_eq!(level_for(f64::NAN, 2.0, 2.0, 1.0, 1.0), 0);
    assert_eq!(level_for(1.0, 2.0, 0.0, 1.0, 1.0), 0);
    assert_eq!(level_for(1.0, 2.0, 2.0, 0.0, 1.0), 0);
}

#[test]
fn a_reading_is_stamped_when_its_input_event_arrived() {
    let (mut w, fake, mock) = wheel_with(SIDEWINDER_ID, 1.87, WheelConfig::default());
    mock.advance_ns(10 * MS);
    fake.set_value(40_000);
    mock.advance_ns(3 * MS);
    let r = w.read().unwrap();
    assert_eq!(r.t_ns, 10 * MS, "the event's time, not the read's");
    assert!(r.angle_rad != 0.0);
    // No new event on a live device at rest: the kernel's state is current as of the read.
    mock.advance_ns(5 * MS);
    assert_eq!(w.read().unwrap().t_ns, 18 * MS);
}

#[test]
fn a_wheel_silent_under_torque_is_a_fault_and_silent_at_rest_is_not() {
    let cfg = WheelConfig {
        max_silence_ms: 100,
        ..Default::default()
    };
    let (mut w, fake, mock) = wheel_with(SIDEWINDER_ID, 1.87, cfg);
    fake.set_silent(true);
    // At rest, silence is normal.
    mock.advance_ns(500 * MS);
    w.read().unwrap();
    // Under torque, silence is tolerated for max_silence_ms, then reported.
    w.command_torque(0.5).unwrap();
    for _ in 0..100 {
        mock.advance_ns(MS);
        w.command_torque(0.5).unwrap();
        w.read().unwrap();
    }
    mock.advance_ns(2 * MS);
    let err = w.read().unwrap_err();
    assert_eq!(err.fault(), Some(WheelFault::Silent), "{err}");
    // Events again: healthy again.
    fake.set_silent(false);
    mock.advance_ns(MS);
    w.read().unwrap();
    // Torque back to zero: silence no longer matters.
    fake.set_silent(true);
    w.command_torque(0.0).unwrap();
    mock.advance_ns(1000 * MS);
    w.read().unwrap();
}

#[test]
fn an_unplugged_wheel_reports_it_on_every_call_and_a_bad_value_is_refused() {
    let (mut w, fake, mock) = wheel_with(SIDEWINDER_ID, 1.87, WheelConfig::default());
    fake.set_value(70_000);
    assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::OutOfRange));
    fake.set_value(30_000);
    w.read().unwrap();
    fake.set_unplugged(true);
    mock.advance_ns(MS);
    assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
    // Replugged at the OS level is a new device node: this handle stays lost.
    fake.set_unplugged(false);
    assert_eq!(
        w.command_torque(0.5).unwrap_err().fault(),
        Some(WheelFault::Unplugged)
    );
    assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
}

#[test]
fn firmware_conditions_play_only_while_the_supervisor_runs_and_are_capped() {
    let cfg = WheelConfig {
        rated_torque_nm: Some(5.0),
        ..Default::default()
    };
    let (mut w, fake, mock) = wheel_with(UNKNOWN_ID, 5.0, cfg);
    let spring = Condition {
        kind: ConditionKind::Spring,
        offset: 0.0,
        positive_coefficient: 2.0,
        negative_coefficient: 2.0,
        positive_saturation_nm: 3.0,
        negative_saturation_nm: 3.0,
        deadband: 0.0,
    };
    // The budget caps the saturation: the spring may add at most 0.5 N·m.
    let added = w.upload_condition(&spring, 0.5).unwrap();
    assert_eq!(added, 0.5);
    assert_eq!(
        fake.playing_conditions(),
        0,
        "not before the supervisor runs"
    );
    w.set_firmware_effects_active(true);
    assert_eq!(fake.playing_conditions(), 1);
    assert!(fake.motor_torque_nm() <= 0.5 + 1e-9);
    // Re-armed with the constant force while running.
    for _ in 0..200 {
        mock.advance_ns(MS);
        w.command_torque(0.2).unwrap();
    }
    assert_eq!(fake.playing_conditions(), 1);
    // Pause, fault or stop: the supervisor is not running, the spring stops at once.
    w.set_firmware_effects_active(false);
    assert_eq!(fake.playing_conditions(), 0);
    for _ in 0..200 {
        mock.advance_ns(MS);
        w.command_torque(0.2).unwrap();
    }
    assert_eq!(fake.playing_conditions(), 0, "not re-armed while stopped");
    // Exit: everything erased, gain back to full, autocentre as configured.
    drop(w);
    assert_eq!(fake.live_effects(), 0);
    assert_eq!(fake.gain(), u16::MAX);
    assert_eq!(fake.autocenter(), 0);
    assert_eq!(fake.motor_torque_nm(), 0.0);
}

#[test]
fn torque_updates_follow_the_driver_rate_and_zero_is_never_throttled() {
    // A G29 on hid-lg4ff: 500 Hz.
    let (mut w, fake, mock) = wheel_with((0x046d, 0xc24f), 2.2, WheelConfig::default());
    assert_eq!(w.min_update_interval_ns(), 2 * MS);
    w.command_torque(0.5).unwrap();
    let writes = fake.effect_writes();
    mock.advance_ns(MS);
    w.command_torque(0.6).unwrap();
    assert_eq!(fake.effect_writes(), writes, "1 ms later: throttled");
    w.command_torque(0.0).unwrap();
    assert_eq!(w.sent_level(), 0, "zero goes out at once");
    mock.advance_ns(2 * MS);
    w.command_torque(0.6).unwrap();
    assert!(w.sent_level() > 0);
}

#[test]
fn opening_a_missing_device_is_an_io_error_not_a_panic() {
    let err = EvdevWheel::open(
        Path::new("/dev/input/event-does-not-exist"),
        WheelConfig::default(),
        Clock::real(),
    )
    .unwrap_err();
    assert!(matches!(err, WheelError::Io { .. }), "{err}");
}

#[test]
fn a_loop_waking_a_few_microseconds_early_or_late_still_gets_each_drivers_full_rate() {
    // G29 (lg4ff, 2 ms) and T300 (tmff2, 8 ms): ticks at k ms plus 0–49 µs of lateness.
    for (usb_id, motor_nm, policy_hz) in [
        ((0x046d, 0xc24f), 2.2, 500.0),
        ((0x044f, 0xb66e), 3.9, 125.0),
    ] {
        let (mut w, _fake, mock) = wheel_with(usb_id, motor_nm, WheelConfig::default());
        let mut late_ns = 0;
        let ticks = 4_000u64;
        for k in 0..ticks {
            let next_late_ns = (k * 7_919 % 50) * 1_000;
            mock.advance_ns(MS + next_late_ns - late_ns);
            late_ns = next_late_ns;
            w.command_torque(0.5 + 0.2 * (k as f64 * 0.01).sin())
                .unwrap();
        }
        let updates = w.motor_updates().unwrap();
        let rate_hz = updates.count as f64 / (ticks as f64 * 1e-3);
        assert!(
            (rate_hz - policy_hz).abs() <= 0.5,
            "{usb_id:04x?}: {rate_hz} updates/s, policy {policy_hz}"
        );
        let period_ms = 1e3 / policy_hz;
        assert!(
            updates.worst_gap_ms() < period_ms + 0.05,
            "{usb_id:04x?}: worst gap {} ms",
            updates.worst_gap_ms()
        );
    }
}
