//! The crate's error type.

/// Everything that can go wrong in the exercise library: bad configuration or bad input.
///
/// Every message names the offending item, field and allowed range, so a therapist editing a
/// regimen file or an analyst feeding a CSV can fix it without reading the source.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum VehicleError {
    /// A configuration value is outside its allowed range (or not finite).
    #[error("{context}: `{field}` = {value} is out of range; allowed: {allowed}")]
    OutOfRange {
        /// What was being validated (e.g. `VehicleParams`, `exercise "sine-road"`).
        context: String,
        /// The field name as written in TOML.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// The allowed range, in words.
        allowed: String,
    },
    /// An input value at run time is not usable (NaN, infinite, non-positive time step...).
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// An exercise name that is not in the built-in library.
    #[error("unknown exercise {name:?}; known exercises: {known}")]
    UnknownExercise {
        /// The name asked for.
        name: String,
        /// The built-in names, comma separated.
        known: String,
    },
}

/// Check `lo <= value <= hi` (and finite); otherwise an [`VehicleError::OutOfRange`].
pub(crate) fn check_range(
    context: &str,
    field: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    unit: &str,
) -> Result<(), VehicleError> {
    common::check_range(field, value, lo, hi).map_err(|e| VehicleError::OutOfRange {
        context: context.to_string(),
        field: e.field,
        value: e.value,
        allowed: e.allowed(unit),
    })
}
