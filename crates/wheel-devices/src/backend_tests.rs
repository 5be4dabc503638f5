//! The same safety tests for every real wheel backend, each on its in-memory device: the
//! evdev backend on [`FakeFfDevice`](crate::evdev_wheel::fake::FakeFfDevice) (Linux) and the
//! DirectInput backend on [`FakeDiDevice`](crate::dinput_wheel::fake::FakeDiDevice) (every
//! system). Every assertion is in N·m at the fake's motor. [`Backend`] is what a test needs of
//! a backend and its fake; [`for_each_backend!`] runs a generic test once per backend.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use clock::{Clock, MockClock};
use proptest::prelude::*;

use haptic_wheel::profile::{ASSUMED_UNKNOWN_MOTOR_NM, DeviceProfile, DriverFamily, TorqueSource};
use haptic_wheel::safety::{SafetyConfig, Supervisor};
use haptic_wheel::wheel::{Wheel, WheelError, WheelFault};
use haptic_wheel::wheel_config::{CeilingReport, WheelConfig};

const MS: u64 = 1_000_000;
/// An id no built-in profile claims.
const UNKNOWN_ID: (u16, u16) = (0x1d50, 0x6015);
/// The thesis SideWinder's id (a built-in profile, 1.87 N·m, hid-pidff at 1 kHz).
const SIDEWINDER_ID: (u16, u16) = (0x045e, 0x0034);
/// A Logitech G29's id: another model, another profile.
const G29_ID: (u16, u16) = (0x046d, 0xc24f);

/// The test's hand on a backend's in-memory motor.
pub(crate) trait Motor {
    /// Torque the motor produces now, N·m (magnitude).
    fn torque_nm(&self) -> f64;
    /// The largest torque the motor produced at any write so far, N·m.
    fn peak_nm(&self) -> f64;
    /// Torque updates the device received.
    fn updates(&self) -> u64;
    /// Unplug the device (or plug this same object back in).
    fn set_unplugged(&self, unplugged: bool);
}

/// A wheel backend over its in-memory device, as the shared tests drive it.
pub(crate) trait Backend {
    /// The backend on its fake device.
    type W: Wheel;
    /// The test's hand on the fake.
    type M: Motor;
    /// Where a rejoining wheel looks for devices (a test plugs new ones in).
    type Bus;
    /// The device's full scale of a torque level (±32 767 on evdev, ±10 000 in DirectInput).
    const FULL_SCALE: f64;

    /// A wheel of model `usb_id` whose motor gives `motor_nm` at full scale, opened with
    /// `config` on a mock clock.
    fn open(
        name: &str,
        usb_id: (u16, u16),
        motor_nm: f64,
        config: WheelConfig,
        clock: Clock,
    ) -> Result<(Self::W, Self::M), WheelError>;
    /// A thesis SideWinder opened with `config`, looked for again on the bus every 5 ms once
    /// lost.
    fn open_rejoining(config: WheelConfig) -> (Self::W, Self::M, MockClock, Self::Bus, Clock);
    /// Plug a new device of model `usb_id` into `bus`.
    fn plug(
        bus: &Self::Bus,
        name: &str,
        usb_id: (u16, u16),
        motor_nm: f64,
        clock: &Clock,
    ) -> Self::M;
    /// Whether every device plugged into `bus` has been looked at.
    fn bus_empty(bus: &Self::Bus) -> bool;
    /// The level last sent, in device units.
    fn sent_level(w: &Self::W) -> i32;
    /// The level the backend sends for `torque_nm` on `w`.
    fn level_for(w: &Self::W, torque_nm: f64) -> i32;
    /// The gain the device runs at, fraction.
    fn gain(w: &Self::W) -> f64;
    /// The rate policy's minimum interval, ns.
    fn min_update_interval_ns(w: &Self::W) -> u64;
}

/// Runs each generic test `name::<B>()` once per backend, as `<backend>::name`.
macro_rules! for_each_backend {
    ($($name:ident),* $(,)?) => {
        #[cfg(all(target_os = "linux", feature = "evdev"))]
        mod evdev {
            $(#[test] fn $name() { super::$name::<super::evdev_rig::Evdev>() })*
        }
        #[cfg(feature = "dinput")]
        mod dinput {
            $(#[test] fn $name() { super::$name::<super::dinput_rig::Dinput>() })*
        }
    };
}

for_each_backend!(
    an_unknown_direct_drive_wheel_gives_at_most_one_newton_metre_whatever_is_commanded,
    a_clinician_entered_rating_lifts_the_cap_and_torque_is_true_in_newton_metres,
    the_device_gain_is_part_of_the_mapping,
    an_unplugged_wheel_reports_it_on_every_call,
    a_lowered_ceiling_holds_at_the_motor_at_once_even_between_throttled_updates,
    a_hung_host_stops_the_motor_within_one_effect_length,
    a_non_finite_command_is_refused_with_zero_sent_and_drop_leaves_no_torque,
    the_updates_written_reach_each_driver_familys_rate_and_gap_from_a_1_khz_loop,
    an_unplug_is_not_counted_as_a_gap_between_updates,
    an_unplugged_wheel_plugged_back_in_is_re_opened_and_driven_from_zero_torque,
    another_wheel_model_plugged_in_is_not_taken_for_the_wheel,
    the_motor_never_exceeds_the_ceiling_on_any_profile,
);

fn open<B: Backend>(
    usb_id: (u16, u16),
    motor_nm: f64,
    config: WheelConfig,
) -> (B::W, B::M, MockClock) {
    let (clock, mock) = Clock::mock();
    let (w, m) = B::open("test wheel", usb_id, motor_nm, config, clock).unwrap();
    (w, m, mock)
}

fn an_unknown_direct_drive_wheel_gives_at_most_one_newton_metre_whatever_is_commanded<
    B: Backend,
>() {
    // The defect of issue 12: a 25 N·m motor, no profile.
    let (mut w, fake, mock) = open::<B>(UNKNOWN_ID, 25.0, WheelConfig::default());
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
            fake.torque_nm() <= 1.0,
            "{cmd} N·m commanded gave {} N·m at the motor",
            fake.torque_nm()
        );
    }
    // 1 N·m commanded is 1/32 of full scale: 0.78 N·m on this 25 N·m motor.
    mock.advance_ns(MS);
    w.command_torque(1.0).unwrap();
    assert_eq!(
        B::sent_level(&w),
        (B::FULL_SCALE / ASSUMED_UNKNOWN_MOTOR_NM) as i32
    );
    // Within one of the device's levels (25 N·m over its full scale).
    let level_nm = 25.0 / B::FULL_SCALE;
    assert!(
        (fake.torque_nm() - 25.0 / 32.0).abs() <= level_nm,
        "{}",
        fake.torque_nm()
    );
}

fn a_clinician_entered_rating_lifts_the_cap_and_torque_is_true_in_newton_metres<B: Backend>() {
    let cfg = WheelConfig {
        rated_torque_nm: Some(8.0),
        ..Default::default()
    };
    let (mut w, fake, mock) = open::<B>(UNKNOWN_ID, 8.0, cfg);
    assert_eq!(w.max_torque_nm(), 8.0);
    mock.advance_ns(MS);
    w.command_torque(3.0).unwrap();
    assert!(
        (fake.torque_nm() - 3.0).abs() < 1e-3,
        "{}",
        fake.torque_nm()
    );
}

fn the_device_gain_is_part_of_the_mapping<B: Backend>() {
    let cfg = WheelConfig {
        rated_torque_nm: Some(10.0),
        gain: 0.5,
        ..Default::default()
    };
    let (mut w, fake, mock) = open::<B>(UNKNOWN_ID, 10.0, cfg);
    assert!((B::gain(&w) - 0.5).abs() < 1e-4);
    assert!(
        (w.max_torque_nm() - 5.0).abs() < 1e-3,
        "half the gain, half the usable torque"
    );
    mock.advance_ns(MS);
    w.command_torque(2.0).unwrap();
    assert!(
        (fake.torque_nm() - 2.0).abs() < 1e-3,
        "{}",
        fake.torque_nm()
    );
    mock.advance_ns(MS);
    w.command_torque(9.0).unwrap();
    assert!(fake.torque_nm() <= w.max_torque_nm() + 1e-9);
}

fn an_unplugged_wheel_reports_it_on_every_call<B: Backend>() {
    let (mut w, fake, mock) = open::<B>(SIDEWINDER_ID, 1.87, WheelConfig::default());
    w.read().unwrap();
    w.command_torque(0.5).unwrap();
    fake.set_unplugged(true);
    mock.advance_ns(MS);
    assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
    // Replugged at the OS level is a new device: this handle stays lost.
    fake.set_unplugged(false);
    for _ in 0..3 {
        mock.advance_ns(MS);
        let err = w.command_torque(0.5).unwrap_err();
        assert_eq!(err.fault(), Some(WheelFault::Unplugged), "{err}");
        assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
    }
}

fn a_lowered_ceiling_holds_at_the_motor_at_once_even_between_throttled_updates<B: Backend>() {
    // A Thrustmaster base (one update per 8 ms) and an unknown wheel.
    for usb_id in [(0x044f, 0xb66e), UNKNOWN_ID] {
        let motor_nm = DeviceProfile::for_usb_id(usb_id.0, usb_id.1).max_torque_nm;
        let (mut w, fake, mock) = open::<B>(usb_id, motor_nm, WheelConfig::default());
        let usable = w.max_torque_nm();
        w.set_torque_ceiling_nm(usable).unwrap();
        w.command_torque(usable).unwrap();
        let held_nm = fake.torque_nm();
        assert!(held_nm > 0.5 * usable.min(motor_nm), "{held_nm} N·m held");
        mock.advance_ns(MS);
        let ceiling = 0.25 * usable;
        w.set_torque_ceiling_nm(ceiling).unwrap();
        assert!(
            fake.torque_nm() <= ceiling + 1e-12,
            "{usb_id:04x?}: {} N·m at the motor over the new {ceiling} N·m ceiling",
            fake.torque_nm()
        );
        // The command within the new ceiling still follows on the rate policy's schedule.
        w.command_torque(0.1 * usable).unwrap();
        assert!(fake.torque_nm() <= ceiling + 1e-12);
        mock.advance_ns(B::min_update_interval_ns(&w));
        w.command_torque(0.1 * usable).unwrap();
        assert_eq!(
            B::sent_level(&w),
            B::level_for(&w, 0.1 * usable),
            "{usb_id:04x?}: the command's level one interval on"
        );
        // Raising the ceiling sends nothing by itself; a non-finite one sends zero.
        let updates = fake.updates();
        w.set_torque_ceiling_nm(usable).unwrap();
        assert_eq!(fake.updates(), updates);
        assert!(w.set_torque_ceiling_nm(f64::NAN).is_err());
        assert_eq!(B::sent_level(&w), 0);
        assert_eq!(fake.torque_nm(), 0.0);
    }
}

fn a_hung_host_stops_the_motor_within_one_effect_length<B: Backend>() {
    let cfg = WheelConfig {
        effect_length_ms: 50,
        ..Default::default()
    };
    let (mut w, fake, mock) = open::<B>(SIDEWINDER_ID, 1.87, cfg);
    for _ in 0..100 {
        mock.advance_ns(MS);
        w.command_torque(1.0).unwrap();
    }
    assert!(fake.torque_nm() > 0.9, "{}", fake.torque_nm());
    // The loop stops calling: within one effect length the motor is free.
    mock.advance_ns(50 * MS);
    assert_eq!(fake.torque_nm(), 0.0);
}

fn a_non_finite_command_is_refused_with_zero_sent_and_drop_leaves_no_torque<B: Backend>() {
    let (mut w, fake, mock) = open::<B>(SIDEWINDER_ID, 1.87, WheelConfig::default());
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        mock.advance_ns(MS);
        w.command_torque(1.0).unwrap();
        assert!(fake.torque_nm() > 0.9);
        mock.advance_ns(MS);
        let err = w.command_torque(bad).unwrap_err();
        assert!(matches!(err, WheelError::NonFiniteTorque(_)), "{err}");
        assert_eq!(fake.torque_nm(), 0.0, "zero sent for {bad}");
    }
    mock.advance_ns(MS);
    w.command_torque(1.0).unwrap();
    drop(w);
    assert_eq!(
        fake.torque_nm(),
        0.0,
        "nothing pushes after the backend is gone"
    );
}

/// Drive `w` as the haptic loop does, one tick per ms for `ticks` ticks, with `torque_nm(k)`.
fn drive_at_1_khz<W: Wheel>(
    w: &mut W,
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

fn the_updates_written_reach_each_driver_familys_rate_and_gap_from_a_1_khz_loop<B: Backend>() {
    let mut families_seen = Vec::new();
    for p in DeviceProfile::builtin() {
        let (Some(vendor), Some(&product)) = (p.usb_vendor, p.usb_products.first()) else {
            continue;
        };
        if families_seen.contains(&p.driver) {
            continue;
        }
        families_seen.push(p.driver);
        let (mut w, fake, mock) = open::<B>((vendor, product), p.max_torque_nm, Default::default());
        let before = (w.motor_updates().unwrap().count, fake.updates());
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
            fake.updates() - before.1,
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

fn an_unplug_is_not_counted_as_a_gap_between_updates<B: Backend>() {
    let (mut w, fake, mock) = open::<B>(SIDEWINDER_ID, 1.87, WheelConfig::default());
    drive_at_1_khz(&mut w, &mock, 10, |_| 0.5);
    fake.set_unplugged(true);
    mock.advance_ns(500 * MS);
    assert!(w.command_torque(0.5).is_err());
    let updates = w.motor_updates().unwrap();
    assert_eq!(updates.count, 10);
    assert_eq!(updates.worst_gap_ns, MS);
    assert_eq!(updates.last_ns, None, "the next update starts a new run");
}

/// Read `w` once a millisecond (of the mock clock and of real time, for a backend that looks
/// on a helper thread) until it answers, or 5 s of real time; every torque command meanwhile
/// fails as unplugged.
fn read_until_back<W: Wheel>(w: &mut W, mock: &MockClock) -> bool {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(5) {
        mock.advance_ns(MS);
        if w.read().is_ok() {
            return true;
        }
        assert_eq!(
            w.command_torque(1.0).unwrap_err().fault(),
            Some(WheelFault::Unplugged)
        );
        std::thread::sleep(Duration::from_millis(1));
    }
    false
}

fn an_unplugged_wheel_plugged_back_in_is_re_opened_and_driven_from_zero_torque<B: Backend>() {
    let config = WheelConfig {
        effect_length_ms: 50,
        ..Default::default()
    };
    let (mut w, old, mock, bus, clock) = B::open_rejoining(config);
    for _ in 0..10 {
        mock.advance_ns(MS);
        w.read().unwrap();
        w.command_torque(1.0).unwrap();
    }
    assert!(old.torque_nm() > 0.9);
    // Unplugged: it says so on every call, and nothing is found while nothing is plugged in.
    old.set_unplugged(true);
    mock.advance_ns(MS);
    assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
    for _ in 0..20 {
        mock.advance_ns(MS);
        assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
        std::thread::sleep(Duration::from_millis(1));
    }
    // The motor stops within one effect length.
    mock.advance_ns(50 * MS);
    assert_eq!(old.torque_nm(), 0.0, "the old device's motor while away");
    // Plugged back in as a new device: taken back on a read, with no torque.
    let new = B::plug(&bus, "SideWinder", SIDEWINDER_ID, 1.87, &clock);
    assert!(read_until_back(&mut w, &mock), "the wheel came back");
    assert_eq!(new.torque_nm(), 0.0);
    // The first torque after re-open is zero whatever is asked, until zero is asked.
    mock.advance_ns(MS);
    w.command_torque(1.0).unwrap();
    assert_eq!(B::sent_level(&w), 0);
    assert_eq!(new.torque_nm(), 0.0);
    mock.advance_ns(MS);
    w.command_torque(0.0).unwrap();
    mock.advance_ns(MS);
    w.command_torque(1.0).unwrap();
    assert!(B::sent_level(&w) > 0);
    assert!((new.torque_nm() - 1.0).abs() < 1e-3, "{}", new.torque_nm());
    assert!(w.read().is_ok());
}

fn another_wheel_model_plugged_in_is_not_taken_for_the_wheel<B: Backend>() {
    let (mut w, old, mock, bus, clock) = B::open_rejoining(WheelConfig::default());
    old.set_unplugged(true);
    mock.advance_ns(MS);
    assert!(w.read().is_err());
    // A G29: another profile, another torque scale.
    let g29 = B::plug(&bus, "G29", G29_ID, 2.2, &clock);
    let start = Instant::now();
    while !B::bus_empty(&bus) {
        assert!(start.elapsed() < Duration::from_secs(5), "never looked at");
        mock.advance_ns(MS);
        let _ = w.read();
        std::thread::sleep(Duration::from_millis(1));
    }
    for _ in 0..10 {
        mock.advance_ns(MS);
        assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
    }
    assert_eq!(g29.updates(), 0, "never driven");
    assert_eq!(g29.peak_nm(), 0.0);
    // The session's own model is taken.
    let same = B::plug(&bus, "SideWinder", SIDEWINDER_ID, 1.87, &clock);
    assert!(read_until_back(&mut w, &mock));
    mock.advance_ns(MS);
    w.command_torque(0.0).unwrap();
    mock.advance_ns(MS);
    w.command_torque(0.5).unwrap();
    assert!(
        (same.torque_nm() - 0.5).abs() < 1e-3,
        "{}",
        same.torque_nm()
    );
}

/// Every built-in profile, an unknown wheel on each driver and a clinician-rated one.
pub(crate) fn any_profile() -> impl Strategy<Value = DeviceProfile> {
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

/// DESIGN.md safety invariant 1 in N·m at the motor: on every built-in profile, an unknown
/// wheel of any plausible motor and a clinician-rated one, at any gain and for any patient
/// ceiling and command sequence (NaN and infinities included), the torque the motor produces
/// never exceeds the ceiling in force.
fn the_motor_never_exceeds_the_ceiling_on_any_profile<B: Backend>() {
    let requests = proptest::collection::vec(
        prop_oneof![
            -100.0f64..100.0,
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(f64::NEG_INFINITY),
            Just(f64::MAX)
        ],
        1..120,
    );
    let cases = (
        any_profile(),
        0.05f64..=1.0,
        0.05f64..=1.0,
        proptest::option::of(0.0f64..50.0),
        requests,
    );
    let mut runner = proptest::test_runner::TestRunner::new_with_rng(
        ProptestConfig::with_cases(96),
        proptest::test_runner::TestRng::deterministic_rng(
            proptest::test_runner::RngAlgorithm::ChaCha,
        ),
    );
    runner
        .run(
            &cases,
            |(profile, motor_share, gain, patient_ceiling, requests)| {
                // The real motor is at most what the profile states.
                let motor_nm = profile.max_torque_nm * motor_share;
                let cfg = WheelConfig {
                    profile: Some(profile.clone()),
                    gain,
                    ..Default::default()
                };
                let (mut w, fake, mock) = open::<B>(UNKNOWN_ID, motor_nm, cfg);
                let report = CeilingReport::new(&profile, gain, patient_ceiling);
                let patient = patient_ceiling.map(|c| c.min(w.max_torque_nm()));
                let mut sup = Supervisor::new(
                    SafetyConfig {
                        ceiling_nm: patient,
                        soft_start_s: 0.01,
                        ..Default::default()
                    },
                    w.max_torque_nm(),
                )
                .unwrap();
                // The report states the ceiling at a 16-bit gain; a device's own gain steps may differ
                // by less than one of its torque levels.
                prop_assert!(
                    (sup.ceiling_nm() - report.ceiling_nm).abs()
                        <= profile.max_torque_nm / B::FULL_SCALE + 1e-9
                );
                for r in requests {
                    mock.advance_ns(MS);
                    let now = mock.now_ns();
                    let out = sup.apply(r, now, Some(now));
                    let _ = w.command_torque(out.torque_nm);
                    prop_assert!(
                        fake.torque_nm() <= sup.ceiling_nm() + 1e-9,
                        "{} N·m at the motor over a {} N·m ceiling",
                        fake.torque_nm(),
                        sup.ceiling_nm()
                    );
                    // Commanded straight to the backend, without the chain: still never above the
                    // usable maximum.
                    let _ = w.command_torque(r);
                    prop_assert!(fake.torque_nm() <= w.max_torque_nm() + 1e-9);
                    prop_assert!(fake.torque_nm() <= profile.usable_max_nm() + 1e-9);
                }
                prop_assert!(fake.peak_nm() <= w.max_torque_nm() + 1e-9);
                Ok(())
            },
        )
        .unwrap();
}

/// Plugged-in devices a rejoining wheel's finder takes, each taken by the first look.
type Plugged<D> = Arc<Mutex<Vec<D>>>;

#[cfg(all(target_os = "linux", feature = "evdev"))]
pub(crate) mod evdev_rig {
    use super::*;
    use crate::evdev_wheel::fake::{FakeFfDevice, FakeHandle};
    use crate::evdev_wheel::{EvdevWheel, level_for};

    /// The evdev backend on its in-memory kernel device.
    pub(crate) struct Evdev;

    impl Motor for FakeHandle {
        fn torque_nm(&self) -> f64 {
            self.motor_torque_nm()
        }
        fn peak_nm(&self) -> f64 {
            self.peak_motor_torque_nm()
        }
        fn updates(&self) -> u64 {
            self.effect_updates()
        }
        fn set_unplugged(&self, unplugged: bool) {
            FakeHandle::set_unplugged(self, unplugged);
        }
    }

    impl Backend for Evdev {
        type W = EvdevWheel<FakeFfDevice>;
        type M = FakeHandle;
        type Bus = Plugged<(String, FakeFfDevice)>;
        const FULL_SCALE: f64 = crate::evdev_wheel::LEVEL_FULL_SCALE;

        fn open(
            name: &str,
            usb_id: (u16, u16),
            motor_nm: f64,
            config: WheelConfig,
            clock: Clock,
        ) -> Result<(Self::W, Self::M), WheelError> {
            let dev = FakeFfDevice::wheel(name, usb_id, motor_nm, clock.clone());
            let handle = dev.handle();
            let w = EvdevWheel::with_device(dev, "/dev/input/event99", config, clock)?;
            Ok((w, handle))
        }

        fn open_rejoining(config: WheelConfig) -> (Self::W, Self::M, MockClock, Self::Bus, Clock) {
            let (clock, mock) = Clock::mock();
            let (w, m) =
                Self::open("SideWinder", SIDEWINDER_ID, 1.87, config, clock.clone()).unwrap();
            let bus: Self::Bus = Arc::default();
            let finder = {
                let bus = bus.clone();
                move || std::mem::take(&mut *bus.lock().unwrap())
            };
            let w = w.reopen_with(finder, Duration::from_millis(5)).unwrap();
            (w, m, mock, bus, clock)
        }

        fn plug(
            bus: &Self::Bus,
            name: &str,
            usb_id: (u16, u16),
            motor_nm: f64,
            clock: &Clock,
        ) -> Self::M {
            let dev = FakeFfDevice::wheel(name, usb_id, motor_nm, clock.clone());
            let handle = dev.handle();
            bus.lock().unwrap().push(("/dev/input/event9".into(), dev));
            handle
        }

        fn bus_empty(bus: &Self::Bus) -> bool {
            bus.lock().unwrap().is_empty()
        }

        fn sent_level(w: &Self::W) -> i32 {
            i32::from(w.sent_level())
        }

        fn level_for(w: &Self::W, torque_nm: f64) -> i32 {
            let p = w.profile();
            i32::from(level_for(
                torque_nm,
                w.max_torque_nm(),
                p.max_torque_nm,
                w.gain(),
                p.torque_sign,
            ))
        }

        fn gain(w: &Self::W) -> f64 {
            w.gain()
        }

        fn min_update_interval_ns(w: &Self::W) -> u64 {
            w.min_update_interval_ns()
        }
    }
}

#[cfg(feature = "dinput")]
pub(crate) mod dinput_rig {
    use super::*;
    use crate::dinput_wheel::fake::{FakeDiDevice, FakeDiHandle};
    use crate::dinput_wheel::{DinputWheel, MAGNITUDE_FULL_SCALE, magnitude_for};

    /// The DirectInput backend on its in-memory device.
    pub(crate) struct Dinput;

    impl Motor for FakeDiHandle {
        fn torque_nm(&self) -> f64 {
            self.motor_torque_nm()
        }
        fn peak_nm(&self) -> f64 {
            self.peak_motor_torque_nm()
        }
        fn updates(&self) -> u64 {
            FakeDiHandle::updates(self)
        }
        fn set_unplugged(&self, unplugged: bool) {
            FakeDiHandle::set_unplugged(self, unplugged);
        }
    }

    impl Backend for Dinput {
        type W = DinputWheel<FakeDiDevice>;
        type M = FakeDiHandle;
        type Bus = Plugged<FakeDiDevice>;
        const FULL_SCALE: f64 = MAGNITUDE_FULL_SCALE;

        fn open(
            name: &str,
            usb_id: (u16, u16),
            motor_nm: f64,
            config: WheelConfig,
            clock: Clock,
        ) -> Result<(Self::W, Self::M), WheelError> {
            let dev = FakeDiDevice::wheel(name, usb_id, 0, motor_nm, clock.clone());
            let handle = dev.handle();
            Ok((DinputWheel::with_device(dev, config, clock)?, handle))
        }

        fn open_rejoining(config: WheelConfig) -> (Self::W, Self::M, MockClock, Self::Bus, Clock) {
            let (clock, mock) = Clock::mock();
            let (w, m) =
                Self::open("SideWinder", SIDEWINDER_ID, 1.87, config, clock.clone()).unwrap();
            let bus: Self::Bus = Arc::default();
            let finder = {
                let bus = bus.clone();
                move || std::mem::take(&mut *bus.lock().unwrap())
            };
            (
                w.reopen_with(finder, Duration::from_millis(5)),
                m,
                mock,
                bus,
                clock,
            )
        }

        fn plug(
            bus: &Self::Bus,
            name: &str,
            usb_id: (u16, u16),
            motor_nm: f64,
            clock: &Clock,
        ) -> Self::M {
            let dev = FakeDiDevice::wheel(name, usb_id, 1, motor_nm, clock.clone());
            let handle = dev.handle();
            bus.lock().unwrap().push(dev);
            handle
        }

        fn bus_empty(bus: &Self::Bus) -> bool {
            bus.lock().unwrap().is_empty()
        }

        fn sent_level(w: &Self::W) -> i32 {
            w.sent_magnitude()
        }

        fn level_for(w: &Self::W, torque_nm: f64) -> i32 {
            let p = w.profile();
            magnitude_for(
                torque_nm,
                w.max_torque_nm(),
                p.max_torque_nm,
                w.gain(),
                p.torque_sign,
            )
        }

        fn gain(w: &Self::W) -> f64 {
            w.gain()
        }

        fn min_update_interval_ns(w: &Self::W) -> u64 {
            w.min_update_interval_ns()
        }
    }
}
