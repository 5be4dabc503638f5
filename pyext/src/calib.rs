//! Calibration bindings.

use pyo3::prelude::*;

/// Add the calibration functions to the native module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let _ = m;
    Ok(())
}
