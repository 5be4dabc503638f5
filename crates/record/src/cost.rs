//! What reading a recording will cost, known before any of it is decompressed: a walk over
//! the top-level records of its data section that reads each record's 9-byte header (and a
//! chunk's own header: the uncompressed size it declares), and seeks past the rest
//! ([`survey`]). [`CostLimits`] holds what a station's own recordings never exceed; a file over
//! them is refused by name before the work starts (the hub's replay: a station's upload is
//! untrusted, and a 175 KB file of zstd chunks declaring 16 MiB of zeros each decoded for
//! half a minute).
//!
//! Each record the file holds is held to the readers' one limit ([`super::MAX_RECORD_BYTES`],
//! [`super::walk`]), so a file they would refuse is refused by the survey already.
//!
//! The survey reads the data section, not the summary: the summary is the writer's word, and
//! the streaming reader ([`super::TickStream`]) reads the data section; a chunk that
//! decompresses to more than it declares is refused by that reader, so what the survey adds up
//! is what the reader can be made to decompress.

use super::error::ReadError;
use super::types::SessionMetadata;
use super::walk::{head, within_limit};
use mcap::records::op;
use std::io::{BufReader, Read, Seek};

/// What the data section of a recording holds, from its record headers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Survey {
    /// The file's size, bytes.
    pub file_bytes: u64,
    /// Top-level records of the data section (chunks, message indexes, metadata, …).
    pub records: u64,
    /// Chunk records.
    pub chunks: u64,
    /// The uncompressed bytes the chunks declare, in all.
    pub uncompressed_bytes: u64,
    /// The largest uncompressed size one chunk declares, bytes.
    pub largest_chunk_bytes: u64,
    /// Whether a top-level `session` metadata record is there.
    pub session_metadata: bool,
    /// Uncompressed bytes the chunks before the `session` metadata declare (all of them when
    /// there is none): what a reader decompresses before it can say what the session was.
    pub uncompressed_before_metadata: u64,
}

impl Survey {
    /// Uncompressed bytes per byte on disk.
    pub fn ratio(&self) -> f64 {
        self.uncompressed_bytes as f64 / self.file_bytes.max(1) as f64
    }
}

/// The MCAP magic that opens a file.
const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// Surveys the recording read by `input` (from its start), walking at most `max_records`
/// top-level records (a file of more is refused: each costs the reader a little).
pub fn survey<R: Read + Seek>(
    input: &mut BufReader<R>,
    max_records: u64,
) -> Result<Survey, ReadError> {
    let io = |source| ReadError::Io {
        path: String::new(),
        source,
    };
    let file_bytes = input.seek(std::io::SeekFrom::End(0)).map_err(io)?;
    input.rewind().map_err(io)?;
    let mut magic = [0u8; 8];
    input.read_exact(&mut magic).map_err(io)?;
    if &magic != MAGIC {
        return Err(ReadError::Damaged {
            chunk: 0,
            reason: "it does not start as an MCAP file".into(),
        });
    }
    let mut s = Survey {
        file_bytes,
        ..Survey::default()
    };
    let mut at = 8u64;
    loop {
        let mut header = [0u8; 9];
        if !read_or_end(input, &mut header).map_err(io)? {
            break;
        }
        let (opcode, len) = head(&header);
        if opcode == op::DATA_END || opcode == op::FOOTER {
            break;
        }
        s.records += 1;
        if s.records > max_records {
            return Err(ReadError::TooLarge {
                what: "the number of its records".into(),
                claimed_bytes: s.records,
                limit_bytes: max_records,
            });
        }
        let mut read = 0u64;
        if opcode == op::CHUNK && len >= 24 {
            // message start time, message end time, uncompressed size (MCAP, "Chunk").
            let mut fields = [0u8; 24];
            if !read_or_end(input, &mut fields).map_err(io)? {
                break;
            }
            read = 24;
            let declared = u64::from_le_bytes(fields[16..].try_into().expect("8 bytes"));
            s.chunks += 1;
            s.uncompressed_bytes = s.uncompressed_bytes.saturating_add(declared);
            s.largest_chunk_bytes = s.largest_chunk_bytes.max(declared);
            if !s.session_metadata {
                s.uncompressed_before_metadata = s.uncompressed_bytes;
            }
        } else if opcode == op::METADATA && !s.session_metadata {
            let name = SessionMetadata::NAME.as_bytes();
            let want = 4 + name.len() as u64;
            if len >= want {
                let mut field = vec![0u8; want as usize];
                if !read_or_end(input, &mut field).map_err(io)? {
                    break;
                }
                read = want;
                s.session_metadata =
                    field[..4] == (name.len() as u32).to_le_bytes() && &field[4..] == name;
            }
        }
        at = at.saturating_add(9).saturating_add(len);
        if at > file_bytes {
            // A cut tail (a killed session's last chunk claims the writer's placeholder
            // length): the reader reads up to it and stops there.
            break;
        }
        // A record the file holds but no reader accepts: refused now, in the readers' words.
        within_limit(opcode, len, "")?;
        let skip = i64::try_from(len - read).map_err(|_| ReadError::Damaged {
            chunk: 0,
            reason: format!("a record claims {len} bytes"),
        })?;
        input.seek_relative(skip).map_err(io)?;
    }
    Ok(s)
}

/// Fills `buf`; `false` at the end of the input (a part read is the end too: the reader
/// refuses a truncated record).
fn read_or_end<R: Read>(input: &mut R, buf: &mut [u8]) -> std::io::Result<bool> {
    let mut got = 0;
    while got < buf.len() {
        match input.read(&mut buf[got..]) {
            Ok(0) => return Ok(false),
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(true)
}

/// The longest session a station records, s: the regimen's longest planned session
/// (`regimen::MAX_PLANNED_SESSION_S`, 2 h) twice over, for rests and pauses.
pub const LONGEST_SESSION_S: u64 = 4 * 3600;

/// Uncompressed bytes a station writes per second of session, at most, with margin: some
/// 0.72 MB (2.6 GB an hour with the raw inputs), twice over and rounded up.
pub const UNCOMPRESSED_BYTES_PER_S: u64 = 2 << 20;

/// What a station's recordings never exceed, for the checks [`CostLimits::check`] makes.
/// The station's writer closes a chunk at 1 MiB uncompressed and flushes every second, so a
/// session writes about one chunk a second (a 1 kHz session with the raw inputs: some
/// 2.6 GB an hour uncompressed, 420 MB on disk, 1/6.1; without them 1/7.0 — BENCHMARKS.md,
/// "Recording size").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CostLimits {
    /// Most chunks: four a second of the longest session.
    pub max_chunks: u64,
    /// Most top-level records: a chunk is followed by one message index a channel.
    pub max_records: u64,
    /// Most uncompressed bytes per byte on disk (a station's recordings: 6–7 while the
    /// patient moves; 35 for minutes of a wheel held perfectly still, every delta zero).
    pub max_ratio: u64,
    /// Uncompressed bytes allowed beyond `max_ratio` times the file: a short recording's
    /// schemas compress better than its samples.
    pub ratio_allowance_bytes: u64,
    /// Most uncompressed bytes in all: [`UNCOMPRESSED_BYTES_PER_S`] for the longest session,
    /// and no more than `max_ratio` times the largest file replayed.
    pub max_uncompressed_bytes: u64,
    /// Most uncompressed bytes before the `session` metadata (the station writes it before
    /// any chunk): the first frames follow at once.
    pub max_before_metadata_bytes: u64,
}

impl CostLimits {
    /// The limits for files of at most `max_file_bytes` on disk.
    pub fn for_files_up_to(max_file_bytes: u64) -> Self {
        let max_ratio = 64;
        Self {
            max_chunks: 4 * LONGEST_SESSION_S,
            max_records: 64 * LONGEST_SESSION_S,
            max_ratio,
            ratio_allowance_bytes: 16 << 20,
            max_uncompressed_bytes: (UNCOMPRESSED_BYTES_PER_S * LONGEST_SESSION_S)
                .min(max_file_bytes.saturating_mul(max_ratio)),
            max_before_metadata_bytes: 16 << 20,
        }
    }

    /// Why `survey`'s recording costs more to read than a station's recording can, in plain
    /// words; `Ok` when it is within every limit.
    pub fn check(&self, s: &Survey) -> Result<(), String> {
        let mb = |b: u64| b as f64 / 1e6;
        if s.chunks > self.max_chunks {
            return Err(format!(
                "it holds {} chunks, more than the {} a station writes in its longest session",
                s.chunks, self.max_chunks
            ));
        }
        let by_ratio = s
            .file_bytes
            .saturating_mul(self.max_ratio)
            .saturating_add(self.ratio_allowance_bytes);
        if s.uncompressed_bytes > by_ratio {
            return Err(format!(
                "its chunks declare {:.1} MB of data uncompressed, {:.0} times its {:.3} MB on \
                 disk; a station's recordings expand at most {} times",
                mb(s.uncompressed_bytes),
                s.ratio(),
                mb(s.file_bytes),
                self.max_ratio
            ));
        }
        if s.uncompressed_bytes > self.max_uncompressed_bytes {
            return Err(format!(
                "its chunks declare {:.1} MB of data uncompressed, more than the {:.1} MB this \
                 hub reads for a replay",
                mb(s.uncompressed_bytes),
                mb(self.max_uncompressed_bytes)
            ));
        }
        if !s.session_metadata {
            return Err(
                "it has no session record (every station's recording starts with one)".into(),
            );
        }
        if s.uncompressed_before_metadata > self.max_before_metadata_bytes {
            return Err(format!(
                "its session record comes after {:.1} MB of data (a station writes it first; at \
                 most {:.1} MB)",
                mb(s.uncompressed_before_metadata),
                mb(self.max_before_metadata_bytes)
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{RecordWriter, TickRecord};
    use std::io::Cursor;

    fn honest(ticks: u64) -> Vec<u8> {
        let meta = SessionMetadata {
            loop_rate_hz: 1000.0,
            ..Default::default()
        };
        let mut w = RecordWriter::new(Cursor::new(Vec::new()), 0, &meta).unwrap();
        for tick in 0..ticks {
            let rec = TickRecord {
                tick,
                t_ns: tick * 1_000_000,
                ..Default::default()
            };
            w.write_tick(&rec, tick % 100 == 0).unwrap();
            if tick % 1000 == 999 {
                w.flush().unwrap();
            }
        }
        w.finish().unwrap().into_inner()
    }

    #[test]
    fn a_record_over_the_readers_limit_is_refused_by_name_and_a_cut_tail_is_not() {
        let bytes = honest(300);
        let header_end = 8 + 9 + u64::from_le_bytes(bytes[9..17].try_into().unwrap()) as usize;
        let with_metadata_of = |len: u64, body: u64| {
            let mut forged = bytes[..header_end].to_vec();
            forged.push(op::METADATA);
            forged.extend(len.to_le_bytes());
            forged.resize(forged.len() + body as usize, 0);
            forged.extend(&bytes[header_end..]);
            forged
        };
        let over = crate::MAX_RECORD_BYTES as u64 + 1;
        let e = survey(
            &mut BufReader::new(Cursor::new(with_metadata_of(over, over))),
            64,
        );
        let e = e.unwrap_err();
        assert!(
            matches!(&e, ReadError::TooLarge { what, claimed_bytes, .. }
                if what == "a record (opcode 0x0c)" && *claimed_bytes == over),
            "{e}"
        );
        // At the limit it is surveyed and skipped.
        let at_limit = with_metadata_of(over - 1, over - 1);
        let s = survey(&mut BufReader::new(Cursor::new(at_limit)), 64).unwrap();
        assert!(s.session_metadata && s.chunks > 0, "{s:?}");
        // Claiming more than the file holds: the cut tail of a killed session, not refused.
        let cut = with_metadata_of(u64::MAX, 0);
        let s = survey(&mut BufReader::new(Cursor::new(cut)), 64).unwrap();
        assert_eq!(
            (s.records, s.chunks),
            (2, 0),
            "the header and the cut record: {s:?}"
        );
    }

    #[test]
    fn a_stations_recording_is_within_the_limits_and_its_chunks_are_counted() {
        let bytes = honest(5000);
        let s = survey(&mut BufReader::new(Cursor::new(bytes.clone())), u64::MAX).unwrap();
        assert!(s.session_metadata);
        // The writer's first chunk (schemas and channels) comes before it: some 33 KB.
        assert!(s.uncompressed_before_metadata < 1 << 20, "{s:?}");
        assert!((5..=8).contains(&s.chunks), "{s:?}");
        assert!(s.uncompressed_bytes > bytes.len() as u64, "{s:?}");
        CostLimits::for_files_up_to(2 << 30).check(&s).unwrap();
        let few = survey(&mut BufReader::new(Cursor::new(bytes)), 3).unwrap_err();
        assert!(few.to_string().contains("number of its records"), "{few}");
    }

    #[test]
    fn a_still_wheel_recorded_for_minutes_expands_well_within_the_ratio() {
        // Every sample the same: the blocks codec's deltas are zeros, what compresses best
        // (35 times; without the allowance for a short file's first chunk).
        let bytes = honest(180_000);
        let s = survey(&mut BufReader::new(Cursor::new(bytes)), u64::MAX).unwrap();
        eprintln!("a still wheel, 3 minutes: {:.1} times, {s:?}", s.ratio());
        let limits = CostLimits {
            ratio_allowance_bytes: 0,
            ..CostLimits::for_files_up_to(2 << 30)
        };
        assert!(
            s.ratio() * 1.5 < limits.max_ratio as f64,
            "{:.1} times: {s:?}",
            s.ratio()
        );
        limits.check(&s).unwrap();
    }

    #[test]
    fn zero_chunks_without_a_session_record_are_refused_by_ratio_and_metadata() {
        let s = Survey {
            file_bytes: 175_000,
            records: 300,
            chunks: 300,
            uncompressed_bytes: 300 << 24,
            largest_chunk_bytes: 16 << 20,
            session_metadata: true,
            uncompressed_before_metadata: 0,
        };
        let limits = CostLimits::for_files_up_to(2 << 30);
        let e = limits.check(&s).unwrap_err();
        assert!(e.contains("5033.2 MB of data uncompressed"), "{e}");
        assert!(e.contains("expand at most 64 times"), "{e}");
        let e = limits
            .check(&Survey {
                session_metadata: false,
                uncompressed_bytes: 1 << 20,
                ..s
            })
            .unwrap_err();
        assert!(e.contains("no session record"), "{e}");
    }
}
