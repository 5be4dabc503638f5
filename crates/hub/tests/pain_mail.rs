//! Pain mails against a real SMTP server started by the test (Python's aiosmtpd,
//! `tests/smtp_sink.py`): a check-in's pain at or over the clinic's threshold reaches the
//! patient's therapist (every admin when the patient has none) with the pseudonym and a link
//! to the patient's page and nothing else; while the server is down the mail waits in the
//! outbox, its failure visible, and goes out once the server is up.

mod common;

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use common::hello;
use hub::care::{CareConfig, SmtpConfig};
use hub::{Db, Role};
use netlink::Bye;

const FP: &str = "1111111111111111111111111111111111111111111111111111111111111111";

/// Long enough for a loaded machine; the waits end as soon as what they wait for happens.
const PATIENCE: Duration = Duration::from_secs(60);

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// aiosmtpd on 127.0.0.1:`port`, writing each message to `dir`; stopped on drop.
struct SmtpSink(Child);

impl SmtpSink {
    fn start(port: u16, dir: &Path) -> Self {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/smtp_sink.py");
        // Debian's python3 (python3-aiosmtpd, scripts/setup.sh), not one a PATH shim picks.
        let python = ["/usr/bin/python3", "python3"]
            .into_iter()
            .find(|p| Path::new(p).exists())
            .unwrap_or("python3");
        let mut child = Command::new(python)
            .arg(script)
            .arg(port.to_string())
            .arg(dir)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .expect("python3 with aiosmtpd (apt-get install python3-aiosmtpd)");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        assert_eq!(line.trim(), "ready", "the SMTP server did not start");
        Self(child)
    }
}

impl Drop for SmtpSink {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The messages in `dir`, in the order taken.
fn messages(dir: &Path) -> Vec<String> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    paths.retain(|p| p.extension().is_some_and(|e| e == "eml"));
    paths.sort_by_key(|p| {
        p.file_stem()
            .and_then(|s| s.to_str())
            .and_then(|s| s.parse::<u32>().ok())
    });
    paths
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect()
}

async fn until<T>(what: &str, mut f: impl AsyncFnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(v) = f().await {
            return v;
        }
        assert!(start.elapsed() < PATIENCE, "waited for {what}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

fn now_ms() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_millis() as i64
}

/// Session `id` of `patient_id` on station `station`, ended with `pain` answered now.
async fn session_with_pain(db: &Db, station: &str, patient_id: &str, id: &str, pain: u8) {
    let mut h = hello(station, patient_id, id);
    h.started_unix_ms = now_ms() as u64;
    db.open_session(&h, now_ms()).await.unwrap();
    let bye = Bye {
        session_id: id.into(),
        reason: "session complete".into(),
        final_seq: None,
        measures: BTreeMap::new(),
        hub_unix_ms: None,
        checkin: Some(netlink::CheckIn {
            pain_0_10: Some(pain),
            tiredness_0_10: Some(4),
            difficulty: Some("too_hard".into()),
        }),
        difficulty: None,
        exercises: Vec::new(),
    };
    db.close_session(&bye, now_ms()).await.unwrap();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_pain_at_the_threshold_is_mailed_to_the_therapist_with_only_the_pseudonym_and_a_link_and_retried_until_the_server_takes_it()
 {
    let (db, _dir) = common::sqlite_db().await;
    let pw = "correct horse battery";
    let ana = db
        .add_therapist("ana@clinic.example", pw, Role::Therapist, now_ms())
        .await
        .unwrap();
    db.add_therapist("boss@clinic.example", pw, Role::Admin, now_ms())
        .await
        .unwrap();
    // Ana reads the console, and so her mails, in German; the admin never chose (English).
    db.set_therapist_language(&ana.id, Some("de"))
        .await
        .unwrap();
    let p42 = db
        .add_patient("P-0042", Some(&ana.id), now_ms())
        .await
        .unwrap();
    let p50 = db.add_patient("P-0050", None, now_ms()).await.unwrap();
    db.add_station("st-a", &p42.id, FP, now_ms()).await.unwrap();
    db.add_station("st-b", &p50.id, &FP.replace('1', "2"), now_ms())
        .await
        .unwrap();
    session_with_pain(&db, "st-a", &p42.id, "s-low", 4).await; // under the threshold
    session_with_pain(&db, "st-a", &p42.id, "s-high", 6).await; // at it
    session_with_pain(&db, "st-b", &p50.id, "s-nobody", 9).await; // no therapist: the admins

    let port = free_port();
    let inbox = tempfile::tempdir().unwrap();
    let care = CareConfig {
        pain_threshold_0_10: 6,
        console_url: Some("https://hub.clinic.example:8443".into()),
        smtp: Some(SmtpConfig {
            url: format!("smtp://127.0.0.1:{port}"),
            from: "telerehab hub <hub@clinic.example>".into(),
            retry_min_ms: 200,
        }),
        ..CareConfig::default()
    };
    // `hub serve --pain-threshold 6`: the clinic's threshold, as the caseload reads it too.
    care.seed_pain_threshold(&db, now_ms()).await.unwrap();
    assert_eq!(db.pain_threshold().await.unwrap(), 6);
    let mailer = tokio::spawn(hub::pain_mail::run(
        db.clone(),
        Arc::new(care),
        clock::Clock::real(),
        Arc::default(),
    ));

    // The server is down: both mails wait, their failure visible to an admin.
    let status = until("the failed attempts", async || {
        let s = db.pain_mail_status().await.unwrap();
        (s.failing == 2).then_some(s)
    })
    .await;
    assert_eq!(status.waiting, 2, "{status:?}");
    assert!(status.last_error.is_some(), "{status:?}");
    assert!(messages(inbox.path()).is_empty());

    // The server comes up: each mail goes out once.
    let _server = SmtpSink::start(port, inbox.path());
    let sent = until("two mails", async || {
        let m = messages(inbox.path());
        (m.len() >= 2).then_some(m)
    })
    .await;
    until("the outbox empty", async || {
        let s = db.pain_mail_status().await.unwrap();
        (s.waiting == 0 && s.last_sent_at_ms.is_some()).then_some(())
    })
    .await;
    assert_eq!(messages(inbox.path()).len(), 2, "each mail once");

    let to_ana = sent
        .iter()
        .find(|m| m.starts_with("X-Envelope-To: ana@clinic.example\r\n"))
        .expect("a mail to the patient's therapist");
    let to_boss = sent
        .iter()
        .find(|m| m.starts_with("X-Envelope-To: boss@clinic.example\r\n"))
        .expect("a mail to the admin for a patient without a therapist");
    for (mail, patient, other) in [(to_ana, &p42, &p50), (to_boss, &p50, &p42)] {
        let (head, body) = mail.split_once("\r\n\r\n").expect("headers and body");
        // A mail in German travels quoted-printable (its umlauts): read it as the recipient does.
        let body = if head.contains("Content-Transfer-Encoding: quoted-printable") {
            let bytes =
                quoted_printable::decode(body, quoted_printable::ParseMode::Robust).unwrap();
            String::from_utf8(bytes).unwrap()
        } else {
            body.to_owned()
        };
        let subject = head
            .lines()
            .find_map(|l| l.strip_prefix("Subject: "))
            .expect("a subject");
        assert!(subject.contains(&patient.pseudonym), "{subject}");
        let language = (patient.id == p42.id).then_some("de");
        let (expected_subject, expected_body) = hub::pain_mail::mail_text(
            language,
            &patient.pseudonym,
            &patient.id,
            Some("https://hub.clinic.example:8443"),
        );
        assert_eq!(
            subject, expected_subject,
            "in the recipient's console language"
        );
        assert_eq!(body.trim_end(), expected_body.trim_end());
        assert!(
            body.contains(&format!(
                "https://hub.clinic.example:8443/#/patients/{}",
                patient.id
            )),
            "{body}"
        );
        // Nothing else about the patient: no score, no answers, no session or station, no
        // other patient.
        for private in [
            "/10", "6", "9", "too_hard", "too hard", "s-high", "s-nobody", "st-a", "st-b",
        ] {
            assert!(!subject.contains(private), "{private} in {subject}");
            let without_link = body.replace(&patient.id, "");
            assert!(!without_link.contains(private), "{private} in {body}");
        }
        assert!(!mail.contains(&other.pseudonym));
    }
    mailer.abort();
}

#[tokio::test]
async fn a_therapist_clears_a_pain_stop_audited_announced_to_the_stations_and_others_cannot() {
    use axum::http::{Method, StatusCode};
    use common::api::{PASSWORD, actions, call, login};
    use serde_json::json;

    let (db, _dir) = common::sqlite_db().await;
    let ana = db
        .add_therapist("ana@clinic.example", PASSWORD, Role::Therapist, now_ms())
        .await
        .unwrap();
    db.add_therapist("bob@clinic.example", PASSWORD, Role::Therapist, now_ms())
        .await
        .unwrap();
    db.add_therapist("boss@clinic.example", PASSWORD, Role::Admin, now_ms())
        .await
        .unwrap();
    let p = db
        .add_patient("P-0042", Some(&ana.id), now_ms())
        .await
        .unwrap();
    let (live, _) = tokio::sync::broadcast::channel(4);
    let (cleared, mut clearances) = tokio::sync::broadcast::channel(4);
    let care = CareConfig {
        pain_threshold_0_10: 6,
        ..CareConfig::default()
    };
    care.seed_pain_threshold(&db, now_ms()).await.unwrap();
    let app = hub::web::router(
        hub::web::AppState::new(db.clone(), live).with_care(Arc::new(care), Some(cleared)),
    );
    let uri = format!("/api/patients/{}/pain-clearance", p.id);
    // Someone else's patient: as if it did not exist.
    let bob = login(&app, "bob@clinic.example").await;
    let (status, _, _) = call(&app, Method::POST, &uri, Some(&bob), Some(json!({}))).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert_eq!(db.pain_cleared_at(&p.id).await.unwrap(), None);
    // The patient's therapist clears it: stored, audited, announced for the stations.
    let cookie = login(&app, "ana@clinic.example").await;
    let (status, body, _) = call(&app, Method::POST, &uri, Some(&cookie), Some(json!({}))).await;
    assert_eq!(status, StatusCode::OK, "{body}");
    let at = body["cleared_at_ms"].as_i64().unwrap();
    assert_eq!(db.pain_cleared_at(&p.id).await.unwrap(), Some(at));
    assert_eq!(clearances.try_recv().unwrap(), p.id);
    assert!(
        actions(&db)
            .await
            .contains(&(ana.actor(), "pain_clearance".into(), p.id.clone()))
    );
    // Admins see the mail's state; a therapist may not.
    let (status, _, _) = call(
        &app,
        Method::GET,
        "/api/clinic/pain-mail",
        Some(&cookie),
        None,
    )
    .await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let boss = login(&app, "boss@clinic.example").await;
    let (status, state, _) = call(
        &app,
        Method::GET,
        "/api/clinic/pain-mail",
        Some(&boss),
        None,
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{state}");
    assert_eq!(state["configured"], false);
    assert_eq!(state["pain_threshold_0_10"], 6);
    assert_eq!(state["waiting"], 0);
}
