//! The DirectInput backend against its in-memory device, what is its own: the magnitude
//! mapping, the set-up at open and exit, readings and buttons, DirectInput's loss codes,
//! refused updates, and which device a lost wheel is taken back from. The safety tests every
//! backend passes are in `crate::backend_tests`.

use super::fake::{FakeDiDevice, FakeDiHandle};
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
) -> (DinputWheel<FakeDiDevice>, FakeDiHandle, MockClock) {
    let (clock, mock) = Clock::mock();
    let dev = FakeDiDevice::wheel("test wheel", usb_id, 0, motor_nm, clock.clone());
    let handle = dev.handle();
    (
        DinputWheel::with_device(dev, config, clock).unwrap(),
        handle,
        mock,
    )
}

#[test]
fn magnitude_mapping_is_thesis_eq_3_3_truncated_towards_zero_and_rejects_nonsense() {
    // The thesis wheel: Kt = 1.873e-4 N·m per unit, 1.87 N·m at 10 000 units.
    assert_eq!(magnitude_for(1.0, 1.87, 1.87, 1.0, 1.0), 5_347);
    assert_eq!(magnitude_for(-1.0, 2.0, 2.0, 1.0, 1.0), -5_000);
    assert_eq!(magnitude_for(1.0, 2.0, 2.0, 1.0, -1.0), -5_000);
    assert_eq!(magnitude_for(50.0, 2.0, 2.0, 1.0, 1.0), DI_FFNOMINALMAX);
    assert_eq!(magnitude_for(f64::NAN, 2.0, 2.0, 1.0, 1.0), 0);
    assert_eq!(magnitude_for(1.0, 2.0, 0.0, 1.0, 1.0), 0);
    assert_eq!(magnitude_for(1.0, 2.0, 2.0, 0.0, 1.0), 0);
    assert_eq!(gain_units(0.5), 5_000);
    assert_eq!(gain_units(2.0), 10_000);
}

#[test]
fn opening_acquires_turns_autocentre_off_sets_the_gain_and_exit_restores_them() {
    let cfg = WheelConfig {
        gain: 0.8,
        ..Default::default()
    };
    let (w, fake, _mock) = wheel_with(SIDEWINDER_ID, 1.87, cfg);
    assert!(fake.acquired());
    assert!(
        !fake.autocenter(),
        "autocentre would fight the haptic models"
    );
    assert_eq!(fake.gain(), 8_000);
    assert!(fake.has_effect());
    assert_eq!(fake.motor_torque_nm(), 0.0, "created at zero, not started");
    drop(w);
    assert!(!fake.acquired());
    assert_eq!(fake.gain(), 10_000);
    assert!(!fake.autocenter(), "the configured exit value is 0: off");
    let cfg = WheelConfig {
        autocenter_on_exit: 0.5,
        ..Default::default()
    };
    let (w, fake, _mock) = wheel_with(SIDEWINDER_ID, 1.87, cfg);
    drop(w);
    assert!(
        fake.autocenter(),
        "any exit value turns DirectInput's autocentre on"
    );
}

#[test]
fn a_device_without_constant_force_or_with_an_empty_range_is_refused_by_name() {
    let (clock, _) = Clock::mock();
    let pad = FakeDiDevice::wheel("Rumble Pad", UNKNOWN_ID, 0, 1.0, clock.clone())
        .without_constant_force();
    let err = DinputWheel::with_device(pad, WheelConfig::default(), clock.clone()).unwrap_err();
    assert!(err.to_string().contains("Rumble Pad"), "{err}");
    assert!(err.to_string().contains("constant force"), "{err}");
    let flat = FakeDiDevice::wheel("Flat", UNKNOWN_ID, 0, 1.0, clock.clone()).with_range(5, 5);
    let err = DinputWheel::with_device(flat, WheelConfig::default(), clock).unwrap_err();
    assert!(err.to_string().contains("empty range"), "{err}");
}

#[test]
fn the_angle_comes_from_the_declared_range_and_a_value_outside_it_is_a_fault() {
    let (mut w, fake, _mock) = wheel_with(SIDEWINDER_ID, 1.87, WheelConfig::default());
    let p = w.profile();
    fake.set_x(65_535);
    let a = w.read().unwrap().angle_rad;
    let half = p.angle_sign * p.half_range_rad;
    assert!(
        (a - half).abs() < 1e-4,
        "{a} rad at full lock, {half} expected"
    );
    fake.set_x(70_000);
    assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::OutOfRange));
    fake.set_x(32_767);
    fake.set_buttons(0b101);
    assert!(w.read().unwrap().angle_rad.abs() < 1e-3);
    assert_eq!(w.buttons(), 0b101);
}

#[test]
fn each_directinput_loss_code_is_the_unplugged_fault_and_other_failures_are_refusals() {
    for code in [
        device::DIERR_INPUTLOST,
        device::DIERR_NOTACQUIRED,
        device::DIERR_UNPLUGGED,
    ] {
        assert!(DiError(code).is_device_loss());
        let (mut w, fake, mock) = wheel_with(SIDEWINDER_ID, 1.87, WheelConfig::default());
        fake.set_refusing(Some(code));
        mock.advance_ns(MS);
        let err = w.command_torque(0.5).unwrap_err();
        assert_eq!(err.fault(), Some(WheelFault::Unplugged), "{code:x}: {err}");
        fake.set_refusing(None);
        assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
    }
    // A driver refusing an update while it still reads: a refused command the safety chain
    // counts (CommandsRefused after a while), not an unplug.
    let (mut w, fake, mock) = wheel_with(SIDEWINDER_ID, 1.87, WheelConfig::default());
    fake.set_refusing(Some(device::E_FAIL));
    mock.advance_ns(MS);
    let err = w.command_torque(0.5).unwrap_err();
    assert_eq!(err.fault(), None, "{err}");
    assert!(matches!(err, WheelError::Io { .. }));
    fake.set_refusing(None);
    w.read().unwrap();
    mock.advance_ns(MS);
    w.command_torque(0.5).unwrap();
    assert!((fake.motor_torque_nm() - 0.5).abs() < 1e-3);
    assert!(DiError(device::E_FAIL).to_string().contains("0x80004005"));
    assert!(
        DiError(device::DIERR_UNPLUGGED)
            .to_string()
            .contains("DIERR_UNPLUGGED")
    );
}

#[test]
fn a_lost_wheel_is_known_by_model_and_range_and_its_own_unit_then_name_is_preferred() {
    let (clock, _) = Clock::mock();
    let dev =
        |usb_id, instance| FakeDiDevice::wheel("SideWinder", usb_id, instance, 1.87, clock.clone());
    let lost = dev(SIDEWINDER_ID, 0).identity().clone();
    assert_eq!(lost.likeness(&lost), Ok(Likeness::SameUnit));
    let second = dev(SIDEWINDER_ID, 1).identity().clone();
    assert_eq!(lost.likeness(&second), Ok(Likeness::SameModel));
    let mut renamed = second.clone();
    renamed.instance_name = lost.instance_name.clone();
    assert_eq!(lost.likeness(&renamed), Ok(Likeness::SameName));
    let g29 = dev((0x046d, 0xc24f), 0).identity().clone();
    assert_eq!(lost.likeness(&g29), Err(Refusal::OtherModel));
    let narrow = dev(SIDEWINDER_ID, 0).with_range(0, 1023).identity().clone();
    assert_eq!(lost.likeness(&narrow), Err(Refusal::OtherRange));
    let pad = dev(SIDEWINDER_ID, 0)
        .without_constant_force()
        .identity()
        .clone();
    assert_eq!(lost.likeness(&pad), Err(Refusal::NoConstantForce));

    // Among several: the very unit is taken, whatever the order.
    let (clock, mock) = Clock::mock();
    let first = FakeDiDevice::wheel("SideWinder", SIDEWINDER_ID, 0, 1.87, clock.clone());
    let first_handle = first.handle();
    let mut w = DinputWheel::with_device(first, WheelConfig::default(), clock.clone())
        .unwrap()
        .reopen_with(
            {
                let clock = clock.clone();
                move || {
                    vec![
                        FakeDiDevice::wheel("SideWinder", SIDEWINDER_ID, 2, 1.87, clock.clone()),
                        FakeDiDevice::wheel("SideWinder", SIDEWINDER_ID, 0, 1.87, clock.clone()),
                        FakeDiDevice::wheel("SideWinder", SIDEWINDER_ID, 1, 1.87, clock.clone()),
                    ]
                }
            },
            std::time::Duration::from_millis(5),
        );
    first_handle.set_unplugged(true);
    mock.advance_ns(MS);
    assert!(w.read().is_err());
    mock.advance_ns(5 * MS);
    w.read().unwrap();
    assert_eq!(w.device().identity().instance_guid, lost.instance_guid);
}

#[test]
fn a_lost_wheel_is_looked_for_at_most_once_per_rescan_interval() {
    let (clock, mock) = Clock::mock();
    let looks = std::sync::Arc::new(std::sync::atomic::AtomicU32::new(0));
    let dev = FakeDiDevice::wheel("SideWinder", SIDEWINDER_ID, 0, 1.87, clock.clone());
    let handle = dev.handle();
    let mut w = DinputWheel::with_device(dev, WheelConfig::default(), clock)
        .unwrap()
        .reopen_with(
            {
                let looks = looks.clone();
                move || {
                    looks.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    Vec::<FakeDiDevice>::new()
                }
            },
            REJOIN_RESCAN_EVERY,
        );
    handle.set_unplugged(true);
    // One second of 1 kHz reads while away: one look at the loss, then one per 250 ms.
    for _ in 0..1_000 {
        mock.advance_ns(MS);
        assert!(w.read().is_err());
    }
    assert_eq!(looks.load(std::sync::atomic::Ordering::Relaxed), 4);
}

#[cfg(windows)]
#[test]
fn the_loss_codes_are_the_windows_crates() {
    use windows::Win32::Devices::HumanInterfaceDevice as di;
    assert_eq!(device::DIERR_INPUTLOST, di::DIERR_INPUTLOST.0);
    assert_eq!(device::DIERR_NOTACQUIRED, di::DIERR_NOTACQUIRED.0);
    assert_eq!(device::DIERR_UNPLUGGED, di::DIERR_UNPLUGGED);
    assert_eq!(DI_FFNOMINALMAX as u32, di::DI_FFNOMINALMAX);
}
