//! The error of every pure `validate()` of this crate (below `wheel` and `profile`, which both
//! return it).

/// A configuration value out of its allowed range: what every pure `validate()` of this crate
/// returns (a configuration problem, not a device one); the message names the field and the
/// allowed range.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("invalid wheel configuration: {0}")]
pub struct ConfigError(pub String);
