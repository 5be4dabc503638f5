//! The crate's error type.

use thiserror::Error;

/// Errors from gyro-imu: bad input, bad configuration, device trouble.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ImuError {
    /// A configuration field is out of its allowed range.
    #[error("invalid config: `{field}` = {value} is outside {allowed}")]
    InvalidConfig {
        /// Field name.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// An input value is not finite or otherwise unusable.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// A HID report could not be parsed.
    #[error("malformed {device} report: {reason}")]
    MalformedReport {
        /// Device family.
        device: &'static str,
        /// What was wrong.
        reason: String,
    },
    /// The arm cannot reach the grip point with the given geometry.
    #[error(
        "grip out of reach: shoulder–grip distance {distance_m:.3} m, arm spans [{min_m:.3}, {max_m:.3}] m"
    )]
    OutOfReach {
        /// Shoulder-to-grip distance (m).
        distance_m: f64,
        /// Shortest reachable distance (m).
        min_m: f64,
        /// Longest reachable distance (m).
        max_m: f64,
    },
    /// A calibration procedure did not get usable data.
    #[error("calibration failed: {0}")]
    Calibration(String),
    /// A guided procedure cannot go on; the text says what the patient should do. Static, so
    /// that failing on a real-time thread allocates nothing.
    #[error("calibration failed: {0}")]
    Procedure(&'static str),
    /// A device backend error (HID open/read/write).
    #[error("device error: {0}")]
    Device(String),
    /// A device that is gone, said in a static text (as [`ImuError::Device`] words it), so
    /// that telling it on a real-time thread allocates nothing.
    #[error("device error: {0}")]
    Gone(&'static str),
}

/// Check `value` is finite and in `[lo, hi]`, else name `field` and `allowed`.
pub(crate) fn check_range(
    field: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    allowed: &'static str,
) -> Result<(), ImuError> {
    common::check_range(field, value, lo, hi).map_err(|e| ImuError::InvalidConfig {
        field: e.field,
        value: e.value,
        allowed,
    })
}
