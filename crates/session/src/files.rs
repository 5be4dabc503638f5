//! The station's small files written whole: atomically (temporary file, fsync, rename) and
//! readable by the patient's account only.

use anyhow::Context;
use serde::Serialize;
use std::fs::OpenOptions;
use std::io::Write;
use std::path::Path;

/// Appends `entry` as one JSON line to the history at `path`, keeping its last `keep` lines
/// (written whole, atomically, 0600: a crash leaves the old history or the new one). The
/// station's session and assessment histories are such files.
pub fn append_kept(path: &Path, entry: &impl Serialize, keep: usize) -> anyhow::Result<()> {
    let old = std::fs::read_to_string(path).unwrap_or_default();
    let mut lines: Vec<String> = old
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(str::to_owned)
        .collect();
    lines.push(serde_json::to_string(entry)?);
    let skip = lines.len().saturating_sub(keep);
    let mut text = lines[skip..].join("\n");
    text.push('\n');
    write_private(path, text.as_bytes())
}

/// Writes `bytes` to `path` as a new 0600 file, atomically (temporary file, fsync, rename).
pub fn write_private(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let tmp = path.with_extension("tmp");
    let mut f =
        crate::platform::owner_only(OpenOptions::new().write(true).create(true).truncate(true))
            .open(&tmp)
            .with_context(|| format!("cannot create {}", tmp.display()))?;
    f.write_all(bytes)
        .and_then(|()| f.sync_all())
        .with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display()))
}
