//! The protobuf wire format of a block message, decoded straight into its columns: a block
//! is one repeated field per column (`sint64`, `bool` or `string`, checked against the
//! descriptor by [`super::Layout`]), so a reader needs only varints, zigzag and lengths
//! (<https://protobuf.dev/programming-guides/encoding/>). Several times faster than a
//! reflective decoder, whose value per element is what a long recording cannot afford.
//! Packed and unpacked repeated fields are both read (a parser must accept both); fields of
//! other numbers are skipped.

use super::Kind;
use std::ops::Range;

/// Wire types (the low 3 bits of a field's key).
const VARINT: u64 = 0;
const I64: u64 = 1;
const LEN: u64 = 2;
const I32: u64 = 5;

/// One column's values as the message holds them: a number column's `sint64`s (before any
/// summing), flags, and where each label lies in the message (checked to be UTF-8: [`text`]).
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Values {
    /// A float or integer column.
    Stored(Vec<i64>),
    /// A flag column.
    Bools(Vec<bool>),
    /// An enum label column: each label's bytes in the message.
    Texts(Vec<Range<usize>>),
}

impl Values {
    /// No value yet, for a column of `kind`.
    pub(super) fn of(kind: Kind) -> Self {
        match kind {
            Kind::Float | Kind::Int => Self::Stored(Vec::new()),
            Kind::Bool => Self::Bools(Vec::new()),
            Kind::Text => Self::Texts(Vec::new()),
        }
    }

    /// Whether these are the values of a column of `kind`.
    pub(super) fn holds(&self, kind: Kind) -> bool {
        matches!(
            (self, kind),
            (Self::Stored(_), Kind::Float | Kind::Int)
                | (Self::Bools(_), Kind::Bool)
                | (Self::Texts(_), Kind::Text)
        )
    }

    /// Values held.
    pub(super) fn len(&self) -> usize {
        match self {
            Self::Stored(v) => v.len(),
            Self::Bools(v) => v.len(),
            Self::Texts(v) => v.len(),
        }
    }

    /// Empties the list, keeping its capacity.
    pub(super) fn clear(&mut self) {
        match self {
            Self::Stored(v) => v.clear(),
            Self::Bools(v) => v.clear(),
            Self::Texts(v) => v.clear(),
        }
    }
}

/// The label at `range` of the message `bytes` [`decode`] read (it checked the range and
/// the UTF-8; `""` for any other).
pub(super) fn text(bytes: &[u8], range: Range<usize>) -> &str {
    bytes
        .get(range)
        .and_then(|b| std::str::from_utf8(b).ok())
        .unwrap_or_default()
}

/// The reader's position in a message.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn done(&self) -> bool {
        self.at >= self.bytes.len()
    }

    #[inline]
    fn varint(&mut self) -> Result<u64, String> {
        // Most of a block's varints are one byte (the differences of a smooth signal).
        if let Some(&b) = self.bytes.get(self.at)
            && b < 0x80
        {
            self.at += 1;
            return Ok(u64::from(b));
        }
        let mut value = 0u64;
        for shift in (0..64).step_by(7) {
            let Some(&b) = self.bytes.get(self.at) else {
                return Err("the message ends inside a varint".into());
            };
            self.at += 1;
            value |= u64::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                return Ok(value);
            }
        }
        Err("a varint longer than 10 bytes".into())
    }

    fn take(&mut self, n: u64) -> Result<&'a [u8], String> {
        let end = usize::try_from(n)
            .ok()
            .and_then(|n| self.at.checked_add(n))
            .filter(|&end| end <= self.bytes.len())
            .ok_or_else(|| format!("a field of {n} bytes past the message's end"))?;
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }
}

/// A `sint64` as stored (zigzag).
fn zigzag(v: u64) -> i64 {
    ((v >> 1) as i64) ^ -((v & 1) as i64)
}

/// A `sint64` as stored (zigzag).
pub(super) fn zigzag_encode(v: i64) -> u64 {
    ((v << 1) ^ (v >> 63)) as u64
}

/// Append `v` as a varint.
pub(super) fn put_varint(out: &mut Vec<u8>, mut v: u64) {
    while v >= 0x80 {
        out.push((v as u8) | 0x80);
        v >>= 7;
    }
    out.push(v as u8);
}

/// Append field `number` of wire type LEN holding `bytes` (a string, or a packed column).
pub(super) fn put_bytes(out: &mut Vec<u8>, number: u32, bytes: &[u8]) {
    put_varint(out, (u64::from(number) << 3) | LEN);
    put_varint(out, bytes.len() as u64);
    out.extend_from_slice(bytes);
}

/// Append packed repeated field `number` (its varints already in `payload`); an empty one is
/// left out, as protobuf encoders do.
pub(super) fn put_packed(out: &mut Vec<u8>, number: u32, payload: &[u8]) {
    if !payload.is_empty() {
        put_bytes(out, number, payload);
    }
}

/// Appends the values of every field of message `bytes` numbered `1..=columns.len()` to
/// `columns[number - 1]` (an integer column gets the `sint64` values, before any summing).
pub(super) fn decode(bytes: &[u8], columns: &mut [Values]) -> Result<(), String> {
    let mut cur = Cursor { bytes, at: 0 };
    while !cur.done() {
        let key = cur.varint()?;
        let (number, wire) = (key >> 3, key & 7);
        let column = usize::try_from(number)
            .ok()
            .and_then(|n| n.checked_sub(1))
            .and_then(|i| columns.get_mut(i));
        match (column, wire) {
            (Some(Values::Stored(out)), VARINT) => out.push(zigzag(cur.varint()?)),
            (Some(Values::Bools(out)), VARINT) => out.push(cur.varint()? != 0),
            (Some(Values::Stored(out)), LEN) => {
                let len = cur.varint()?;
                let mut packed = Cursor {
                    bytes: cur.take(len)?,
                    at: 0,
                };
                // At most a value a byte.
                out.reserve(packed.bytes.len());
                while !packed.done() {
                    out.push(zigzag(packed.varint()?));
                }
            }
            (Some(Values::Bools(out)), LEN) => {
                let len = cur.varint()?;
                let mut packed = Cursor {
                    bytes: cur.take(len)?,
                    at: 0,
                };
                out.reserve(packed.bytes.len());
                while !packed.done() {
                    out.push(packed.varint()? != 0);
                }
            }
            (Some(Values::Texts(out)), LEN) => {
                let len = cur.varint()?;
                let start = cur.at;
                std::str::from_utf8(cur.take(len)?)
                    .map_err(|e| format!("field {number} holds a string that is not UTF-8: {e}"))?;
                out.push(start..cur.at);
            }
            (Some(_), _) => {
                return Err(format!(
                    "field {number} has wire type {wire}, not its column's"
                ));
            }
            (None, VARINT) => {
                cur.varint()?;
            }
            (None, I64) => {
                cur.take(8)?;
            }
            (None, LEN) => {
                let len = cur.varint()?;
                cur.take(len)?;
            }
            (None, I32) => {
                cur.take(4)?;
            }
            (None, _) => return Err(format!("field {number} has wire type {wire} (a group)")),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use prost::Message as _;

    /// A message of the same fields as a block of ours, encoded by prost.
    #[derive(Clone, PartialEq, prost::Message)]
    struct Block {
        #[prost(sint64, repeated, tag = "1")]
        ints: Vec<i64>,
        #[prost(bool, repeated, tag = "2")]
        flags: Vec<bool>,
        #[prost(string, repeated, tag = "3")]
        labels: Vec<String>,
        #[prost(sint64, repeated, packed = "false", tag = "4")]
        unpacked: Vec<i64>,
        #[prost(double, tag = "9")]
        other: f64,
        #[prost(string, tag = "10")]
        other_text: String,
    }

    #[test]
    fn fields_packed_or_not_decode_and_unknown_fields_are_skipped() {
        let block = Block {
            ints: vec![0, -1, 1, i64::MIN, i64::MAX, 1 << 40],
            flags: vec![true, false, true],
            labels: vec!["ok".into(), "".into(), "stalled".into()],
            unpacked: vec![-5, 7],
            other: 1.5,
            other_text: "skip me".into(),
        };
        let mut columns = vec![
            Values::Stored(Vec::new()),
            Values::Bools(Vec::new()),
            Values::Texts(Vec::new()),
            Values::Stored(Vec::new()),
        ];
        let bytes = block.encode_to_vec();
        decode(&bytes, &mut columns).unwrap();
        let Values::Texts(labels) = columns[2].clone() else {
            unreachable!("a text column")
        };
        let labels: Vec<&str> = labels.into_iter().map(|r| text(&bytes, r)).collect();
        assert_eq!(labels, block.labels);
        columns[2] = Values::Texts(Vec::new());
        assert_eq!(
            columns,
            [
                Values::Stored(block.ints),
                Values::Bools(block.flags),
                Values::Texts(Vec::new()),
                Values::Stored(block.unpacked),
            ]
        );
    }

    #[test]
    fn a_cut_or_mistyped_message_is_an_error_not_a_panic() {
        let block = Block {
            ints: (0..100).collect(),
            labels: vec!["ok".into()],
            ..Default::default()
        };
        let bytes = block.encode_to_vec();
        for end in 0..bytes.len() {
            let mut columns = vec![
                Values::Stored(Vec::new()),
                Values::Bools(Vec::new()),
                Values::Texts(Vec::new()),
            ];
            let _ = decode(&bytes[..end], &mut columns);
        }
        let mut wrong = vec![Values::Texts(Vec::new())];
        let e = decode(&bytes, &mut wrong).unwrap_err();
        assert!(e.contains("field 1"), "{e}");
    }
}
