//! The strength test on every wheel: its spring, ramped up to the ceiling against a rim held
//! off centre, stays within the ceiling in N·m at the motor of every built-in wheel profile
//! and of an unknown wheel (capped at 1 N·m), as every other exercise does.
#![cfg(target_os = "linux")]

use clock::Clock;
use haptic_wheel::DeviceProfile;
use record::TickRecord;
use regimen::Regimen;
use session::Controls;
use session::config::StationConfig;
use session::course;
use session::haptic::{self, Pacing};
use session::plant::{Body, Plant};
use wheel_devices::evdev_wheel::EvdevWheel;
use wheel_devices::evdev_wheel::fake::FakeFfDevice;

/// A fast strength test: the limit rises at 5 N·m/s, each side at most 3 s.
const STRENGTH: &str = "[[exercise]]\nkind = \"strength\"\nramp_nm_per_s = 5.0\nside_s = 3.0\n";

/// A strength session on wheel `usb_id` with a `motor_nm` motor, its rim held off centre to
/// one side: the largest torque at the motor, the ceiling in force, and the test's results.
fn strength_on(usb_id: (u16, u16), motor_nm: f64) -> (f64, f64, exercises::StrengthSummary) {
    // A rim held still sends no events: allow the longest silence, and run the left side
    // (3 s) within it.
    let mut cfg = StationConfig::default();
    cfg.wheel.max_silence_ms = 5000;
    let regimen = Regimen::from_toml(STRENGTH, "test").unwrap();
    let (clock, _mock) = Clock::mock();
    let dev = FakeFfDevice::wheel("fake wheel", usb_id, motor_nm, clock.clone());
    let fake = dev.handle();
    let wheel = EvdevWheel::with_device(dev, "fake", cfg.wheel.clone(), clock.clone()).unwrap();
    let body = Body::real_wheel(Box::new(wheel), None, clock.clone());
    let course = course::build(&cfg, Some(&regimen)).unwrap();
    let mut plant = Plant::new(&cfg, body, course).unwrap();
    // Held off centre, as a patient pushing harder than the wheel may push back.
    fake.set_moves_under_torque(false);
    fake.set_value(45_000);
    // Room for every tick and the fade-out: nothing dropped.
    let (mut producer, mut consumer) = rtrb::RingBuffer::<TickRecord>::new(20_000);
    let ticks = (4.5 * cfg.session.loop_rate_hz) as u64;
    let outcome = haptic::run(
        &mut plant,
        &mut producer,
        ticks,
        Pacing::RealTime,
        false,
        &Controls::default(),
        &clock,
    );
    let mut ceiling_nm: f64 = f64::INFINITY;
    while let Ok(r) = consumer.pop() {
        ceiling_nm = ceiling_nm.min(r.wheel.ceiling_nm);
    }
    let peak_nm = fake.peak_motor_torque_nm();
    assert_eq!(outcome.wheel_fault, None, "{usb_id:?}");
    assert!(
        outcome.ticks >= ticks,
        "{usb_id:?}: {} ticks",
        outcome.ticks
    );
    let summary = outcome.exercise_scores.first().and_then(|s| s.strength);
    (peak_nm, ceiling_nm, summary.expect("a strength test"))
}

#[test]
fn the_strength_spring_stays_within_the_ceiling_at_the_motor_of_every_wheel_and_an_unknown_one() {
    let mut wheels: Vec<(String, (u16, u16), f64)> = DeviceProfile::builtin()
        .into_iter()
        .filter_map(|p| {
            Some((
                p.name.clone(),
                (p.usb_vendor?, *p.usb_products.first()?),
                p.max_torque_nm,
            ))
        })
        .collect();
    // A 25 N·m direct drive the station has no profile for: 1 N·m at most.
    wheels.push(("unknown direct drive".into(), (0x1d50, 0x6015), 25.0));
    assert!(wheels.len() > 3);
    for (name, usb_id, motor_nm) in wheels {
        let (peak_nm, ceiling_nm, summary) = strength_on(usb_id, motor_nm);
        let usable = DeviceProfile::for_usb_id(usb_id.0, usb_id.1).usable_max_nm();
        assert!(
            ceiling_nm <= usable + 1e-9,
            "{name}: ceiling {ceiling_nm} of {usable}"
        );
        assert!(
            peak_nm <= ceiling_nm + 1e-9,
            "{name}: {peak_nm} N·m at the motor over {ceiling_nm}"
        );
        // The left side's spring, measured, within the ceiling too.
        let left = summary
            .left
            .unwrap_or_else(|| panic!("{name}: {summary:?}"));
        assert!(left.peak_nm <= ceiling_nm, "{name}: {left:?}");
        assert!(peak_nm > 0.0, "{name}: the spring pushed");
        if name.starts_with("unknown") {
            assert!(peak_nm <= 1.0 + 1e-9, "{name}: {peak_nm}");
        }
    }
}
