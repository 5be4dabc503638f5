//! The force-feedback wheel without its device: the patient's sensor and the therapy's actuator
//! (thesis §3.2.1) as the 1 kHz loop sees it — the trait, the profiles, the haptic models and
//! the safety chain — with no device library in its graph (the real wheels are the
//! `wheel-devices` crate above it, so the hub, Python and the renderer never link one).
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
//! - `strategies` (tests only): proptest strategies over the chain's inputs.
//!
//! The real wheels (evdev on Linux, DirectInput 8 on Windows), pedals and gamepads, and the
//! device listing are the `wheel-devices` crate; its safety tests drive this crate's chain on
//! both backends' in-memory devices.
//!
//! SI units inside: rad, rad/s, N·m, s. Device units are converted at the device edge.

// The shared test strategies (`strategies`) name this crate by its name, as `wheel-devices`
// does when it compiles the same file.
extern crate self as haptic_wheel;

pub mod calibrate;
pub mod chain;
pub mod config_error;
pub mod effects;
pub mod filter;
pub mod model;
pub mod profile;
pub mod safety;
pub mod sim;
#[cfg(test)]
pub mod strategies;
pub mod wheel;
pub mod wheel_config;

pub use chain::{
    HapticChain, HapticChainConfig, HapticRegimen, HapticStats, TickInput, TickTelemetry,
};
pub use effects::{
    Condition, ConditionKind, Effect, EffectError, EffectId, EffectKind, EffectStack, Envelope,
    Periodic, Waveform, WheelState,
};
pub use filter::{KalmanEstimator, KalmanParams, MovingAverage, StateEstimator};
pub use model::{PassivityController, PassivityParams, SpringDamper};
pub use profile::{DeviceProfile, DriverFamily, TorqueSource};
pub use safety::{Fault, LimitedTorque, SafetyConfig, Supervisor, TorqueLimiter, WatchdogState};
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
