//! The one error type of the crate.

/// Why a measure could not be computed. Every message names the signal, and where it helps the
/// sample index or the parameter and its allowed range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MetricError {
    /// The signal has no samples.
    #[error("{signal}: no samples")]
    Empty {
        /// Which signal (e.g. `speed`, `joint "elbow"`).
        signal: String,
    },
    /// The signal has fewer samples than the measure needs.
    #[error("{signal}: {len} sample(s), at least {min} needed")]
    TooShort {
        /// Which signal.
        signal: String,
        /// How many samples it has.
        len: usize,
        /// How many the measure needs.
        min: usize,
    },
    /// A sample is NaN or infinite.
    #[error("{signal}: sample at index {index} is not finite ({value})")]
    NonFinite {
        /// Which signal.
        signal: String,
        /// Index of the first non-finite sample.
        index: usize,
        /// Its value (NaN, inf or -inf).
        value: f64,
    },
    /// The sampling rate is not a finite number > 0.
    #[error("sampling rate fs = {fs_hz} Hz: must be finite and > 0")]
    BadSampleRate {
        /// The rate given, Hz.
        fs_hz: f64,
    },
    /// A parameter is out of its allowed range.
    #[error("{context}: `{field}` = {value} is out of range; allowed: {allowed}")]
    BadParameter {
        /// Which parameter set (e.g. `SparcParams`).
        context: &'static str,
        /// The field name.
        field: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// The signal has no shape the measure can score (all zero, or a constant speed with no
    /// jerk at all, where LDLJ would be +∞).
    #[error("{signal}: {why}")]
    Degenerate {
        /// Which signal.
        signal: String,
        /// What makes it degenerate.
        why: &'static str,
    },
    /// `LiveMeasures::update` got a different number of joint samples than joints it tracks.
    #[error("live measures track {expected} joint(s) but got {got} sample(s)")]
    JointCount {
        /// Joints given at construction.
        expected: usize,
        /// Joint samples in this update.
        got: usize,
    },
}

/// Check a sampling rate: finite and > 0.
pub(crate) fn check_fs(fs_hz: f64) -> Result<(), MetricError> {
    if fs_hz.is_finite() && fs_hz > 0.0 {
        Ok(())
    } else {
        Err(MetricError::BadSampleRate { fs_hz })
    }
}

/// Check a signal: at least `min` samples (and not empty), every sample finite.
pub(crate) fn check_signal(signal: &str, x: &[f64], min: usize) -> Result<(), MetricError> {
    if x.is_empty() {
        return Err(MetricError::Empty {
            signal: signal.to_owned(),
        });
    }
    if x.len() < min {
        return Err(MetricError::TooShort {
            signal: signal.to_owned(),
            len: x.len(),
            min,
        });
    }
    if let Some((index, &value)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(MetricError::NonFinite {
            signal: signal.to_owned(),
            index,
            value,
        });
    }
    Ok(())
}
