//! Reading newline-delimited JSON (one value a line), the one way every NDJSON file of the
//! product is read back: the hub's per-session summary files ([`crate::store`]), the
//! station's queue and its assessment and difficulty histories.
//!
//! Each writer appends whole lines, each ending in `\n`; a process killed mid-write leaves a
//! last line without its newline, which was never complete (never acknowledged, never
//! counted): [`complete_len`] says where it starts, and [`read_lines`] leaves it out. Each caller
//! keeps its own policy for a complete line that does not read (the hub's store refuses the
//! file naming the line; the station's queue stops there; a history skips it).

use std::io::{BufRead, Read};

use serde::de::DeserializeOwned;

/// The longest line read, bytes: far above any line written (a summary is ~1–2 KB, a
/// history's entry less), so a line over it is damage, refused by [`parse`] without being
/// handed to the JSON parser.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The length of `bytes`' complete lines: up to and including the last `\n` (0 without one).
#[must_use]
pub fn complete_len(bytes: &[u8]) -> usize {
    bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1)
}

/// The complete, non-empty lines read from `reader` (without their `\n`), each with its
/// 1-based line number, streamed: at most [`MAX_LINE_BYTES`] + 1 bytes of a line are held (a
/// longer one is handed on cut there, for [`parse`] to refuse by its length, and the rest of
/// it skipped). A last line without its newline is left out; a read error ends the lines.
pub fn read_lines<R: BufRead>(mut reader: R) -> impl Iterator<Item = (usize, Vec<u8>)> {
    let mut number = 0;
    std::iter::from_fn(move || {
        loop {
            let mut line = Vec::new();
            let limit = MAX_LINE_BYTES as u64 + 1;
            if (&mut reader)
                .take(limit)
                .read_until(b'\n', &mut line)
                .ok()?
                == 0
            {
                return None;
            }
            number += 1;
            if line.last() == Some(&b'\n') {
                line.pop();
                if line.is_empty() {
                    continue;
                }
                return Some((number, line));
            }
            if line.len() <= MAX_LINE_BYTES {
                return None; // the end: a last line a crash cut short
            }
            skip_past_newline(&mut reader)?;
            return Some((number, line));
        }
    })
}

/// Consumes `reader` up to and including its next `\n`; `None` at its end or on an error.
fn skip_past_newline(reader: &mut impl BufRead) -> Option<()> {
    loop {
        let buf = reader.fill_buf().ok()?;
        if buf.is_empty() {
            return None;
        }
        match buf.iter().position(|&b| b == b'\n') {
            Some(i) => {
                reader.consume(i + 1);
                return Some(());
            }
            None => {
                let n = buf.len();
                reader.consume(n);
            }
        }
    }
}

/// One line as a `T`: an error naming what is wrong (a line over [`MAX_LINE_BYTES`], or the
/// JSON parser's complaint).
pub fn parse<T: DeserializeOwned>(line: &[u8]) -> Result<T, String> {
    if line.len() > MAX_LINE_BYTES {
        return Err(format!(
            "a line of {} bytes, over the {MAX_LINE_BYTES} bytes any line may have",
            line.len()
        ));
    }
    serde_json::from_slice(line).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(bytes: &[u8]) -> Vec<(usize, Vec<u8>)> {
        read_lines(bytes).collect()
    }

    #[test]
    fn complete_lines_are_read_numbered_and_a_cut_last_line_is_left_out() {
        let text = b"{\"a\":1}\n\n{\"a\":2}\n{\"a\":";
        assert_eq!(complete_len(text), 17);
        assert_eq!(
            read(text),
            [(1, b"{\"a\":1}".to_vec()), (3, b"{\"a\":2}".to_vec())]
        );
        assert_eq!(complete_len(b"no newline"), 0);
        assert!(read(b"no newline").is_empty());
        assert!(read(b"").is_empty());
    }

    #[test]
    fn a_line_over_the_limit_is_handed_on_cut_and_the_next_line_read_whole() {
        let mut text = vec![b'x'; 3 * MAX_LINE_BYTES];
        text.extend_from_slice(b"\n{\"a\":3}\n");
        let got = read(&text);
        assert_eq!(got.len(), 2);
        assert_eq!((got[0].0, got[0].1.len()), (1, MAX_LINE_BYTES + 1));
        assert!(parse::<serde_json::Value>(&got[0].1).is_err());
        assert_eq!(got[1], (2, b"{\"a\":3}".to_vec()));
        // Over the limit and never ended: a last line cut short, left out as any other.
        assert!(read(&text[..2 * MAX_LINE_BYTES]).is_empty());
    }

    #[test]
    fn a_line_over_the_limit_is_refused_by_its_length_and_bad_json_by_the_parser() {
        let ok: serde_json::Value = parse(b"{\"a\":1}").unwrap();
        assert_eq!(ok["a"], 1);
        let long = vec![b' '; MAX_LINE_BYTES + 1];
        let e = parse::<serde_json::Value>(&long).unwrap_err();
        assert!(e.contains("over the 1048576 bytes"), "{e}");
        // One byte less is handed to the parser (whitespace alone: its own complaint).
        let e = parse::<serde_json::Value>(&long[1..]).unwrap_err();
        assert!(e.contains("EOF"), "{e}");
        assert!(parse::<serde_json::Value>(b"{\"a\":").is_err());
    }
}
