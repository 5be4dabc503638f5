//! Logins, live streams and the audit log against a hostile client (issue 25): the database
//! rules run on SQLite and PostgreSQL (`<name>::sqlite`, `<name>::postgres`), the HTTP rules
//! against the router, and the login flood against a whole hub with a paired station.

mod common;

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use axum::Router;
use axum::body::Body;
use axum::extract::ConnectInfo;
use axum::http::{HeaderMap, Method, Request, StatusCode, header};
use http_body_util::BodyExt;
use hub::db::{
    ACCOUNT_FREE_FAILURES, ACCOUNT_MAX_DELAY_MS, ADDRESS_MAX_DELAY_MS, LoginAttempt,
    REFUSAL_AUDITS_PER_ACCOUNT_PER_MINUTE, REFUSAL_AUDITS_PER_MINUTE,
    REFUSAL_AUDITS_TOTAL_PER_MINUTE,
};
use hub::web::{self, LiveEvent, MAX_LIVE_STREAMS_PER_ACCOUNT, MAX_LIVE_STREAMS_PER_LOGIN};
use hub::{Db, HubError, Role};
use netlink::Summary;
use serde_json::{Value, json};
use tower::ServiceExt;

use common::T0;
use common::api::{PASSWORD, clinician, send};
use common::fixture::{Fixture, fixture};

const EMAIL: &str = "ada@clinic.example";

fn ip(last: u8) -> std::net::IpAddr {
    std::net::IpAddr::from([127, 0, 3, last])
}

on_both_backends!(
    a_hundred_parallel_guesses_evaluate_at_most_the_free_allowance,
    an_attacker_elsewhere_cannot_keep_the_therapist_out,
    a_new_browser_gets_in_during_an_attack_and_its_success_gives_the_attacker_nothing,
    the_address_throttle_grows_to_fifteen_minutes_whatever_accounts_it_tries,
    weak_passwords_are_refused,
    a_one_time_password_is_flagged_until_changed,
    a_password_change_ends_every_old_token,
    a_revoked_therapist_cannot_log_in_and_their_sessions_end,
    refusal_audits_are_rate_limited_and_count_what_they_suppress,
    refusal_audits_from_rotating_addresses_are_bounded_per_account_and_in_all,
    the_audit_log_pages_by_time_without_losing_an_entry,
);

/// Runs `n` logins at once (the last one with the right password) at one instant.
async fn parallel_logins(db: &Db, n: usize, address: Option<std::net::IpAddr>) -> Vec<String> {
    let mut tasks = tokio::task::JoinSet::new();
    for i in 0..n {
        let db = db.clone();
        tasks.spawn(async move {
            let password = if i + 1 == n {
                PASSWORD.to_owned()
            } else {
                format!("wrong guess {i:04}")
            };
            let attempt = LoginAttempt {
                address,
                ..LoginAttempt::new(EMAIL, &password)
            };
            match db.login(attempt, T0).await {
                Ok(_) => "ok".to_owned(),
                Err(HubError::LoginRefused) => "refused".to_owned(),
                Err(HubError::Throttled { .. }) => "throttled".to_owned(),
                Err(e) => format!("error {e}"),
            }
        });
    }
    let mut out = Vec::new();
    while let Some(r) = tasks.join_next().await {
        out.push(r.unwrap());
    }
    out
}

async fn a_hundred_parallel_guesses_evaluate_at_most_the_free_allowance(db: Db) {
    clinician(&db, EMAIL, Role::Therapist).await;
    let outcomes = parallel_logins(&db, 100, Some(ip(1))).await;
    let evaluated = outcomes
        .iter()
        .filter(|o| *o == "ok" || *o == "refused")
        .count();
    assert!(
        outcomes.iter().all(|o| !o.starts_with("error")),
        "{outcomes:?}"
    );
    assert!(evaluated >= 1, "{outcomes:?}");
    assert!(
        evaluated <= usize::try_from(ACCOUNT_FREE_FAILURES).unwrap(),
        "{evaluated} of 100 parallel guesses were evaluated: {outcomes:?}"
    );
}

/// One attempt; `Err(retry_after_ms)` when throttled.
async fn try_login(
    db: &Db,
    password: &str,
    address: u8,
    device: Option<&str>,
    now_ms: i64,
) -> Result<bool, i64> {
    let attempt = LoginAttempt {
        address: Some(ip(address)),
        device,
        ..LoginAttempt::new(EMAIL, password)
    };
    match db.login(attempt, now_ms).await {
        Ok(_) => Ok(true),
        Err(HubError::LoginRefused) => Ok(false),
        Err(HubError::Throttled { retry_after_ms, .. }) => Err(retry_after_ms),
        Err(e) => panic!("{e}"),
    }
}

async fn an_attacker_elsewhere_cannot_keep_the_therapist_out(db: Db) {
    let t = clinician(&db, EMAIL, Role::Therapist).await;
    // The therapist's own browser logged in before and holds a device cookie.
    let device = db.create_device(&t.id, T0).await.unwrap();
    // An attacker with twenty addresses guesses for a simulated hour, whenever a throttle
    // lets them.
    let mut now = T0;
    let mut guesses = 0;
    while now < T0 + 3_600_000 {
        let mut next_ms = i64::MAX;
        let mut guessed = false;
        for a in 10..30 {
            match try_login(&db, "a wrong guess", a, None, now).await {
                Ok(ok) => {
                    assert!(!ok);
                    guesses += 1;
                    guessed = true;
                }
                Err(wait) => next_ms = next_ms.min(wait),
            }
        }
        if guessed {
            // Right after the attacker's latest failure, the therapist's browser gets in.
            assert_eq!(
                try_login(&db, PASSWORD, 1, Some(&device), now).await,
                Ok(true),
                "the therapist's device was kept out at {} s",
                (now - T0) / 1000
            );
            next_ms = next_ms.min(1000);
        }
        assert!(next_ms <= ACCOUNT_MAX_DELAY_MS, "{next_ms}");
        now += next_ms.max(1);
    }
    assert!(guesses >= 20, "{guesses}");
    assert!(
        guesses <= 100,
        "{guesses} guesses in an hour: the account throttle does not hold"
    );
    // Without the device cookie, from a clean address, the wait is the account's at most.
    let wait = match try_login(&db, PASSWORD, 2, None, now).await {
        Ok(true) => 0,
        Err(wait) => wait,
        Ok(false) => panic!("the right password was refused"),
    };
    assert!(wait <= ACCOUNT_MAX_DELAY_MS, "{wait}");
    assert_eq!(
        try_login(&db, PASSWORD, 2, None, now + wait).await,
        Ok(true)
    );
}

/// An attacker rotating over twenty addresses who guesses whenever a throttle lets one
/// through, from `from_ms` for `for_ms`; the therapist, on a new browser (no device cookie)
/// at an address they logged in from before, logs in at the first of the attacker's
/// evaluated guesses at or after each of `logins_at_ms`. Returns the times of the attacker's
/// evaluated guesses.
async fn attack_around_logins(
    db: &Db,
    from_ms: i64,
    for_ms: i64,
    logins_at_ms: &[i64],
) -> Vec<i64> {
    let mut now = from_ms;
    let mut evaluated = Vec::new();
    let mut logins = logins_at_ms.iter().copied().peekable();
    while now < from_ms + for_ms {
        let mut next_ms = i64::MAX;
        let mut guessed = false;
        for a in 10..30 {
            match try_login(db, "a wrong guess", a, None, now).await {
                Ok(ok) => {
                    assert!(!ok);
                    evaluated.push(now);
                    guessed = true;
                }
                Err(wait) => next_ms = next_ms.min(wait),
            }
        }
        while guessed && logins.peek().is_some_and(|&at| at <= now) {
            logins.next();
            // Right after a guess of the attacker was evaluated: the account's delay runs.
            assert_eq!(
                try_login(db, PASSWORD, 1, None, now).await,
                Ok(true),
                "the therapist's new browser was kept out at {} s",
                (now - from_ms) / 1000
            );
        }
        now += next_ms.max(1);
    }
    assert!(
        logins.next().is_none(),
        "a login of the therapist was not tried"
    );
    evaluated
}

async fn a_new_browser_gets_in_during_an_attack_and_its_success_gives_the_attacker_nothing(db: Db) {
    clinician(&db, EMAIL, Role::Therapist).await;
    // The therapist logged in from the clinic (127.0.3.1) yesterday; today, a new browser
    // there has no device cookie.
    assert_eq!(
        try_login(&db, PASSWORD, 1, None, T0 - 86_400_000).await,
        Ok(true)
    );
    // Ten minutes of attack bring the account's delay to its longest (a minute) …
    let warm = attack_around_logins(&db, T0, 600_000, &[]).await;
    // … then 150 s around two logins of the therapist's new browser (the probe:
    // 21 guesses evaluated in 150 s, the success having reset the account's count).
    let start = T0 + 600_000;
    let around = attack_around_logins(&db, start, 150_000, &[start + 30_000, start + 75_000]).await;
    println!(
        "evaluated guesses of an attacker rotating 20 addresses: {} in the first 10 min, {} in \
         the 150 s around two logins of the therapist's new browser",
        warm.len(),
        around.len()
    );
    let cap = 150_000 / ACCOUNT_MAX_DELAY_MS + 1;
    assert!(
        i64::try_from(around.len()).unwrap() <= cap,
        "{} guesses evaluated in 150 s around the therapist's logins (at most {cap} at the \
         account's longest delay): {around:?}",
        around.len()
    );
    // The hourly budget holds across the therapist's logins: an hour in all, logging in
    // every five minutes.
    let rest_from = start + 150_000;
    let logins: Vec<i64> = (1..10).map(|k| rest_from + k * 300_000).collect();
    let rest = attack_around_logins(&db, rest_from, 3_600_000 - 750_000, &logins).await;
    let hour = warm.len() + around.len() + rest.len();
    let budget =
        usize::try_from(3_600_000 / ACCOUNT_MAX_DELAY_MS + 2 * ACCOUNT_FREE_FAILURES + 2).unwrap();
    assert!(
        hour <= budget,
        "{hour} guesses evaluated in an hour (budget {budget})"
    );
}

async fn the_address_throttle_grows_to_fifteen_minutes_whatever_accounts_it_tries(db: Db) {
    clinician(&db, EMAIL, Role::Therapist).await;
    let mut now = T0;
    let mut waits = Vec::new();
    for i in 0..30 {
        let email = format!("guess{i}@clinic.example");
        let attempt = LoginAttempt {
            address: Some(ip(50)),
            ..LoginAttempt::new(&email, "a wrong guess")
        };
        match db.login(attempt, now).await {
            Err(HubError::LoginRefused) => {}
            Err(HubError::Throttled { retry_after_ms, .. }) => {
                waits.push(retry_after_ms);
                now += retry_after_ms;
            }
            other => panic!("{other:?}"),
        }
    }
    assert!(waits.windows(2).all(|w| w[0] <= w[1]), "{waits:?}");
    assert_eq!(
        waits.last().copied(),
        Some(ADDRESS_MAX_DELAY_MS),
        "{waits:?}"
    );
    // Another address is not affected.
    let attempt = LoginAttempt {
        address: Some(ip(51)),
        ..LoginAttempt::new(EMAIL, PASSWORD)
    };
    assert!(db.login(attempt, now).await.is_ok());
}

async fn weak_passwords_are_refused(db: Db) {
    for (password, why) in [
        ("          ", "spaces"),
        (" \t a b c   \n ", "spaces"),
        ("short", "at least 10"),
        ("bob@clinic.example", "e-mail"),
        ("Password123", "common"),
        ("1234567890", "common"),
        // The second hostile round's (issue 44): each refused by its rule.
        ("aaaaaaaaaa", "repeated"),
        ("Password1!", "common password with a few characters added"),
        ("correcthorse", "common words"),
        (
            "a\u{200b}\u{200b}\u{200b}\u{200b}\u{200b}",
            "invisible characters",
        ),
        ("\u{200b}correct horse battery", "invisible characters"),
        ("abcdefghijk", "consecutive"),
    ] {
        let err = db
            .add_therapist("bob@clinic.example", password, Role::Therapist, T0)
            .await
            .unwrap_err();
        assert!(err.to_string().contains(why), "{password:?}: {err}");
    }
    assert!(
        db.add_therapist("bob@clinic.example", PASSWORD, Role::Therapist, T0)
            .await
            .is_ok()
    );
}

async fn a_one_time_password_is_flagged_until_changed(db: Db) {
    let t = clinician(&db, EMAIL, Role::Therapist).await;
    assert!(!t.must_change_password);
    db.require_password_change(&t.id).await.unwrap();
    let token = db.create_web_session(&t.id, T0, 60_000).await.unwrap();
    assert!(
        db.web_session(&token, T0)
            .await
            .unwrap()
            .unwrap()
            .must_change_password
    );
    let new_token = db
        .change_password(EMAIL, PASSWORD, "a brand new passphrase", T0, 60_000)
        .await
        .unwrap();
    let after = db.web_session(&new_token, T0).await.unwrap().unwrap();
    assert!(!after.must_change_password);
}

async fn a_password_change_ends_every_old_token(db: Db) {
    let t = clinician(&db, EMAIL, Role::Therapist).await;
    let old: Vec<String> = futures_tokens(&db, &t.id, 3).await;
    let new = db
        .change_password(EMAIL, PASSWORD, "a brand new passphrase", T0, 60_000)
        .await
        .unwrap();
    for token in &old {
        assert_eq!(db.web_session(token, T0).await.unwrap(), None);
    }
    assert!(db.web_session(&new, T0).await.unwrap().is_some());
    assert!(!old.contains(&new));
}

async fn futures_tokens(db: &Db, id: &str, n: usize) -> Vec<String> {
    let mut out = Vec::new();
    for _ in 0..n {
        out.push(db.create_web_session(id, T0, 60_000).await.unwrap());
    }
    out
}

async fn a_revoked_therapist_cannot_log_in_and_their_sessions_end(db: Db) {
    let t = clinician(&db, EMAIL, Role::Therapist).await;
    let token = db.create_web_session(&t.id, T0, 60_000).await.unwrap();
    db.revoke_therapist(&t.id, T0).await.unwrap();
    assert_eq!(db.web_session(&token, T0).await.unwrap(), None);
    let again = db.verify_login(EMAIL, PASSWORD, T0).await;
    assert!(matches!(again, Err(HubError::LoginRefused)), "{again:?}");
    assert!(matches!(
        db.revoke_therapist("t-nobody", T0).await,
        Err(HubError::NotFound { .. })
    ));
}

async fn refusal_audits_are_rate_limited_and_count_what_they_suppress(db: Db) {
    for i in 0..100 {
        db.audit_refusal("web", "refused_401", "/api/me", "", "127.0.0.9", T0 + i)
            .await
            .unwrap();
    }
    db.audit_refusal("web", "refused_401", "/api/me", "", "127.0.0.10", T0 + 100)
        .await
        .unwrap();
    let log = db.audit_log(1000).await.unwrap();
    let from = |source: &str| {
        log.iter()
            .filter(|e| e.action == "refused_401" && e.detail == format!("from {source}"))
            .count()
    };
    assert_eq!(
        from("127.0.0.9"),
        usize::try_from(REFUSAL_AUDITS_PER_MINUTE).unwrap()
    );
    assert_eq!(from("127.0.0.10"), 1, "another source has its own budget");
    db.flush_refusal_audits(T0 + 60_000).await.unwrap();
    let log = db.audit_log(1000).await.unwrap();
    let suppressed: Vec<_> = log
        .iter()
        .filter(|e| e.action == "refusals_suppressed")
        .collect();
    assert_eq!(suppressed.len(), 1, "{suppressed:?}");
    assert_eq!(suppressed[0].target, "127.0.0.9");
    assert!(
        suppressed[0].detail.starts_with("80 more refusals"),
        "{suppressed:?}"
    );
}

/// The count at the start of a `refusals_suppressed` entry's detail.
fn suppressed_count(detail: &str) -> u64 {
    detail.split(' ').next().unwrap().parse().unwrap()
}

async fn refusal_audits_from_rotating_addresses_are_bounded_per_account_and_in_all(db: Db) {
    // The probe wrote 5 582 rows in 40 s: refused logins, each from a new address.
    const BURST: i64 = 5_000;
    let address = |i: i64| format!("127.{}.{}.{}", 10 + i / 65_536, (i / 256) % 256, i % 256);
    for i in 0..BURST {
        db.audit_account_refusal(
            "web",
            "login_failed",
            EMAIL,
            "",
            &address(i),
            Some(EMAIL),
            T0 + i * 8,
        )
        .await
        .unwrap();
    }
    let log = db.audit_log(10_000).await.unwrap();
    let one_by_one = log.iter().filter(|e| e.action == "login_failed").count();
    assert_eq!(
        one_by_one,
        usize::try_from(REFUSAL_AUDITS_PER_ACCOUNT_PER_MINUTE).unwrap(),
        "one account's refusals from {BURST} addresses"
    );
    db.flush_refusal_audits(T0 + 120_000).await.unwrap();
    let log = db.audit_log(10_000).await.unwrap();
    let summaries: Vec<_> = log
        .iter()
        .filter(|e| e.action == "refusals_suppressed")
        .collect();
    assert_eq!(summaries.len(), 1, "{summaries:?}");
    assert!(summaries[0].target.contains(EMAIL), "{summaries:?}");
    assert!(
        summaries[0].detail.contains("were not recorded one by one"),
        "{summaries:?}"
    );
    let counted: u64 = summaries.iter().map(|e| suppressed_count(&e.detail)).sum();
    assert_eq!(
        counted + one_by_one as u64,
        BURST as u64,
        "nothing is silently lost"
    );
    let rows_a = log.len();

    // Rotating accounts too: the hub's total bounds them.
    let start = T0 + 600_000;
    for i in 0..BURST {
        let email = format!("guess{i}@clinic.example");
        db.audit_account_refusal(
            "web",
            "login_failed",
            &email,
            "",
            &address(i),
            Some(&email),
            start + i * 8,
        )
        .await
        .unwrap();
    }
    db.flush_refusal_audits(start + 120_000).await.unwrap();
    let log = db.audit_log(20_000).await.unwrap();
    let new = &log[..log.len() - rows_a];
    let one_by_one = new.iter().filter(|e| e.action == "login_failed").count();
    let summaries: Vec<_> = new
        .iter()
        .filter(|e| e.action == "refusals_suppressed")
        .collect();
    assert_eq!(
        one_by_one,
        usize::try_from(REFUSAL_AUDITS_TOTAL_PER_MINUTE).unwrap()
    );
    assert!(summaries.len() <= 2, "{summaries:?}");
    let counted: u64 = summaries.iter().map(|e| suppressed_count(&e.detail)).sum();
    assert_eq!(
        counted + one_by_one as u64,
        BURST as u64,
        "nothing is silently lost"
    );
    println!(
        "a burst of {BURST} refused logins in 40 s from as many addresses wrote {rows_a} audit \
         rows on one account and {} on rotating accounts",
        new.len()
    );
}

async fn the_audit_log_pages_by_time_without_losing_an_entry(db: Db) {
    // 250 entries over 50 milliseconds (five per millisecond).
    for i in 0..250_i64 {
        db.audit("cli", "step", &format!("{i:03}"), "", T0 + i / 5)
            .await
            .unwrap();
    }
    let mut seen = Vec::new();
    let mut cursor = None;
    loop {
        let page = db.audit_page(cursor.as_ref(), 40).await.unwrap();
        assert!(page.entries.len() <= 40);
        seen.extend(page.entries.iter().map(|e| e.target.clone()));
        match page.next {
            Some(next) => cursor = Some(next),
            None => break,
        }
    }
    let want: Vec<String> = (0..250).rev().map(|i| format!("{i:03}")).collect();
    assert_eq!(seen, want);
}

// ----- HTTP -----

/// A request ([`common::api::request`]) from 127.0.3.`from`.
fn request(
    method: Method,
    uri: &str,
    cookie: Option<&str>,
    body: Option<Value>,
    from: u8,
) -> Request<Body> {
    let mut request = common::api::request(method, uri, cookie, body);
    request
        .extensions_mut()
        .insert(ConnectInfo(SocketAddr::new(ip(from), 40_000)));
    request
}

async fn call(
    app: &Router,
    method: Method,
    uri: &str,
    cookie: Option<&str>,
    body: Option<Value>,
) -> (StatusCode, HeaderMap, Value) {
    send(app, request(method, uri, cookie, body, 1)).await
}

fn first_cookie(headers: &HeaderMap, name: &str) -> Option<String> {
    headers
        .get_all(header::SET_COOKIE)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .map(|v| v.split(';').next().unwrap().to_owned())
        .find(|c| c.starts_with(&format!("{name}=")))
}

async fn login_as(app: &Router, email: &str, password: &str) -> String {
    let body = json!({"email": email, "password": password});
    let (status, headers, body) = call(app, Method::POST, "/api/login", None, Some(body)).await;
    assert_eq!(status, StatusCode::OK, "{body}");
    first_cookie(&headers, web::SESSION_COOKIE).unwrap()
}

/// Opens a live stream; its body.
async fn open_live(f: &Fixture, cookie: &str) -> Result<Body, StatusCode> {
    let uri = format!("/api/patients/{}/live", f.p_ada.id);
    let response = f
        .app
        .clone()
        .oneshot(request(Method::GET, &uri, Some(cookie), None, 1))
        .await
        .unwrap();
    if response.status() == StatusCode::OK {
        Ok(response.into_body())
    } else {
        Err(response.status())
    }
}

/// Reads the stream until it ends (`Ok(text)`) or `limit` passes (`Err(text)`).
async fn until_end(body: &mut Body, limit: Duration) -> Result<String, String> {
    let deadline = tokio::time::Instant::now() + limit;
    let mut text = String::new();
    loop {
        match tokio::time::timeout_at(deadline, body.frame()).await {
            Err(_) => return Err(text),
            Ok(None) => return Ok(text),
            Ok(Some(frame)) => {
                if let Ok(data) = frame.unwrap().into_data() {
                    text.push_str(&String::from_utf8_lossy(&data));
                }
            }
        }
    }
}

fn event(f: &Fixture, seq: u64) -> LiveEvent {
    LiveEvent {
        patient_id: f.p_ada.id.clone(),
        session_id: "s-ada".to_owned(),
        summary: Summary::example("s-ada", seq),
    }
}

/// Opens a stream, checks it delivers, runs `end_it`, and returns how long the stream took to
/// end and its last text.
async fn stream_ended_by<Fut: Future<Output = ()>>(
    f: &Fixture,
    cookie: &str,
    end_it: impl FnOnce() -> Fut,
) -> (Duration, String) {
    let mut body = open_live(f, cookie).await.unwrap();
    f.live.send(event(f, 1)).unwrap();
    let first = tokio::time::timeout(Duration::from_secs(5), body.frame())
        .await
        .expect("a first event")
        .unwrap()
        .unwrap();
    assert!(first.is_data());
    end_it().await;
    let t = Instant::now();
    // The ingest keeps broadcasting meanwhile.
    let live = f.live.clone();
    let p = event(f, 2);
    let feeder = tokio::spawn(async move {
        for _ in 0..100 {
            let _ = live.send(p.clone());
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    });
    let text = until_end(&mut body, Duration::from_secs(5))
        .await
        .unwrap_or_else(|text| panic!("the stream still ran after 5 s: {text}"));
    feeder.abort();
    (t.elapsed(), text)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn live_streams_end_within_two_seconds_of_logout_expiry_password_change_revocation_and_reassignment()
 {
    let f = fixture().await;
    let mut ends = Vec::new();
    // Logout.
    let cookie = login_as(&f.app, EMAIL, PASSWORD).await;
    let c = cookie.clone();
    ends.push(
        stream_ended_by(&f, &cookie, || async {
            let (s, _, _) = call(
                &f.app,
                Method::POST,
                "/api/logout",
                Some(&c),
                Some(json!({})),
            )
            .await;
            assert_eq!(s, StatusCode::NO_CONTENT);
        })
        .await,
    );
    // Expiry (the clock moves past the login's lifetime).
    let cookie = login_as(&f.app, EMAIL, PASSWORD).await;
    ends.push(
        stream_ended_by(&f, &cookie, || async {
            f.clock
                .advance(Duration::from_millis(web::DEFAULT_LOGIN_TTL_MS as u64));
        })
        .await,
    );
    // A password change (from this very login: its token rotates).
    let cookie = login_as(&f.app, EMAIL, PASSWORD).await;
    let c = cookie.clone();
    ends.push(
        stream_ended_by(&f, &cookie, || async {
            let body = json!({"current": PASSWORD, "new": "a brand new passphrase"});
            let (s, h, _) = call(
                &f.app,
                Method::POST,
                "/api/me/password",
                Some(&c),
                Some(body),
            )
            .await;
            assert_eq!(s, StatusCode::NO_CONTENT);
            assert!(first_cookie(&h, web::SESSION_COOKIE).is_some());
        })
        .await,
    );
    // The patient is assigned to nobody any more.
    let cookie = login_as(&f.app, EMAIL, "a brand new passphrase").await;
    ends.push(
        stream_ended_by(&f, &cookie, || async {
            sqlx::query("UPDATE patients SET therapist_id = NULL WHERE id = $1")
                .bind(&f.p_ada.id)
                .execute(f.db.pool())
                .await
                .unwrap();
        })
        .await,
    );
    sqlx::query("UPDATE patients SET therapist_id = $2 WHERE id = $1")
        .bind(&f.p_ada.id)
        .bind(&f.ada.id)
        .execute(f.db.pool())
        .await
        .unwrap();
    // The therapist is revoked.
    let cookie = login_as(&f.app, EMAIL, "a brand new passphrase").await;
    ends.push(
        stream_ended_by(&f, &cookie, || async {
            f.db.revoke_therapist(&f.ada.id, T0).await.unwrap();
        })
        .await,
    );
    // Each says why by its code, for the console's words in any language.
    let why = [
        "login-ended",
        "login-ended",
        "login-ended",
        "not-your-patient",
        "login-ended",
    ];
    for (i, (took, text)) in ends.iter().enumerate() {
        assert!(
            *took <= Duration::from_secs(2),
            "cause {i}: the stream ended after {took:?}"
        );
        assert!(text.contains("event: ended"), "cause {i}: {text}");
        assert!(
            text.contains(&format!("data: {}", why[i])),
            "cause {i}: {text}"
        );
    }
}

#[tokio::test]
async fn a_login_holds_at_most_four_live_streams() {
    let f = fixture().await;
    let cookie = login_as(&f.app, EMAIL, PASSWORD).await;
    let mut open = Vec::new();
    for _ in 0..MAX_LIVE_STREAMS_PER_LOGIN {
        open.push(open_live(&f, &cookie).await.unwrap());
    }
    assert_eq!(
        open_live(&f, &cookie).await.err(),
        Some(StatusCode::TOO_MANY_REQUESTS)
    );
    // Another login of the same therapist has its own allowance.
    let other = login_as(&f.app, EMAIL, PASSWORD).await;
    assert!(open_live(&f, &other).await.is_ok());
    // Closing one frees its place (the stream notices its client left).
    drop(open.pop());
    let mut reopened = None;
    for _ in 0..50 {
        if let Ok(body) = open_live(&f, &cookie).await {
            reopened = Some(body);
            break;
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    assert!(reopened.is_some(), "a closed stream's place was not freed");
}

#[tokio::test]
async fn an_account_holds_at_most_eight_live_streams_across_its_logins() {
    let f = fixture().await;
    // Logins of one therapist, each opening its own allowance of streams, until the account's
    // cap: the probe opened 25 logins × 4 = 100.
    let mut open = Vec::new();
    let mut cookies = Vec::new();
    while open.len() < MAX_LIVE_STREAMS_PER_ACCOUNT {
        let cookie = login_as(&f.app, EMAIL, PASSWORD).await;
        for _ in 0..MAX_LIVE_STREAMS_PER_LOGIN.min(MAX_LIVE_STREAMS_PER_ACCOUNT - open.len()) {
            open.push(open_live(&f, &cookie).await.unwrap());
        }
        cookies.push(cookie);
    }
    let fresh = login_as(&f.app, EMAIL, PASSWORD).await;
    let uri = format!("/api/patients/{}/live", f.p_ada.id);
    let (status, headers, body) =
        send(&f.app, request(Method::GET, &uri, Some(&fresh), None, 1)).await;
    assert_eq!(status, StatusCode::TOO_MANY_REQUESTS, "{body}");
    assert_eq!(headers.get(header::RETRY_AFTER).unwrap(), "1");
    let message = body["error"].as_str().unwrap();
    assert!(
        message.contains(&format!(
            "at most {MAX_LIVE_STREAMS_PER_ACCOUNT} live streams per therapist"
        )),
        "{message}"
    );
    for cookie in &cookies {
        assert_eq!(
            open_live(&f, cookie).await.err(),
            Some(StatusCode::TOO_MANY_REQUESTS)
        );
    }
    // Another therapist is not affected.
    let root = login_as(&f.app, "root@clinic.example", PASSWORD).await;
    assert!(open_live(&f, &root).await.is_ok());
    // Closing one frees the account's place, for any of its logins.
    drop(open.pop());
    let mut reopened = None;
    for _ in 0..50 {
        if let Ok(body) = open_live(&f, &fresh).await {
            reopened = Some(body);
            break;
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    assert!(reopened.is_some(), "a closed stream's place was not freed");
}

#[tokio::test]
async fn a_one_time_password_blocks_every_call_but_me_password_and_logout() {
    let f = fixture().await;
    f.db.require_password_change(&f.ada.id).await.unwrap();
    let cookie = login_as(&f.app, EMAIL, PASSWORD).await;
    let (status, _, me) = call(&f.app, Method::GET, "/api/me", Some(&cookie), None).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(me["must_change_password"], true);
    for uri in [
        "/api/patients".to_owned(),
        format!("/api/patients/{}", f.p_ada.id),
        format!("/api/patients/{}/live", f.p_ada.id),
        "/api/audit".to_owned(),
    ] {
        let (status, _, body) = call(&f.app, Method::GET, &uri, Some(&cookie), None).await;
        assert_eq!(status, StatusCode::FORBIDDEN, "{uri}");
        assert!(
            body["error"]
                .as_str()
                .unwrap()
                .contains("one-time password"),
            "{body}"
        );
    }
    let body = json!({"current": PASSWORD, "new": "          "});
    let (status, _, err) = call(
        &f.app,
        Method::POST,
        "/api/me/password",
        Some(&cookie),
        Some(body),
    )
    .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(err["error"].as_str().unwrap().contains("spaces"), "{err}");
    let body = json!({"current": PASSWORD, "new": "a brand new passphrase"});
    let (status, headers, _) = call(
        &f.app,
        Method::POST,
        "/api/me/password",
        Some(&cookie),
        Some(body),
    )
    .await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    let rotated = first_cookie(&headers, web::SESSION_COOKIE).unwrap();
    let (status, _, _) = call(&f.app, Method::GET, "/api/patients", Some(&rotated), None).await;
    assert_eq!(status, StatusCode::OK);
    let (status, _, _) = call(&f.app, Method::GET, "/api/me", Some(&cookie), None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED, "the old token ended");
}

#[tokio::test]
async fn logout_cannot_be_sent_by_a_no_cors_request() {
    let f = fixture().await;
    let cookie = login_as(&f.app, EMAIL, PASSWORD).await;
    // What a `no-cors` fetch or a form may send: no body, or a safelisted content type.
    for content_type in [
        None,
        Some("text/plain"),
        Some("application/x-www-form-urlencoded"),
        Some("multipart/form-data; boundary=x"),
    ] {
        let mut builder = Request::builder()
            .method(Method::POST)
            .uri("/api/logout")
            .header(header::COOKIE, &cookie);
        if let Some(ct) = content_type {
            builder = builder.header(header::CONTENT_TYPE, ct);
        }
        let (status, _, body) = send(&f.app, builder.body(Body::from("{}")).unwrap()).await;
        assert_eq!(
            status,
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            "{content_type:?}"
        );
        assert!(
            body["error"].as_str().unwrap().contains("application/json"),
            "{body}"
        );
    }
    let (status, _, _) = call(&f.app, Method::GET, "/api/me", Some(&cookie), None).await;
    assert_eq!(status, StatusCode::OK, "still logged in");
    let (status, _, _) = call(
        &f.app,
        Method::POST,
        "/api/logout",
        Some(&cookie),
        Some(json!({})),
    )
    .await;
    assert_eq!(status, StatusCode::NO_CONTENT);
}

#[tokio::test]
async fn throttled_logins_answer_429_with_retry_after_and_are_audited() {
    let f = fixture().await;
    let mut statuses = Vec::new();
    let mut retry_after = None;
    for i in 0..8 {
        let body = json!({"email": format!("x{i}@clinic.example"), "password": "wrong guess!"});
        let (status, headers, _) = send(
            &f.app,
            request(Method::POST, "/api/login", None, Some(body), 77),
        )
        .await;
        statuses.push(status);
        if status == StatusCode::TOO_MANY_REQUESTS {
            retry_after = headers.get(header::RETRY_AFTER).cloned();
        }
    }
    assert_eq!(statuses[..5], [StatusCode::UNAUTHORIZED; 5]);
    assert_eq!(statuses[5..], [StatusCode::TOO_MANY_REQUESTS; 3]);
    assert_eq!(retry_after.unwrap().to_str().unwrap(), "1");
    // The right password from this address waits too; from another address it does not.
    let right = json!({"email": EMAIL, "password": PASSWORD});
    let (status, _, _) = send(
        &f.app,
        request(Method::POST, "/api/login", None, Some(right.clone()), 77),
    )
    .await;
    assert_eq!(status, StatusCode::TOO_MANY_REQUESTS);
    let (status, _, _) = send(
        &f.app,
        request(Method::POST, "/api/login", None, Some(right), 78),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    let log = f.db.audit_log(1000).await.unwrap();
    assert!(
        log.iter()
            .any(|e| e.action == "login_throttled" && e.detail.contains("127.0.3.77")),
        "{log:?}"
    );
    assert_eq!(log.iter().filter(|e| e.action == "login_failed").count(), 5);
}

#[tokio::test]
async fn refused_reads_403s_401s_and_rate_limits_are_audited() {
    let f = fixture().await;
    let p_bob = &f.p_bob;
    let cookie = login_as(&f.app, EMAIL, PASSWORD).await;
    for uri in [
        format!("/api/patients/{}", p_bob.id),
        format!("/api/patients/{}/regimen", p_bob.id),
        format!("/api/patients/{}/live", p_bob.id),
        "/api/audit".to_owned(),
    ] {
        call(&f.app, Method::GET, &uri, Some(&cookie), None).await;
    }
    call(&f.app, Method::GET, "/api/patients", None, None).await;
    let mut streams = Vec::new();
    for _ in 0..=MAX_LIVE_STREAMS_PER_LOGIN {
        streams.push(open_live(&f, &cookie).await);
    }
    let log = f.db.audit_log(1000).await.unwrap();
    let has = |actor: &str, action: &str, target: &str| {
        log.iter()
            .any(|e| e.actor == actor && e.action == action && e.target == target)
    };
    let me = f.ada.actor();
    assert!(
        has(&me, "refused_404", &format!("/api/patients/{}", p_bob.id)),
        "{log:?}"
    );
    assert!(has(
        &me,
        "refused_404",
        &format!("/api/patients/{}/regimen", p_bob.id)
    ));
    assert!(has(
        &me,
        "refused_404",
        &format!("/api/patients/{}/live", p_bob.id)
    ));
    assert!(has(&me, "refused_403", "/api/audit"));
    assert!(has("web", "refused_401", "/api/patients"));
    assert!(has(
        &me,
        "refused_429",
        &format!("/api/patients/{}/live", f.p_ada.id)
    ));
    assert!(
        log.iter()
            .all(|e| !e.action.starts_with("refused_") || e.detail.contains("127.0.3.1"))
    );
}

#[tokio::test]
async fn the_audit_api_pages_with_a_next_cursor() {
    let f = fixture().await;
    for i in 0..30 {
        f.db.audit("cli", "step", &format!("{i:02}"), "", T0 - 1000 + i)
            .await
            .unwrap();
    }
    let admin = login_as(&f.app, "root@clinic.example", PASSWORD).await;
    let mut uri = "/api/audit?limit=7".to_owned();
    let mut steps = Vec::new();
    loop {
        let (status, _, page) = call(&f.app, Method::GET, &uri, Some(&admin), None).await;
        assert_eq!(status, StatusCode::OK, "{page}");
        for e in page["entries"].as_array().unwrap() {
            if e["action"] == "step" {
                steps.push(e["target"].as_str().unwrap().to_owned());
            }
        }
        match page["next"].as_object() {
            Some(next) => {
                uri = format!(
                    "/api/audit?limit=7&before_ms={}&before_id={}",
                    next["before_ms"],
                    next["before_id"].as_str().unwrap()
                );
            }
            None => break,
        }
    }
    let want: Vec<String> = (0..30).rev().map(|i| format!("{i:02}")).collect();
    assert_eq!(steps, want);
}

// ----- a whole hub under a login flood -----

/// 64 clients over TLS, each sending wrong passwords (a fresh e-mail each time, so no account
/// throttle helps) as fast as the hub answers, until `stop`. Each client moves to a new
/// loopback address (127.1.c.k) after every [`ADDRESS_FREE_FAILURES`] tries, so neither the
/// per-address connection cap nor the address throttle takes the load off the password
/// hashing: the worst case for the stations.
fn login_flood(
    web: SocketAddr,
    tls: netlink::ClientTls,
    stop: Arc<AtomicBool>,
    answers: Arc<[AtomicU64; 3]>,
) -> std::thread::JoinHandle<()> {
    std::thread::spawn(move || {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        rt.block_on(async move {
            let (connector, name) = tls.connector().unwrap();
            let mut clients = tokio::task::JoinSet::new();
            for c in 0..64_u8 {
                let (connector, name) = (connector.clone(), name.clone());
                let (stop, answers) = (Arc::clone(&stop), Arc::clone(&answers));
                clients.spawn(async move {
                    let mut i = 0_u32;
                    for k in (1..=250_u8).cycle() {
                        let socket = tokio::net::TcpSocket::new_v4().unwrap();
                        socket
                            .bind(SocketAddr::from(([127, 1, c, k], 0)))
                            .unwrap();
                        let Ok(tcp) = socket.connect(web).await else {
                            return;
                        };
                        let Ok(tls) = connector.connect(name.clone(), tcp).await else {
                            return;
                        };
                        let (mut sender, connection) = hyper::client::conn::http1::handshake(
                            hyper_util::rt::TokioIo::new(tls),
                        )
                        .await
                        .unwrap();
                        tokio::spawn(connection);
                        for _ in 0..hub::db::ADDRESS_FREE_FAILURES {
                            if stop.load(Ordering::Relaxed) {
                                return;
                            }
                            i += 1;
                            let body = json!({"email": format!("guess-{c}-{i}@clinic.example"), "password": format!("wrong guess {i}")});
                            let request = Request::post("/api/login")
                                .header(header::HOST, "localhost")
                                .header(header::CONTENT_TYPE, "application/json")
                                .body(http_body_util::Full::new(axum::body::Bytes::from(body.to_string())))
                                .unwrap();
                            let Ok(response) = sender.send_request(request).await else {
                                break;
                            };
                            let slot = match response.status() {
                                StatusCode::UNAUTHORIZED => 0,
                                StatusCode::TOO_MANY_REQUESTS => 1,
                                _ => 2,
                            };
                            answers[slot].fetch_add(1, Ordering::Relaxed);
                            let _ = response.into_body().collect().await;
                        }
                    }
                });
            }
            while clients.join_next().await.is_some() {}
        });
    })
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_login_flood_leaves_station_acks_within_twice_quiet() {
    use hub::bench;
    use hub::clinic::{Bound, Clinic, ServeOptions, serve};
    let dir = tempfile::tempdir().unwrap();
    let clinic = Clinic::at(dir.path().join("clinic"));
    clinic
        .init("root@clinic.example", &["localhost".to_owned()], None, T0)
        .await
        .unwrap();
    let db = clinic.open_db(None).await.unwrap();
    let mut stations = bench::provision(
        &db,
        &clinic.ca().unwrap(),
        "localhost",
        2,
        &dir.path().join("stations"),
        T0,
    )
    .await
    .unwrap();
    let options = ServeOptions {
        max_connections: (256, 64),
        ..ServeOptions::new(
            "127.0.0.1:0".parse().unwrap(),
            Some("127.0.0.1:0".parse().unwrap()),
        )
    };
    let (bound_tx, bound_rx) = tokio::sync::oneshot::channel::<Bound>();
    let (stop_tx, stop_rx) = tokio::sync::oneshot::channel::<()>();
    let hub = tokio::spawn(async move {
        serve(
            &clinic,
            db,
            options,
            move |b| {
                let _ = bound_tx.send(b);
            },
            |_| {},
            async {
                let _ = stop_rx.await;
            },
        )
        .await
    });
    let bound = bound_rx.await.unwrap();
    let rate_hz = 20.0;
    let measure = Duration::from_secs(3);
    let quiet_station = stations.remove(0);
    let quiet = bench::load(bound.stations, vec![quiet_station], rate_hz, measure).await;
    assert!(quiet.first_error.is_none(), "{quiet:?}");

    let stop = Arc::new(AtomicBool::new(false));
    let answers = Arc::new([AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)]);
    let web_tls = netlink::ClientTls {
        ca_pem_path: dir.path().join("clinic/tls/ca.crt"),
        server_name: "localhost".to_owned(),
        identity: None,
    };
    let flood = login_flood(
        bound.web.unwrap(),
        web_tls,
        Arc::clone(&stop),
        Arc::clone(&answers),
    );
    tokio::time::sleep(Duration::from_millis(700)).await;
    let before = answers[0].load(Ordering::Relaxed);
    let loaded = bench::load(bound.stations, stations, rate_hz, measure).await;
    let refused_during = answers[0].load(Ordering::Relaxed) - before;
    stop.store(true, Ordering::Relaxed);
    tokio::task::spawn_blocking(move || flood.join().unwrap())
        .await
        .unwrap();
    let _ = stop_tx.send(());
    hub.await.unwrap().unwrap();

    assert!(loaded.first_error.is_none(), "{loaded:?}");
    let (quiet_ms, loaded_ms) = (quiet.latency_ms.0, loaded.latency_ms.0);
    println!(
        "station Ack p50: quiet {quiet_ms:.2} ms, under a 64-client login flood {loaded_ms:.2} ms \
         ({:.2}×); during it {refused_during} passwords checked and refused, answers \
         401/429/other {:?}",
        loaded_ms / quiet_ms,
        answers
            .iter()
            .map(|a| a.load(Ordering::Relaxed))
            .collect::<Vec<_>>()
    );
    assert!(
        refused_during >= 10,
        "the flood checked only {refused_during} passwords: it did not load the hub"
    );
    assert!(
        answers[1].load(Ordering::Relaxed) > 0,
        "the hashing pool never filled"
    );
    assert_eq!(answers[2].load(Ordering::Relaxed), 0);
    assert!(
        loaded_ms <= 2.0 * quiet_ms,
        "station Acks: p50 {loaded_ms:.2} ms under the flood vs {quiet_ms:.2} ms quiet"
    );
}
