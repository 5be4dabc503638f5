//! The real wheels behind [`haptic_wheel::Wheel`], and the other game controllers a patient
//! plugs in: the only crate of ours that links a device library for force feedback.
//!
//! - [`devices`] and [`scan`]: [`enumerate_devices`] for `telerehab devices` and `doctor`
//!   (each device's class, capabilities and the profile it would get).
//! - `evdev_wheel` (Linux, feature `evdev`): the kernel force-feedback backend (EV_FF,
//!   `EVIOCSFF`), its controls, its calibration pulses and its re-join helper thread.
//! - `dinput_wheel` (feature `dinput`; its device on the `windows` crate on Windows only):
//!   DirectInput 8 force feedback.
//! - `peripherals` (feature `gilrs`): pedals, buttons and gamepads.
//! - [`real_wheel`]: `open_first`, the first real wheel of this system behind the trait (evdev
//!   on Linux, DirectInput on Windows).
//!
//! Both backends map N·m to device units through `haptic_wheel`'s per-model profiles and rate
//! policy. Their safety tests (`backend_tests`, a macro over both in-memory devices) and the
//! whole chain's all-modes proptest (`chain_modes`) drive `haptic_wheel::HapticChain` on both
//! backends and assert N·m at the motor for every profile, an unknown one included.

pub mod devices;
#[cfg(feature = "dinput")]
pub mod dinput_wheel;
#[cfg(all(target_os = "linux", feature = "evdev"))]
pub mod evdev_wheel;
#[cfg(feature = "gilrs")]
pub mod peripherals;
pub mod real_wheel;
pub mod scan;

#[cfg(test)]
mod backend_tests;
#[cfg(all(test, feature = "dinput"))]
mod chain_modes;
/// The chain's proptest strategies, the same file as `haptic_wheel`'s own tests use.
#[cfg(all(test, feature = "dinput"))]
#[path = "../../haptic-wheel/src/strategies.rs"]
mod strategies;

pub use devices::DeviceReport;
pub use scan::enumerate_devices;
