//! `telerehab recover`: turn the recording of a killed session into a finished MCAP file
//! (the copy itself is [`record::recover`]).
//!
//! The input is streamed (memory does not grow with its size) and never written to; the
//! output is written to a temporary file beside it, synced, then renamed into place, so a
//! crash during recovery never leaves a half-written file under the asked-for name.

use anyhow::{Context, bail};
use record::recover::{Recovered, recover as recover_stream};
use std::io::{BufReader, BufWriter};
use std::path::{Path, PathBuf};

/// `telerehab recover`.
#[derive(Debug, clap::Args)]
pub struct RecoverArgs {
    /// The recording left by the killed session.
    pub input: PathBuf,
    /// Where to write the finished file (a new file: never the input, never over another).
    #[arg(long)]
    pub out: PathBuf,
}

/// Recover `args.input` into `args.out` and say what was copied.
pub fn run(args: &RecoverArgs) -> anyhow::Result<()> {
    let r = recover(&args.input, &args.out)?;
    println!(
        "recovered {} messages on {} channels into {}{}",
        r.messages,
        r.channels,
        args.out.display(),
        r.stopped_at
            .map(|e| format!(" (the truncated tail was dropped: {e})"))
            .unwrap_or_default()
    );
    Ok(())
}

/// Copy the readable part of `input` into a finished MCAP file `output`, a new file.
pub fn recover(input: &Path, output: &Path) -> anyhow::Result<Recovered> {
    let file =
        std::fs::File::open(input).with_context(|| format!("cannot read {}", input.display()))?;
    let input_meta = file
        .metadata()
        .with_context(|| format!("cannot read {}", input.display()))?;
    let input_handle = file
        .try_clone()
        .and_then(same_file::Handle::from_file)
        .with_context(|| format!("cannot read {}", input.display()))?;
    // Never over an existing file: above all not over the input, the only copy of the
    // session, whatever the spelling of its path (a symlink, `./`, a hard link): the same
    // device and inode on Linux, the same volume and file index on Windows. (Only a regular
    // file is opened to compare: opening a FIFO would wait for a writer; anything else that
    // exists is refused by the rename below.)
    if std::fs::metadata(output).is_ok_and(|m| m.is_file())
        && let Ok(out_handle) = same_file::Handle::from_path(output)
        && out_handle == input_handle
    {
        bail!(
            "cannot create {}: it is the input {} itself (recover never writes over an \
             existing file, its input least of all)",
            output.display(),
            input.display()
        );
    }
    if std::fs::symlink_metadata(output).is_ok() {
        bail!(
            "cannot create {}: it exists (recover never writes over an existing file, its \
             input least of all)",
            output.display()
        );
    }
    let dir = match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    // A temporary file beside the output (same filesystem), renamed into place when whole.
    let tmp = tempfile::Builder::new()
        .prefix(".recover-")
        .suffix(".mcap.tmp")
        .tempfile_in(dir)
        .with_context(|| format!("cannot create a temporary file in {}", dir.display()))?;
    let (copied, sink) = recover_stream(
        BufReader::with_capacity(256 * 1024, file),
        BufWriter::new(tmp),
    )
    .with_context(|| format!("cannot recover {}", input.display()))?;
    let tmp = sink
        .into_inner()
        .map_err(|e| e.into_error())
        .with_context(|| format!("cannot write {}", output.display()))?;
    // The recovered file has the input's permissions (a station's recordings are private).
    tmp.as_file()
        .set_permissions(input_meta.permissions())
        .and_then(|()| tmp.as_file().sync_all())
        .with_context(|| format!("cannot write {}", output.display()))?;
    // Renamed only if nothing took the name meanwhile: still never over an existing file.
    tmp.persist_noclobber(output).map_err(|e| {
        anyhow::Error::new(e.error).context(format!(
            "cannot create {} (recover never writes over an existing file, its input least \
             of all)",
            output.display()
        ))
    })?;
    // The rename itself reaches the disk with its directory.
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(copied)
}

#[cfg(test)]
mod tests {
    use super::recover;

    /// A finished 3-tick recording at `path`, then the file cut to a killed session's.
    fn killed_recording(path: &std::path::Path) {
        use record::{RecordWriter, SessionMetadata, TickRecord};
        let meta = SessionMetadata {
            exercise: "sine-road".into(),
            seed: 7,
            patient_id: "p".into(),
            loop_rate_hz: 1000.0,
            ..Default::default()
        };
        let file = std::fs::File::create(path).unwrap();
        let mut w = RecordWriter::new(std::io::BufWriter::new(file), 0, &meta).unwrap();
        for tick in 0..3 {
            let rec = TickRecord {
                tick,
                t_ns: tick * 1_000_000,
                ..Default::default()
            };
            w.write_tick(&rec, false).unwrap();
        }
        w.flush().unwrap();
        let len = std::fs::metadata(path).unwrap().len();
        drop(w.finish().unwrap());
        // Cut the summary section off, as a SIGKILL after the flush leaves the file.
        std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .unwrap()
            .set_len(len)
            .unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn recover_refuses_its_own_input_through_a_symlink_or_another_spelling() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("killed.mcap");
        killed_recording(&input);
        let before = std::fs::read(&input).unwrap();
        let link = dir.path().join("link.mcap");
        std::os::unix::fs::symlink(&input, &link).unwrap();
        let hard = dir.path().join("hard.mcap");
        std::fs::hard_link(&input, &hard).unwrap();
        let dotted = dir.path().join(".").join("killed.mcap");
        for out in [&input, &link, &hard, &dotted] {
            let err = format!("{:#}", recover(&input, out).unwrap_err());
            assert!(
                err.contains("is the input") && err.contains("never writes over"),
                "{}: {err}",
                out.display()
            );
        }
        assert_eq!(
            std::fs::read(&input).unwrap(),
            before,
            "the input is untouched"
        );
    }

    #[cfg(unix)]
    #[test]
    fn recover_refuses_any_existing_file_or_dangling_symlink() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("killed.mcap");
        killed_recording(&input);
        let other = dir.path().join("other.mcap");
        std::fs::write(&other, b"keep me").unwrap();
        let dangling = dir.path().join("dangling.mcap");
        std::os::unix::fs::symlink(dir.path().join("nowhere"), &dangling).unwrap();
        for out in [&other, &dangling] {
            let err = format!("{:#}", recover(&input, out).unwrap_err());
            assert!(err.contains("never writes over an existing file"), "{err}");
        }
        assert_eq!(std::fs::read(&other).unwrap(), b"keep me");
        assert!(!dir.path().join("nowhere").exists());
    }

    #[test]
    fn recover_writes_the_finished_file_and_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("killed.mcap");
        killed_recording(&input);
        let out = dir.path().join("fixed.mcap");
        let copied = recover(&input, &out).unwrap();
        assert!(
            copied.messages > 0 && copied.stopped_at.is_some(),
            "{copied:?}"
        );
        let bytes = std::fs::read(&out).unwrap();
        assert!(mcap::Summary::read(&bytes).unwrap().is_some(), "finished");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
    }

    #[test]
    fn a_failed_recovery_leaves_nothing_under_the_output_name() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("garbage.mcap");
        std::fs::write(&input, b"not a recording at all").unwrap();
        let out = dir.path().join("fixed.mcap");
        let err = format!("{:#}", recover(&input, &out).unwrap_err());
        assert!(err.contains("not an MCAP file"), "{err}");
        assert!(!out.exists());
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "no temporary file left"
        );
    }
}
