//! The device trait every wheel backend implements.

/// One reading of the wheel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WheelReading {
    /// Steering angle, rad (positive = counter-clockwise, steering left).
    pub angle_rad: f64,
    /// When the reading was taken, ns on the backend's clock.
    pub t_ns: u64,
}

/// What can go wrong talking to a wheel.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum WheelError {
    /// The device went away (unplugged, permissions revoked).
    #[error("wheel disconnected: {0}")]
    Disconnected(String),
    /// A torque command that is not a finite number was refused.
    #[error("refused non-finite torque command {0}")]
    NonFiniteTorque(f64),
}

/// A steering wheel the haptic loop reads and drives.
pub trait Wheel {
    /// The latest steering angle.
    fn read(&mut self) -> Result<WheelReading, WheelError>;
    /// Command a motor torque, N·m. The caller has already passed it through the safety chain.
    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError>;
    /// Largest torque the device can produce, N·m.
    fn max_torque_nm(&self) -> f64;
}
