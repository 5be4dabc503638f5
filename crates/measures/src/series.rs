//! Where the measures keep their [`MEASURE_RATE_HZ`](super::MEASURE_RATE_HZ) series until the
//! session's end: the end-of-session analysis reads them whole (a speed threshold taken from
//! the whole session's peak, zero-phase filters over each run), so they cannot be dropped as
//! they come, but they need not stay in RAM either.
//!
//! A recorded session spills them to an anonymous temporary file on the recording's disk
//! ([`SeriesStore::spilled_in`]: `O_TMPFILE` on Linux, gone when closed, even after a crash),
//! appended through a fixed buffer of [`SPILL_BUFFER_BYTES`]; the process's resident memory
//! stays flat however long the session (the file's pages are the kernel's cache, reclaimable).
//! [`SeriesStore::load`] reads them back at the end, bit for bit. Without a recording directory
//! (a session not recorded, a report built from a recording already in memory) they stay in
//! memory ([`SeriesStore::in_memory`]).
//!
//! A spill that fails is not the analysis lost: a file that cannot be created leaves the
//! series in memory from the start; a write that fails (a full disk) reads back what was
//! spilled and keeps the series in memory from then on. Only when that read fails too are
//! the series gone, and [`SeriesStore::load`] says why.

use std::fmt;
use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};

/// Bytes of one sample in the spill file: wheel angle, its session time, shoulder elevation
/// and elbow flexion, `f64` little-endian each (NaN joints: not tracked).
const SAMPLE_BYTES: usize = 4 * 8;

/// The spill's buffer, bytes: 128 samples (1.28 s of session), one write each time it fills.
pub const SPILL_BUFFER_BYTES: usize = 128 * SAMPLE_BYTES;

/// One sample of the series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeriesSample {
    /// Wheel angle, rad.
    pub wheel_rad: f64,
    /// Session time of the sample, s.
    pub t_s: f64,
    /// Shoulder elevation and elbow flexion, rad, while the arm sensing tracks (kept only
    /// when both are finite).
    pub joints_rad: Option<[f64; 2]>,
}

/// The series, whole.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// Wheel angle of each sample, rad.
    pub wheel_rad: Vec<f64>,
    /// Session time of each sample of `wheel_rad`, s.
    pub t_s: Vec<f64>,
    /// Shoulder elevation of the samples with the arm tracked, rad.
    pub shoulder_elevation_rad: Vec<f64>,
    /// Elbow flexion of the same samples, rad.
    pub elbow_flexion_rad: Vec<f64>,
}

impl Series {
    fn with_capacity(samples: usize, joint_samples: usize) -> Self {
        Self {
            wheel_rad: Vec::with_capacity(samples),
            t_s: Vec::with_capacity(samples),
            shoulder_elevation_rad: Vec::with_capacity(joint_samples),
            elbow_flexion_rad: Vec::with_capacity(joint_samples),
        }
    }

    fn push(&mut self, s: SeriesSample) {
        self.wheel_rad.push(s.wheel_rad);
        self.t_s.push(s.t_s);
        if let Some([shoulder, elbow]) = s.joints_rad {
            self.shoulder_elevation_rad.push(shoulder);
            self.elbow_flexion_rad.push(elbow);
        }
    }

    /// The samples encoded in `bytes`, whole samples only.
    fn extend_from_bytes(&mut self, bytes: &[u8]) {
        for sample in bytes.chunks_exact(SAMPLE_BYTES) {
            let f = |k: usize| {
                let mut le = [0; 8];
                le.copy_from_slice(&sample[8 * k..8 * k + 8]);
                f64::from_le_bytes(le)
            };
            let joints = [f(2), f(3)];
            self.push(SeriesSample {
                wheel_rad: f(0),
                t_s: f(1),
                joints_rad: joints.iter().all(|j| j.is_finite()).then_some(joints),
            });
        }
    }
}

/// The series of a session, in memory or spilled to a file.
#[derive(Debug)]
pub struct SeriesStore {
    /// Samples taken.
    len: usize,
    /// Samples taken with the joints.
    joint_len: usize,
    held: Held,
}

/// Where the series are.
#[derive(Debug)]
enum Held {
    Memory(Series),
    Spilled(Spill),
    /// Neither in memory nor readable from the spill: why.
    Lost(String),
}

/// The series can no longer be had.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the measures' series are lost: {0}")]
pub struct SeriesLost(String);

/// What a spill writes to: a file on the recording's disk ([`std::fs::File`]; tests put one
/// that fills up in its place).
pub(super) trait SpillFile: fmt::Debug + Send {
    /// Write all of `buf` at `offset`.
    fn write_all_at(&self, buf: &[u8], offset: u64) -> io::Result<()>;
    /// Read exactly `buf.len()` bytes at `offset`.
    fn read_exact_at(&self, buf: &mut [u8], offset: u64) -> io::Result<()>;
}

/// Positional reads and writes, where Linux and Windows differ: `pread`/`pwrite` on Linux,
/// `ReadFile`/`WriteFile` at an offset on Windows (which may move the file's cursor; no caller
/// uses the cursor).
impl SpillFile for File {
    fn write_all_at(&self, buf: &[u8], offset: u64) -> io::Result<()> {
        write_all_at(self, buf, offset)
    }

    fn read_exact_at(&self, buf: &mut [u8], offset: u64) -> io::Result<()> {
        read_exact_at(self, buf, offset)
    }
}

/// Writes all of `buf` at `offset` of `file`.
fn write_all_at(file: &File, buf: &[u8], offset: u64) -> io::Result<()> {
    #[cfg(unix)]
    {
        std::os::unix::fs::FileExt::write_all_at(file, buf, offset)
    }
    #[cfg(windows)]
    {
        use std::os::windows::fs::FileExt;
        let (mut buf, mut offset) = (buf, offset);
        while !buf.is_empty() {
            match file.seek_write(buf, offset)? {
                0 => return Err(io::ErrorKind::WriteZero.into()),
                n => {
                    buf = &buf[n..];
                    offset += n as u64;
                }
            }
        }
        Ok(())
    }
}

/// Reads exactly `buf.len()` bytes at `offset` of `file`.
fn read_exact_at(file: &File, buf: &mut [u8], offset: u64) -> io::Result<()> {
    #[cfg(unix)]
    {
        std::os::unix::fs::FileExt::read_exact_at(file, buf, offset)
    }
    #[cfg(windows)]
    {
        use std::os::windows::fs::FileExt;
        let (mut buf, mut offset) = (buf, offset);
        while !buf.is_empty() {
            match file.seek_read(buf, offset)? {
                0 => return Err(io::ErrorKind::UnexpectedEof.into()),
                n => {
                    buf = &mut buf[n..];
                    offset += n as u64;
                }
            }
        }
        Ok(())
    }
}

/// Series spilled to a file: the file holds the first `written` bytes, `buf` the samples
/// after them.
#[derive(Debug)]
struct Spill {
    file: Box<dyn SpillFile>,
    /// The directory of the file (it has no name), for messages.
    dir: PathBuf,
    /// Bytes in the file: a failed write leaves them as they were.
    written: u64,
    /// Samples not yet written (never more than [`SPILL_BUFFER_BYTES`]).
    buf: Vec<u8>,
}

impl Spill {
    fn new(file: Box<dyn SpillFile>, dir: &Path) -> Self {
        Self {
            file,
            dir: dir.to_path_buf(),
            written: 0,
            buf: Vec::with_capacity(SPILL_BUFFER_BYTES),
        }
    }

    /// Buffers `s`, writing the buffer out when full; on a failed write the buffer keeps
    /// its samples.
    fn push(&mut self, s: SeriesSample) -> io::Result<()> {
        let [shoulder, elbow] = s.joints_rad.unwrap_or([f64::NAN; 2]);
        for v in [s.wheel_rad, s.t_s, shoulder, elbow] {
            self.buf.extend_from_slice(&v.to_le_bytes());
        }
        if self.buf.len() + SAMPLE_BYTES > SPILL_BUFFER_BYTES {
            self.file.write_all_at(&self.buf, self.written)?;
            self.written += self.buf.len() as u64;
            self.buf.clear();
        }
        Ok(())
    }

    /// The series: the file's samples, then the buffer's; `len` samples of which
    /// `joint_len` with the joints.
    fn read_back(&self, len: usize, joint_len: usize) -> io::Result<Series> {
        let mut series = Series::with_capacity(len, joint_len);
        let mut chunk = vec![0; SPILL_BUFFER_BYTES];
        let mut at = 0;
        while at < self.written {
            let n = (self.written - at).min(SPILL_BUFFER_BYTES as u64) as usize;
            self.file.read_exact_at(&mut chunk[..n], at)?;
            series.extend_from_bytes(&chunk[..n]);
            at += n as u64;
        }
        series.extend_from_bytes(&self.buf);
        Ok(series)
    }
}

impl SeriesStore {
    /// The series in memory, room made for `expected_samples`.
    pub fn in_memory(expected_samples: usize) -> Self {
        Self {
            len: 0,
            joint_len: 0,
            held: Held::Memory(Series::with_capacity(expected_samples, 0)),
        }
    }

    /// The series spilled to an anonymous temporary file in `dir` (the recording's directory:
    /// its disk, not `/tmp`, which may be RAM); in memory, with a warning, when no file can be
    /// made there.
    pub fn spilled_in(dir: &Path) -> Self {
        match tempfile::tempfile_in(dir) {
            Ok(file) => Self::spilled_to(Box::new(file), dir),
            Err(e) => {
                tracing::warn!(
                    "cannot make the measures' temporary file in {}: {e}; their series stay \
                     in memory",
                    dir.display()
                );
                Self::in_memory(0)
            }
        }
    }

    /// The series spilled to `file`, in `dir`.
    pub(super) fn spilled_to(file: Box<dyn SpillFile>, dir: &Path) -> Self {
        Self {
            len: 0,
            joint_len: 0,
            held: Held::Spilled(Spill::new(file, dir)),
        }
    }

    /// Samples taken.
    pub fn len(&self) -> usize {
        self.len
    }

    /// No sample taken yet.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The series are in a file (not in memory).
    pub fn is_spilled(&self) -> bool {
        matches!(self.held, Held::Spilled(_))
    }

    /// Takes one sample (its joints only when both are finite).
    pub fn push(&mut self, mut s: SeriesSample) {
        s.joints_rad = s.joints_rad.filter(|j| j.iter().all(|v| v.is_finite()));
        self.len += 1;
        self.joint_len += usize::from(s.joints_rad.is_some());
        match &mut self.held {
            Held::Memory(series) => series.push(s),
            Held::Spilled(spill) => {
                if let Err(e) = spill.push(s) {
                    self.held = Self::recalled(spill, self.len, self.joint_len, &e);
                }
            }
            Held::Lost(_) => {}
        }
    }

    /// The series of a spill whose write failed with `e`, back in memory (or lost, when they
    /// cannot be read either).
    fn recalled(spill: &Spill, len: usize, joint_len: usize, e: &io::Error) -> Held {
        let dir = spill.dir.display();
        match spill.read_back(len, joint_len) {
            Ok(series) => {
                tracing::warn!(
                    "cannot write the measures' series to their temporary file in {dir}: {e}; \
                     they stay in memory from now on"
                );
                Held::Memory(series)
            }
            Err(read) => {
                let why = format!(
                    "writing them to their temporary file in {dir} failed ({e}), and reading \
                     back what was written failed too ({read})"
                );
                tracing::warn!("the measures' series are lost: {why}");
                Held::Lost(why)
            }
        }
    }

    /// The series whole: read back from the spill (which is then closed and freed) or as they
    /// are in memory.
    pub fn load(&mut self) -> Result<&Series, SeriesLost> {
        if let Held::Spilled(spill) = &self.held {
            self.held = match spill.read_back(self.len, self.joint_len) {
                Ok(series) => Held::Memory(series),
                Err(e) => Held::Lost(format!(
                    "reading them back from their temporary file in {} failed: {e}",
                    spill.dir.display()
                )),
            };
        }
        match &self.held {
            Held::Memory(series) => Ok(series),
            Held::Lost(why) => Err(SeriesLost(why.clone())),
            Held::Spilled(_) => unreachable!("a spill was just read back"),
        }
    }

    /// The series, if in memory (always before a spill, after [`Self::load`] with one).
    pub fn loaded(&self) -> Option<&Series> {
        match &self.held {
            Held::Memory(series) => Some(series),
            Held::Spilled(_) | Held::Lost(_) => None,
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    #[test]
    fn positional_writes_and_reads_round_trip_at_any_offset() {
        let dir = tempfile::tempdir().unwrap();
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(dir.path().join("spill"))
            .unwrap();
        write_all_at(&file, b"world", 6).unwrap();
        write_all_at(&file, b"hello ", 0).unwrap();
        let mut back = [0u8; 11];
        read_exact_at(&file, &mut back, 0).unwrap();
        assert_eq!(&back, b"hello world");
        let mut past_the_end = [0u8; 4];
        let e = read_exact_at(&file, &mut past_the_end, 9).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::UnexpectedEof);
    }

    /// A file on a disk with room for `room` bytes: writes past it fail with ENOSPC (nothing
    /// of them written), as a full disk's do; `unreadable` makes every read fail with EIO.
    #[derive(Debug)]
    pub(crate) struct FillingUp {
        pub file: File,
        pub room: u64,
        pub unreadable: bool,
    }

    impl FillingUp {
        pub fn new(room: u64, unreadable: bool) -> Self {
            Self {
                file: tempfile::tempfile().unwrap(),
                room,
                unreadable,
            }
        }
    }

    impl SpillFile for FillingUp {
        fn write_all_at(&self, buf: &[u8], offset: u64) -> io::Result<()> {
            if offset + buf.len() as u64 > self.room {
                return Err(io::Error::from_raw_os_error(28));
            }
            self.file.write_all_at(buf, offset)
        }

        fn read_exact_at(&self, buf: &mut [u8], offset: u64) -> io::Result<()> {
            if self.unreadable {
                return Err(io::Error::from_raw_os_error(5));
            }
            self.file.read_exact_at(buf, offset)
        }
    }

    /// `n` samples, every third without joints, some joints not finite, some angles NaN.
    fn samples(n: usize) -> Vec<SeriesSample> {
        (0..n)
            .map(|k| {
                let x = k as f64;
                SeriesSample {
                    wheel_rad: if k % 97 == 5 {
                        f64::NAN
                    } else {
                        (x * 0.01).sin()
                    },
                    t_s: x * 0.01 + 1e-12 * x * x,
                    joints_rad: match k % 3 {
                        0 => None,
                        1 if k % 11 == 1 => Some([f64::NAN, 0.3]),
                        _ => Some([0.1 * x, -0.2 * x]),
                    },
                }
            })
            .collect()
    }

    fn bits(x: &[f64]) -> Vec<u64> {
        x.iter().map(|v| v.to_bits()).collect()
    }

    fn assert_same_bits(a: &Series, b: &Series) {
        assert_eq!(bits(&a.wheel_rad), bits(&b.wheel_rad));
        assert_eq!(bits(&a.t_s), bits(&b.t_s));
        assert_eq!(
            bits(&a.shoulder_elevation_rad),
            bits(&b.shoulder_elevation_rad)
        );
        assert_eq!(bits(&a.elbow_flexion_rad), bits(&b.elbow_flexion_rad));
    }

    fn filled(mut store: SeriesStore, s: &[SeriesSample]) -> SeriesStore {
        for &x in s {
            store.push(x);
        }
        store
    }

    #[test]
    fn a_spilled_series_reads_back_bit_for_bit_as_kept_in_memory() {
        let dir = tempfile::tempdir().unwrap();
        // Several buffers' worth and a partial one.
        let s = samples(5 * 128 + 17);
        let mut memory = filled(SeriesStore::in_memory(s.len()), &s);
        let mut spilled = filled(SeriesStore::spilled_in(dir.path()), &s);
        assert!(spilled.is_spilled());
        assert!(spilled.loaded().is_none());
        assert_eq!(spilled.len(), s.len());
        let expected = memory.load().unwrap().clone();
        assert_eq!(expected.wheel_rad.len(), s.len());
        assert!(expected.shoulder_elevation_rad.len() < s.len() * 2 / 3);
        assert_same_bits(spilled.load().unwrap(), &expected);
        // Read back once, then in memory.
        assert!(!spilled.is_spilled());
        assert_same_bits(spilled.loaded().unwrap(), &expected);
    }

    #[test]
    fn a_spill_without_its_directory_keeps_the_series_in_memory() {
        let dir = tempfile::tempdir().unwrap();
        let s = samples(300);
        let mut store = filled(SeriesStore::spilled_in(&dir.path().join("gone")), &s);
        assert!(!store.is_spilled());
        let mut memory = filled(SeriesStore::in_memory(0), &s);
        assert_same_bits(store.load().unwrap(), memory.load().unwrap());
    }

    #[test]
    fn a_disk_that_fills_up_mid_session_leaves_the_series_in_memory_whole() {
        let s = samples(10 * 128);
        let file = FillingUp::new(3 * SPILL_BUFFER_BYTES as u64 + 100, false);
        let mut store = SeriesStore::spilled_to(Box::new(file), Path::new("/rec"));
        store.push(s[0]);
        assert!(store.is_spilled());
        for &x in &s[1..] {
            store.push(x);
        }
        assert!(
            !store.is_spilled(),
            "the fourth buffer could not be written"
        );
        let mut memory = filled(SeriesStore::in_memory(0), &s);
        assert_same_bits(store.load().unwrap(), memory.load().unwrap());
    }

    #[test]
    fn a_spill_neither_writable_nor_readable_says_the_series_are_lost() {
        let s = samples(10 * 128);
        let file = FillingUp::new(2 * SPILL_BUFFER_BYTES as u64, true);
        let mut store = filled(
            SeriesStore::spilled_to(Box::new(file), Path::new("/rec")),
            &s,
        );
        assert_eq!(store.len(), s.len());
        let e = store.load().unwrap_err().to_string();
        assert!(e.contains("series are lost"), "{e}");
        assert!(e.contains("temporary file in /rec"), "{e}");
        assert!(e.contains("reading back"), "{e}");
    }

    #[test]
    fn a_spill_unreadable_at_the_end_says_so() {
        let s = samples(3 * 128);
        let file = FillingUp::new(u64::MAX / 2, true);
        let mut store = filled(
            SeriesStore::spilled_to(Box::new(file), Path::new("/rec")),
            &s,
        );
        let e = store.load().unwrap_err().to_string();
        assert!(e.contains("reading them back"), "{e}");
        // Asked again, the same answer.
        assert_eq!(store.load().unwrap_err().to_string(), e);
    }
}
