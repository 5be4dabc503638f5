//! `GET /api/patients/{id}/assessments.csv`: the patient's standard assessments (issue 42) as
//! a spreadsheet of their own, never mixed with the sessions' (`measures.csv`), audited as
//! `export_assessments_csv`.
//!
//! Long ("tidy") form: one row a measure of a part of an assessment, oldest assessment first,
//! its parts in course order, a part's measures in the words table's reading order then any
//! other alphabetically; each row marked by the session, the protocol's version, the steps'
//! seed and the part, so a pivot table or a join needs nothing else. The same two header rows,
//! local and UTC start, rounding, language and formula guard as the measures' spreadsheet
//! ([`super::spreadsheet`]). Columns (crates/hub/API.md): `session_id`, `started_local`,
//! `started_at_utc`, `assessment_protocol`, `assessment_seed`, `assessment_part` (`steps`),
//! `part` (its name in words), `measure` (`reaction_time_s_median`), `measure_name` (its name
//! in words), `value` (rounded), `unit` (the words table's, else the UCUM unit its name
//! carries; empty for a count or a ratio).

use std::collections::BTreeSet;

use axum::extract::rejection::{PathRejection, QueryRejection};
use axum::extract::{Path, Query, State};
use axum::response::Response;

use super::auth::Authed;
use super::spreadsheet::{
    LocalZone, SheetQuery, csv_response, number_cell, ordered, text_cell, zone_and_words,
};
use super::{ApiError, AppState};
use hub_care::sheet_words::SheetWords;
use hub_store::db::{Assessment, day_of, iso_utc};

/// The columns: (the words' id, technical name); the session's three are the measures'
/// spreadsheet's.
const COLUMNS: [(&str, &str); 11] = [
    ("sheet-col-session", "session_id"),
    ("sheet-col-started-local", "started_local"),
    ("sheet-col-started-utc", "started_at_utc"),
    ("sheet-assessment-col-protocol", "assessment_protocol"),
    ("sheet-assessment-col-seed", "assessment_seed"),
    ("sheet-assessment-col-part-key", "assessment_part"),
    ("sheet-assessment-col-part", "part"),
    ("sheet-assessment-col-measure-key", "measure"),
    ("sheet-assessment-col-measure", "measure_name"),
    ("sheet-assessment-col-value", "value"),
    ("sheet-assessment-col-unit", "unit"),
];

/// A line of `cells` (each already a CSV cell) with its CRLF.
fn line(cells: &[String]) -> String {
    let mut l = cells.join(",");
    l.push_str("\r\n");
    l
}

/// The two header lines.
fn header(zone: &LocalZone, words: &SheetWords) -> String {
    let plain: Vec<String> = COLUMNS
        .iter()
        .map(|(id, _)| text_cell(&words.t(id, &[("zone", zone.name.clone())])))
        .collect();
    let technical: Vec<String> = COLUMNS.iter().map(|(_, t)| (*t).to_owned()).collect();
    format!("{}{}", line(&plain), line(&technical))
}

/// A measure's unit as a reader writes it: the words table's (`°`), else the UCUM unit its
/// name carries; empty for a count or a ratio.
fn unit_of(name: &str) -> String {
    match metrics::words::measure_words(name) {
        Some(m) => m.unit.to_owned(),
        None => match hub_care::fhir::ucum_unit(name) {
            "1" => String::new(),
            u => u.to_owned(),
        },
    }
}

/// The rows of `assessments` (any order: written oldest first) appended to `out`; how many.
fn rows(
    assessments: &[Assessment],
    zone: &LocalZone,
    words: &SheetWords,
    out: &mut String,
) -> usize {
    let mut oldest_first: Vec<&Assessment> = assessments.iter().collect();
    oldest_first.sort_by_key(|a| (a.started_unix_ms, a.session_id.clone()));
    let mut n = 0;
    for a in oldest_first {
        let mut parts: Vec<_> = a.parts.iter().collect();
        parts.sort_by_key(|p| p.index);
        for part in parts {
            let key = part
                .kind
                .strip_prefix("assessment-")
                .unwrap_or(&part.kind)
                .to_owned();
            let part_id = format!("progress-assessment-part-{key}");
            let part_words = if words.has(&part_id) {
                words.t(&part_id, &[])
            } else {
                key.replace('-', " ")
            };
            let names: BTreeSet<String> = part.scores.keys().cloned().collect();
            for name in ordered(&names) {
                let Some(v) = part.scores.get(&name).filter(|v| v.is_finite()) else {
                    continue;
                };
                out.push_str(&line(&[
                    text_cell(&a.session_id),
                    zone.local(a.started_unix_ms),
                    iso_utc(a.started_unix_ms),
                    a.protocol.to_string(),
                    a.seed.to_string(),
                    text_cell(&key),
                    text_cell(&part_words),
                    text_cell(&name),
                    text_cell(&words.measure_name(&name)),
                    number_cell(&name, *v),
                    text_cell(&unit_of(&name)),
                ]));
                n += 1;
            }
        }
    }
    n
}

/// `GET /api/patients/{id}/assessments.csv` (404 for a patient the therapist may not see;
/// `?tz=`, `?lang=` as the measures' spreadsheet), audited as `export_assessments_csv` with
/// the counts.
pub(crate) async fn patient_csv(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
    query: Result<Query<SheetQuery>, QueryRejection>,
) -> Result<Response, ApiError> {
    let Path(id) = id?;
    let (zone, words) = zone_and_words(&state, &therapist, query).await?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let assessments = state.db.assessments_of(&patient.id).await?;
    let mut body = header(&zone, &words);
    let count = rows(&assessments, &zone, &words, &mut body);
    state
        .audit(
            &therapist.actor(),
            "export_assessments_csv",
            &patient.id,
            &format!("{} assessments, {count} measures", assessments.len()),
        )
        .await?;
    // The pseudonym is 1–64 of A-Z a-z 0-9 . _ - (check_pseudonym): safe in the header.
    let filename = format!(
        "assessments-{}-{}.csv",
        patient.pseudonym,
        day_of(state.now())
    );
    Ok(csv_response(body, &filename))
}
