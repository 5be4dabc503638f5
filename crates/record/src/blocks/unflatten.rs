//! A sample struct rebuilt from a block's decoded values, through `serde`: the inverse of
//! [`super::flatten`], so a NaN or an infinity a sensor sent reads back as it was recorded
//! (JSON, which has neither, is not in the way). The values come from a sample's cells
//! ([`unflatten`]) or straight from a decoded block's columns (`Layout::decode_samples`:
//! no cell, no vector, no string a sample).

use super::Cell;
use serde::de::{self, DeserializeOwned, IntoDeserializer, Visitor};
use std::fmt;

/// Why cells do not make the sample.
#[derive(Debug)]
pub struct Mismatch(String);

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "the block's cells do not make the sample: {}", self.0)
    }
}

impl std::error::Error for Mismatch {}

impl de::Error for Mismatch {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        Mismatch(msg.to_string())
    }
}

/// One value of a sample as the unflattener reads it: a [`Cell`], borrowed.
#[derive(Clone, Copy, Debug)]
pub(super) enum CellRef<'a> {
    /// A float (NaN and infinities included).
    Float(f64),
    /// An unsigned integer.
    Int(u64),
    /// A flag.
    Bool(bool),
    /// An enum label.
    Text(&'a str),
    /// An optional field left out.
    Absent,
}

/// Where the unflattener reads a sample's values from, one after the other.
pub(super) trait Source<'a> {
    /// The next value, without taking it (`None` past the sample's last).
    fn peek(&self) -> Option<CellRef<'a>>;
    /// Moves past the next value.
    fn advance(&mut self);
    /// Values left in the sample.
    fn left(&self) -> usize;
    /// The next value, taken (`None` past the sample's last).
    #[inline(always)]
    fn next(&mut self) -> Option<CellRef<'a>> {
        let cell = self.peek()?;
        self.advance();
        Some(cell)
    }
}

/// A sample's cells, in order.
struct Cells<'a> {
    cells: &'a [Cell],
    at: usize,
}

impl<'a> Source<'a> for Cells<'a> {
    fn peek(&self) -> Option<CellRef<'a>> {
        Some(match self.cells.get(self.at)? {
            Cell::Float(x) => CellRef::Float(*x),
            Cell::Int(n) => CellRef::Int(*n),
            Cell::Bool(b) => CellRef::Bool(*b),
            Cell::Text(t) => CellRef::Text(t),
            Cell::Absent => CellRef::Absent,
        })
    }

    fn advance(&mut self) {
        self.at += 1;
    }

    fn left(&self) -> usize {
        self.cells.len().saturating_sub(self.at)
    }
}

/// `T` from `cells`, in the field order of its `Serialize` derive (every cell used).
pub fn unflatten<T: DeserializeOwned>(cells: &[Cell]) -> Result<T, Mismatch> {
    from_source(Cells { cells, at: 0 })
}

/// `T` from the values of `source`, in the field order of its `Serialize` derive (every value
/// used).
pub(super) fn from_source<'a, T: DeserializeOwned>(source: impl Source<'a>) -> Result<T, Mismatch> {
    let mut u = Unflattener { source };
    let value = T::deserialize(&mut u)?;
    match u.source.left() {
        0 => Ok(value),
        left => Err(Mismatch(format!("{left} cells left over"))),
    }
}

struct Unflattener<S> {
    source: S,
}

impl<'a, S: Source<'a>> Unflattener<S> {
    #[inline(always)]
    fn next(&mut self) -> Result<CellRef<'a>, Mismatch> {
        self.source
            .next()
            .ok_or_else(|| Mismatch("too few cells".into()))
    }
}

/// A run of `len` values (a struct's fields, an array's elements).
struct Run<'u, S> {
    u: &'u mut Unflattener<S>,
    left: usize,
}

impl<'de, 'a, S: Source<'a>> de::SeqAccess<'de> for Run<'_, S> {
    type Error = Mismatch;
    fn next_element_seed<T: de::DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, Mismatch> {
        if self.left == 0 {
            return Ok(None);
        }
        self.left -= 1;
        seed.deserialize(&mut *self.u).map(Some)
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.left)
    }
}

impl<'de, 'a, S: Source<'a>> de::Deserializer<'de> for &mut Unflattener<S> {
    type Error = Mismatch;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Mismatch> {
        match self.next()? {
            CellRef::Float(x) => visitor.visit_f64(x),
            CellRef::Int(n) => visitor.visit_u64(n),
            CellRef::Bool(b) => visitor.visit_bool(b),
            CellRef::Text(t) => visitor.visit_str(t),
            CellRef::Absent => visitor.visit_none(),
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Mismatch> {
        if matches!(self.source.peek(), Some(CellRef::Absent)) {
            self.source.advance();
            visitor.visit_none()
        } else {
            visitor.visit_some(self)
        }
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Mismatch> {
        visitor.visit_seq(Run {
            u: self,
            left: fields.len(),
        })
    }

    fn deserialize_tuple<V: Visitor<'de>>(
        self,
        len: usize,
        visitor: V,
    ) -> Result<V::Value, Mismatch> {
        visitor.visit_seq(Run { u: self, left: len })
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Mismatch> {
        match self.next()? {
            CellRef::Text(t) => visitor.visit_enum(t.into_deserializer()),
            other => Err(Mismatch(format!(
                "an enum label expected, found {:?}",
                other.owned()
            ))),
        }
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf unit unit_struct newtype_struct seq tuple_struct
        map identifier ignored_any
    }
}

impl CellRef<'_> {
    /// The cell this value is.
    fn owned(self) -> Cell {
        match self {
            CellRef::Float(x) => Cell::Float(x),
            CellRef::Int(n) => Cell::Int(n),
            CellRef::Bool(b) => Cell::Bool(b),
            CellRef::Text(t) => Cell::Text(t.into()),
            CellRef::Absent => Cell::Absent,
        }
    }
}
