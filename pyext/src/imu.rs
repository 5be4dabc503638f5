//! Gyro integration and orientation-fusion bindings (`telerehab.imu`).
//!
//! Arrays arrive as float64 `(N, 3)`; shapes, dtypes and finiteness are checked here (the
//! Python facade converts first, this layer re-checks so the native functions are safe on
//! their own). The GIL is released around the loops.

use gyro_imu::bias::{RestConfig, estimate_bias};
use gyro_imu::fusion::{FusionConfig, fuse};
use gyro_imu::integrate::{Method, integrate_with};
use nalgebra::Vector3;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Read argument `name` as a finite float64 array of shape `(N, 3)`.
fn vectors(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vec<Vector3<f64>>> {
    let arr: PyReadonlyArray2<'_, f64> = obj.extract().map_err(|_| {
        PyValueError::new_err(format!("`{name}` must be a float64 array of shape (N, 3)"))
    })?;
    let shape = arr.shape();
    if shape[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "`{name}` must have shape (N, 3), got ({}, {})",
            shape[0], shape[1]
        )));
    }
    let view = arr.as_array();
    let mut out = Vec::with_capacity(shape[0]);
    for (i, row) in view.rows().into_iter().enumerate() {
        let v = Vector3::new(row[0], row[1], row[2]);
        if !v.iter().all(|x| x.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "`{name}` row {i} is not finite"
            )));
        }
        out.push(v);
    }
    Ok(out)
}

fn check_dt(dt: f64) -> PyResult<()> {
    if dt.is_finite() && dt > 0.0 && dt <= 1.0 {
        Ok(())
    } else {
        Err(PyValueError::new_err(format!(
            "`dt` must be in (0, 1] s, got {dt}"
        )))
    }
}

/// Integrate body rates `(N, 3)` rad/s at period `dt` s; returns `(N + 1, 3, 3)` rotation
/// matrices with `R0 = I` and `R_{k+1} = R_k · exp([ω_k]× dt)` (thesis eq. 4.12–4.13).
#[pyfunction]
#[pyo3(signature = (rates, dt, method = "exp"))]
fn imu_integrate<'py>(
    py: Python<'py>,
    rates: &Bound<'py, PyAny>,
    dt: f64,
    method: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let w = vectors("rates", rates)?;
    check_dt(dt)?;
    let m = Method::from_name(method).ok_or_else(|| {
        let names: Vec<_> = Method::ALL.iter().map(|m| m.name()).collect();
        PyValueError::new_err(format!("`method` must be one of {names:?}, got {method:?}"))
    })?;
    let n = w.len();
    let flat = py.detach(|| {
        let mut flat = Vec::with_capacity((n + 1) * 9);
        integrate_with(&w, dt, m, |r| {
            for i in 0..3 {
                for j in 0..3 {
                    flat.push(r[(i, j)]);
                }
            }
        });
        flat
    });
    Ok(PyArray1::from_vec(py, flat)
        .reshape([n + 1, 3, 3])?
        .into_any())
}

/// Gyro + accelerometer orientation fusion; returns `(N, 4)` unit quaternions `(w, x, y, z)`,
/// sensor-to-earth, earth z up.
#[pyfunction]
#[pyo3(signature = (gyr, acc, dt, tau_acc_s = 3.0))]
fn imu_fuse<'py>(
    py: Python<'py>,
    gyr: &Bound<'py, PyAny>,
    acc: &Bound<'py, PyAny>,
    dt: f64,
    tau_acc_s: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let g = vectors("gyr", gyr)?;
    let a = vectors("acc", acc)?;
    check_dt(dt)?;
    if g.len() != a.len() {
        return Err(PyValueError::new_err(format!(
            "`gyr` has {} rows but `acc` has {}",
            g.len(),
            a.len()
        )));
    }
    let cfg = FusionConfig {
        tau_acc_s,
        ..FusionConfig::default()
    };
    cfg.validate()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let n = g.len();
    let flat = py
        .detach(|| {
            fuse(&g, &a, dt, cfg).map(|qs| {
                qs.iter()
                    .flat_map(|q| [q.w, q.i, q.j, q.k])
                    .collect::<Vec<_>>()
            })
        })
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(PyArray1::from_vec(py, flat).reshape([n, 4])?.into_any())
}

/// Mean rate over the detected rest periods: returns `(bias (3,), rest_fraction)`.
#[pyfunction]
#[pyo3(signature = (rates, dt, acc = None, rate_threshold_deg_s = 2.0, min_rest_s = 1.5))]
fn imu_estimate_bias<'py>(
    py: Python<'py>,
    rates: &Bound<'py, PyAny>,
    dt: f64,
    acc: Option<&Bound<'py, PyAny>>,
    rate_threshold_deg_s: f64,
    min_rest_s: f64,
) -> PyResult<(Bound<'py, PyAny>, f64)> {
    let w = vectors("rates", rates)?;
    let a = acc.map(|a| vectors("acc", a)).transpose()?;
    check_dt(dt)?;
    let cfg = RestConfig {
        rate_threshold_deg_s,
        min_duration_s: min_rest_s,
        ..RestConfig::default()
    };
    let (b, frac) = py
        .detach(|| estimate_bias(&w, a.as_deref(), dt, cfg))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((PyArray1::from_vec(py, vec![b.x, b.y, b.z]).into_any(), frac))
}

/// Add the IMU functions to the native module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(imu_integrate, m)?)?;
    m.add_function(wrap_pyfunction!(imu_fuse, m)?)?;
    m.add_function(wrap_pyfunction!(imu_estimate_bias, m)?)?;
    Ok(())
}
