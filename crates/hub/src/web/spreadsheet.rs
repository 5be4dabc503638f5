//! The per-session measures as a spreadsheet a clinic files: `GET
//! /api/patients/{id}/measures.csv` (one patient) and `GET /api/measures.csv` (an admin's whole
//! caseload, a `Patient` column first), both audited.
//!
//! Two header rows: the first in plain words with units (`Time in lane (%)`) in the therapist's
//! language (`?lang=de`, else the language they chose for the console, else English; the
//! console's words, [`hub_care::sheet_words`]), the second the technical names (`pct_in_lane`) for
//! whoever joins the file to other data. Then one row a session, oldest first: its start in
//! local time (the time zone the console's browser sends as `?tz=Europe/Berlin`, else the hub's
//! own; the header names it) and in UTC (ISO 8601), its exercises in order, how it ended (the
//! one wording), whether it ran as prescribed, the patient's check-in (pain, effort, how hard
//! it felt), then every measure any of the sessions has: the table's in its reading order, any
//! other alphabetically. Numbers are rounded to the table's meaningful decimals (a measure the
//! table lacks to 4 significant digits): never `999.9999999999999`. A session without a measure
//! leaves its cell empty. A text cell starting with `=`, `+`, `-` or `@` is prefixed with `'`
//! so that no spreadsheet takes it for a formula.

use std::collections::{BTreeMap, BTreeSet};

use axum::extract::rejection::{PathRejection, QueryRejection};
use axum::extract::{Path, Query, State};
use axum::http::{HeaderValue, header};
use axum::response::{IntoResponse, Response};
use jiff::tz::TimeZone;
use metrics::words::{MEASURES, measure_words, round_unknown};

use hub_care::sheet_words::SheetWords;
use serde::Deserialize;

use super::Says as _;
use super::auth::Authed;
use super::{ApiError, AppState};
use hub_store::db::{MeasuresBySession, NamedSession, Patient, SessionCheckIn, day_of, iso_utc};
use hub_store::refusal::{Code, Why};

/// One patient's sessions (oldest first) with their measures and check-ins.
struct PatientRows {
    patient: Patient,
    sessions: Vec<NamedSession>,
    measures: MeasuresBySession,
    checkins: BTreeMap<String, SessionCheckIn>,
}

async fn rows_of(state: &AppState, patient: Patient) -> Result<PatientRows, hub_store::HubError> {
    let (sessions, measures) = state.db.sessions_with_measures(&patient.id).await?;
    let checkins = state
        .db
        .checkins_of(&patient.id)
        .await?
        .into_iter()
        .map(|c| (c.session_id.clone(), c))
        .collect();
    Ok(PatientRows {
        patient,
        sessions,
        measures,
        checkins,
    })
}

/// Query of both spreadsheets.
#[derive(Deserialize)]
pub(crate) struct SheetQuery {
    /// The IANA time zone of the local times (`Europe/Berlin`); the hub's own when absent.
    tz: Option<String>,
    /// The language of the words (`de`); the therapist's console language when absent.
    lang: Option<String>,
}

/// The time zone the local times are written in, and its name for the header.
pub(super) struct LocalZone {
    zone: TimeZone,
    pub(super) name: String,
}

impl LocalZone {
    /// `tz` (IANA name), else the hub's system time zone; an unknown name is refused naming it.
    fn of(tz: Option<&str>) -> Result<Self, ApiError> {
        match tz.map(str::trim).filter(|t| !t.is_empty()) {
            Some(name) => {
                let zone = TimeZone::get(name).map_err(|_| {
                    ApiError::BadRequest(Why::new(Code::UnknownTimeZone).says(format!(
                        "unknown time zone \"{}\": give an IANA name such as Europe/Berlin",
                        name.chars().take(64).collect::<String>()
                    )))
                })?;
                Ok(Self {
                    zone,
                    name: name.to_owned(),
                })
            }
            None => {
                let zone = TimeZone::system();
                let name = zone.iana_name().unwrap_or("the hub's time zone").to_owned();
                Ok(Self { zone, name })
            }
        }
    }

    /// `ms` as local date and time: `2026-11-27 09:51`.
    pub(super) fn local(&self, ms: i64) -> String {
        jiff::Timestamp::from_millisecond(ms).map_or_else(
            |_| String::new(),
            |t| {
                t.to_zoned_datetime(self.zone.clone())
                    .strftime("%Y-%m-%d %H:%M")
                    .to_string()
            },
        )
    }
}

/// A text cell as CSV (RFC 4180 quoting; a leading formula character neutralised).
pub(super) fn text_cell(text: &str) -> String {
    let text = if text.starts_with(['=', '+', '-', '@']) {
        format!("'{text}")
    } else {
        text.to_owned()
    };
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text
    }
}

/// `names` in the columns' order: the table's measures in its reading order, then any other
/// alphabetically.
pub(super) fn ordered(names: &BTreeSet<String>) -> Vec<String> {
    let known = MEASURES
        .iter()
        .filter(|m| names.contains(m.key))
        .map(|m| m.key.to_owned());
    let unknown = names.iter().filter(|n| measure_words(n).is_none()).cloned();
    known.chain(unknown).collect()
}

/// The measure columns of `rows`: every measure any of its sessions has.
fn names_of(rows: &PatientRows) -> Vec<String> {
    ordered(
        &rows
            .measures
            .values()
            .flat_map(|m| m.keys().cloned())
            .collect(),
    )
}

/// The columns before the measures: (the words' `sheet-col-<key>`, technical name).
const FIXED_COLUMNS: [(&str, &str); 9] = [
    ("session", "session_id"),
    ("started-local", "started_local"),
    ("started-utc", "started_at_utc"),
    ("exercises", "exercise"),
    ("ended", "end_reason"),
    ("as-prescribed", "ran_as_prescribed"),
    ("pain", "pain_0_10"),
    ("effort", "tiredness_0_10"),
    ("felt", "difficulty"),
];

/// The two header lines (a `Patient` column first when `with_patient`).
fn header(names: &[String], with_patient: bool, zone: &LocalZone, words: &SheetWords) -> String {
    let mut plain: Vec<String> = Vec::new();
    let mut technical: Vec<String> = Vec::new();
    let fixed = with_patient
        .then_some(("patient", "patient"))
        .into_iter()
        .chain(FIXED_COLUMNS);
    for (key, t) in fixed {
        plain.push(words.column(key, &zone.name));
        technical.push(t.to_owned());
    }
    for n in names {
        plain.push(words.measure(n));
        technical.push(n.clone());
    }
    let line = |cells: &[String]| {
        let mut l = cells
            .iter()
            .map(|c| text_cell(c))
            .collect::<Vec<_>>()
            .join(",");
        l.push_str("\r\n");
        l
    };
    format!("{}{}", line(&plain), line(&technical))
}

/// A measure's value as a cell: rounded to the table's decimals (4 significant digits for a
/// measure the table lacks).
pub(super) fn number_cell(name: &str, v: f64) -> String {
    match measure_words(name) {
        Some(m) => m.number(v),
        None => format!("{}", round_unknown(v)),
    }
}

/// One patient's session lines appended to `out` (columns `names`); how many.
fn lines_of(
    p: &PatientRows,
    names: &[String],
    with_patient: bool,
    zone: &LocalZone,
    words: &SheetWords,
    out: &mut String,
) -> usize {
    for s in &p.sessions {
        let mut cells: Vec<String> = Vec::with_capacity(names.len() + 10);
        if with_patient {
            cells.push(text_cell(&p.patient.pseudonym));
        }
        let checkin = p.checkins.get(&s.row.session_id);
        let opt = |v: Option<i64>| v.map_or_else(String::new, |v| v.to_string());
        cells.push(text_cell(&s.row.session_id));
        cells.push(zone.local(s.row.started_unix_ms));
        cells.push(iso_utc(s.row.started_unix_ms));
        cells.push(text_cell(
            &words.exercises(&s.exercise_shorts, &s.exercise_name),
        ));
        cells.push(text_cell(
            &words.ended(s.end_kind, s.recording_stopped_early),
        ));
        cells.push(words.yes_no(s.ran_as_prescribed));
        cells.push(opt(checkin.and_then(|c| c.pain_0_10)));
        cells.push(opt(checkin.and_then(|c| c.tiredness_0_10)));
        cells.push(
            checkin
                .and_then(|c| c.difficulty.as_deref())
                .map_or_else(String::new, |d| text_cell(&words.felt(d))),
        );
        let measures = p.measures.get(&s.row.session_id);
        for name in names {
            cells.push(
                measures
                    .and_then(|m| m.get(name))
                    .map_or_else(String::new, |&v| number_cell(name, v)),
            );
        }
        out.push_str(&cells.join(","));
        out.push_str("\r\n");
    }
    p.sessions.len()
}

/// The local time zone and the words a spreadsheet's query asks for (see [`LocalZone::of`]):
/// its language, else `therapist`'s console language.
pub(super) async fn zone_and_words(
    state: &AppState,
    therapist: &hub_store::db::Therapist,
    query: Result<Query<SheetQuery>, QueryRejection>,
) -> Result<(LocalZone, SheetWords), ApiError> {
    let Query(q) = query.map_err(|e| {
        ApiError::BadRequest(Why::field(Code::FieldRefused, "query").says(e.body_text()))
    })?;
    let zone = LocalZone::of(q.tz.as_deref())?;
    let lang = match q.lang {
        Some(lang) => Some(lang),
        None => state.db.therapist_language(&therapist.id).await?,
    };
    Ok((zone, SheetWords::of(lang.as_deref())))
}

/// `body` as a CSV download named `filename`.
pub(super) fn csv_response(body: impl IntoResponse, filename: &str) -> Response {
    let mut response = body.into_response();
    let headers = response.headers_mut();
    headers.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static("text/csv; charset=utf-8"),
    );
    if let Ok(v) = HeaderValue::from_str(&format!("attachment; filename=\"{filename}\"")) {
        headers.insert(header::CONTENT_DISPOSITION, v);
    }
    response
}

/// `GET /api/patients/{id}/measures.csv`: the patient's sessions and measures (404 for a
/// patient the therapist may not see), audited as `export_measures_csv`.
pub(crate) async fn patient_csv(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    query: Result<Query<SheetQuery>, QueryRejection>,
) -> Result<Response, ApiError> {
    let Path(id) = id?;
    let (zone, words) = zone_and_words(&state, &therapist, query).await?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let rows = rows_of(&state, patient).await?;
    let names = names_of(&rows);
    let mut body = header(&names, false, &zone, &words);
    let sessions = lines_of(&rows, &names, false, &zone, &words, &mut body);
    let patient = &rows.patient;
    state
        .audit(
            &therapist.actor(),
            "export_measures_csv",
            &patient.id,
            &format!("{sessions} sessions"),
        )
        .await?;
    // The pseudonym is 1–64 of A-Z a-z 0-9 . _ - (check_pseudonym): safe in the header.
    let filename = format!("measures-{}-{}.csv", patient.pseudonym, day_of(state.now()));
    Ok(csv_response(body, &filename))
}

/// `GET /api/measures.csv` (admin): every patient's sessions and measures, a `patient` column
/// (the pseudonym) first, by pseudonym; audited as `export_caseload_csv`. Streamed one patient
/// at a time (a year of a 1 000-patient clinic is ~260 000 lines and ~15 million measures:
/// held whole it took GBs), a few patients' lines in flight; the columns are every measure any
/// session has.
pub(crate) async fn caseload_csv(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    query: Result<Query<SheetQuery>, QueryRejection>,
) -> Result<Response, ApiError> {
    super::clinic::admins_only(&therapist, "the whole caseload's spreadsheet")?;
    let (zone, words) = zone_and_words(&state, &therapist, query).await?;
    let patients = state.db.all_patients().await?;
    let names = ordered(&state.db.measure_names().await?.into_iter().collect());
    state
        .audit(
            &therapist.actor(),
            "export_caseload_csv",
            "patients",
            &format!("{} patients", patients.len()),
        )
        .await?;
    let (tx, rx) = tokio::sync::mpsc::channel::<Result<String, std::io::Error>>(4);
    let filename = format!("measures-caseload-{}.csv", day_of(state.now()));
    tokio::spawn(async move {
        if tx
            .send(Ok(header(&names, true, &zone, &words)))
            .await
            .is_err()
        {
            return;
        }
        for p in patients {
            let chunk = match rows_of(&state, p).await {
                Ok(rows) => {
                    let mut out = String::new();
                    lines_of(&rows, &names, true, &zone, &words, &mut out);
                    Ok(out)
                }
                // The download ends cut short rather than with a wrong file.
                Err(e) => Err(std::io::Error::other(e.to_string())),
            };
            let failed = chunk.is_err();
            // A console gone away ends it.
            if tx.send(chunk).await.is_err() || failed {
                return;
            }
        }
    });
    let body = axum::body::Body::from_stream(tokio_stream::wrappers::ReceiverStream::new(rx));
    Ok(csv_response(body, &filename))
}

#[cfg(test)]
mod tests {
    use super::text_cell;

    #[test]
    fn text_cells_are_quoted_and_formulas_neutralised() {
        assert_eq!(text_cell("Sine road"), "Sine road");
        assert_eq!(text_cell("Dial, then road"), "\"Dial, then road\"");
        assert_eq!(text_cell("say \"hi\""), "\"say \"\"hi\"\"\"");
        assert_eq!(text_cell("=HYPERLINK(1)"), "'=HYPERLINK(1)");
        assert_eq!(text_cell("-x"), "'-x");
    }
}
