//! The first real force-feedback wheel of this system, behind [`Wheel`]: the kernel's evdev
//! backend on Linux ([`crate::evdev_wheel`]), DirectInput 8 on Windows
//! ([`crate::dinput_wheel`]). Either looks for its wheel again once it is unplugged, and takes
//! back only the same model. The one call the station makes to get a real wheel.

use clock::Clock;

use haptic_wheel::wheel::{Wheel, WheelError};
use haptic_wheel::wheel_config::WheelConfig;

/// Open the first force-feedback wheel found with `config`, its readings on `clock` (a real
/// one), re-found by its identity when it is unplugged and plugged back in.
#[cfg(all(target_os = "linux", feature = "evdev"))]
pub fn open_first(config: WheelConfig, clock: Clock) -> Result<Box<dyn Wheel + Send>, WheelError> {
    use crate::evdev_wheel::EvdevWheel;
    use crate::evdev_wheel::rejoin::{KernelFinder, RESCAN_EVERY};
    let wheel = EvdevWheel::open_first(config, clock)?.reopen_with(KernelFinder, RESCAN_EVERY)?;
    Ok(Box::new(wheel))
}

/// Open the first force-feedback wheel found with `config`, its readings on `clock` (a real
/// one), re-found by its identity when it is unplugged and plugged back in.
#[cfg(all(windows, feature = "dinput"))]
pub fn open_first(config: WheelConfig, clock: Clock) -> Result<Box<dyn Wheel + Send>, WheelError> {
    use crate::dinput_wheel::DinputWheel;
    use crate::dinput_wheel::com::ComDevice;
    Ok(Box::new(DinputWheel::<ComDevice>::open_first(
        config, clock,
    )?))
}

/// No force-feedback backend is built for this system.
#[cfg(not(any(
    all(target_os = "linux", feature = "evdev"),
    all(windows, feature = "dinput")
)))]
pub fn open_first(config: WheelConfig, clock: Clock) -> Result<Box<dyn Wheel + Send>, WheelError> {
    let _ = (config, clock);
    Err(WheelError::Unsupported {
        device: "force-feedback wheel".into(),
        reason: "no force-feedback backend is built for this system (Linux: feature `evdev`; \
                 Windows: feature `dinput`)"
            .into(),
    })
}
