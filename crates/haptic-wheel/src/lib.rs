//! The force-feedback wheel: the patient's sensor and the therapy's actuator (thesis §3.2.1).
//!
//! - [`wheel`]: [`Wheel`], the device trait (read angle, command torque, the safety chain's
//!   ceiling every tick, profile, capabilities); [`ZeroTorqueOnDrop`] guards any wheel.
//! - [`sim`]: [`SimWheel`], a simulated wheel with inertia, friction, end stops, encoder/torque
//!   quantisation and a delayed, jittered USB command path.
//! - [`profile`]: per-model angle/torque scales (thesis eq. 3.1–3.3) and the per-driver
//!   torque update rate policy; `CALIBRATION.md` tells how to measure a new wheel.
//! - [`config_error`]: [`config_error::ConfigError`], what every pure `validate()` returns.
//! - [`wheel_config`]: the station's `[wheel]` section (profile, rated torque, gain) and the
//!   ceiling it gives in N·m; [`calibrate`]: the analysis behind `telerehab wheel calibrate`.
//! - [`effects`]: the DirectInput effect set of the thesis toolbox (Appendix B), rendered
//!   on the host in a fixed-capacity [`EffectStack`].
//! - [`filter`]: the thesis moving average (eq. 3.4) and a Kalman velocity estimator.
//! - [`model`]: the spring–mass–damper of eq. 3.5 and a Hannaford–Ryu passivity controller.
//! - [`safety`]: limiter, soft start, fade-out, deadline watchdog.
//! - [`chain`]: [`HapticChain`], all of the above as the one call per tick the haptic loop
//!   makes.
//! - [`devices`] and [`scan`]: `enumerate_devices()` for `telerehab devices`; `evdev_wheel` (Linux,
//!   feature `evdev`): the kernel force-feedback backend; `dinput_wheel` (feature `dinput`; its
//!   device on the `windows` crate on Windows only): DirectInput 8 force feedback on Windows;
//!   `peripherals` (feature `gilrs`):
//!   pedals, buttons and gamepads.
//!
//! - [`real_wheel`]: `open_first`, the first real wheel of this system behind [`Wheel`] (evdev
//!   on Linux, DirectInput on Windows).
//!
//! SI units inside: rad, rad/s, N·m, s. Device units are converted at the device edge.

pub mod calibrate;
pub mod chain;
pub mod config_error;
pub mod devices;
#[cfg(feature = "dinput")]
pub mod dinput_wheel;
pub mod effects;
#[cfg(all(target_os = "linux", feature = "evdev"))]
pub mod evdev_wheel;
pub mod filter;
pub mod model;
#[cfg(feature = "gilrs")]
pub mod peripherals;
pub mod profile;
pub mod real_wheel;
pub mod safety;
pub mod scan;
pub mod sim;
pub mod wheel;
pub mod wheel_config;

#[cfg(test)]
mod backend_tests;

pub use chain::{
    HapticChain, HapticChainConfig, HapticRegimen, HapticStats, TickInput, TickTelemetry,
};
pub use devices::DeviceReport;
pub use effects::{
    Condition, ConditionKind, Effect, EffectError, EffectId, EffectKind, EffectStack, Envelope,
    Periodic, Waveform, WheelState,
};
pub use filter::{KalmanEstimator, KalmanParams, MovingAverage, StateEstimator};
pub use model::{PassivityController, PassivityParams, SpringDamper};
pub use profile::{DeviceProfile, DriverFamily, TorqueSource};
pub use safety::{Fault, LimitedTorque, SafetyConfig, Supervisor, TorqueLimiter, WatchdogState};
pub use scan::enumerate_devices;
pub use sim::{SimWheel, SimWheelParams};
pub use wheel::{
    MotorUpdates, Wheel, WheelCapabilities, WheelError, WheelFault, WheelReading, ZeroTorqueOnDrop,
};
pub use wheel_config::{CeilingReport, WheelConfig};

/// Torque range of the thesis wheel (Microsoft SideWinder FFB), N·m (thesis §3.2.1).
pub const THESIS_WHEEL_MAX_TORQUE_NM: f64 = 1.87;
/// Angle calibration of the thesis wheel `Ka`, rad per DirectX unit (eq. 3.2).
pub const THESIS_KA_RAD_PER_UNIT: f64 = 0.002253;
/// Torque calibration of the thesis wheel `Kt`, N·m per DirectX unit (eq. 3.3).
pub const THESIS_KT_NM_PER_UNIT: f64 = 1.873e-4;
