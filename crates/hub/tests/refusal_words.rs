//! Why the hub refused, in any language (issue 40): every refusal answers a code and its
//! arguments (`why`) beside the English sentence, and every code has words in the console's
//! catalogues naming no argument the code does not give.

mod common;

use std::collections::BTreeMap;

use axum::http::{Method, StatusCode};
use common::api::{call, clinician, login, router_at_t0};
use hub::refusal::Code;
use hub::{Role, db::MAX_NOTE_CHARS};
use serde_json::{Value, json};

#[test]
fn every_refusal_code_has_console_words_naming_only_its_arguments() {
    let (messages, errors) = i18n::console_messages_of("en");
    assert!(errors.is_empty(), "{errors:#?}");
    let words: BTreeMap<String, Vec<String>> =
        messages.into_iter().map(|m| (m.id, m.variables)).collect();
    for code in Code::ALL {
        let id = format!("api-why-{}", code.as_str());
        let variables = words
            .get(&id)
            .unwrap_or_else(|| panic!("the console has no words for refusal {id}"));
        for v in variables {
            assert!(
                code.args().contains(&v.as_str()),
                "{id} names ${v}, which the hub does not give ({:?})",
                code.args()
            );
        }
    }
    // And no words for a code the hub no longer has.
    let codes: Vec<String> = Code::ALL
        .iter()
        .map(|c| format!("api-why-{}", c.as_str()))
        .collect();
    for id in words.keys().filter(|id| id.starts_with("api-why-")) {
        assert!(codes.contains(id), "{id} is not a refusal code of the hub");
    }
}

/// `(status, why)` of one call.
async fn why_of(
    app: &axum::Router,
    method: Method,
    uri: &str,
    cookie: Option<&str>,
    body: Option<Value>,
) -> (StatusCode, Value) {
    let (status, answer, _) = call(app, method, uri, cookie, body).await;
    assert!(
        answer["error"].as_str().is_some_and(|e| !e.is_empty()),
        "{uri}: the English sentence is kept for API clients: {answer}"
    );
    (status, answer["why"].clone())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn refusals_answer_their_code_and_the_arguments_the_words_need() {
    let (db, _dir) = common::sqlite_db().await;
    let ada = clinician(&db, "ada@clinic.example", Role::Therapist).await;
    let patient = db
        .add_patient("p-ada-1", Some(&ada.id), common::T0)
        .await
        .unwrap();
    let app = router_at_t0(&db);
    let (status, why) = why_of(&app, Method::GET, "/api/patients", None, None).await;
    assert_eq!(
        (status, why),
        (StatusCode::UNAUTHORIZED, json!({"code": "log-in-first"}))
    );
    let cookie = login(&app, "ada@clinic.example").await;
    let cookie = Some(cookie.as_str());

    let cases = [
        (
            Method::POST,
            format!("/api/patients/{}/messages", patient.id),
            Some(json!({"text": "   "})),
            StatusCode::BAD_REQUEST,
            json!({"code": "empty", "args": {"field": "text"}}),
        ),
        (
            Method::POST,
            "/api/sessions/no-such-session/notes".to_owned(),
            Some(json!({"text": "x".repeat(MAX_NOTE_CHARS + 1)})),
            StatusCode::NOT_FOUND,
            json!({"code": "not-found", "args": {"what": "session"}}),
        ),
        (
            Method::GET,
            "/api/patients?sort=shoe-size".to_owned(),
            None,
            StatusCode::BAD_REQUEST,
            json!({"code": "not-one-of", "args": {"field": "sort"}}),
        ),
        (
            Method::POST,
            format!("/api/patients/{}/scales", patient.id),
            Some(json!({"scale": "arat", "assessed_on": "2026-13-40", "score": 30})),
            StatusCode::BAD_REQUEST,
            json!({"code": "bad-date", "args": {"field": "assessed_on"}}),
        ),
        (
            Method::POST,
            format!("/api/patients/{}/scales", patient.id),
            Some(json!({"scale": "arat", "assessed_on": "2026-11-01", "score": 99})),
            StatusCode::BAD_REQUEST,
            json!({"code": "out-of-range", "args": {"field": "score", "min": 0, "max": 57}}),
        ),
        (
            Method::PUT,
            format!("/api/patients/{}/regimen", patient.id),
            Some(json!({"toml": "[[exercise]]\nkind = \"sine\"\nduration_s = \"long\"\n"})),
            StatusCode::UNPROCESSABLE_ENTITY,
            json!({"code": "regimen-text", "args": {"line": 3}}),
        ),
        (
            Method::PUT,
            "/api/clinic/settings".to_owned(),
            Some(json!({"pain_threshold_0_10": 5})),
            StatusCode::FORBIDDEN,
            json!({"code": "admin-only"}),
        ),
        (
            Method::PUT,
            "/api/me/language".to_owned(),
            Some(json!({"language": "tlh"})),
            StatusCode::BAD_REQUEST,
            json!({"code": "unknown-language"}),
        ),
        (
            Method::POST,
            format!("/api/patients/{}/messages", patient.id),
            Some(json!({"words": "not the field"})),
            StatusCode::BAD_REQUEST,
            json!({"code": "body-malformed"}),
        ),
        (
            Method::GET,
            "/api/no-such-thing".to_owned(),
            None,
            StatusCode::NOT_FOUND,
            json!({"code": "no-endpoint"}),
        ),
    ];
    for (method, uri, body, status, expected) in cases {
        let (got_status, why) = why_of(&app, method, &uri, cookie, body).await;
        assert_eq!((got_status, &why), (status, &expected), "{uri}");
        let code = why["code"].as_str().unwrap();
        assert!(
            Code::ALL.iter().any(|c| c.as_str() == code),
            "{uri}: {code} is not a code"
        );
    }
}
