//! Reading newline-delimited JSON (one value a line), the one way every NDJSON file of the
//! product is read back: the hub's per-session summary files ([`crate::store`]), the
//! station's queue and its assessment and difficulty histories.
//!
//! Each writer appends whole lines, each ending in `\n`; a process killed mid-write leaves a
//! last line without its newline, which was never complete (never acknowledged, never
//! counted): [`complete_len`] says where it starts, and [`lines`] leaves it out. Each caller
//! keeps its own policy for a complete line that does not read (the hub's store refuses the
//! file naming the line; the station's queue stops there; a history skips it).

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

/// The complete, non-empty lines of `bytes` (without their `\n`), each with its 1-based line
/// number in the file; a last line without its newline is left out.
pub fn lines(bytes: &[u8]) -> impl Iterator<Item = (usize, &[u8])> {
    bytes[..complete_len(bytes)]
        .split(|&b| b == b'\n')
        .enumerate()
        .filter(|(_, line)| !line.is_empty())
        .map(|(i, line)| (i + 1, line))
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

    #[test]
    fn complete_lines_are_read_numbered_and_a_cut_last_line_is_left_out() {
        let text = b"{\"a\":1}\n\n{\"a\":2}\n{\"a\":";
        assert_eq!(complete_len(text), 17);
        let got: Vec<(usize, &[u8])> = lines(text).collect();
        assert_eq!(got, [(1, &b"{\"a\":1}"[..]), (3, &b"{\"a\":2}"[..])]);
        assert_eq!(complete_len(b"no newline"), 0);
        assert_eq!(lines(b"no newline").count(), 0);
        assert_eq!(lines(b"").count(), 0);
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
