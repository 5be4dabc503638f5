//! Compact blocks: the high-rate channels recorded as protobuf messages of one column per
//! field over a block of consecutive samples, the protobuf descriptor in the file.
//!
//! A block message holds `tick` and `t_ns` (session time, ns) and each field of the sample as
//! one packed repeated column, samples in order (an array field's elements interleaved,
//! sample by sample). Numbers are stored as `sint64` *differences* from the previous sample's
//! value of the same element (the first from 0, wrapping), so a smooth 1 kHz signal costs a
//! byte or two a sample before the file's zstd; a float is first quantised to an integer
//! number of its *quantum*: a millionth of its SI unit (1 µrad, 1 µN·m, 1 µm, 1 µm/s²,
//! 1 µs), a thousandth of a newton, a billionth for a unitless number (quaternion components,
//! axes, levels) — finer than any sensor of the station measures. Four integers are reserved:
//! [`ABSENT`] (an optional field left out), [`NAN`], [`NEG_INF`] and [`POS_INF`]; finite values
//! saturate at ±2⁶² quanta. Flags are packed `bool`s, enum labels repeated strings (zstd folds
//! their repeats).
//!
//! Every block channel's record carries its columns as JSON ([`COLUMNS_KEY`]: name, type,
//! elements, quantum, description with the unit), so a reader needs only the file (Foxglove's
//! protobuf decoder reads the blocks; the Python package reads them through
//! [`crate::columns`]).
//!
//! The fields, their order and their names come from the sample's `Serialize` derive (through
//! [`flatten`]) and their descriptions from its JSON schema: one definition per channel.

pub mod flatten;
pub mod unflatten;
mod wire;

use flatten::{FieldStart, Prim, Unsupported};
use prost::Message as _;
use prost_reflect::{DescriptorPool, MessageDescriptor};
#[cfg(test)]
use prost_reflect::{DynamicMessage, Value};
use prost_types::field_descriptor_proto::{Label, Type};
use prost_types::{DescriptorProto, FieldDescriptorProto, FileDescriptorProto, FileDescriptorSet};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Schema and message encoding of a block channel.
pub const ENCODING: &str = "protobuf";
/// The channel metadata key of the columns (JSON).
pub const COLUMNS_KEY: &str = "telerehab.columns";
/// The channel metadata key naming the block encoding.
pub const ENCODING_KEY: &str = "telerehab.encoding";
/// The block encoding described above, by name.
pub const ENCODING_NAME: &str = "delta-quantised-columns-v1";

/// Stored for an optional field left out of a sample.
pub const ABSENT: i64 = i64::MIN;
/// Stored for a NaN.
pub const NAN: i64 = i64::MIN + 1;
/// Stored for −∞.
pub const NEG_INF: i64 = i64::MIN + 2;
/// Stored for +∞.
pub const POS_INF: i64 = i64::MAX;
/// Largest magnitude of a finite quantised value (2⁶²).
const FINITE_LIMIT: f64 = (1u64 << 62) as f64;

/// The type of one column.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Floating point, quantised.
    Float,
    /// Unsigned integer, exact.
    Int,
    /// Flag.
    Bool,
    /// Enum label.
    Text,
}

/// One column of a block channel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Column {
    /// The field's name (the sample's JSON field name).
    pub name: String,
    /// Its type.
    #[serde(rename = "type")]
    pub kind: Kind,
    /// Elements per sample (1, or an array field's length).
    pub elements: usize,
    /// The quantum of a float, in the field's unit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quantum: Option<f64>,
    /// What the field is, unit included (from the sample's documentation).
    pub description: String,
}

/// Why a block does not encode or decode.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BlockError {
    /// The sample type holds a field blocks cannot store.
    #[error(transparent)]
    Unsupported(#[from] Unsupported),
    /// The channel's columns or descriptor are not what this reader understands.
    #[error("the block layout is unreadable: {0}")]
    Layout(String),
    /// A block message does not decode.
    #[error("a block message does not decode: {0}")]
    Decode(String),
}

/// The columns of a block channel and its protobuf descriptor.
#[derive(Clone, Debug)]
pub struct Layout {
    columns: Vec<Column>,
    /// Where each column's first element sits in a flattened row.
    offsets: Vec<usize>,
    row_width: usize,
    descriptor: MessageDescriptor,
    descriptor_set: Vec<u8>,
}

/// The two stamp columns every block starts with.
fn stamp_columns() -> [Column; 2] {
    let int = |name: &str, description: &str| Column {
        name: name.into(),
        kind: Kind::Int,
        elements: 1,
        quantum: None,
        description: description.into(),
    };
    [
        int("tick", "Haptic tick number since the session start."),
        int("t_ns", "Session time, ns."),
    ]
}

/// The quantum of a float field, from the unit its name ends with; an IMU axis as the device
/// delivered it (`gyro_…`, `acc_…` on `/raw/imu`) is recorded to 100 µrad/s or 100 µm/s², ten
/// times finer than a game controller's least significant bit (its noise would cost two bytes a
/// sample more at a millionth).
pub fn quantum_of(name: &str) -> f64 {
    if name.starts_with("gyro_") || name.starts_with("acc_") {
        return 1e-4;
    }
    const MICRO: [&str; 9] = [
        "_rad",
        "_rad_s",
        "_m",
        "_m_s",
        "_m_s2",
        "_nm",
        "_s",
        "_j",
        "_nm_s_per_rad",
    ];
    if name.ends_with("_n") {
        1e-3
    } else if MICRO.iter().any(|u| name.ends_with(u)) {
        1e-6
    } else {
        1e-9
    }
}

impl Layout {
    /// The layout of samples of type `T`, as message `telerehab.<message>`.
    pub fn of<T: Serialize + Default + schemars::JsonSchema>(
        message: &str,
    ) -> Result<Self, BlockError> {
        let schema = serde_json::to_value(schemars::schema_for!(T))
            .map_err(|e| BlockError::Layout(e.to_string()))?;
        let props = &schema["properties"];
        let mut row = Vec::new();
        let mut starts: Vec<FieldStart> = Vec::new();
        flatten::flatten(&T::default(), &mut row, Some(&mut starts))?;
        let mut columns = stamp_columns().to_vec();
        for (i, start) in starts.iter().enumerate() {
            let end = starts.get(i + 1).map_or(row.len(), |s| s.at);
            let prop = &props[start.name];
            let kind = match row[start.at] {
                Prim::Float(_) => Kind::Float,
                Prim::Int(_) => Kind::Int,
                Prim::Bool(_) => Kind::Bool,
                Prim::Text(_) => Kind::Text,
                Prim::Absent if prop["type"] == "number" => Kind::Float,
                Prim::Absent => {
                    return Err(BlockError::Layout(format!(
                        "optional field {} is not a number",
                        start.name
                    )));
                }
            };
            columns.push(Column {
                name: start.name.into(),
                kind,
                elements: end - start.at,
                quantum: (kind == Kind::Float).then(|| quantum_of(start.name)),
                description: prop["description"].as_str().unwrap_or_default().into(),
            });
        }
        let descriptor_set = descriptor_set(message, &columns);
        Self::new(message, columns, descriptor_set)
    }

    /// The layout a recording's channel declares: its columns (channel metadata) and its
    /// schema (a `FileDescriptorSet` holding `telerehab.<message>`).
    pub fn from_file(
        schema_name: &str,
        schema: &[u8],
        metadata: &BTreeMap<String, String>,
    ) -> Result<Self, BlockError> {
        let columns: Vec<Column> = metadata
            .get(COLUMNS_KEY)
            .ok_or_else(|| BlockError::Layout(format!("no {COLUMNS_KEY} in the channel")))
            .and_then(|j| serde_json::from_str(j).map_err(|e| BlockError::Layout(e.to_string())))?;
        let message = schema_name
            .strip_prefix("telerehab.")
            .unwrap_or(schema_name);
        Self::new(message, columns, schema.to_vec())
    }

    fn new(
        message: &str,
        columns: Vec<Column>,
        descriptor_set: Vec<u8>,
    ) -> Result<Self, BlockError> {
        let pool = DescriptorPool::decode(descriptor_set.as_slice())
            .map_err(|e| BlockError::Layout(e.to_string()))?;
        let descriptor = pool
            .get_message_by_name(&format!("telerehab.{message}"))
            .ok_or_else(|| BlockError::Layout(format!("no message telerehab.{message}")))?;
        if columns.len() < 2 || columns[..2] != stamp_columns() {
            return Err(BlockError::Layout("the stamp columns are missing".into()));
        }
        for (number, c) in (1u32..).zip(&columns) {
            let wire = match c.kind {
                Kind::Float | Kind::Int => prost_reflect::Kind::Sint64,
                Kind::Bool => prost_reflect::Kind::Bool,
                Kind::Text => prost_reflect::Kind::String,
            };
            if descriptor
                .get_field(number)
                .is_none_or(|f| f.name() != c.name || !f.is_list() || f.kind() != wire)
            {
                return Err(BlockError::Layout(format!(
                    "column {} is not field {number} of the descriptor (repeated, of its type)",
                    c.name
                )));
            }
        }
        let mut offsets = Vec::with_capacity(columns.len());
        let mut row_width = 0;
        for c in &columns {
            offsets.push(row_width);
            row_width += c.elements;
        }
        Ok(Self {
            columns,
            offsets,
            row_width,
            descriptor,
            descriptor_set,
        })
    }

    /// The columns, stamps first.
    pub fn columns(&self) -> &[Column] {
        &self.columns
    }

    /// The schema data: the serialised `FileDescriptorSet`.
    pub fn schema(&self) -> &[u8] {
        &self.descriptor_set
    }

    /// The message's full name (the MCAP schema name).
    pub fn message_name(&self) -> &str {
        self.descriptor.full_name()
    }

    /// The channel metadata that describes the columns.
    pub fn channel_metadata(&self) -> BTreeMap<String, String> {
        BTreeMap::from([
            (ENCODING_KEY.into(), ENCODING_NAME.into()),
            (
                COLUMNS_KEY.into(),
                serde_json::to_string(&self.columns).expect("columns serialise"),
            ),
        ])
    }

    /// Encode `rows` flattened samples (`prims`, stamps first) as one block message into
    /// `out` (emptied first), written straight in the protobuf wire format ([`wire`]): the
    /// bytes a reflective encoder of the descriptor writes (the test `encoder_matches_prost_reflect`),
    /// without a dynamic value per element. `scratch` holds one column at a time.
    pub(crate) fn encode_into(
        &self,
        prims: &[Prim],
        rows: usize,
        out: &mut Vec<u8>,
        scratch: &mut Scratch,
    ) {
        out.clear();
        for (number, (c, &offset)) in (1u32..).zip(self.columns.iter().zip(&self.offsets)) {
            let cells = (0..rows).flat_map(|r| {
                let at = r * self.row_width + offset;
                &prims[at..at + c.elements]
            });
            match c.kind {
                Kind::Text => {
                    for prim in cells {
                        let text = match prim {
                            Prim::Text(t) => t,
                            _ => "",
                        };
                        wire::put_bytes(out, number, text.as_bytes());
                    }
                }
                Kind::Bool => {
                    scratch.packed.clear();
                    scratch
                        .packed
                        .extend(cells.map(|p| u8::from(matches!(p, Prim::Bool(true)))));
                    wire::put_packed(out, number, &scratch.packed);
                }
                Kind::Float | Kind::Int => {
                    let quantum = c.quantum.unwrap_or(1.0);
                    scratch.prev.clear();
                    scratch.prev.resize(c.elements, 0);
                    scratch.packed.clear();
                    for (i, prim) in cells.enumerate() {
                        let v = match *prim {
                            Prim::Float(x) => quantise(x, quantum),
                            Prim::Int(n) => n as i64,
                            _ => ABSENT,
                        };
                        let p = &mut scratch.prev[i % c.elements];
                        let d = v.wrapping_sub(*p);
                        *p = v;
                        wire::put_varint(&mut scratch.packed, wire::zigzag_encode(d));
                    }
                    wire::put_packed(out, number, &scratch.packed);
                }
            }
        }
    }

    /// The reflective encoder the block format was first written with (`prost-reflect`'s
    /// dynamic message), kept to check [`Layout::encode_into`] against.
    #[cfg(test)]
    pub(crate) fn encode_reflective(&self, prims: &[Prim], rows: usize) -> Vec<u8> {
        let mut msg = DynamicMessage::new(self.descriptor.clone());
        for (number, (c, &offset)) in (1u32..).zip(self.columns.iter().zip(&self.offsets)) {
            let mut prev = vec![0i64; c.elements];
            let mut list = Vec::with_capacity(rows * c.elements);
            for r in 0..rows {
                let at = r * self.row_width + offset;
                for (e, p) in prev.iter_mut().enumerate() {
                    let prim = prims[at + e];
                    list.push(match c.kind {
                        Kind::Bool => Value::Bool(matches!(prim, Prim::Bool(true))),
                        Kind::Text => Value::String(match prim {
                            Prim::Text(t) => t.to_owned(),
                            _ => String::new(),
                        }),
                        Kind::Float | Kind::Int => {
                            let v = match prim {
                                Prim::Float(x) => quantise(x, c.quantum.unwrap_or(1.0)),
                                Prim::Int(n) => n as i64,
                                _ => ABSENT,
                            };
                            let d = v.wrapping_sub(*p);
                            *p = v;
                            Value::I64(d)
                        }
                    });
                }
            }
            msg.set_field_by_number(number, Value::List(list));
        }
        msg.encode_to_vec()
    }

    /// Decode one block message column by column: `visit` gets each column (stamps first)
    /// with its values, every sample's elements in order (an array field's elements
    /// interleaved, sample by sample). Returns the number of samples. What the block readers
    /// ([`Layout::decode_cells`], [`crate::columns`]) share: the differences summed (wrapping),
    /// every column checked to hold one value per element of every sample.
    pub fn decode_columns(
        &self,
        bytes: &[u8],
        mut visit: impl FnMut(&Column, ColumnValues) -> Result<(), BlockError>,
    ) -> Result<usize, BlockError> {
        let mut scratch = DecodeScratch::default();
        let rows = self.decode_values(bytes, &mut scratch)?;
        for (c, values) in self.columns.iter().zip(&mut scratch.lists) {
            let values = match values {
                wire::Values::Stored(v) => ColumnValues::Stored(std::mem::take(v)),
                wire::Values::Bools(v) => ColumnValues::Bools(std::mem::take(v)),
                wire::Values::Texts(v) => ColumnValues::Texts(
                    v.iter()
                        .map(|r| wire::text(bytes, r.clone()).to_owned())
                        .collect(),
                ),
            };
            visit(c, values)?;
        }
        Ok(rows)
    }

    /// Decode one block message into `scratch`'s columns (one a column of the layout, its
    /// differences summed) and check that every column holds one value per element of every
    /// sample. Returns the number of samples.
    fn decode_values(
        &self,
        bytes: &[u8],
        scratch: &mut DecodeScratch,
    ) -> Result<usize, BlockError> {
        let lists = &mut scratch.lists;
        let fits = lists.len() == self.columns.len()
            && lists
                .iter()
                .zip(&self.columns)
                .all(|(l, c)| l.holds(c.kind));
        if fits {
            lists.iter_mut().for_each(wire::Values::clear);
        } else {
            *lists = self
                .columns
                .iter()
                .map(|c| wire::Values::of(c.kind))
                .collect();
        }
        wire::decode(bytes, lists).map_err(BlockError::Decode)?;
        let mut rows = None;
        for (c, values) in self.columns.iter().zip(lists.iter_mut()) {
            let n = values.len();
            let rows = *rows.get_or_insert(n);
            if n != rows * c.elements {
                return Err(BlockError::Decode(format!(
                    "column {} holds {n} values for {rows} samples of {} elements",
                    c.name, c.elements
                )));
            }
            if let wire::Values::Stored(v) = values {
                // Differences from the previous sample's value of the same element.
                if c.elements == 1 {
                    let mut p = 0i64;
                    for d in v.iter_mut() {
                        p = p.wrapping_add(*d);
                        *d = p;
                    }
                } else {
                    let prev = &mut scratch.prev;
                    prev.clear();
                    prev.resize(c.elements, 0);
                    for sample in v.chunks_exact_mut(c.elements) {
                        for (d, p) in sample.iter_mut().zip(prev.iter_mut()) {
                            *p = p.wrapping_add(*d);
                            *d = *p;
                        }
                    }
                }
            }
        }
        Ok(rows.unwrap_or(0))
    }

    /// Decode one block message straight into its samples of type `T` (whose `Serialize`
    /// derive made this layout's columns), column by column, and hand each to `each` with
    /// its `tick` and `t_ns`: what [`Self::decode_cells`] and [`unflatten::unflatten`] give,
    /// without a cell, a vector or a string a sample (`scratch` holds the columns, kept from
    /// message to message). Returns the number of samples, or the error and the index within
    /// the message of the sample it is about (0 for the message as a whole).
    pub(crate) fn decode_samples<T: serde::de::DeserializeOwned>(
        &self,
        bytes: &[u8],
        scratch: &mut DecodeScratch,
        mut each: impl FnMut(u64, u64, T),
    ) -> Result<usize, (usize, BlockError)> {
        let rows = self.decode_values(bytes, scratch).map_err(|e| (0, e))?;
        let lists = &scratch.lists;
        let stamp = |column: usize, row: usize| match &lists[column] {
            wire::Values::Stored(v) => v[row] as u64,
            _ => unreachable!("the stamp columns are checked to be integers"),
        };
        for row in 0..rows {
            let sample = unflatten::from_source(SampleCells::new(self, lists, bytes, row))
                .map_err(|e| (row, BlockError::Decode(e.to_string())))?;
            each(stamp(0, row), stamp(1, row), sample);
        }
        Ok(rows)
    }

    /// The number of samples in one block message and the tick of its last one, from its
    /// first column (`tick`) alone: the other columns are skipped, not decoded (what a reader
    /// that compares whole messages needs to count and place them).
    pub fn stamps(&self, bytes: &[u8]) -> Result<(usize, Option<u64>), BlockError> {
        let mut ticks = [wire::Values::Stored(Vec::new())];
        wire::decode(bytes, &mut ticks).map_err(BlockError::Decode)?;
        let [wire::Values::Stored(deltas)] = ticks else {
            unreachable!("one stored column asked for")
        };
        let last = deltas.iter().fold(0i64, |p, d| p.wrapping_add(*d));
        Ok((deltas.len(), (!deltas.is_empty()).then_some(last as u64)))
    }

    /// Decode one block message into its samples, each the cells of every column in order
    /// (stamps first, an array field's elements one cell each).
    pub fn decode_cells(&self, bytes: &[u8]) -> Result<Vec<Vec<Cell>>, BlockError> {
        let mut out: Vec<Vec<Cell>> = Vec::new();
        self.decode_columns(bytes, |c, values| {
            let n = values.len();
            if out.is_empty() && n > 0 {
                out = vec![Vec::with_capacity(self.row_width); n / c.elements.max(1)];
            }
            let width = c.elements.max(1);
            match values {
                ColumnValues::Stored(v) => {
                    for (i, q) in v.into_iter().enumerate() {
                        out[i / width].push(match c.kind {
                            Kind::Int => Cell::Int(q as u64),
                            _ => unquantise(q, c.quantum.unwrap_or(1.0))
                                .map_or(Cell::Absent, Cell::Float),
                        });
                    }
                }
                ColumnValues::Bools(v) => {
                    for (i, b) in v.into_iter().enumerate() {
                        out[i / width].push(Cell::Bool(b));
                    }
                }
                ColumnValues::Texts(v) => {
                    for (i, t) in v.into_iter().enumerate() {
                        out[i / width].push(Cell::Text(t));
                    }
                }
            }
            Ok(())
        })?;
        Ok(out)
    }

    /// Decode one block message into its samples, each a JSON object (`tick`, `t_s`, then the
    /// fields; an absent optional field left out, a NaN or infinity as null).
    pub fn decode(
        &self,
        bytes: &[u8],
    ) -> Result<Vec<serde_json::Map<String, serde_json::Value>>, BlockError> {
        let rows = self.decode_cells(bytes)?;
        Ok(rows.iter().map(|cells| self.row_of(cells)).collect())
    }

    /// One sample's cells ([`Self::decode_cells`]) as a JSON object, as [`Self::decode`]
    /// gives it.
    pub fn row_of(&self, cells: &[Cell]) -> serde_json::Map<String, serde_json::Value> {
        use serde_json::Value as J;
        let json = Cell::json;
        let mut row = serde_json::Map::new();
        for (c, &at) in self.columns.iter().zip(&self.offsets) {
            let Some(cells) = cells.get(at..at + c.elements) else {
                break;
            };
            match (c.name.as_str(), cells) {
                ("t_ns", [Cell::Int(t_ns)]) => {
                    row.insert("t_s".into(), J::from(*t_ns as f64 * 1e-9));
                }
                (_, [Cell::Absent]) => {}
                (name, [one]) => {
                    row.insert(name.into(), json(one));
                }
                (name, many) => {
                    row.insert(name.into(), J::Array(many.iter().map(json).collect()));
                }
            }
        }
        row
    }

    /// Whether `other` lays its samples out cell for cell as this one does (the same column
    /// names, types, element counts and quanta): their cells then compare as their rows do.
    pub fn same_cells_as(&self, other: &Layout) -> bool {
        self.columns.len() == other.columns.len()
            && self.columns.iter().zip(&other.columns).all(|(a, b)| {
                a.name == b.name
                    && a.kind == b.kind
                    && a.elements == b.elements
                    && a.quantum.map(f64::to_bits) == b.quantum.map(f64::to_bits)
            })
    }

    /// The column names, in order.
    pub fn column_names(&self) -> impl Iterator<Item = &str> {
        self.columns.iter().map(|c| c.name.as_str())
    }
}

/// One column of a decoded block message ([`Layout::decode_columns`]), every sample's
/// elements in order.
#[derive(Clone, Debug, PartialEq)]
pub enum ColumnValues {
    /// A float or integer column: the whole numbers stored (a float's quanta, the reserved
    /// values included: [`unquantise`] gives the float; an integer is its `u64` bits).
    Stored(Vec<i64>),
    /// A flag column.
    Bools(Vec<bool>),
    /// An enum label column.
    Texts(Vec<String>),
}

impl ColumnValues {
    /// Values held.
    pub fn len(&self) -> usize {
        match self {
            Self::Stored(v) => v.len(),
            Self::Bools(v) => v.len(),
            Self::Texts(v) => v.len(),
        }
    }

    /// No value held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One decoded value of a block's sample.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    /// A float (NaN and infinities included).
    Float(f64),
    /// An unsigned integer.
    Int(u64),
    /// A flag.
    Bool(bool),
    /// An enum label.
    Text(String),
    /// An optional field left out.
    Absent,
}

impl Cell {
    /// The cell as a row holds it (a NaN or infinity, and an absent field, as null).
    pub fn json(&self) -> serde_json::Value {
        use serde_json::Value as J;
        match self {
            Cell::Float(x) => serde_json::Number::from_f64(*x).map_or(J::Null, J::Number),
            Cell::Int(n) => J::from(*n),
            Cell::Bool(b) => J::Bool(*b),
            Cell::Text(t) => J::String(t.clone()),
            Cell::Absent => J::Null,
        }
    }
}

/// `x` as a whole number of `quantum`s (the reserved values for NaN and infinities).
pub fn quantise(x: f64, quantum: f64) -> i64 {
    if x.is_nan() {
        NAN
    } else if x == f64::INFINITY {
        POS_INF
    } else if x == f64::NEG_INFINITY {
        NEG_INF
    } else {
        (x / quantum).round().clamp(-FINITE_LIMIT, FINITE_LIMIT) as i64
    }
}

/// The value `quantise` stored as `q` (`None` for an absent field).
pub fn unquantise(q: i64, quantum: f64) -> Option<f64> {
    match q {
        ABSENT => None,
        NAN => Some(f64::NAN),
        NEG_INF => Some(f64::NEG_INFINITY),
        POS_INF => Some(f64::INFINITY),
        _ => Some(q as f64 * quantum),
    }
}

/// `sample` as its recording reads back: every float rounded to its field's quantum (what a
/// block stores), the rest unchanged. A NaN or infinite float does not read back into the
/// sample type (JSON has no such number): such a sample is returned as it was.
pub fn as_recorded<T: Serialize + serde::de::DeserializeOwned + Clone>(sample: &T) -> T {
    fn round(name: &str, v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Number(n) if n.is_f64() => {
                let q = quantum_of(name);
                let x = n.as_f64().and_then(|x| unquantise(quantise(x, q), q));
                if let Some(n) = x.and_then(serde_json::Number::from_f64) {
                    *v = serde_json::Value::Number(n);
                }
            }
            serde_json::Value::Array(items) => items.iter_mut().for_each(|x| round(name, x)),
            _ => {}
        }
    }
    let Ok(mut json) = serde_json::to_value(sample) else {
        return sample.clone();
    };
    if let Some(fields) = json.as_object_mut() {
        fields.iter_mut().for_each(|(name, v)| round(name, v));
    }
    serde_json::from_value(json).unwrap_or_else(|_| sample.clone())
}

/// The `FileDescriptorSet` of message `telerehab.<message>`: one repeated field per column,
/// numbered from 1 in column order.
fn descriptor_set(message: &str, columns: &[Column]) -> Vec<u8> {
    let field = columns
        .iter()
        .zip(1..)
        .map(|(c, number)| FieldDescriptorProto {
            name: Some(c.name.clone()),
            number: Some(number),
            label: Some(Label::Repeated as i32),
            r#type: Some(match c.kind {
                Kind::Float | Kind::Int => Type::Sint64,
                Kind::Bool => Type::Bool,
                Kind::Text => Type::String,
            } as i32),
            json_name: Some(c.name.clone()),
            ..Default::default()
        })
        .collect();
    FileDescriptorSet {
        file: vec![FileDescriptorProto {
            name: Some(format!("telerehab/{message}.proto")),
            package: Some("telerehab".into()),
            message_type: vec![DescriptorProto {
                name: Some(message.into()),
                field,
                ..Default::default()
            }],
            syntax: Some("proto3".into()),
            ..Default::default()
        }],
    }
    .encode_to_vec()
}

/// The columns of the last block message decoded by [`Layout::decode_samples`], kept for the
/// next one (no allocation a message once grown).
#[derive(Debug, Default)]
pub(crate) struct DecodeScratch {
    /// One list of values a column.
    lists: Vec<wire::Values>,
    /// A column's previous sample, element by element.
    prev: Vec<i64>,
}

/// The cells of one sample of a decoded block, after its stamps, read from its columns in
/// place ([`Layout::decode_samples`]).
struct SampleCells<'a> {
    columns: &'a [Column],
    lists: &'a [wire::Values],
    bytes: &'a [u8],
    row: usize,
    /// The column and the element within it of the next cell.
    column: usize,
    element: usize,
    left: usize,
}

impl<'a> SampleCells<'a> {
    fn new(layout: &'a Layout, lists: &'a [wire::Values], bytes: &'a [u8], row: usize) -> Self {
        let mut cells = Self {
            columns: &layout.columns,
            lists,
            bytes,
            row,
            column: 2,
            element: 0,
            left: layout.row_width.saturating_sub(2),
        };
        cells.skip_empty_columns();
        cells
    }

    /// Past any column of no element.
    fn skip_empty_columns(&mut self) {
        while self
            .columns
            .get(self.column)
            .is_some_and(|c| c.elements == 0)
        {
            self.column += 1;
        }
    }
}

impl<'a> unflatten::Source<'a> for SampleCells<'a> {
    #[inline(always)]
    fn peek(&self) -> Option<unflatten::CellRef<'a>> {
        use unflatten::CellRef;
        if self.left == 0 {
            return None;
        }
        let c = &self.columns[self.column];
        let i = self.row * c.elements + self.element;
        Some(match &self.lists[self.column] {
            wire::Values::Stored(v) if c.kind == Kind::Int => CellRef::Int(v[i] as u64),
            wire::Values::Stored(v) => {
                unquantise(v[i], c.quantum.unwrap_or(1.0)).map_or(CellRef::Absent, CellRef::Float)
            }
            wire::Values::Bools(v) => CellRef::Bool(v[i]),
            wire::Values::Texts(v) => CellRef::Text(wire::text(self.bytes, v[i].clone())),
        })
    }

    #[inline(always)]
    fn advance(&mut self) {
        if self.left == 0 {
            return;
        }
        self.left -= 1;
        self.element += 1;
        if self.element == self.columns[self.column].elements {
            self.element = 0;
            self.column += 1;
            self.skip_empty_columns();
        }
    }

    fn left(&self) -> usize {
        self.left
    }
}

/// Samples of one channel gathered into a block.
#[derive(Debug)]
pub struct BlockBuilder {
    prims: Vec<Prim>,
    rows: usize,
    first_t_ns: u64,
    scratch: Scratch,
}

/// The encoder's working space, kept from block to block (no allocation once grown).
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    /// A column's previous sample, element by element (quantised).
    prev: Vec<i64>,
    /// A packed column's payload.
    packed: Vec<u8>,
}

impl BlockBuilder {
    /// An empty block.
    pub fn new() -> Self {
        Self {
            prims: Vec::new(),
            rows: 0,
            first_t_ns: 0,
            scratch: Scratch::default(),
        }
    }

    /// Add one sample stamped with `tick` and `t_ns`.
    pub fn push<T: Serialize>(
        &mut self,
        tick: u64,
        t_ns: u64,
        sample: &T,
    ) -> Result<(), BlockError> {
        if self.rows == 0 {
            self.first_t_ns = t_ns;
        }
        self.prims.push(Prim::Int(tick));
        self.prims.push(Prim::Int(t_ns));
        flatten::flatten(sample, &mut self.prims, None)?;
        self.rows += 1;
        Ok(())
    }

    /// Samples gathered.
    pub fn len(&self) -> usize {
        self.rows
    }

    /// No sample gathered.
    pub fn is_empty(&self) -> bool {
        self.rows == 0
    }

    /// Session time of the first sample, ns.
    pub fn first_t_ns(&self) -> u64 {
        self.first_t_ns
    }

    /// The block's message in `layout`; the builder is emptied for the next block.
    pub fn take(&mut self, layout: &Layout) -> Result<Vec<u8>, BlockError> {
        let mut bytes = Vec::new();
        self.take_into(layout, &mut bytes)?;
        Ok(bytes)
    }

    /// The block's message in `layout` written into `out` (emptied first; its capacity is
    /// reused); the builder is emptied for the next block.
    pub fn take_into(&mut self, layout: &Layout, out: &mut Vec<u8>) -> Result<(), BlockError> {
        if self.prims.len() != self.rows * layout.row_width {
            return Err(BlockError::Layout(format!(
                "{} values for {} samples of {} values",
                self.prims.len(),
                self.rows,
                layout.row_width
            )));
        }
        layout.encode_into(&self.prims, self.rows, out, &mut self.scratch);
        self.prims.clear();
        self.rows = 0;
        Ok(())
    }
}

impl Default for BlockBuilder {
    fn default() -> Self {
        Self::new()
    }
}
