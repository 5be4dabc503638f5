//! Gyro integration and orientation-fusion bindings.

use pyo3::prelude::*;

/// Add the IMU functions to the native module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let _ = m;
    Ok(())
}
