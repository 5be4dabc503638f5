//! `telerehab devices`: list wheels, pedals, gamepads (and what to check when there are none).

/// Print the devices found; exits successfully when there are none (that is an answer).
pub fn run() -> anyhow::Result<()> {
    println!("{}", haptic_wheel::enumerate_devices());
    Ok(())
}
