//! The hub's on-disk store: `DIR/<station_id>/<session_id>.jsonl` (one JSON summary per line,
//! in sequence order), `DIR/<station_id>/<session_id>.hello.json` and, once the station's
//! `Bye` brought them, the session's movement measures in `<session_id>.measures.json`.
//!
//! Dedup survives reconnects and hub restarts: opening a session file reads the sequence
//! number of its last complete line, and only summaries with a higher one are appended. A
//! partial last line (the hub was killed mid-write, so it was never acknowledged) is cut off.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::error::NetlinkError;
use crate::frame::{Bye, Hello, Summary, check_id};

/// One session's summary file, open for appending.
#[derive(Debug)]
pub struct SessionFile {
    path: PathBuf,
    file: File,
    last_seq: Option<u64>,
}

/// What [`SessionFile::append`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Appended {
    /// The summary was new and is now in the file.
    Stored,
    /// A summary with this or a higher sequence number was already stored; nothing written.
    Duplicate,
}

/// The directory of one station inside the store, checking the id is a safe path component.
fn station_dir(store_dir: &Path, station_id: &str) -> Result<PathBuf, NetlinkError> {
    check_id("station_id", station_id).map_err(|e| NetlinkError::Protocol(e.to_string()))?;
    Ok(store_dir.join(station_id))
}

/// Path of a session's summary file.
pub fn session_path(
    store_dir: &Path,
    station_id: &str,
    session_id: &str,
) -> Result<PathBuf, NetlinkError> {
    check_id("session_id", session_id).map_err(|e| NetlinkError::Protocol(e.to_string()))?;
    Ok(station_dir(store_dir, station_id)?.join(format!("{session_id}.jsonl")))
}

/// Writes `DIR/<station_id>/<session_id>.hello.json` atomically (temp file + rename).
pub fn write_hello(store_dir: &Path, hello: &Hello) -> Result<(), NetlinkError> {
    write_session_json(
        store_dir,
        &hello.station_id,
        &hello.session_id,
        "hello",
        hello,
    )
}

/// Writes the session's movement measures from its `Bye` to
/// `DIR/<station_id>/<session_id>.measures.json` atomically (a repeated Bye rewrites them).
pub fn write_measures(store_dir: &Path, station_id: &str, bye: &Bye) -> Result<(), NetlinkError> {
    write_session_json(
        store_dir,
        station_id,
        &bye.session_id,
        "measures",
        &bye.measures,
    )
}

/// Writes `DIR/<station_id>/<session_id>.<what>.json` atomically (temp file + rename).
fn write_session_json<T: serde::Serialize>(
    store_dir: &Path,
    station_id: &str,
    session_id: &str,
    what: &str,
    value: &T,
) -> Result<(), NetlinkError> {
    let dir = station_dir(store_dir, station_id)?;
    check_id("session_id", session_id).map_err(|e| NetlinkError::Protocol(e.to_string()))?;
    std::fs::create_dir_all(&dir)
        .map_err(|e| NetlinkError::io(format!("creating {}", dir.display()), e))?;
    let path = dir.join(format!("{session_id}.{what}.json"));
    let tmp = dir.join(format!("{session_id}.{what}.json.tmp"));
    let json = serde_json::to_vec_pretty(value)
        .map_err(|e| NetlinkError::Protocol(format!("cannot serialise the {what}: {e}")))?;
    std::fs::write(&tmp, json)
        .map_err(|e| NetlinkError::io(format!("writing {}", tmp.display()), e))?;
    std::fs::rename(&tmp, &path)
        .map_err(|e| NetlinkError::io(format!("renaming {} into place", tmp.display()), e))
}

impl SessionFile {
    /// Opens (creating if needed) a session's file and reads the last stored sequence number.
    pub fn open(
        store_dir: &Path,
        station_id: &str,
        session_id: &str,
    ) -> Result<Self, NetlinkError> {
        let path = session_path(store_dir, station_id, session_id)?;
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)
                .map_err(|e| NetlinkError::io(format!("creating {}", dir.display()), e))?;
        }
        let ctx = |what: &str| format!("{what} {}", path.display());
        let mut file = OpenOptions::new()
            .read(true)
            .append(true)
            .create(true)
            .open(&path)
            .map_err(|e| NetlinkError::io(ctx("opening"), e))?;
        let mut content = Vec::new();
        file.read_to_end(&mut content)
            .map_err(|e| NetlinkError::io(ctx("reading"), e))?;
        let complete = crate::ndjson::complete_len(&content);
        if complete < content.len() {
            tracing::warn!(
                path = %path.display(),
                bytes = content.len() - complete,
                "cutting off a partial last line (hub stopped mid-write; it was never acknowledged)"
            );
            file.set_len(complete as u64)
                .map_err(|e| NetlinkError::io(ctx("truncating"), e))?;
            file.seek(SeekFrom::End(0))
                .map_err(|e| NetlinkError::io(ctx("seeking"), e))?;
        }
        let last_line = crate::ndjson::read_lines(&content[..]).last();
        let last_seq = match last_line {
            None => None,
            Some((_, line)) => {
                let s: Summary = crate::ndjson::parse(&line).map_err(|e| {
                    NetlinkError::Protocol(format!(
                        "{}: last line is not a summary ({e}); refusing to append to a damaged file",
                        path.display()
                    ))
                })?;
                Some(s.seq)
            }
        };
        Ok(Self {
            path,
            file,
            last_seq,
        })
    }

    /// Highest sequence number stored, `None` if the file is empty.
    pub fn last_seq(&self) -> Option<u64> {
        self.last_seq
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends `summary` as one line unless its sequence number is not above the last stored.
    ///
    /// The line is handed to the OS with one `write` call before returning (it survives a hub
    /// crash); [`Self::sync`] makes it survive power loss.
    pub fn append(&mut self, summary: &Summary) -> Result<Appended, NetlinkError> {
        if self.last_seq.is_some_and(|last| summary.seq <= last) {
            return Ok(Appended::Duplicate);
        }
        let mut line = serde_json::to_vec(summary)
            .map_err(|e| NetlinkError::Protocol(format!("cannot serialise summary: {e}")))?;
        line.push(b'\n');
        self.file
            .write_all(&line)
            .map_err(|e| NetlinkError::io(format!("appending to {}", self.path.display()), e))?;
        self.last_seq = Some(summary.seq);
        Ok(Appended::Stored)
    }

    /// A second handle on the file, to `sync_data` it off the async threads.
    pub fn try_clone_file(&self) -> Result<File, NetlinkError> {
        self.file.try_clone().map_err(|e| {
            NetlinkError::io(format!("duplicating handle of {}", self.path.display()), e)
        })
    }

    /// Flushes the file's data to disk (fsync).
    pub fn sync(&self) -> Result<(), NetlinkError> {
        self.file
            .sync_data()
            .map_err(|e| NetlinkError::io(format!("syncing {}", self.path.display()), e))
    }
}

/// Reads every summary stored for a session, in file order (a last line cut short is no
/// summary: [`SessionFile::open`] cuts it off; a complete line that does not read is an error
/// naming it).
pub fn read_session(
    store_dir: &Path,
    station_id: &str,
    session_id: &str,
) -> Result<Vec<Summary>, NetlinkError> {
    let path = session_path(store_dir, station_id, session_id)?;
    let file = File::open(&path)
        .map_err(|e| NetlinkError::io(format!("reading {}", path.display()), e))?;
    crate::ndjson::read_lines(std::io::BufReader::new(file))
        .map(|(n, line)| {
            crate::ndjson::parse(&line)
                .map_err(|e| NetlinkError::Protocol(format!("{} line {n}: {e}", path.display())))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::tests::summary;

    #[test]
    fn duplicates_are_skipped_across_reopen() {
        let dir = tempfile::tempdir().unwrap();
        let mut f = SessionFile::open(dir.path(), "st1", "s1").unwrap();
        assert_eq!(f.last_seq(), None);
        for seq in 0..5 {
            assert_eq!(f.append(&summary("s1", seq)).unwrap(), Appended::Stored);
        }
        assert_eq!(f.append(&summary("s1", 3)).unwrap(), Appended::Duplicate);
        f.sync().unwrap();
        drop(f);
        let mut f = SessionFile::open(dir.path(), "st1", "s1").unwrap();
        assert_eq!(f.last_seq(), Some(4));
        assert_eq!(f.append(&summary("s1", 4)).unwrap(), Appended::Duplicate);
        assert_eq!(f.append(&summary("s1", 5)).unwrap(), Appended::Stored);
        let seqs: Vec<u64> = read_session(dir.path(), "st1", "s1")
            .unwrap()
            .iter()
            .map(|s| s.seq)
            .collect();
        assert_eq!(seqs, vec![0, 1, 2, 3, 4, 5]);
    }

    #[test]
    fn partial_last_line_is_cut_off_on_open() {
        let dir = tempfile::tempdir().unwrap();
        let mut f = SessionFile::open(dir.path(), "st1", "s1").unwrap();
        f.append(&summary("s1", 1)).unwrap();
        let path = f.path().to_owned();
        drop(f);
        let mut raw = OpenOptions::new().append(true).open(&path).unwrap();
        raw.write_all(br#"{"session_id":"s1","seq":2,"t_s"#)
            .unwrap();
        drop(raw);
        let mut f = SessionFile::open(dir.path(), "st1", "s1").unwrap();
        assert_eq!(f.last_seq(), Some(1));
        f.append(&summary("s1", 2)).unwrap();
        let seqs: Vec<u64> = read_session(dir.path(), "st1", "s1")
            .unwrap()
            .iter()
            .map(|s| s.seq)
            .collect();
        assert_eq!(seqs, vec![1, 2]);
    }

    #[test]
    fn damaged_last_line_is_an_error_not_a_silent_restart() {
        let dir = tempfile::tempdir().unwrap();
        let path = session_path(dir.path(), "st1", "s1").unwrap();
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, "not json\n").unwrap();
        let err = SessionFile::open(dir.path(), "st1", "s1")
            .unwrap_err()
            .to_string();
        assert!(err.contains("damaged"), "{err}");
    }

    #[test]
    fn path_traversal_ids_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        assert!(SessionFile::open(dir.path(), "..", "s1").is_err());
        assert!(SessionFile::open(dir.path(), "st", "../x").is_err());
    }

    #[test]
    fn hello_is_written_next_to_the_session_file() {
        let dir = tempfile::tempdir().unwrap();
        let hello = Hello {
            protocol_version: crate::frame::PROTOCOL_VERSION,
            station_id: "st1".into(),
            patient_id: "p1".into(),
            session_id: "s1".into(),
            exercise: "sine-road".into(),
            started_unix_ms: 5,
            software_version: "t".into(),
            min_protocol_version: None,
            wheel: None,
        };
        write_hello(dir.path(), &hello).unwrap();
        let back: Hello =
            serde_json::from_slice(&std::fs::read(dir.path().join("st1/s1.hello.json")).unwrap())
                .unwrap();
        assert_eq!(back, hello);
    }
}
