//! A sample struct rebuilt from a block's decoded cells, through `serde`: the inverse of
//! [`super::flatten`], so a NaN or an infinity a sensor sent reads back as it was recorded
//! (JSON, which has neither, is not in the way).

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

/// `T` from `cells`, in the field order of its `Serialize` derive (every cell used).
pub fn unflatten<T: DeserializeOwned>(cells: &[Cell]) -> Result<T, Mismatch> {
    let mut u = Unflattener { cells, at: 0 };
    let value = T::deserialize(&mut u)?;
    if u.at != cells.len() {
        return Err(Mismatch(format!("{} cells left over", cells.len() - u.at)));
    }
    Ok(value)
}

struct Unflattener<'a> {
    cells: &'a [Cell],
    at: usize,
}

impl Unflattener<'_> {
    fn next(&mut self) -> Result<&Cell, Mismatch> {
        let cell = self
            .cells
            .get(self.at)
            .ok_or_else(|| Mismatch("too few cells".into()))?;
        self.at += 1;
        Ok(cell)
    }

    fn peek(&self) -> Option<&Cell> {
        self.cells.get(self.at)
    }
}

/// A run of `len` values (a struct's fields, an array's elements).
struct Run<'a, 'b> {
    u: &'a mut Unflattener<'b>,
    left: usize,
}

impl<'de> de::SeqAccess<'de> for Run<'_, '_> {
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
}

impl<'de> de::Deserializer<'de> for &mut Unflattener<'_> {
    type Error = Mismatch;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Mismatch> {
        match self.next()?.clone() {
            Cell::Float(x) => visitor.visit_f64(x),
            Cell::Int(n) => visitor.visit_u64(n),
            Cell::Bool(b) => visitor.visit_bool(b),
            Cell::Text(t) => visitor.visit_string(t),
            Cell::Absent => visitor.visit_none(),
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Mismatch> {
        if matches!(self.peek(), Some(Cell::Absent)) {
            self.at += 1;
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
        match self.next()?.clone() {
            Cell::Text(t) => visitor.visit_enum(t.into_deserializer()),
            other => Err(Mismatch(format!("an enum label expected, found {other:?}"))),
        }
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf unit unit_struct newtype_struct seq tuple_struct
        map identifier ignored_any
    }
}
