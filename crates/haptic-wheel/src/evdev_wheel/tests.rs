//! The evdev backend against an in-memory device: the N·m to kernel-level mapping on every
//! profile, the ceiling at the motor, stale and bad readings, unplug, the firmware-effect
//! lifecycle, throttling and re-arming.

use super::fake::{FakeFfDevice, FakeHandle};
use super::*;
use crate::profile::{ASSUMED_UNKNOWN_MOTOR_NM, DriverFamily, TorqueSource};
use crate::safety::{SafetyConfig, Supervisor};
use crate::wheel_config::CeilingReport;
use clock::MockClock;
use proptest::prelude::*;

const MS: u64 = 1_000_000;

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

/// An id no built-in profile claims.
const UNKNOWN_ID: (u16, u16) = (0x1d50, 0x6015);
/// The thesis SideWinder's id (a built-in profile, 1.87 N·m, hid-pidff at 1 kHz).
const SIDEWINDER_ID: (u16, u16) = (0x045e, 0x0034);

#[test]
fn an_unknown_direct_drive_wheel_gives_at_most_one_newton_metre_whatever_is_commanded() {
    // The defect of issue 12: a 25 N·m motor, no profile. Commanding 1 N·m used to send the
    // full kernel level (25 N·m at the rim).
    let (mut w, fake, mock) = wheel_with(UNKNOWN_ID, 25.0, WheelConfig::default());
    assert_eq!(w.profile().torque_source, TorqueSource::Assumed);
    assert_eq!(
        w.max_torque_nm(),
        1.0,
        "the usable torque of an unknown wheel"
    );
    for cmd in [1.0, 5.0, 25.0, -100.0, f64::MAX] {
        mock.advance_ns(MS);
        let _ = w.command_torque(cmd);
        assert!(
            fake.motor_torque_nm() <= 1.0,
            "{cmd} N·m commanded gave {} N·m at the motor",
            fake.motor_torque_nm()
        );
    }
    // 1 N·m commanded is 1/32 of the level: 0.78 N·m on this 25 N·m motor.
    mock.advance_ns(MS);
    w.command_torque(1.0).unwrap();
    assert_eq!(
        w.sent_level(),
        (LEVEL_FULL_SCALE / ASSUMED_UNKNOWN_MOTOR_NM) as i16
    );
    assert!((fake.motor_torque_nm() - 25.0 / 32.0).abs() < 1e-3);
}

#[test]
fn a_clinician_entered_rating_lifts_the_cap_and_torque_is_true_in_newton_metres() {
    let cfg = WheelConfig {
        rated_torque_nm: Some(8.0),
        ..Default::default()
    };
    let (mut w, fake, mock) = wheel_with(UNKNOWN_ID, 8.0, cfg);
    assert_eq!(w.max_torque_nm(), 8.0);
    mock.advance_ns(MS);
    w.command_torque(3.0).unwrap();
    assert!(
        (fake.motor_torque_nm() - 3.0).abs() < 1e-3,
        "{}",
        fake.motor_torque_nm()
    );
}

#[test]
fn the_device_gain_is_part_of_the_mapping() {
    let cfg = WheelConfig {
        rated_torque_nm: Some(10.0),
        gain: 0.5,
        ..Default::default()
    };
    let (mut w, fake, mock) = wheel_with(UNKNOWN_ID, 10.0, cfg);
    assert_eq!(fake.gain(), 32_768);
    assert!(
        (w.max_torque_nm() - 5.0).abs() < 1e-3,
        "half the gain, half the usable torque"
    );
    mock.advance_ns(MS);
    w.command_torque(2.0).unwrap();
    assert!(
        (fake.motor_torque_nm() - 2.0).abs() < 1e-3,
        "{}",
        fake.motor_torque_nm()
    );
    mock.advance_ns(MS);
    w.command_torque(9.0).unwrap();
    assert!(fake.motor_torque_nm() <= w.max_torque_nm() + 1e-9);
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

fn any_profile() -> impl Strategy<Value = DeviceProfile> {
    let builtin = DeviceProfile::builtin();
    prop_oneof![
        (0..builtin.len()).prop_map(move |i| builtin[i].clone()),
        prop_oneof![
            Just(DriverFamily::HidPidff),
            Just(DriverFamily::Lg4ff),
            Just(DriverFamily::Hidpp),
            Just(DriverFamily::Tmff2),
            Just(DriverFamily::Fanatec),
        ]
        .prop_map(DeviceProfile::unknown),
        (0.1f64..40.0)
            .prop_map(|t| DeviceProfile::unknown(DriverFamily::HidPidff).with_rated_torque(t)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// DESIGN.md safety invariant 1 in N·m at the motor: on every built-in profile, an
    /// unknown wheel of any plausible motor and a clinician-rated one, at any gain and for any
    /// patient ceiling and command sequence (NaN and infinities included), the torque the
    /// motor produces never exceeds the ceiling in force.
    #[test]
    fn the_motor_never_exceeds_the_ceiling_on_any_profile(
        profile in any_profile(),
        motor_share in 0.05f64..=1.0,
        gain in 0.05f64..=1.0,
        patient_ceiling in proptest::option::of(0.0f64..50.0),
        requests in proptest::collection::vec(prop_oneof![
            -100.0f64..100.0, Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY),
            Just(f64::MAX)], 1..120),
    ) {
        // The real motor is at most what the profile states (for an unknown wheel: anything
        // up to the assumed strongest motor).
        let motor_nm = profile.max_torque_nm * motor_share;
        let cfg = WheelConfig { profile: Some(profile.clone()), gain, ..Default::default() };
        let (mut w, fake, mock) = wheel_with(UNKNOWN_ID, motor_nm, cfg);
        let report = CeilingReport::new(&profile, gain, patient_ceiling);
        let patient = patient_ceiling.map(|c| c.min(w.max_torque_nm()));
        let mut sup = Supervisor::new(
            SafetyConfig { ceiling_nm: patient, soft_start_s: 0.01, ..Default::default() },
            w.max_torque_nm(),
        ).unwrap();
        prop_assert!((sup.ceiling_nm() - report.ceiling_nm).abs() < 1e-9);
        for r in requests {
            mock.advance_ns(MS);
            let now = mock.now_ns();
            let out = sup.apply(r, now, Some(now));
            let _ = w.command_torque(out.torque_nm);
            prop_assert!(fake.motor_torque_nm() <= sup.ceiling_nm() + 1e-9,
                "{} N·m at the motor over a {} N·m ceiling", fake.motor_torque_nm(), sup.ceiling_nm());
            // Commanded straight to the backend, without the chain: still never above the
            // usable maximum.
            let _ = w.command_torque(r);
            prop_assert!(fake.motor_torque_nm() <= w.max_torque_nm() + 1e-9);
            prop_assert!(fake.motor_torque_nm() <= profile.usable_max_nm() + 1e-9);
        }
        prop_assert!(fake.peak_motor_torque_nm() <= w.max_torque_nm() + 1e-9);
    }
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
fn a_lowered_ceiling_holds_at_the_motor_at_once_even_between_throttled_updates() {
    // A Thrustmaster base on hid-tmff2: one update per 8 ms. The level sent a moment ago is
    // held until the next update; a regimen lowering the ceiling meanwhile must not wait.
    for usb_id in [(0x044f, 0xb66e), UNKNOWN_ID] {
        // The motor as strong as the profile states (an unknown wheel: the strongest assumed).
        let motor_nm = DeviceProfile::for_usb_id(usb_id.0, usb_id.1).max_torque_nm;
        let (mut w, fake, mock) = wheel_with(usb_id, motor_nm, WheelConfig::default());
        let usable = w.max_torque_nm();
        w.set_torque_ceiling_nm(usable).unwrap();
        w.command_torque(usable).unwrap();
        let held_nm = fake.motor_torque_nm();
        assert!(held_nm > 0.5 * usable.min(motor_nm), "{held_nm} N·m held");
        mock.advance_ns(MS);
        let ceiling = 0.25 * usable;
        w.set_torque_ceiling_nm(ceiling).unwrap();
        assert!(
            fake.motor_torque_nm() <= ceiling + 1e-12,
            "{usb_id:04x?}: {} N·m at the motor over the new {ceiling} N·m ceiling",
            fake.motor_torque_nm()
        );
        // The command within the new ceiling still follows on the rate policy's schedule.
        w.command_torque(0.1 * usable).unwrap();
        assert!(fake.motor_torque_nm() <= ceiling + 1e-12);
        mock.advance_ns(w.min_update_interval_ns());
        w.command_torque(0.1 * usable).unwrap();
        let p = w.profile();
        let own = level_for(
            0.1 * usable,
            usable,
            p.max_torque_nm,
            w.gain(),
            p.torque_sign,
        );
        assert_eq!(
            w.sent_level(),
            own,
            "{usb_id:04x?}: the command's level one interval on"
        );
        // Raising the ceiling sends nothing by itself; a non-finite one sends zero.
        let writes = fake.effect_writes();
        w.set_torque_ceiling_nm(usable).unwrap();
        assert_eq!(fake.effect_writes(), writes);
        assert!(w.set_torque_ceiling_nm(f64::NAN).is_err());
        assert_eq!(w.sent_level(), 0);
    }
}

#[test]
fn a_hung_host_stops_the_motor_within_one_effect_length() {
    let cfg = WheelConfig {
        effect_length_ms: 50,
        ..Default::default()
    };
    let (mut w, fake, mock) = wheel_with(SIDEWINDER_ID, 1.87, cfg);
    for _ in 0..100 {
        mock.advance_ns(MS);
        w.command_torque(1.0).unwrap();
    }
    assert!(fake.motor_torque_nm() > 0.9);
    // The loop stops calling: within one effect length the motor is free.
    mock.advance_ns(50 * MS);
    assert_eq!(fake.motor_torque_nm(), 0.0);
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

/// Drive `w` as the haptic loop does, one tick per ms for `ticks` ticks, with `torque_nm(k)`.
fn drive_at_1_khz(
    w: &mut EvdevWheel<FakeFfDevice>,
    mock: &MockClock,
    ticks: u64,
    torque_nm: impl Fn(u64) -> f64,
) {
    for k in 0..ticks {
        mock.advance_ns(MS);
        w.set_torque_ceiling_nm(w.max_torque_nm()).unwrap();
        w.command_torque(torque_nm(k)).unwrap();
    }
}

#[test]
fn the_updates_written_reach_each_driver_familys_rate_and_gap_from_a_1_khz_loop() {
    let mut families_seen = Vec::new();
    for p in DeviceProfile::builtin() {
        let (Some(vendor), Some(&product)) = (p.usb_vendor, p.usb_products.first()) else {
            continue;
        };
        if families_seen.contains(&p.driver) {
            continue;
        }
        families_seen.push(p.driver);
        let (mut w, fake, mock) =
            wheel_with((vendor, product), p.max_torque_nm, Default::default());
        let before = (w.motor_updates().unwrap().count, fake.effect_updates());
        let ticks = 2_000;
        // A second of varying torque that never reaches zero, then a second held at zero.
        let usable = w.max_torque_nm();
        drive_at_1_khz(&mut w, &mock, ticks, |k| {
            if k < ticks / 2 {
                usable * (0.4 + 0.3 * (k as f64 * 0.01).sin())
            } else {
                0.0
            }
        });
        let updates = w.motor_updates().unwrap();
        let counted = updates.count - before.0;
        assert_eq!(
            counted,
            fake.effect_updates() - before.1,
            "{}: the count is the device's own",
            p.name
        );
        let rate_hz = counted as f64 / (ticks as f64 * 1e-3);
        let policy_hz = p.driver.max_update_rate_hz();
        // One extra update where the torque drops to zero (never throttled).
        assert!(
            (rate_hz - policy_hz).abs() <= 1.0,
            "{} ({:?}): {rate_hz} updates/s, policy {policy_hz}",
            p.name,
            p.driver
        );
        let period_ms = 1e3 / policy_hz;
        assert!(
            (updates.worst_gap_ms() - period_ms).abs() < 1e-9,
            "{}: worst gap {} ms, policy period {period_ms} ms",
            p.name,
            updates.worst_gap_ms()
        );
    }
    for family in [
        DriverFamily::HidPidff,
        DriverFamily::Lg4ff,
        DriverFamily::Hidpp,
        DriverFamily::Tmff2,
        DriverFamily::Fanatec,
    ] {
        assert!(
            families_seen.contains(&family),
            "no built-in {family:?} wheel"
        );
    }
}

#[test]
fn an_unplug_is_not_counted_as_a_gap_between_updates() {
    let (mut w, fake, mock) = wheel_with(SIDEWINDER_ID, 1.87, WheelConfig::default());
    drive_at_1_khz(&mut w, &mock, 10, |_| 0.5);
    fake.set_unplugged(true);
    mock.advance_ns(500 * MS);
    assert!(w.command_torque(0.5).is_err());
    let updates = w.motor_updates().unwrap();
    assert_eq!(updates.count, 10);
    assert_eq!(updates.worst_gap_ns, MS);
    assert_eq!(updates.last_ns, None, "the next update starts a new run");
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
