//! The force-feedback wheel: the patient's sensor and the therapy's actuator (thesis §3.2.1).
//!
//! - [`Wheel`]: the device trait (read angle, command torque), with [`SimWheel`], a simulated
//!   wheel with inertia, friction and encoder/torque quantisation.
//! - [`SpringDamper`]: the haptic model of thesis eq. 3.5.
//! - [`TorqueLimiter`]: the safety clamp every commanded torque passes through last.
//!
//! SI units inside: rad, rad/s, N·m, s. Device units are converted at the device edge.

pub mod model;
pub mod safety;
pub mod sim;
pub mod wheel;

pub use model::SpringDamper;
pub use safety::{LimitedTorque, TorqueLimiter};
pub use sim::{SimWheel, SimWheelParams};
pub use wheel::{Wheel, WheelError, WheelReading};

/// Torque range of the thesis wheel (Microsoft SideWinder FFB), N·m (thesis §3.2.1).
pub const THESIS_WHEEL_MAX_TORQUE_NM: f64 = 1.87;
/// Angle calibration of the thesis wheel `Ka`, rad per DirectX unit (eq. 3.2).
pub const THESIS_KA_RAD_PER_UNIT: f64 = 0.002253;
/// Torque calibration of the thesis wheel `Kt`, N·m per DirectX unit (eq. 3.3).
pub const THESIS_KT_NM_PER_UNIT: f64 = 1.873e-4;
