//! Recording bindings (`telerehab.session`): a recording read by the `record` crate's column
//! reader ([`record::columns`]: the file streamed once, in bounded memory, the GIL released),
//! its columns handed to numpy without a copy.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use record::columns::{ChannelData, ColumnData, Values, read_columns_path};
use record::{ReadError, StreamLimits};
use std::path::PathBuf;

use crate::check::value_error;

/// Add the recording functions to the native module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(session_read, m)?)?;
    Ok(())
}

/// The Python exception for a recording at `path` that cannot be read.
fn read_error(path: &str, e: ReadError) -> PyErr {
    match e {
        ReadError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(format!("no recording at {path}: {source}"))
        }
        ReadError::Io { source, .. } => {
            PyOSError::new_err(format!("cannot read the recording {path}: {source}"))
        }
        ReadError::NoMetadata => value_error(format!(
            "{path} has no 'session' metadata record: not a telerehab recording"
        )),
        e => value_error(format!(
            "{path} is not a readable telerehab recording (a killed session's file: run \
             `telerehab recover` on it): {e}"
        )),
    }
}

/// One column as a numpy array (`(N,)`, or `(N, elements)` for an array field), or, for enum
/// labels, a tuple `(codes, labels)`: uint32 codes into the list of distinct labels.
fn column<'py>(py: Python<'py>, c: ColumnData) -> PyResult<Bound<'py, PyAny>> {
    fn shaped<'py, T: numpy::Element>(
        py: Python<'py>,
        v: Vec<T>,
        elements: usize,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = v.len();
        let a = PyArray1::from_vec(py, v);
        if elements == 1 {
            return Ok(a.into_any());
        }
        Ok(a.reshape([n / elements.max(1), elements])?.into_any())
    }
    match c.values {
        Values::F64(v) => shaped(py, v, c.elements),
        Values::U64(v) => shaped(py, v, c.elements),
        Values::Bool(v) => shaped(py, v, c.elements),
        Values::Text { codes, labels } => {
            let codes = shaped(py, codes, c.elements)?;
            Ok((codes, PyList::new(py, labels)?)
                .into_pyobject(py)?
                .into_any())
        }
    }
}

/// The recording at `path`: `(metadata, columns, units, json)` — the `session` metadata
/// record; each high-rate channel's columns and their descriptions (unit included), by topic
/// and field; each low-rate channel's `(schema, messages)` as JSON bytes. See
/// `telerehab.session.read`.
#[pyfunction]
#[pyo3(signature = (path))]
fn session_read<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let shown = path.display().to_string();
    let read = py
        .detach(|| read_columns_path(&path, StreamLimits::default()))
        .map_err(|e| read_error(&shown, e))?;
    let columns = PyDict::new(py);
    let units = PyDict::new(py);
    let json = PyDict::new(py);
    for (topic, channel) in read.channels {
        match channel {
            ChannelData::Columns(cols) => {
                let (these, described) = (PyDict::new(py), PyDict::new(py));
                for c in cols {
                    described.set_item(&c.name, &c.description)?;
                    let name = c.name.clone();
                    these.set_item(name, column(py, c)?)?;
                }
                columns.set_item(&topic, these)?;
                units.set_item(&topic, described)?;
            }
            ChannelData::Json { schema, messages } => {
                let messages = messages.iter().map(|m| PyBytes::new(py, m));
                let pair = (PyBytes::new(py, &schema), PyList::new(py, messages)?);
                json.set_item(&topic, pair)?;
            }
        }
    }
    Ok((read.metadata, columns, units, json)
        .into_pyobject(py)?
        .into_any())
}
