//! What the station does differently on its two systems, Linux and Windows (issue 46), in one
//! place; every other module is the same code on both.
//!
//! - **Owner-only files.** Health data and keys are the patient's account's only. On Linux:
//!   files 0600 in directories 0700. On Windows a file under the user's profile (the station's
//!   home is in `%APPDATA%`) inherits an access list that admits that user, SYSTEM and the
//!   administrators only, so there is nothing to add and no mode to check.
//! - **Starting over in a fresh process** (one window event loop a process): `exec` on Linux;
//!   Windows has no `exec`, so the new process runs to its end and this one exits with its
//!   status.
//! - **How a child ended**: Linux adds the signal that killed it.

use std::fs::{Metadata, OpenOptions};
use std::io;
use std::path::Path;
use std::process::{Command, ExitStatus};

/// `options` made to create a file only its owner may read and write (0600 on Linux; on
/// Windows the profile's inherited access list).
pub fn owner_only(options: &mut OpenOptions) -> &mut OpenOptions {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.mode(0o600)
    }
    #[cfg(not(unix))]
    {
        options
    }
}

/// Creates `dir` (and its parents) if missing and makes it its owner's only (0700 on Linux,
/// also when it existed; on Windows the profile's inherited access list).
pub fn owner_only_dir(dir: &Path) -> io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::{DirBuilderExt, PermissionsExt};
        std::fs::DirBuilder::new()
            .recursive(true)
            .mode(0o700)
            .create(dir)?;
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o700))
    }
    #[cfg(not(unix))]
    {
        std::fs::create_dir_all(dir)
    }
}

/// The permission bits (`0o777`) of a file that others than its owner may use, or `None` when
/// only the owner may (always `None` on Windows, where access lists decide).
pub fn open_to_others(meta: &Metadata) -> Option<u32> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = meta.permissions().mode();
        (mode & 0o077 != 0).then_some(mode & 0o777)
    }
    #[cfg(not(unix))]
    {
        let _ = meta;
        None
    }
}

/// Continues as `command` in a fresh process image. Returns only when that could not be done:
/// on Linux this process becomes `command` (`exec`); on Windows `command` runs to its end and
/// this process exits with its status.
pub fn replace_process(mut command: Command) -> io::Error {
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        command.exec()
    }
    #[cfg(not(unix))]
    {
        match command.status() {
            Ok(status) => std::process::exit(status.code().unwrap_or(1)),
            Err(e) => e,
        }
    }
}

/// How a child process ended, in words for a log ("exited", "exited with status 3", "was
/// killed by signal 9").
pub fn describe_exit(status: ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(sig) = status.signal() {
            return format!("was killed by signal {sig}");
        }
    }
    match status.code() {
        Some(0) => "exited".to_owned(),
        Some(code) => format!("exited with status {code}"),
        None => "ended".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn owner_only_files_and_directories_are_closed_to_others() {
        let dir = tempfile::tempdir().unwrap();
        let home = dir.path().join("a/b");
        owner_only_dir(&home).unwrap();
        assert_eq!(open_to_others(&std::fs::metadata(&home).unwrap()), None);
        let key = home.join("key");
        owner_only(OpenOptions::new().write(true).create_new(true))
            .open(&key)
            .unwrap();
        assert_eq!(open_to_others(&std::fs::metadata(&key).unwrap()), None);
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&key, std::fs::Permissions::from_mode(0o644)).unwrap();
        assert_eq!(
            open_to_others(&std::fs::metadata(&key).unwrap()),
            Some(0o644)
        );
    }

    #[test]
    fn an_exit_is_described_by_its_status() {
        let ok = Command::new(std::env::current_exe().unwrap())
            .arg("--list")
            .stdout(std::process::Stdio::null())
            .status()
            .unwrap();
        assert_eq!(describe_exit(ok), "exited");
    }
}
