//! The `tracing` subscriber: set up once, here, for the whole process (DESIGN.md, house style 4).
//!
//! Two layers: stderr — human text by default, one JSON object a line on request
//! ([`LogFormat::Json`], `--log-format json` or `TELEREHAB_LOG_FORMAT=json`, for a clinic
//! network's log collector) — and the running session's own log file in the station's home
//! ([`SessionLog`], plain text) so that a clinic's support can ask for it.

use std::ffi::OsStr;
use std::fs::File;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use tracing_subscriber::EnvFilter;
use tracing_subscriber::fmt::MakeWriter;
use tracing_subscriber::layer::SubscriberExt as _;
use tracing_subscriber::util::SubscriberInitExt as _;

/// Session log files a station keeps in `<home>/logs`; the oldest go at a session's start.
pub const SESSION_LOGS_KEPT: usize = 30;

/// The running session's log file, if any: what the file layer writes to.
static SESSION_FILE: Mutex<Option<File>> = Mutex::new(None);

/// Writes to the running session's log file, or nowhere between sessions.
struct SessionFileWriter;

impl Write for SessionFileWriter {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match SESSION_FILE.lock() {
            Ok(mut slot) => match slot.as_mut() {
                Some(f) => f.write_all(buf).map(|()| buf.len()),
                None => Ok(buf.len()),
            },
            Err(_) => Ok(buf.len()),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match SESSION_FILE.lock() {
            Ok(mut slot) => slot.as_mut().map_or(Ok(()), Write::flush),
            Err(_) => Ok(()),
        }
    }
}

impl<'a> MakeWriter<'a> for SessionFileWriter {
    type Writer = SessionFileWriter;

    fn make_writer(&'a self) -> Self::Writer {
        SessionFileWriter
    }
}

/// While alive, every log line of the process also goes to its file, without colour codes.
#[derive(Debug)]
pub struct SessionLog {
    path: PathBuf,
}

impl SessionLog {
    /// Starts `<home>/logs/<name>.log` after deleting the oldest logs there beyond the last
    /// [`SESSION_LOGS_KEPT`] − 1, so that with this one the last 30 are kept.
    pub fn start(home_dir: &Path, name: &str) -> anyhow::Result<Self> {
        let dir = home_dir.join("logs");
        crate::home::private_dir(&dir)?;
        prune_logs(&dir, SESSION_LOGS_KEPT - 1);
        let path = dir.join(format!("{name}.log"));
        let file = File::options()
            .create(true)
            .append(true)
            .open(&path)
            .map_err(|e| anyhow::anyhow!("cannot write the session log {}: {e}", path.display()))?;
        if let Ok(mut slot) = SESSION_FILE.lock() {
            *slot = Some(file);
        }
        Ok(Self { path })
    }

    /// The log file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for SessionLog {
    fn drop(&mut self) {
        if let Ok(mut slot) = SESSION_FILE.lock()
            && let Some(mut f) = slot.take()
        {
            let _ = f.flush();
        }
    }
}

/// Removes the oldest `.log` files of `dir` beyond `keep` (names sort by time).
pub fn prune_logs(dir: &Path, keep: usize) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut logs: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "log"))
        .collect();
    logs.sort();
    let excess = logs.len().saturating_sub(keep);
    for old in &logs[..excess] {
        if let Err(e) = std::fs::remove_file(old) {
            tracing::warn!(path = %old.display(), "cannot delete an old session log: {e}");
        }
    }
}

/// How stderr's log lines are written.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum LogFormat {
    /// For people: `TIME LEVEL target: message field=value`.
    #[default]
    Text,
    /// For log collectors: one JSON object a line with `timestamp` (RFC 3339, UTC), `level`,
    /// `target`, `message` and the event's fields beside them (and its spans').
    Json,
}

/// Log to stderr in `format` with `filter` (e.g. `info`, `station=trace`), else `RUST_LOG`,
/// else `info`. Text is coloured only on a terminal and never with `NO_COLOR` set
/// (no-color.org): a log redirected to a file or a service's journal is plain text.
pub fn init(filter: Option<&str>, format: LogFormat) {
    let filter = match filter {
        Some(f) => EnvFilter::new(f),
        None => EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")),
    };
    let colour = use_colour(
        std::io::stderr().is_terminal(),
        std::env::var_os("NO_COLOR").as_deref(),
    );
    let (text, json) = match format {
        LogFormat::Text => (
            Some(
                tracing_subscriber::fmt::layer()
                    .with_ansi(colour)
                    .with_writer(std::io::stderr),
            ),
            None,
        ),
        LogFormat::Json => (
            None,
            Some(
                tracing_subscriber::fmt::layer()
                    .json()
                    .flatten_event(true)
                    .with_writer(std::io::stderr),
            ),
        ),
    };
    let file = tracing_subscriber::fmt::layer()
        .with_ansi(false)
        .with_writer(SessionFileWriter);
    let _ = tracing_subscriber::registry()
        .with(filter)
        .with(text)
        .with(json)
        .with(file)
        .try_init();
}

/// Whether to colour the log: on a terminal, unless `NO_COLOR` is set to anything but "".
pub fn use_colour(stderr_is_terminal: bool, no_color: Option<&OsStr>) -> bool {
    stderr_is_terminal && no_color.is_none_or(OsStr::is_empty)
}

#[cfg(test)]
mod tests {
    use super::{prune_logs, use_colour};
    use std::ffi::OsStr;

    #[test]
    fn pruning_session_logs_keeps_the_newest_and_leaves_other_files() {
        let dir = tempfile::tempdir().unwrap();
        for i in 0..5 {
            std::fs::write(dir.path().join(format!("session-{i:02}.log")), "x").unwrap();
        }
        std::fs::write(dir.path().join("notes.txt"), "x").unwrap();
        prune_logs(dir.path(), 3);
        let mut left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        left.sort();
        assert_eq!(
            left,
            [
                "notes.txt",
                "session-02.log",
                "session-03.log",
                "session-04.log"
            ]
        );
    }

    #[test]
    fn the_log_is_coloured_only_on_a_terminal_without_no_color() {
        assert!(use_colour(true, None));
        assert!(use_colour(true, Some(OsStr::new(""))));
        assert!(!use_colour(true, Some(OsStr::new("1"))));
        assert!(!use_colour(false, None));
        assert!(!use_colour(false, Some(OsStr::new(""))));
    }
}
