//! Real change told from noise through the console API (issue 42): `GET
//! /api/patients/{id}/assessments` answers each measure's change since the patient's first
//! assessment, its noise band and the verdict beside every assessment, pages the list
//! (`?before=&limit=`, bounded) and takes the verdict from the whole history whatever the
//! page. On SQLite and PostgreSQL (the latter needs `TELEREHAB_TEST_PG_URL`, see
//! `scripts/with-postgres.sh`).

mod common;

use std::collections::BTreeMap;

use axum::Router;
use axum::http::{Method, StatusCode};
use common::T0;
use common::api::{call, clinician, login, router_at_t0};
use hub::{Db, Patient, Role};
use metrics::change::History;
use netlink::{AssessmentTag, Bye, ExerciseResult};
use serde_json::Value;

const WEEK_MS: i64 = 7 * 24 * 3_600_000;
const FP1: &str = "1111111111111111111111111111111111111111111111111111111111111111";

/// Eight weekly assessments: active range gains beyond its noise at the end, reaction time
/// stays within it, strength on the left falls beyond it, smoothness wanders a little.
const ROM_DEG: [f64; 8] = [120.0, 122.0, 119.0, 123.0, 121.0, 124.0, 122.0, 140.0];
const REACTION_S: [f64; 8] = [0.60, 0.62, 0.58, 0.61, 0.59, 0.60, 0.62, 0.59];
const STRENGTH_LEFT_NM: [f64; 8] = [5.0, 5.1, 4.9, 5.0, 5.1, 5.0, 4.9, 3.0];
const SPARC: [f64; 8] = [-2.0, -1.9, -2.1, -1.95, -2.05, -2.0, -1.9, -1.85];

async fn patient(db: &Db) -> Patient {
    let t = clinician(db, "ada@clinic.example", Role::Therapist).await;
    let p = db.add_patient("P-0042", Some(&t.id), T0).await.unwrap();
    db.add_station("st-1", &p.id, FP1, T0).await.unwrap();
    p
}

fn part(index: u32, kind: &str, scores: &[(&str, f64)]) -> ExerciseResult {
    ExerciseResult {
        index,
        kind: kind.to_owned(),
        name: kind.to_owned(),
        prescribed_s: 30.0,
        active_s: 30.0,
        scores: scores.iter().map(|(k, v)| ((*k).to_owned(), *v)).collect(),
        assessment: Some(AssessmentTag {
            protocol: 1,
            seed: 7,
        }),
    }
}

/// Session `week` of the patient: an assessment of `parts` (and an exercise after it).
async fn assessment(db: &Db, p: &Patient, week: i64, parts: Vec<ExerciseResult>) {
    let at = T0 + week * WEEK_MS;
    let sid = format!("s-{week:04}");
    let mut hello = common::hello("st-1", &p.id, &sid);
    hello.started_unix_ms = at as u64;
    db.open_session(&hello, at).await.unwrap();
    let mut exercises = parts;
    exercises.push(ExerciseResult {
        index: exercises.len() as u32,
        kind: "dial".into(),
        name: "Dial".into(),
        prescribed_s: 60.0,
        active_s: 60.0,
        scores: BTreeMap::from([("dial_rms_error_deg".to_owned(), 4.0)]),
        assessment: None,
    });
    let bye = Bye {
        session_id: sid,
        reason: "complete".into(),
        final_seq: None,
        measures: BTreeMap::new(),
        hub_unix_ms: None,
        checkin: None,
        difficulty: None,
        exercises,
    };
    db.close_session(&bye, at + 600_000).await.unwrap();
}

async fn eight_weeks(db: &Db, p: &Patient) {
    for w in 0..8 {
        assessment(
            db,
            p,
            w as i64,
            vec![
                part(0, "assessment-range", &[("wheel_rom_deg", ROM_DEG[w])]),
                part(
                    1,
                    "assessment-steps",
                    &[
                        ("reaction_time_s_median", REACTION_S[w]),
                        ("sparc_median", SPARC[w]),
                        ("not_a_measure_of_the_words_table", 1.0),
                    ],
                ),
                part(
                    2,
                    "assessment-strength",
                    &[("strength_peak_left_nm", STRENGTH_LEFT_NM[w])],
                ),
            ],
        )
        .await;
    }
}

async fn get(app: &Router, cookie: &str, uri: &str) -> (StatusCode, Value) {
    let (status, value, _) = call(app, Method::GET, uri, Some(cookie), None).await;
    (status, value)
}

/// The change of `measure` in `part` of assessment `a` as served.
fn change<'a>(a: &'a Value, part: &str, measure: &str) -> &'a Value {
    a["changes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["part"] == part && c["measure"] == measure)
        .unwrap_or_else(|| panic!("no change of {part}/{measure} in {a}"))
}

async fn the_newest_assessment_says_better_worse_or_within_noise_against_the_first(db: Db) {
    let p = patient(&db).await;
    eight_weeks(&db, &p).await;
    let app = router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let (status, list) = get(
        &app,
        &cookie,
        &format!("/api/patients/{}/assessments", p.id),
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{list}");
    let list = list.as_array().unwrap();
    assert_eq!(list.len(), 8, "a year's page holds all eight");
    let newest = &list[0];
    assert_eq!(newest["session_id"], "s-0007", "newest first");
    // The assessment as before, its parts in course order (the additive API).
    assert_eq!(newest["parts"].as_array().unwrap().len(), 3);
    assert_eq!(newest["parts"][0]["scores"]["wheel_rom_deg"], 140.0);
    // Eight repeats: the patient's own noise, whatever the cohort's table holds.
    let rom = change(newest, "range", "wheel_rom_deg");
    assert_eq!(rom["band_source"], "own", "{rom}");
    assert_eq!(
        (rom["baseline"].as_f64(), rom["latest"].as_f64()),
        (Some(120.0), Some(140.0))
    );
    assert_eq!(rom["change"], 20.0);
    assert_eq!(rom["repeats"], 8);
    assert_eq!(
        rom["baseline_started_unix_ms"], T0,
        "the first week's session"
    );
    // SD of the weekly differences 7.22°: MDC95 14.2°, stated as 15°.
    assert_eq!(rom["band"], 15.0, "{rom}");
    assert_eq!(rom["verdict"], "better");
    let rt = change(newest, "steps", "reaction_time_s_median");
    assert_eq!(
        (&rt["band_source"], &rt["verdict"]),
        (&"own".into(), &"within-noise".into()),
        "{rt}"
    );
    let strength = change(newest, "strength", "strength_peak_left_nm");
    assert_eq!(strength["verdict"], "worse", "{strength}");
    // A measure the words table lacks gets no verdict.
    assert!(
        newest["changes"]
            .as_array()
            .unwrap()
            .iter()
            .all(|c| c["measure"] != "not_a_measure_of_the_words_table")
    );
    // The first assessment has nothing to compare with.
    assert_eq!(list[7]["changes"], Value::Array(vec![]));
    // Before six repeats: the cohort's noise, else the published one (SPARC's 34.7 %), else
    // none; never the patient's own.
    let second = &list[6];
    for (part, measure) in [("range", "wheel_rom_deg"), ("steps", "sparc_median")] {
        let c = change(second, part, measure);
        let cohort = metrics::assessment_noise::cohort_mdc95(1, part, measure);
        let published = metrics::words::measure_words(measure).unwrap().noise;
        let want = match (cohort, published) {
            (Some(_), _) => "cohort",
            (None, Some(_)) => "published",
            (None, None) => "",
        };
        if want.is_empty() {
            assert!(
                c["band_source"].is_null() && c["verdict"] == "no-noise-figure",
                "{c}"
            );
        } else {
            assert_eq!(c["band_source"], want, "{c}");
        }
    }
    // Each verdict is metrics::change's on the values up to that assessment.
    for (i, a) in list.iter().enumerate() {
        let upto = 8 - i;
        if upto < 2 {
            continue;
        }
        let served = change(a, "steps", "sparc_median");
        let want = metrics::change::assessment_change(
            1,
            "steps",
            "sparc_median",
            &History::of(&SPARC[..upto]),
        )
        .unwrap();
        for (k, v) in serde_json::to_value(want).unwrap().as_object().unwrap() {
            assert_eq!(&served[k], v, "{k} of assessment {i}: {served}");
        }
    }
}

async fn pages_hold_the_verdict_of_the_whole_history_and_bad_paging_is_refused_by_name(db: Db) {
    let p = patient(&db).await;
    eight_weeks(&db, &p).await;
    let app = router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let base = format!("/api/patients/{}/assessments", p.id);
    let (_, all) = get(&app, &cookie, &format!("{base}?limit=104")).await;
    // Pages of three, each from the last start of the one before: every assessment once, the
    // same as in one page, changes and all.
    let mut paged: Vec<Value> = Vec::new();
    let mut uri = format!("{base}?limit=3");
    loop {
        let (status, page) = get(&app, &cookie, &uri).await;
        assert_eq!(status, StatusCode::OK, "{page}");
        let page = page.as_array().unwrap().clone();
        assert!(page.len() <= 3);
        let Some(last) = page.last() else { break };
        uri = format!("{base}?limit=3&before={}", last["started_unix_ms"]);
        paged.extend(page);
    }
    assert_eq!(Value::Array(paged), all);
    // The newest alone carries the verdict on all eight.
    let (_, one) = get(&app, &cookie, &format!("{base}?limit=1")).await;
    assert_eq!(one[0], all[0]);
    assert_eq!(change(&one[0], "range", "wheel_rom_deg")["repeats"], 8);
    // An older page's verdicts are as they were then.
    let before = all[3]["started_unix_ms"].as_i64().unwrap() + 1;
    let (_, older) = get(&app, &cookie, &format!("{base}?limit=2&before={before}")).await;
    assert_eq!(older[0], all[3]);
    assert_eq!(change(&older[0], "range", "wheel_rom_deg")["repeats"], 5);
    for (query, field) in [
        ("limit=0", "limit"),
        ("limit=105", "limit"),
        ("limit=-3", "limit"),
        ("before=-1", "before"),
    ] {
        let (status, body) = get(&app, &cookie, &format!("{base}?{query}")).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{query}: {body}");
        assert_eq!(body["why"]["code"], "out-of-range", "{query}: {body}");
        assert_eq!(body["why"]["args"]["field"], field, "{query}: {body}");
        assert!(body["error"].as_str().unwrap().contains(field), "{body}");
    }
    let (status, body) = get(&app, &cookie, &format!("{base}?limit=many")).await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{body}");
    assert!(body["error"].as_str().unwrap().contains("limit"), "{body}");
}

/// Ten years of weekly assessments: a page of four, and the newest's verdict still reads
/// all 520 (its baseline the first week's).
async fn ten_years_of_weekly_assessments_give_a_page_of_four_and_the_verdict_of_all_520(db: Db) {
    let p = patient(&db).await;
    for w in 0..520i64 {
        let rom = 100.0 + (w % 5) as f64 + if w == 519 { 30.0 } else { 0.0 };
        assessment(
            &db,
            &p,
            w,
            vec![part(0, "assessment-range", &[("wheel_rom_deg", rom)])],
        )
        .await;
    }
    let app = router_at_t0(&db);
    let cookie = login(&app, "ada@clinic.example").await;
    let (status, page) = get(
        &app,
        &cookie,
        &format!("/api/patients/{}/assessments?limit=4", p.id),
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{page}");
    let page = page.as_array().unwrap();
    assert_eq!(page.len(), 4);
    assert_eq!(page[0]["session_id"], "s-0519");
    let rom = change(&page[0], "range", "wheel_rom_deg");
    assert_eq!(rom["repeats"], 520);
    assert_eq!(rom["baseline"], 100.0);
    assert_eq!(rom["latest"], 134.0);
    assert_eq!(rom["verdict"], "better", "{rom}");
    let (_, default) = get(
        &app,
        &cookie,
        &format!("/api/patients/{}/assessments", p.id),
    )
    .await;
    assert_eq!(default.as_array().unwrap().len(), 52, "a year by default");
}

on_both_backends!(
    the_newest_assessment_says_better_worse_or_within_noise_against_the_first,
    pages_hold_the_verdict_of_the_whole_history_and_bad_paging_is_refused_by_name,
    ten_years_of_weekly_assessments_give_a_page_of_four_and_the_verdict_of_all_520,
);
