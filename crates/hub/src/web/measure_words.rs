//! `GET /api/measures/words`: the one table of measure words (`metrics::words`) as JSON, so
//! that the console never re-types a measure's plain name, unit, decimals, axis range or
//! noise, nor an end reason's wording.

use axum::Json;
use axum::extract::State;
use metrics::words::{EndKind, MEASURES, MeasureWords};
use serde::Serialize;

use super::AppState;
use super::auth::Authed;

/// One way a session ends: its key and its one wording.
#[derive(Serialize)]
pub(crate) struct EndWording {
    kind: EndKind,
    words: &'static str,
}

/// The table served.
#[derive(Serialize)]
pub(crate) struct Words {
    /// Every measure with words, in reading order.
    measures: &'static [MeasureWords],
    /// Every way a session ends with its wording.
    end_reasons: Vec<EndWording>,
}

/// The table (no patient data: not audited; a login is required, as for every endpoint).
pub(crate) async fn measure_words(Authed(_): Authed) -> Json<Words> {
    Json(Words {
        measures: &MEASURES,
        end_reasons: EndKind::ALL
            .iter()
            .map(|&kind| EndWording {
                kind,
                words: kind.words(),
            })
            .collect(),
    })
}

/// `GET /api/clinic/name`: `{"name": "Rehab Clinic Nord"}` (`null` when `hub.toml` has no
/// `clinic_name`), for the one-page print's header.
pub(crate) async fn clinic_name(
    State(state): State<AppState>,
    Authed(_): Authed,
) -> Json<serde_json::Value> {
    Json(serde_json::json!({ "name": state.clinic_name }))
}
