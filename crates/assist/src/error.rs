//! Errors of the assist crate.

/// Everything that can go wrong when building an assist controller from a spec.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum AssistError {
    /// A configuration value is outside its allowed range (or not finite).
    #[error("invalid assist config: `{field}` = {value} is outside the allowed range {allowed}")]
    InvalidConfig {
        /// Dotted path of the offending field, e.g. `motion.poles_rad_s[1]`.
        field: &'static str,
        /// The rejected value.
        value: f64,
        /// Human-readable allowed range, e.g. `(0, 1]`.
        allowed: &'static str,
    },
    /// Two fields are individually fine but contradict each other.
    #[error("invalid assist config: {0}")]
    Inconsistent(&'static str),
}

/// Check that `value` is finite and inside `[lo, hi]`, naming `field` and `allowed` otherwise.
pub(crate) fn check_range(
    field: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    allowed: &'static str,
) -> Result<(), AssistError> {
    common::check_range(field, value, lo, hi).map_err(|e| AssistError::InvalidConfig {
        field: e.field,
        value: e.value,
        allowed,
    })
}
