//! End-to-end: today's page stays current. A clinic's hub (`hub serve`, its embedded
//! database) and a paired simulated station showing today's page in a real window (under the
//! test's own Xvfb when no display is set); the therapist prescribes a plan and writes a
//! message through the console's API while the page is open, and within the page's next check
//! (every 30 s) the station keeps the hub's regimen and message and the page's plan changes,
//! in the language the prescription sets for the patient. Followed by the page's state in the
//! log (`language=`, `prescribed=`, `exercises=`, `message_id=`) and the kept files, never by
//! words.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use telerehab_tests::clinic::{Hub, NewClinic, pair};
use telerehab_tests::console::Console;
use telerehab_tests::logged::{self, Xvfb};
use telerehab_tests::{Reaper, telerehab_bin};

/// Today's page asks the hub on opening and every 30 s; one period and a margin.
const WITHIN: Duration = Duration::from_secs(75);

#[test]
fn a_plan_a_message_and_the_patients_language_sent_while_todays_page_is_open_show_within_its_next_check()
 {
    let tmp = tempfile::tempdir().unwrap();
    let (display, _xvfb) = Xvfb::set_or_start();
    let clinic = NewClinic::make(tmp.path(), None);
    let hub = Hub::serve_console(&clinic.data, "127.0.0.1:0");
    let console = Console::new(&clinic.data, hub.web());
    let cookie = console.login("ana@clinic.example", &clinic.admin_password);
    let patients = console.get("/api/patients", &cookie).json();
    let patient = patients[0]["id"].as_str().unwrap().to_owned();
    let home = tmp.path().join("station");
    pair(&hub, &clinic.code, &home);
    // The language was chosen on an earlier day: today's page comes first.
    std::fs::write(home.join("settings.toml"), "language = \"en\"\n").unwrap();
    let script = tmp.path().join("wheel.script");
    std::fs::write(&script, "").unwrap();
    let mut child = Command::new(telerehab_bin())
        .env("DISPLAY", &display)
        .env("TELEREHAB_HOME", &home)
        .env("TELEREHAB_WHEEL_SCRIPT", &script)
        .env("RUST_LOG", "info")
        .env_remove("TELEREHAB_LANGUAGE")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let _reaper = Reaper(child.id());
    let lines = logged::stderr_lines(&mut child);

    // Today's page opens (its plan may be logged before the window's page line): nothing
    // prescribed yet, the station's default drive, no message.
    logged::wait_within(
        &lines,
        &[
            "plan_changed",
            "language=\"en\"",
            "prescribed=false",
            "exercises=1",
            "message_id=\"\"",
        ],
        WITHIN,
    );
    assert!(!home.join("regimen.toml").exists());

    // The therapist prescribes two exercises in the patient's German and writes a message,
    // the page still open.
    let toml = "[patient]\nlanguage = \"de\"\n\n\
                [[exercise]]\nkind = \"dial\"\nduration_s = 60.0\nrest_s = 30.0\n\n\
                [[exercise]]\nkind = \"sine\"\nduration_s = 90.0\n";
    let body = serde_json::json!({ "toml": toml }).to_string();
    let put = console.request(
        "PUT",
        &format!("/api/patients/{patient}/regimen"),
        Some(&cookie),
        &body,
    );
    assert_eq!(put.status, 200, "{}", String::from_utf8_lossy(&put.body));
    let body = serde_json::json!({ "text": "Two short ones today." }).to_string();
    let posted = console.request(
        "POST",
        &format!("/api/patients/{patient}/messages"),
        Some(&cookie),
        &body,
    );
    assert_eq!(
        posted.status,
        201,
        "{}",
        String::from_utf8_lossy(&posted.body)
    );
    let message_id = posted.json()["id"].as_str().unwrap().to_owned();
    let sent = Instant::now();

    let changed = logged::wait_within(
        &lines,
        &[
            "plan_changed",
            "language=\"de\"",
            "prescribed=true",
            "exercises=2",
        ],
        WITHIN,
    );
    assert!(
        changed.contains(&format!("message_id=\"{message_id}\"")),
        "the page shows the new message too: {changed}"
    );
    eprintln!(
        "today's page changed {:.1} s after the prescription",
        sent.elapsed().as_secs_f64()
    );
    assert_eq!(
        std::fs::read_to_string(home.join("regimen.toml")).unwrap(),
        toml
    );
    assert_eq!(
        std::fs::read_to_string(home.join("regimen-prescriber.txt")).unwrap(),
        "ana@clinic.example"
    );
    let kept: serde_json::Value =
        serde_json::from_slice(&std::fs::read(home.join("messages.json")).unwrap()).unwrap();
    assert_eq!(kept[0]["id"], message_id.as_str(), "{kept}");
    // The hub noted the message delivered to the station.
    let listed = console
        .get(&format!("/api/patients/{patient}/messages"), &cookie)
        .json();
    assert!(listed[0]["delivered_at_ms"].is_i64(), "{listed}");
    drop(child);
    hub.stop();
}
