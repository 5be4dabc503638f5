//! The per-session measures as a spreadsheet: `GET /api/patients/{id}/measures.csv` (one
//! patient) and `GET /api/measures.csv` (an admin's whole caseload, a `patient` column first),
//! both audited.
//!
//! One row a session, oldest first; the columns `session_id`, `started_at_utc` (ISO 8601),
//! `exercise` (in words, a regimen's exercises in order), `ran_as_prescribed` (`true` or
//! `false`), then every measure any of the sessions has, by its stored name, which carries its
//! unit (`_deg`, `_s`, `_nm`, `_pct`, `_per_min`; none for a ratio or a count such as
//! `sparc_median`), alphabetically. A session without a measure leaves its cell empty. Numbers
//! are written as Rust's shortest exact decimal (they read back as the same `f64`); a text cell
//! starting with `=`, `+`, `-` or `@` is prefixed with `'` so that no spreadsheet takes it
//! for a formula.

use std::collections::BTreeSet;

use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use axum::http::{HeaderValue, header};
use axum::response::{IntoResponse, Response};

use super::auth::Authed;
use super::{ApiError, AppState};
use crate::db::{MeasuresBySession, NamedSession, Patient, iso_utc};

/// One patient's sessions (oldest first) with their measures.
struct PatientRows {
    patient: Patient,
    sessions: Vec<NamedSession>,
    measures: MeasuresBySession,
}

async fn rows_of(state: &AppState, patient: Patient) -> Result<PatientRows, ApiError> {
    let mut sessions = state.db.named_sessions_of(&patient.id).await?;
    sessions.reverse();
    let measures = state.db.measures_of_patient(&patient.id).await?;
    Ok(PatientRows {
        patient,
        sessions,
        measures,
    })
}

/// A text cell as CSV (RFC 4180 quoting; a leading formula character neutralised).
fn text_cell(text: &str) -> String {
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

/// The CSV of `patients` (with a `patient` column, the pseudonym, when `with_patient`); the
/// number of sessions written.
fn csv_of(patients: &[PatientRows], with_patient: bool) -> (String, usize) {
    let names: BTreeSet<&str> = patients
        .iter()
        .flat_map(|p| {
            p.measures
                .values()
                .flat_map(|m| m.keys().map(String::as_str))
        })
        .collect();
    let mut head: Vec<&str> = Vec::new();
    if with_patient {
        head.push("patient");
    }
    head.extend([
        "session_id",
        "started_at_utc",
        "exercise",
        "ran_as_prescribed",
    ]);
    head.extend(names.iter().copied());
    let mut out = head
        .iter()
        .map(|h| text_cell(h))
        .collect::<Vec<_>>()
        .join(",");
    out.push_str("\r\n");
    let mut written = 0;
    for p in patients {
        for s in &p.sessions {
            let mut cells: Vec<String> = Vec::with_capacity(head.len());
            if with_patient {
                cells.push(text_cell(&p.patient.pseudonym));
            }
            cells.push(text_cell(&s.row.session_id));
            cells.push(iso_utc(s.row.started_unix_ms));
            cells.push(text_cell(&s.exercise_name));
            cells.push(s.ran_as_prescribed.to_string());
            let measures = p.measures.get(&s.row.session_id);
            for name in &names {
                cells.push(
                    measures
                        .and_then(|m| m.get(*name))
                        .map_or_else(String::new, |v| format!("{v}")),
                );
            }
            out.push_str(&cells.join(","));
            out.push_str("\r\n");
            written += 1;
        }
    }
    (out, written)
}

/// `body` as a CSV download named `filename`.
fn csv_response(body: String, filename: &str) -> Response {
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

/// The UTC day of `now_ms` for a file name: `2026-11-21`.
fn day_of(now_ms: i64) -> String {
    iso_utc(now_ms).chars().take(10).collect()
}

/// `GET /api/patients/{id}/measures.csv`: the patient's sessions and measures (404 for a
/// patient the therapist may not see), audited as `export_measures_csv`.
pub(crate) async fn patient_csv(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    id: Result<Path<String>, PathRejection>,
) -> Result<Response, ApiError> {
    let Path(id) = id?;
    let patient = state.visible_patient(&therapist, &id).await?;
    let rows = [rows_of(&state, patient).await?];
    let (body, sessions) = csv_of(&rows, false);
    let patient = &rows[0].patient;
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
/// (the pseudonym) first, by pseudonym; audited as `export_caseload_csv`.
pub(crate) async fn caseload_csv(
    State(state): State<AppState>,
    Authed(therapist): Authed,
) -> Result<Response, ApiError> {
    super::clinic::admins_only(&therapist, "the whole caseload's spreadsheet")?;
    let mut patients: Vec<Patient> = state
        .db
        .patients_for(&therapist, state.now())
        .await?
        .into_iter()
        .map(|o| o.patient)
        .collect();
    patients.sort_by(|a, b| a.pseudonym.cmp(&b.pseudonym));
    let mut rows = Vec::with_capacity(patients.len());
    for p in patients {
        rows.push(rows_of(&state, p).await?);
    }
    let (body, sessions) = csv_of(&rows, true);
    state
        .audit(
            &therapist.actor(),
            "export_caseload_csv",
            "patients",
            &format!("{} patients, {sessions} sessions", rows.len()),
        )
        .await?;
    Ok(csv_response(
        body,
        &format!("measures-caseload-{}.csv", day_of(state.now())),
    ))
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
