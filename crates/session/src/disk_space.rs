//! Room on the recording's disk: checked before a session starts (refused when the planned
//! session would not fit) and by the recorder thread each time it closes a chunk (recording
//! stops cleanly, the file finished and readable, before the disk is full).
//!
//! Free space is what an unprivileged writer may use (`statvfs`'s `f_bavail × f_frsize`; on
//! Windows `GetDiskFreeSpaceExW`'s bytes available to the caller, which count the user's
//! quota), measured on the filesystem that holds the recording.

use std::fmt;
use std::path::{Path, PathBuf};

/// What a recording takes, bytes per second of session: 600 MB per hour at 1 kHz, the largest
/// measured (~470 MB/h, slalom with the raw input channels; `telerehab bench recording`,
/// BENCHMARKS.md) plus a quarter for what varies (the exercise, the arm, paused time that
/// still records).
pub const RECORDING_BYTES_PER_S: u64 = 600_000_000 / 3600;

/// Space the recorder never writes into, bytes: recording stops when less is free, leaving
/// room to finish the file (the last chunk, the summary section and index, well under 1 MB
/// for a 4 h session) and for the rest of the system.
pub const RESERVE_BYTES: u64 = 64_000_000;

/// Bytes free for the station on the filesystem holding `path` (the recording itself, or the
/// directory it will be created in).
#[cfg(unix)]
pub fn free_bytes(path: &Path) -> std::io::Result<u64> {
    let s = rustix::fs::statvfs(path)?;
    Ok(s.f_bavail.saturating_mul(s.f_frsize))
}

/// Bytes free on the filesystem of the open file `file`.
#[cfg(unix)]
pub fn free_bytes_of(file: &std::fs::File) -> std::io::Result<u64> {
    let s = rustix::fs::fstatvfs(file)?;
    Ok(s.f_bavail.saturating_mul(s.f_frsize))
}

/// Bytes free for the station on the filesystem holding `path` (the recording itself, or the
/// directory it will be created in).
#[cfg(windows)]
#[expect(unsafe_code, reason = "GetDiskFreeSpaceExW, which std does not wrap")]
pub fn free_bytes(path: &Path) -> std::io::Result<u64> {
    use std::os::windows::ffi::OsStrExt as _;
    // A directory is asked about (a file's name is not accepted), and it must exist.
    let dir = if std::fs::metadata(path)?.is_dir() {
        path
    } else {
        directory_of(path)
    };
    let wide: Vec<u16> = dir.as_os_str().encode_wide().chain([0]).collect();
    let mut available = 0u64;
    // SAFETY: `wide` is NUL-terminated and outlives the call; the out-pointers are valid u64s
    // (the two totals are optional and not asked for).
    let ok = unsafe {
        windows_sys::Win32::Storage::FileSystem::GetDiskFreeSpaceExW(
            wide.as_ptr(),
            &mut available,
            std::ptr::null_mut(),
            std::ptr::null_mut(),
        )
    };
    if ok == 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(available)
}

/// Bytes free on the filesystem of the open file `file` (found by the file's final path).
#[cfg(windows)]
#[expect(
    unsafe_code,
    reason = "GetFinalPathNameByHandleW, which std does not wrap"
)]
pub fn free_bytes_of(file: &std::fs::File) -> std::io::Result<u64> {
    use std::os::windows::ffi::OsStringExt as _;
    use std::os::windows::io::AsRawHandle as _;
    let mut buf = vec![0u16; 1024];
    loop {
        // SAFETY: the handle is `file`'s, open for the call; `buf` holds `buf.len()` u16s.
        let n = unsafe {
            windows_sys::Win32::Storage::FileSystem::GetFinalPathNameByHandleW(
                file.as_raw_handle(),
                buf.as_mut_ptr(),
                buf.len() as u32,
                0,
            )
        } as usize;
        match n {
            0 => return Err(std::io::Error::last_os_error()),
            // Too small: `n` is the size needed, with the NUL.
            n if n > buf.len() => buf.resize(n, 0),
            n => {
                let path = PathBuf::from(std::ffi::OsString::from_wide(&buf[..n]));
                return free_bytes(&path);
            }
        }
    }
}

/// The directory a recording at `path` is created in.
pub fn directory_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Bytes a session of `duration_s` needs free before it starts: its recording at
/// [`RECORDING_BYTES_PER_S`] plus the [`RESERVE_BYTES`] it never writes into.
pub fn needed_bytes(duration_s: f64) -> u64 {
    (duration_s.max(0.0) * RECORDING_BYTES_PER_S as f64).ceil() as u64 + RESERVE_BYTES
}

/// Too little room on the recording's disk.
#[derive(Debug, thiserror::Error)]
pub struct LowSpace {
    /// The recording (or where it was to be created).
    pub path: PathBuf,
    /// Bytes free on its filesystem.
    pub free_bytes: u64,
    /// Bytes needed (before a session: the whole planned recording and the reserve; while
    /// recording: the reserve).
    pub needed_bytes: u64,
    /// Planned session length, s (`None` while recording).
    pub planned_s: Option<f64>,
}

/// `n` bytes as MB, one decimal.
fn mb(n: u64) -> String {
    format!("{:.1} MB", n as f64 / 1e6)
}

impl fmt::Display for LowSpace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.planned_s {
            Some(s) => write!(
                f,
                "not enough disk space to record {}: {} free on its filesystem, a {s:.0} s \
                 session needs {} ({} per hour of recording plus {} kept free); free some \
                 space, record elsewhere or plan a shorter session",
                self.path.display(),
                mb(self.free_bytes),
                mb(self.needed_bytes),
                mb(RECORDING_BYTES_PER_S * 3600),
                mb(RESERVE_BYTES),
            ),
            None => write!(
                f,
                "recording {}: stopped before the disk filled up, {} free on its filesystem \
                 (below the {} kept free); the file is finished and readable up to here",
                self.path.display(),
                mb(self.free_bytes),
                mb(self.needed_bytes),
            ),
        }
    }
}

/// Refuse a session of `duration_s` recorded at `path` when its filesystem has not room for
/// it (see [`needed_bytes`]); a filesystem that cannot be measured is let through (creating
/// the file then says what is wrong).
pub fn ensure_room(path: &Path, duration_s: f64) -> Result<(), LowSpace> {
    let Ok(free) = free_bytes(directory_of(path)) else {
        return Ok(());
    };
    check_room(path, free, duration_s)
}

/// [`ensure_room`] with the free bytes measured.
pub fn check_room(path: &Path, free_bytes: u64, duration_s: f64) -> Result<(), LowSpace> {
    let needed = needed_bytes(duration_s);
    if free_bytes >= needed {
        return Ok(());
    }
    Err(LowSpace {
        path: path.to_path_buf(),
        free_bytes,
        needed_bytes: needed,
        planned_s: Some(duration_s),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_hour_needs_600_mb_and_the_reserve() {
        assert_eq!(RECORDING_BYTES_PER_S, 166_666);
        let hour = needed_bytes(3600.0);
        assert!((663_000_000..665_000_000).contains(&hour), "{hour}");
        assert_eq!(needed_bytes(0.0), RESERVE_BYTES);
    }

    #[test]
    fn a_session_that_does_not_fit_is_refused_naming_the_path_the_free_bytes_and_the_need() {
        let path = Path::new("/data/session.mcap");
        assert!(check_room(path, needed_bytes(600.0), 600.0).is_ok());
        let err = check_room(path, needed_bytes(600.0) - 1, 600.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("/data/session.mcap"), "{err}");
        assert!(err.contains("164.0 MB free"), "{err}");
        assert!(err.contains("a 600 s session needs 164.0 MB"), "{err}");
        assert!(err.contains("600.0 MB per hour"), "{err}");
    }

    #[test]
    fn free_space_is_measured_on_the_recording_s_filesystem() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.mcap");
        let free = free_bytes(directory_of(&path)).unwrap();
        let file = std::fs::File::create(&path).unwrap();
        let free_of = free_bytes_of(&file).unwrap();
        // The same filesystem, a moment apart (others write to it too).
        assert!(
            free > 0 && free.abs_diff(free_of) < 1_000_000_000,
            "{free} {free_of}"
        );
        assert!(free_bytes(&dir.path().join("missing/s.mcap")).is_err());
        assert_eq!(directory_of(Path::new("s.mcap")), Path::new("."));
    }
}
