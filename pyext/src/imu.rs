//! Gyro integration and orientation-fusion bindings (`telerehab.imu`), following the
//! convention in [`crate::check`]: float64 arrays in (rates rad/s, accelerations m/s²,
//! periods s), shapes and finiteness re-checked, the GIL released around the loops.

use gyro_imu::bias::{RestConfig, estimate_bias};
use gyro_imu::fusion::{FusionConfig, fuse};
use gyro_imu::integrate::{Method, integrate_with};
use nalgebra::Vector3;
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyIterator, PyTuple};

use crate::check::{rows3, same_len, value_error};

/// Argument `name` (shape `(N, 3)`, finite) as vectors.
fn vectors(name: &str, a: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<Vector3<f64>>> {
    Ok(rows3(name, a)?.into_iter().map(Vector3::from).collect())
}

fn check_dt(dt_s: f64) -> PyResult<()> {
    if dt_s.is_finite() && dt_s > 0.0 && dt_s <= 1.0 {
        Ok(())
    } else {
        Err(value_error(format!("dt_s must be in (0, 1] s, got {dt_s}")))
    }
}

fn imu_error(e: gyro_imu::error::ImuError) -> PyErr {
    value_error(e.to_string())
}

/// Integrate body rates `(N, 3)` rad/s at period `dt_s`; returns `(N + 1, 3, 3)` rotation
/// matrices with `R0 = I` and `R_{k+1} = R_k · exp([ω_k]× dt)` (thesis eq. 4.12–4.13).
#[pyfunction]
#[pyo3(signature = (rates_rad_s, dt_s, method))]
fn imu_integrate<'py>(
    py: Python<'py>,
    rates_rad_s: PyReadonlyArray2<'py, f64>,
    dt_s: f64,
    method: &str,
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let w = vectors("rates_rad_s", &rates_rad_s)?;
    check_dt(dt_s)?;
    let m = Method::from_name(method).ok_or_else(|| {
        let names: Vec<_> = Method::ALL.iter().map(|m| m.name()).collect();
        value_error(format!("method must be one of {names:?}, got {method:?}"))
    })?;
    let n = w.len();
    let flat = py.detach(|| {
        let mut flat = Vec::with_capacity((n + 1) * 9);
        integrate_with(&w, dt_s, m, |r| {
            for i in 0..3 {
                for j in 0..3 {
                    flat.push(r[(i, j)]);
                }
            }
        });
        flat
    });
    PyArray1::from_vec(py, flat).reshape([n + 1, 3, 3])
}

/// Gyro + accelerometer orientation fusion; returns `(N, 4)` unit quaternions `(w, x, y, z)`,
/// sensor-to-earth, earth z up.
#[pyfunction]
#[pyo3(signature = (gyr_rad_s, acc_m_s2, dt_s, tau_acc_s, scale_estimation, rest_tilt_check))]
fn imu_fuse<'py>(
    py: Python<'py>,
    gyr_rad_s: PyReadonlyArray2<'py, f64>,
    acc_m_s2: PyReadonlyArray2<'py, f64>,
    dt_s: f64,
    tau_acc_s: f64,
    scale_estimation: bool,
    rest_tilt_check: bool,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let g = vectors("gyr_rad_s", &gyr_rad_s)?;
    let a = vectors("acc_m_s2", &acc_m_s2)?;
    same_len("acc_m_s2", a.len(), "gyr_rad_s", g.len())?;
    check_dt(dt_s)?;
    let cfg = FusionConfig {
        tau_acc_s,
        gyro_scale_estimation: scale_estimation,
        rest_tilt_check,
        ..FusionConfig::default()
    };
    cfg.validate().map_err(imu_error)?;
    let n = g.len();
    let flat = py
        .detach(|| {
            fuse(&g, &a, dt_s, cfg).map(|qs| {
                qs.iter()
                    .flat_map(|q| [q.w, q.i, q.j, q.k])
                    .collect::<Vec<_>>()
            })
        })
        .map_err(imu_error)?;
    PyArray1::from_vec(py, flat).reshape([n, 4])
}

/// A constant gyro bias estimated from the rest periods of a record. Unpacks as
/// `(bias_rad_s, rest_fraction)`.
#[pyclass(frozen, module = "telerehab._native")]
pub struct BiasEstimate {
    bias: [f64; 3],
    /// Fraction of the samples detected as rest, in (0, 1].
    #[pyo3(get)]
    rest_fraction: f64,
}

#[pymethods]
impl BiasEstimate {
    /// The mean rate over the rest samples, shape (3,), rad/s.
    #[getter]
    fn bias_rad_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.bias)
    }

    /// `(bias_rad_s, rest_fraction)`, so that `bias, frac = estimate_bias(...)` works.
    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyIterator>> {
        let bias = self.bias_rad_s(py).into_any();
        let fraction = self.rest_fraction.into_pyobject(py)?.into_any();
        PyTuple::new(py, [bias, fraction])?.try_iter()
    }

    fn __repr__(&self) -> String {
        format!(
            "BiasEstimate(bias_rad_s=[{:.6e}, {:.6e}, {:.6e}], rest_fraction={:.4})",
            self.bias[0], self.bias[1], self.bias[2], self.rest_fraction
        )
    }
}

/// Mean rate over the detected rest periods.
#[pyfunction]
#[pyo3(signature = (rates_rad_s, dt_s, acc_m_s2, rate_threshold_deg_s, min_rest_s))]
fn imu_estimate_bias(
    py: Python<'_>,
    rates_rad_s: PyReadonlyArray2<'_, f64>,
    dt_s: f64,
    acc_m_s2: Option<PyReadonlyArray2<'_, f64>>,
    rate_threshold_deg_s: f64,
    min_rest_s: f64,
) -> PyResult<BiasEstimate> {
    let w = vectors("rates_rad_s", &rates_rad_s)?;
    let a = acc_m_s2
        .as_ref()
        .map(|a| vectors("acc_m_s2", a))
        .transpose()?;
    if let Some(a) = &a {
        same_len("acc_m_s2", a.len(), "rates_rad_s", w.len())?;
    }
    check_dt(dt_s)?;
    let cfg = RestConfig {
        rate_threshold_deg_s,
        min_duration_s: min_rest_s,
        ..RestConfig::default()
    };
    let (b, rest_fraction) = py
        .detach(|| estimate_bias(&w, a.as_deref(), dt_s, cfg))
        .map_err(imu_error)?;
    Ok(BiasEstimate {
        bias: [b.x, b.y, b.z],
        rest_fraction,
    })
}

/// Add the IMU functions to the native module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(imu_integrate, m)?)?;
    m.add_function(wrap_pyfunction!(imu_fuse, m)?)?;
    m.add_function(wrap_pyfunction!(imu_estimate_bias, m)?)?;
    m.add_class::<BiasEstimate>()?;
    Ok(())
}
