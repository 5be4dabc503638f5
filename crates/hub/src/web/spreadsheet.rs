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

async fn rows_of(state: &AppState, patient: Patient) -> Result<PatientRows, crate::HubError> {
    let (sessions, measures) = state.db.sessions_with_measures(&patient.id).await?;
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

/// The measure columns of `rows`: every measure any of its sessions has, sorted.
fn names_of(rows: &PatientRows) -> Vec<String> {
    let names: BTreeSet<&String> = rows.measures.values().flat_map(|m| m.keys()).collect();
    names.into_iter().cloned().collect()
}

/// The header line (with a `patient` column first when `with_patient`).
fn header(names: &[String], with_patient: bool) -> String {
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
    head.extend(names.iter().map(String::as_str));
    let mut out = head
        .iter()
        .map(|h| text_cell(h))
        .collect::<Vec<_>>()
        .join(",");
    out.push_str("\r\n");
    out
}

/// One patient's session lines appended to `out` (columns `names`); how many.
fn lines_of(p: &PatientRows, names: &[String], with_patient: bool, out: &mut String) -> usize {
    for s in &p.sessions {
        let mut cells: Vec<String> = Vec::with_capacity(names.len() + 5);
        if with_patient {
            cells.push(text_cell(&p.patient.pseudonym));
        }
        cells.push(text_cell(&s.row.session_id));
        cells.push(iso_utc(s.row.started_unix_ms));
        cells.push(text_cell(&s.exercise_name));
        cells.push(s.ran_as_prescribed.to_string());
        let measures = p.measures.get(&s.row.session_id);
        for name in names {
            cells.push(
                measures
                    .and_then(|m| m.get(name))
                    .map_or_else(String::new, |v| format!("{v}")),
            );
        }
        out.push_str(&cells.join(","));
        out.push_str("\r\n");
    }
    p.sessions.len()
}

/// `body` as a CSV download named `filename`.
fn csv_response(body: impl IntoResponse, filename: &str) -> Response {
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
    let rows = rows_of(&state, patient).await?;
    let names = names_of(&rows);
    let mut body = header(&names, false);
    let sessions = lines_of(&rows, &names, false, &mut body);
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
) -> Result<Response, ApiError> {
    super::clinic::admins_only(&therapist, "the whole caseload's spreadsheet")?;
    let patients = state.db.all_patients().await?;
    let names = state.db.measure_names().await?;
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
        if tx.send(Ok(header(&names, true))).await.is_err() {
            return;
        }
        for p in patients {
            let chunk = match rows_of(&state, p).await {
                Ok(rows) => {
                    let mut out = String::new();
                    lines_of(&rows, &names, true, &mut out);
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
