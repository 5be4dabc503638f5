//! End-to-end: the binary runs.

#[test]
fn binary_reports_its_version() {
    let out = std::process::Command::new(telerehab_tests::telerehab_bin())
        .arg("--version")
        .output()
        .expect("run telerehab");
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("telerehab "));
}
