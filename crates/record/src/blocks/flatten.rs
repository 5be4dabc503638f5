//! A sample struct as a flat row of plain values, in field order, through `serde`: the one
//! description of a sample's fields (its `Serialize` derive) drives the JSON and the block
//! encodings alike, so they cannot drift apart.

use serde::ser::{self, Impossible, Serialize};
use std::fmt;

/// One plain value of a flattened sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Prim {
    /// A floating-point field (or one element of a float array).
    Float(f64),
    /// An unsigned integer field.
    Int(u64),
    /// A flag.
    Bool(bool),
    /// A unit enum variant, by its serialised name.
    Text(&'static str),
    /// An optional field left out of this sample.
    Absent,
}

/// A field of a flattened sample: its name and where its values start in the row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FieldStart {
    /// The field's serialised name.
    pub name: &'static str,
    /// Index of its first value in the row.
    pub at: usize,
}

/// Why a sample cannot be flattened: it holds something other than numbers, flags, unit enum
/// variants, optional numbers and fixed arrays of numbers (a programming error, caught by the
/// layout test of every channel).
#[derive(Debug)]
pub struct Unsupported(String);

impl fmt::Display for Unsupported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "cannot flatten a sample field: {}", self.0)
    }
}

impl std::error::Error for Unsupported {}

impl ser::Error for Unsupported {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        Unsupported(msg.to_string())
    }
}

/// Append `sample`'s values to `row`; with `fields`, also note where each field starts.
pub fn flatten<T: Serialize>(
    sample: &T,
    row: &mut Vec<Prim>,
    fields: Option<&mut Vec<FieldStart>>,
) -> Result<(), Unsupported> {
    sample.serialize(&mut Flattener { row, fields })
}

struct Flattener<'a> {
    row: &'a mut Vec<Prim>,
    fields: Option<&'a mut Vec<FieldStart>>,
}

impl Flattener<'_> {
    fn push(&mut self, p: Prim) -> Result<(), Unsupported> {
        self.row.push(p);
        Ok(())
    }

    fn start(&mut self, name: &'static str) {
        let at = self.row.len();
        if let Some(fields) = self.fields.as_deref_mut() {
            fields.push(FieldStart { name, at });
        }
    }
}

fn unsupported<T>(what: &str) -> Result<T, Unsupported> {
    Err(Unsupported(what.to_owned()))
}

impl<'a, 'b> ser::Serializer for &'a mut Flattener<'b> {
    type Ok = ();
    type Error = Unsupported;
    type SerializeSeq = Self;
    type SerializeTuple = Self;
    type SerializeTupleStruct = Impossible<(), Unsupported>;
    type SerializeTupleVariant = Impossible<(), Unsupported>;
    type SerializeMap = Impossible<(), Unsupported>;
    type SerializeStruct = Self;
    type SerializeStructVariant = Impossible<(), Unsupported>;

    fn serialize_bool(self, v: bool) -> Result<(), Unsupported> {
        self.push(Prim::Bool(v))
    }
    fn serialize_i8(self, _: i8) -> Result<(), Unsupported> {
        unsupported("a signed integer")
    }
    fn serialize_i16(self, _: i16) -> Result<(), Unsupported> {
        unsupported("a signed integer")
    }
    fn serialize_i32(self, _: i32) -> Result<(), Unsupported> {
        unsupported("a signed integer")
    }
    fn serialize_i64(self, _: i64) -> Result<(), Unsupported> {
        unsupported("a signed integer")
    }
    fn serialize_u8(self, v: u8) -> Result<(), Unsupported> {
        self.push(Prim::Int(v.into()))
    }
    fn serialize_u16(self, v: u16) -> Result<(), Unsupported> {
        self.push(Prim::Int(v.into()))
    }
    fn serialize_u32(self, v: u32) -> Result<(), Unsupported> {
        self.push(Prim::Int(v.into()))
    }
    fn serialize_u64(self, v: u64) -> Result<(), Unsupported> {
        self.push(Prim::Int(v))
    }
    fn serialize_f32(self, v: f32) -> Result<(), Unsupported> {
        self.push(Prim::Float(v.into()))
    }
    fn serialize_f64(self, v: f64) -> Result<(), Unsupported> {
        self.push(Prim::Float(v))
    }
    fn serialize_char(self, _: char) -> Result<(), Unsupported> {
        unsupported("a char")
    }
    fn serialize_str(self, _: &str) -> Result<(), Unsupported> {
        unsupported("a string (only unit enum variants are text)")
    }
    fn serialize_bytes(self, _: &[u8]) -> Result<(), Unsupported> {
        unsupported("bytes")
    }
    fn serialize_none(self) -> Result<(), Unsupported> {
        self.push(Prim::Absent)
    }
    fn serialize_some<T: ?Sized + Serialize>(self, v: &T) -> Result<(), Unsupported> {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), Unsupported> {
        unsupported("a unit")
    }
    fn serialize_unit_struct(self, _: &'static str) -> Result<(), Unsupported> {
        unsupported("a unit struct")
    }
    fn serialize_unit_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
    ) -> Result<(), Unsupported> {
        self.push(Prim::Text(variant))
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<(), Unsupported> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<(), Unsupported> {
        unsupported("an enum variant with data")
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self, Unsupported> {
        Ok(self)
    }
    fn serialize_tuple(self, _: usize) -> Result<Self, Unsupported> {
        Ok(self)
    }
    fn serialize_tuple_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, Unsupported> {
        unsupported("a tuple struct")
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, Unsupported> {
        unsupported("a tuple variant")
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, Unsupported> {
        unsupported("a map")
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self, Unsupported> {
        Ok(self)
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, Unsupported> {
        unsupported("a struct variant")
    }
}

impl ser::SerializeSeq for &mut Flattener<'_> {
    type Ok = ();
    type Error = Unsupported;
    fn serialize_element<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), Unsupported> {
        v.serialize(&mut **self)
    }
    fn end(self) -> Result<(), Unsupported> {
        Ok(())
    }
}

impl ser::SerializeTuple for &mut Flattener<'_> {
    type Ok = ();
    type Error = Unsupported;
    fn serialize_element<T: ?Sized + Serialize>(&mut self, v: &T) -> Result<(), Unsupported> {
        v.serialize(&mut **self)
    }
    fn end(self) -> Result<(), Unsupported> {
        Ok(())
    }
}

impl ser::SerializeStruct for &mut Flattener<'_> {
    type Ok = ();
    type Error = Unsupported;
    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        v: &T,
    ) -> Result<(), Unsupported> {
        self.start(key);
        v.serialize(&mut **self)
    }
    fn skip_field(&mut self, key: &'static str) -> Result<(), Unsupported> {
        self.start(key);
        self.push(Prim::Absent)
    }
    fn end(self) -> Result<(), Unsupported> {
        Ok(())
    }
}
