//! End-to-end: `telerehab doctor` on this machine (no wheel, no arm sensor): not ready, the
//! wheel named as missing, one line per check, and a home it cannot read said so (exit 2).

use std::path::Path;
use std::process::{Command, Output};
use telerehab_tests::telerehab_bin;

/// `telerehab doctor ARGS --home HOME` with a clean environment for the home.
fn doctor(home: &Path, args: &[&str]) -> Output {
    Command::new(telerehab_bin())
        .arg("doctor")
        .args(args)
        .arg("--home")
        .arg(home)
        .env_remove("TELEREHAB_HOME")
        .output()
        .expect("run telerehab doctor")
}

fn json_of(out: &Output) -> serde_json::Value {
    let text = String::from_utf8_lossy(&out.stdout);
    serde_json::from_str(text.trim())
        .unwrap_or_else(|e| panic!("not one JSON object ({e}): {text}"))
}

fn check<'a>(report: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    report["checks"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("no `{name}` check in {report}"))
}

#[test]
fn doctor_json_without_a_wheel_exits_1_with_the_wheel_failed_and_what_to_plug_in() {
    let home = tempfile::tempdir().unwrap();
    let out = doctor(home.path(), &["--json"]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report = json_of(&out);
    assert_eq!(report["ready"], false, "{report}");
    let wheel = check(&report, "wheel");
    assert_eq!(wheel["status"], "fail", "{report}");
    assert!(
        wheel["fix"].as_str().unwrap().contains("plug in the wheel"),
        "{wheel}"
    );
    for c in report["checks"].as_array().unwrap() {
        let status = c["status"].as_str().unwrap();
        assert!(["pass", "fail", "warn", "skip"].contains(&status), "{c}");
        assert!(c["detail"].is_string() && c["fix"].is_string(), "{c}");
    }
    // An empty home: not paired (a warning, not a failure), versions stated.
    assert_eq!(check(&report, "clinic pairing")["status"], "warn");
    let versions = check(&report, "versions")["detail"]
        .as_str()
        .unwrap()
        .to_owned();
    assert!(versions.contains("link protocol"), "{versions}");
    assert!(versions.contains("recording format"), "{versions}");
}

#[test]
fn doctor_prints_one_line_per_check_then_the_verdict() {
    let home = tempfile::tempdir().unwrap();
    let json = json_of(&doctor(home.path(), &["--json"]));
    let out = doctor(home.path(), &[]);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = text.lines().collect();
    let checks = json["checks"].as_array().unwrap();
    assert_eq!(lines.len(), checks.len() + 1, "{text}");
    for (line, c) in lines.iter().zip(checks) {
        let tag = c["status"].as_str().unwrap().to_uppercase();
        let name = c["name"].as_str().unwrap();
        assert!(line.starts_with(&format!("{tag}  {name}: ")), "{line}");
    }
    let wheel = lines.iter().find(|l| l.contains("  wheel: ")).unwrap();
    assert!(
        wheel.starts_with("FAIL") && wheel.contains("plug in the wheel"),
        "{wheel}"
    );
    assert!(lines.last().unwrap().starts_with("Not ready"), "{text}");
}

#[test]
fn doctor_with_a_home_it_cannot_read_exits_2_naming_the_home() {
    // A home under a regular file cannot be read by anyone, root included.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("not-a-directory");
    std::fs::write(&file, b"x").unwrap();
    let home = file.join("home");
    let out = doctor(&home, &["--json"]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let report = json_of(&out);
    assert_eq!(report["ready"], false);
    let c = check(&report, "station home");
    assert_eq!(c["status"], "fail");
    let detail = c["detail"].as_str().unwrap();
    assert!(detail.contains(home.to_str().unwrap()), "{detail}");
    assert!(c["fix"].as_str().unwrap().contains("--home"), "{c}");
}

#[test]
fn doctor_on_a_paired_station_states_the_certificate_and_reaches_the_hub_only_with_hub_flag() {
    use telerehab_tests::clinic::{Hub, clinic, ok};
    let dir = tempfile::tempdir().unwrap();
    let (data, code) = clinic(dir.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = dir.path().join("station");
    ok(
        &["pair", "--hub", &hub.stations, "--code", &code],
        Some(&home),
    );

    let quiet = json_of(&doctor(&home, &["--json"]));
    let pairing = check(&quiet, "clinic pairing");
    assert_eq!(pairing["status"], "pass", "{pairing}");
    let detail = pairing["detail"].as_str().unwrap();
    assert!(
        detail.contains(&hub.stations) && detail.contains("certificate valid for"),
        "{detail}"
    );
    assert_eq!(check(&quiet, "hub")["status"], "skip", "{quiet}");

    let reached = json_of(&doctor(&home, &["--json", "--hub"]));
    assert_eq!(check(&reached, "hub")["status"], "pass", "{reached}");
    // The hub told its clock (same machine: within the 5 s the check allows) and serves
    // this station's protocol.
    let clock = check(&reached, "clock");
    assert_eq!(clock["status"], "pass", "{clock}");
    assert!(
        clock["detail"]
            .as_str()
            .unwrap()
            .contains("the hub's clock is"),
        "{clock}"
    );
    let versions = check(&reached, "versions");
    assert!(
        versions["detail"]
            .as_str()
            .unwrap()
            .contains("the hub serves it"),
        "{versions}"
    );

    hub.stop();
    let down = json_of(&doctor(&home, &["--json", "--hub"]));
    let c = check(&down, "hub");
    assert_eq!(c["status"], "warn", "{c}");
    assert!(
        c["detail"].as_str().unwrap().contains("cannot reach"),
        "{c}"
    );
}
