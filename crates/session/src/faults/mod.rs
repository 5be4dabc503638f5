//! Faults injected into a simulated session, compiled into the product so that tests and
//! demos exercise the real safety paths (`telerehab run --sim --fault KIND@SECONDS`, or a
//! `[[faults]]` table in the configuration).
//!
//! The wheel's faults act at the device seam, where a real wheel's do: [`FaultyWheel`] wraps
//! the simulated wheel and, from the fault's session time on, answers as an unplugged,
//! misbehaving or stalled device would. Everything above it — the haptic chain, its safety
//! supervisor, the session's end — is the code a real wheel runs.
//!
//! The faults' parsing and windows are `crate::config::faults` (the configuration names them);
//! here `wheel` is the faulty wheel, `disk` the disk that fills up, `hub` the switch that takes
//! the hub down.

mod disk;
mod hub;
mod wheel;

pub use crate::config::faults::{
    FaultKind, FaultSpec, disk_full_at_ns, imu_faults, validate_all, windows,
};
pub use disk::{Disk, FillingFile};
pub use hub::HubSwitch;
pub use wheel::{FaultyWheel, Stallable};
