//! Recording bindings (`telerehab.session`): a recording read by the `record` crate's column
//! reader ([`record::columns`]: the file streamed once, in bounded memory, the GIL released),
//! or chosen channels over a window of it ([`record::select`]: only the chunks holding them
//! decompressed, through the file's summary), its columns handed to numpy without a copy; and
//! what a recording holds, from its summary ([`record::select::info`]).

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyKeyError, PyOSError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use record::columns::{ChannelData, ColumnData, Values, read_columns_path};
use record::select::{RecordingInfo, recording_info_path};
use record::{ReadError, Selection, StreamLimits, read_selected_path};
use std::path::PathBuf;

use crate::check::value_error;

/// Add the recording functions to the native module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(session_read, m)?)?;
    m.add_function(wrap_pyfunction!(session_info, m)?)?;
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
        e @ ReadError::NoSuchChannel { .. } => PyKeyError::new_err(format!("{path}: {e}")),
        e @ ReadError::BadSelection(_) => value_error(format!("{path}: {e}")),
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

/// The recording at `path` (its `channels` over `[start_s, end_s)` of session time, when
/// given): `(metadata, columns, units, json)` — the `session` metadata record; each high-rate
/// channel's columns and their descriptions (unit included), by topic and field; each low-rate
/// channel's `(schema, messages)` as JSON bytes. See `telerehab.session.read`.
#[pyfunction]
#[pyo3(signature = (path, channels=None, start_s=None, end_s=None))]
fn session_read<'py>(
    py: Python<'py>,
    path: PathBuf,
    channels: Option<Vec<String>>,
    start_s: Option<f64>,
    end_s: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let shown = path.display().to_string();
    let selection = Selection {
        topics: channels,
        start_s,
        end_s,
    };
    let limits = StreamLimits::default();
    let read = py
        .detach(|| {
            if selection == Selection::default() {
                read_columns_path(&path, limits)
            } else {
                read_selected_path(&path, limits, &selection).map(|s| s.columns)
            }
        })
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

/// What the recording at `path` holds, from its summary (walked when it has none):
/// `(metadata, chunks, indexed, channels)`, each channel `(topic, encoding, schema, readable,
/// messages, first_s, last_s)`. See `telerehab.session.info`.
#[pyfunction]
#[pyo3(signature = (path))]
fn session_info<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let shown = path.display().to_string();
    let info: RecordingInfo = py
        .detach(|| recording_info_path(&path, StreamLimits::default()))
        .map_err(|e| read_error(&shown, e))?;
    let channels = info
        .channels
        .into_iter()
        .map(|c| {
            (
                c.topic, c.encoding, c.schema, c.readable, c.messages, c.first_s, c.last_s,
            )
        })
        .collect::<Vec<_>>();
    Ok((info.metadata, info.chunks, info.indexed, channels)
        .into_pyobject(py)?
        .into_any())
}
