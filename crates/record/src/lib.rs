//! The recording format: one type per MCAP channel, the channel table with their schemas, the
//! writer, a reader of whole files ([`Recording`]) and a streaming one in bounded memory for
//! untrusted or long recordings ([`TickStream`], which the hub's replay uses; [`columns`], the
//! same reader giving one column per field, which Python's `telerehab.session.read` uses), and
//! what the therapist's console draws of a recording ([`view`]).
//!
//! Below the station, the hub and the Python package, which all read recordings with it: it
//! depends on the sensing, wheel, calibration and metrics crates for their sample types only,
//! never on the session, the command line or the configuration. The station's recorder thread
//! writes with it; replay, reports, `recover`, the hub's replay and Python read with it.
//!
//! # Module map
//!
//! - [`types`]: one type per channel ([`TickRecord`] holds a tick's samples), the session
//!   metadata and the format version ([`FORMAT_VERSION`]); [`raw`]: the raw inputs and the
//!   body's facts a replay needs; [`scene`]: the arm as a Foxglove 3-D scene.
//! - [`channels`]: the channel table — topic, schema, encoding — with schema snapshots.
//! - [`blocks`]: the compact codec of the high-rate channels (delta-coded quantised columns).
//! - [`writer`]: [`RecordWriter`]; [`recover`]: a killed session's file finished, streaming.
//! - [`reader`]: [`Recording`], a whole file in memory (small files and tests);
//!   [`stream`]: [`TickStream`], ticks one at a time in bounded memory (untrusted or long files).
//! - [`walk`]: the one walk over a file's records that every reader above stands on, with
//!   the one record limit ([`MAX_RECORD_BYTES`]) and the length checks before any parse.
//! - [`selection`]: what to read of a recording ([`Selection`]: channels, a span of session
//!   time), honoured by [`columns`] and [`select`].
//! - [`select`]: chosen channels over a span of session time, read through the file's
//!   summary and indexes without decompressing the rest ([`read_selected`]), and what a file
//!   holds from its summary alone ([`select::recording_info`]).
//! - [`cost`]: what reading a file will cost, from its record headers, before it is read.
//! - [`view`]: what the therapist's console draws of a session, live and replayed.
//!
//! # Example
//!
//! ```
//! use record::{Recording, RecordWriter, SessionMetadata, TickRecord};
//! use std::io::Cursor;
//!
//! let meta = SessionMetadata { seed: 7, loop_rate_hz: 1000.0, ..Default::default() };
//! let mut writer = RecordWriter::new(Cursor::new(Vec::new()), 0, &meta)?;
//! let tick = TickRecord { tick: 1, t_ns: 1_000_000, ..Default::default() };
//! writer.write_tick(&tick, true)?;
//! let bytes = writer.finish()?.into_inner();
//!
//! let recording = Recording::from_bytes(&bytes)?;
//! assert_eq!(recording.metadata, meta);
//! assert_eq!(recording.ticks().collect::<Vec<_>>(), [tick]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod blocks;
pub mod channels;
pub mod columns;
pub mod compare;
pub mod cost;
#[cfg(test)]
mod encoder_tests;
mod error;
pub mod raw;
pub mod reader;
pub mod recover;
pub mod scene;
pub mod select;
pub mod selection;
pub mod stream;
#[cfg(test)]
mod tests;
pub mod types;
pub mod view;
pub mod walk;
pub mod writer;

pub use channels::{CHANNELS, Channel, ChannelSpec};
pub use columns::{RecordingColumns, read_columns, read_columns_path};
pub use cost::{CostLimits, Survey, survey};
pub use error::ReadError;
pub use raw::{BodyFacts, RawImuSample, RawTick, RawWheelSample};
pub use reader::{RecordedRows, Recording, Row, recorded_rows};
pub use select::{Selected, read_selected, read_selected_path};
pub use selection::Selection;
pub use stream::TickStream;
pub use types::{
    ArmCalibrationSample, ArmSample, ArmSetup, AssistSample, ClinicNote, DifficultyNote,
    ExerciseResult, FORMAT_VERSION, MetricsSample, MovementSample, OnlineArmCalibrationSample,
    ScoreSample, SessionMetadata, Stamped, StrengthNow, TickRecord, TimingSample, VehicleSample,
    Watchdog, WheelSample,
};
pub use walk::{Check, MAX_RECORD_BYTES, StreamLimits};
pub use writer::RecordWriter;
