//! Helpers for the end-to-end tests: locate the `telerehab` binary cargo built.

use std::path::PathBuf;

/// Path of the `telerehab` binary next to the test executable (cargo builds it for
/// `cargo test --workspace`); builds it with cargo if it is missing.
pub fn telerehab_bin() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let dir = exe
        .parent()
        .and_then(|d| d.parent())
        .expect("target profile directory");
    let bin = dir.join(format!("telerehab{}", std::env::consts::EXE_SUFFIX));
    if !bin.exists() {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let status = std::process::Command::new(cargo)
            .args(["build", "-p", "station", "--bin", "telerehab"])
            .status()
            .expect("run cargo build");
        assert!(status.success(), "cargo build of telerehab failed");
    }
    bin
}
