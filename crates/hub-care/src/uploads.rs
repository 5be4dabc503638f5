//! Recordings uploaded by stations, on the hub's disk: partial uploads that no station resumes
//! are removed after [`PARTIAL_UPLOAD_MAX_AGE`], so a station that announces uploads and goes
//! away cannot fill the disk beside the database.

use std::path::Path;
use std::time::{Duration, SystemTime};

use hub_store::HubError;

/// A partial upload (`<session>.<sha256 prefix>.part`) untouched this long is removed (7 days:
/// a station offline for a week starts that upload again).
pub const PARTIAL_UPLOAD_MAX_AGE: Duration = Duration::from_secs(7 * 24 * 3600);

/// How often `hub serve` looks for expired partial uploads.
pub const PARTIAL_UPLOAD_SWEEP: Duration = Duration::from_secs(3600);

/// Removes every `*.part` file under `recordings/<station>/` last written more than `max_age`
/// before `now`; returns how many. A missing `recordings` directory holds none.
pub fn expire_partial_uploads(
    recordings: &Path,
    max_age: Duration,
    now: SystemTime,
) -> Result<usize, HubError> {
    let io = |what: &str, path: &Path| {
        let context = format!("{what} {}", path.display());
        move |e| HubError::io(context, e)
    };
    let stations = match std::fs::read_dir(recordings) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(io("listing", recordings)(e)),
    };
    let mut removed = 0;
    for station in stations {
        let station = station.map_err(io("listing", recordings))?.path();
        if !station.is_dir() {
            continue;
        }
        for entry in std::fs::read_dir(&station).map_err(io("listing", &station))? {
            let path = entry.map_err(io("listing", &station))?.path();
            if path.extension().is_none_or(|e| e != "part") {
                continue;
            }
            let written = std::fs::metadata(&path)
                .and_then(|m| m.modified())
                .map_err(io("reading the age of", &path))?;
            if now.duration_since(written).unwrap_or_default() > max_age {
                std::fs::remove_file(&path).map_err(io("removing", &path))?;
                tracing::info!(path = %path.display(), "expired partial upload removed");
                removed += 1;
            }
        }
    }
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partial_uploads_older_than_the_limit_are_removed_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let station = dir.path().join("st-0123456789abcdef");
        std::fs::create_dir(&station).unwrap();
        let now = SystemTime::now();
        let file = |name: &str, age_s: u64| {
            let path = station.join(name);
            let f = std::fs::File::create(&path).unwrap();
            f.set_modified(now - Duration::from_secs(age_s)).unwrap();
            path
        };
        let week = PARTIAL_UPLOAD_MAX_AGE.as_secs();
        let old_part = file("s1.0123456789abcdef.part", week + 60);
        let fresh_part = file("s2.0123456789abcdef.part", week - 60);
        let old_recording = file("s3.mcap", 10 * week);
        let n = expire_partial_uploads(dir.path(), PARTIAL_UPLOAD_MAX_AGE, now).unwrap();
        assert_eq!(n, 1);
        assert!(!old_part.exists());
        assert!(fresh_part.exists() && old_recording.exists());
        let none = expire_partial_uploads(&dir.path().join("absent"), PARTIAL_UPLOAD_MAX_AGE, now);
        assert_eq!(none.unwrap(), 0);
    }
}
