//! Calibration helper (CALIBRATION.md §2): hold a constant force of `units` on the ±10 000
//! effect scale for `seconds`, printing the steering axis, then release.
//!
//! `cargo run -p haptic-wheel --example ff_constant -- /dev/input/event7 1000 5`

#[cfg(all(target_os = "linux", feature = "evdev"))]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    use haptic_wheel::WheelConfig;
    use haptic_wheel::{DeviceProfile, Wheel, ZeroTorqueOnDrop, profile::EFFECT_FULL_SCALE_UNITS};
    use std::time::{Duration, Instant};
    use wheel_devices::evdev_wheel::EvdevWheel;

    let args: Vec<String> = std::env::args().collect();
    if args.len() != 4 {
        eprintln!("usage: ff_constant <device> <units -10000..10000> <seconds>");
        std::process::exit(2);
    }
    let units: f64 = args[2].parse()?;
    let seconds: f64 = args[3].parse()?;
    if !(units.abs() <= EFFECT_FULL_SCALE_UNITS && (0.0..=60.0).contains(&seconds)) {
        return Err("units must be within ±10000 and seconds within 0..60".into());
    }
    // A unit-less profile: 1 "N·m" = full scale, so torque = units / 10 000 of full scale.
    // Marked as measured so that the unknown-wheel cap does not apply: this tool exists to
    // measure the torque with hands off and known masses (CALIBRATION.md §2).
    let profile = DeviceProfile {
        torque_sign: 1.0,
        angle_sign: 1.0,
        torque_source: haptic_wheel::profile::TorqueSource::Measured,
        ..DeviceProfile::unknown(haptic_wheel::DriverFamily::HidPidff).with_rated_torque(1.0)
    };
    let wheel = EvdevWheel::open(
        std::path::Path::new(&args[1]),
        WheelConfig {
            profile: Some(profile),
            // A mass held still by the motor sends no input events: do not call that a hang.
            max_silence_ms: 5000,
            ..Default::default()
        },
        clock::Clock::real(),
    )?;
    let mut wheel = ZeroTorqueOnDrop::new(wheel);
    let start = Instant::now();
    let mut last_print = start;
    while start.elapsed().as_secs_f64() < seconds {
        wheel.command_torque(units / EFFECT_FULL_SCALE_UNITS)?;
        if last_print.elapsed() >= Duration::from_millis(250) {
            let r = wheel.read()?;
            println!("angle {:+.4} rad (profile scale)", r.angle_rad);
            last_print = Instant::now();
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    Ok(())
}

#[cfg(not(all(target_os = "linux", feature = "evdev")))]
fn main() {
    eprintln!("ff_constant needs Linux and the `evdev` feature");
}
