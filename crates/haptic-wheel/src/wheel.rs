//! The device trait every wheel backend implements.

use crate::profile::DeviceProfile;

/// How often a backend looks for its wheel once it has gone away (unplugged), until it is
/// plugged back in.
pub const REJOIN_RESCAN_EVERY: std::time::Duration = std::time::Duration::from_millis(250);

/// One reading of the wheel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WheelReading {
    /// Steering angle, rad (positive = counter-clockwise, steering left).
    pub angle_rad: f64,
    /// When the reading was taken, ns on the backend's clock.
    pub t_ns: u64,
}

pub use crate::config_error::ConfigError;

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
    /// The operating system refused an operation on the device (open, ioctl, write).
    #[error("wheel device I/O on {device}: {source}")]
    Io {
        /// The device node or name.
        device: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The device lacks something the backend needs (an axis, constant force).
    #[error("wheel {device} is not usable: {reason}")]
    Unsupported {
        /// The device node or name.
        device: String,
        /// What is missing.
        reason: String,
    },
    /// A configuration value is out of its allowed range.
    #[error(transparent)]
    InvalidConfig(#[from] ConfigError),
    /// A device fault found on the 1 kHz path (carries no heap data: the haptic thread makes
    /// and drops it every tick while it lasts, and must not allocate).
    #[error("wheel fault: {0}")]
    Fault(WheelFault),
}

/// What went wrong with a running wheel, as the haptic loop sees it. `Copy`, so it can be
/// reported every tick without allocating and told to the patient after the loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum WheelFault {
    /// The device went away (unplugged; the kernel answers ENODEV).
    Unplugged,
    /// The wheel sent no input event for longer than `max_silence_ms` while a torque was
    /// commanded: a hung device or firmware.
    Silent,
    /// A reading outside the axis range the device declared.
    OutOfRange,
    /// The wheel refused the station's force commands (the ceiling's or the torque's write
    /// failed) for longer than the station allows while it still answered reads: the force at
    /// the motor is no longer the one the safety chain chose.
    CommandsRefused,
}

impl WheelFault {
    /// Plain words for the patient and the session report.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Unplugged => "the wheel was unplugged",
            Self::Silent => "the wheel stopped reporting its position while a force was applied",
            Self::OutOfRange => "the wheel reported an angle outside its own range",
            Self::CommandsRefused => "the wheel stopped taking the station's force commands",
        }
    }
}

impl std::fmt::Display for WheelFault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.describe())
    }
}

impl WheelError {
    /// A write the device refused, as the kernel answers one (EIO), made without allocating
    /// (for the 1 kHz path: a simulated fault, a replayed refusal).
    pub fn write_refused() -> Self {
        Self::Io {
            device: String::new(),
            source: std::io::Error::from_raw_os_error(5),
        }
    }

    /// The running-wheel fault this error is, if it is one (every other error is a set-up
    /// problem, or a refused command the safety chain already handled).
    pub fn fault(&self) -> Option<WheelFault> {
        match self {
            Self::Fault(f) => Some(*f),
            Self::Disconnected(_) => Some(WheelFault::Unplugged),
            _ => None,
        }
    }
}

/// What a wheel backend can do, for logs, `telerehab devices` and the rate policy.
#[derive(Clone, Debug, PartialEq)]
pub struct WheelCapabilities {
    /// Human-readable device name.
    pub name: String,
    /// Largest torque the device can produce, N·m.
    pub max_torque_nm: f64,
    /// Half range of motion (lock to centre), rad.
    pub half_range_rad: f64,
    /// Smallest angle change the encoder reports, rad.
    pub angle_resolution_rad: f64,
    /// Highest useful torque update rate, Hz (per-driver rate policy).
    pub max_update_rate_hz: f64,
    /// Spring and friction can be uploaded to the device's firmware (run inside the wheel).
    pub firmware_conditions: bool,
}

/// The torque updates a backend actually wrote to the device: how many, and the largest gap
/// between two. Plain counters, updated on the 1 kHz thread without allocating.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MotorUpdates {
    /// Updates written since the backend was opened.
    pub count: u64,
    /// The largest time between two updates written, ns (0 before the second).
    pub worst_gap_ns: u64,
    /// When the last update was written, ns on the backend's clock.
    pub last_ns: Option<u64>,
}

impl MotorUpdates {
    /// One update written at `now_ns`.
    pub fn written(&mut self, now_ns: u64) {
        if let Some(last) = self.last_ns {
            self.worst_gap_ns = self.worst_gap_ns.max(now_ns.saturating_sub(last));
        }
        self.count += 1;
        self.last_ns = Some(now_ns);
    }

    /// The device went away: the next update starts a new run (the time without a device is
    /// told as an unplug, not as a gap between updates).
    pub fn interrupted(&mut self) {
        self.last_ns = None;
    }

    /// The worst gap, ms.
    pub fn worst_gap_ms(&self) -> f64 {
        self.worst_gap_ns as f64 * 1e-6
    }
}

/// A steering wheel the haptic loop reads and drives.
pub trait Wheel {
    /// The latest steering angle.
    fn read(&mut self) -> Result<WheelReading, WheelError>;
    /// Command a motor torque, N·m. The caller has already passed it through the safety chain.
    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError>;
    /// The safety chain's ceiling in force, N·m. A backend that holds its last level between
    /// updates (a driver's rate policy) brings a held level above it down at once, so a
    /// lowered ceiling holds at the motor from this call, not one update interval later.
    /// The haptic loop calls it every tick before [`Wheel::command_torque`]. Backends that
    /// send every command as it comes ignore it (the default); the evdev backend refuses a
    /// non-finite ceiling and sends zero.
    fn set_torque_ceiling_nm(&mut self, _ceiling_nm: f64) -> Result<(), WheelError> {
        Ok(())
    }
    /// Largest torque the device can produce, N·m.
    fn max_torque_nm(&self) -> f64;

    /// The named device profile (angle and torque scales, rate policy) this backend uses.
    /// The default is the thesis SideWinder profile with this backend's torque range.
    fn profile(&self) -> DeviceProfile {
        DeviceProfile {
            max_torque_nm: self.max_torque_nm(),
            ..DeviceProfile::thesis_sidewinder()
        }
    }

    /// Let condition effects that run in the wheel's firmware (spring, damper, friction) play
    /// (`true`) or stop them (`false`). The haptic loop calls it every tick with whether the
    /// safety supervisor is running at full scale, so nothing moves the motor outside the
    /// supervisor. Backends without firmware effects ignore it.
    fn set_firmware_effects_active(&mut self, _active: bool) {}

    /// What this backend can do. Derived from [`Wheel::profile`] unless the backend knows better.
    fn capabilities(&self) -> WheelCapabilities {
        let p = self.profile();
        WheelCapabilities {
            name: p.name.clone(),
            max_torque_nm: p.max_torque_nm,
            half_range_rad: p.half_range_rad,
            angle_resolution_rad: p.ka_rad_per_unit,
            max_update_rate_hz: p.max_update_rate_hz,
            firmware_conditions: false,
        }
    }

    /// The torque updates written to the device so far (the achieved rate at the motor, which
    /// a driver's rate policy may hold below the loop's). `None` for a backend that does not
    /// count them (the default).
    fn motor_updates(&self) -> Option<MotorUpdates> {
        None
    }
}

impl<W: Wheel + ?Sized> Wheel for &mut W {
    fn read(&mut self) -> Result<WheelReading, WheelError> {
        (**self).read()
    }
    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError> {
        (**self).command_torque(torque_nm)
    }
    fn set_torque_ceiling_nm(&mut self, ceiling_nm: f64) -> Result<(), WheelError> {
        (**self).set_torque_ceiling_nm(ceiling_nm)
    }
    fn max_torque_nm(&self) -> f64 {
        (**self).max_torque_nm()
    }
    fn profile(&self) -> DeviceProfile {
        (**self).profile()
    }
    fn set_firmware_effects_active(&mut self, active: bool) {
        (**self).set_firmware_effects_active(active)
    }
    fn capabilities(&self) -> WheelCapabilities {
        (**self).capabilities()
    }
    fn motor_updates(&self) -> Option<MotorUpdates> {
        (**self).motor_updates()
    }
}

impl<W: Wheel + ?Sized> Wheel for Box<W> {
    fn read(&mut self) -> Result<WheelReading, WheelError> {
        (**self).read()
    }
    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError> {
        (**self).command_torque(torque_nm)
    }
    fn set_torque_ceiling_nm(&mut self, ceiling_nm: f64) -> Result<(), WheelError> {
        (**self).set_torque_ceiling_nm(ceiling_nm)
    }
    fn max_torque_nm(&self) -> f64 {
        (**self).max_torque_nm()
    }
    fn profile(&self) -> DeviceProfile {
        (**self).profile()
    }
    fn set_firmware_effects_active(&mut self, active: bool) {
        (**self).set_firmware_effects_active(active)
    }
    fn capabilities(&self) -> WheelCapabilities {
        (**self).capabilities()
    }
    fn motor_updates(&self) -> Option<MotorUpdates> {
        (**self).motor_updates()
    }
}

/// Owns a wheel and commands zero torque when dropped: on scope exit, on an early `return`
/// or `?`, and on a panic that unwinds through the haptic thread (safety invariant 3).
///
/// Signals: the station's handler sets a flag the loop checks each tick; the loop then
/// returns and this guard is dropped. With `panic = "abort"` nothing runs on panic, but the
/// kernel erases the process's effects when the device file closes, and the evdev backend
/// keeps every effect short and re-armed so the motor stops within one effect length anyway.
#[derive(Debug)]
pub struct ZeroTorqueOnDrop<W: Wheel> {
    wheel: W,
}

impl<W: Wheel> ZeroTorqueOnDrop<W> {
    /// Guard `wheel`.
    pub fn new(wheel: W) -> Self {
        Self { wheel }
    }

    /// The guarded wheel.
    pub fn wheel(&mut self) -> &mut W {
        &mut self.wheel
    }
}

impl<W: Wheel> std::ops::Deref for ZeroTorqueOnDrop<W> {
    type Target = W;
    fn deref(&self) -> &W {
        &self.wheel
    }
}

impl<W: Wheel> std::ops::DerefMut for ZeroTorqueOnDrop<W> {
    fn deref_mut(&mut self) -> &mut W {
        &mut self.wheel
    }
}

impl<W: Wheel> Drop for ZeroTorqueOnDrop<W> {
    fn drop(&mut self) {
        // Nothing useful can be done with an error while dropping: the device is gone, and
        // a gone device applies no torque.
        let _ = self.wheel.command_torque(0.0);
    }
}
