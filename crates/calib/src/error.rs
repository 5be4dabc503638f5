//! The one error type of the crate.

use thiserror::Error;

/// Why a calibration could not be computed. Bad input is reported, never silently "fixed".
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CalibError {
    /// A sample is NaN or infinite.
    #[error("{argument}[{index}] is not finite (NaN or infinity)")]
    NonFinite {
        /// Name of the offending argument.
        argument: &'static str,
        /// Index of the first bad element.
        index: usize,
    },
    /// Two arrays that must have equal lengths do not.
    #[error(
        "{argument} has {got} elements but {expected} were expected (it must match {reference})"
    )]
    LengthMismatch {
        /// Name of the offending argument.
        argument: &'static str,
        /// Its length.
        got: usize,
        /// The length it must have.
        expected: usize,
        /// The argument whose length is the reference.
        reference: &'static str,
    },
    /// Not enough samples or measurements to determine the parameters.
    #[error("{argument}: {got} samples given, at least {needed} are needed")]
    TooFewSamples {
        /// Name of the offending argument.
        argument: &'static str,
        /// Samples given.
        got: usize,
        /// Minimum needed.
        needed: usize,
    },
    /// A scalar argument or option is outside its allowed range.
    #[error("{argument} = {value} is out of range: {allowed}")]
    OutOfRange {
        /// Name of the argument or option field.
        argument: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A direction that must be a unit vector is not one.
    #[error("{argument}[{index}] has norm {norm}, but it must be a unit vector (norm 1 ± 1e-6)")]
    NotUnitVector {
        /// Name of the offending argument.
        argument: &'static str,
        /// Index of the bad vector.
        index: usize,
        /// Its norm.
        norm: f64,
    },
    /// A 4×4 matrix is not a rigid transform (orthonormal rotation, det +1, last row 0 0 0 1).
    #[error("{argument}[{index}] is not a rigid transform: {reason}")]
    NotRigidTransform {
        /// Name of the offending argument.
        argument: &'static str,
        /// Index of the bad matrix.
        index: usize,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The method needs an initial guess and none was given.
    #[error("method {method} needs an initial guess (pass `initial`) ")]
    MissingInitialGuess {
        /// The method that needs it.
        method: &'static str,
    },
    /// The data do not determine the parameters (the motion excites too few of them).
    #[error("parameters not identifiable from these data: {reason}")]
    NotIdentifiable {
        /// Which parameters and why, with the remedy.
        reason: String,
    },
    /// An iterative method diverged or hit its iteration limit without converging.
    #[error("{method} did not converge after {iterations} iterations: {reason}")]
    NotConverged {
        /// The method.
        method: &'static str,
        /// Iterations run.
        iterations: usize,
        /// What happened.
        reason: &'static str,
    },
}

/// Check that every element of `values` is finite.
pub(crate) fn check_finite(argument: &'static str, values: &[f64]) -> Result<(), CalibError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(CalibError::NonFinite { argument, index }),
        None => Ok(()),
    }
}

/// Check a recursive estimator's forgetting factor λ per sample: in [0.9, 1] (1 = never
/// forget), else name the `forgetting` field.
pub(crate) fn check_forgetting(forgetting: f64) -> Result<(), CalibError> {
    if (0.9..=1.0).contains(&forgetting) {
        Ok(())
    } else {
        Err(CalibError::OutOfRange {
            argument: "forgetting",
            value: forgetting,
            allowed: "[0.9, 1]",
        })
    }
}
