//! `GET /api/measures/words`: the one table of measure words (`metrics::words`) as JSON, so
//! that the console never re-types a measure's plain name, unit, decimals, axis range or
//! noise, nor an end reason's wording.

use axum::Json;
use axum::extract::State;
use metrics::words::{EndKind, MEASURES, MeasureWords};
use serde::Serialize;

use super::AppState;
use super::auth::Authed;
pub(crate) use hub_care::sheet_words::{end_words_id, measure_definition_id, measure_name_id};

/// One way a session ends: its key, its one wording (English) and the id of that wording in
/// the console's catalogues (`words-end-…`).
#[derive(Serialize)]
pub(crate) struct EndWording {
    kind: EndKind,
    words: &'static str,
    words_id: String,
}

/// One measure's words with the ids of its plain name and of its definition in the console's
/// catalogues (`words-measure-…`, `words-definition-…`); the key, unit, decimals, ranges and
/// source stay `metrics::words`'s alone.
#[derive(Serialize)]
pub(crate) struct MeasureEntry {
    #[serde(flatten)]
    words: &'static MeasureWords,
    name_id: String,
    definition_id: String,
}

/// The table served.
#[derive(Serialize)]
pub(crate) struct Words {
    /// Every measure with words, in reading order.
    measures: Vec<MeasureEntry>,
    /// Every way a session ends with its wording.
    end_reasons: Vec<EndWording>,
}

/// The table (no patient data: not audited; a login is required, as for every endpoint).
pub(crate) async fn measure_words(Authed(_): Authed) -> Json<Words> {
    Json(Words {
        measures: MEASURES
            .iter()
            .map(|words| MeasureEntry {
                words,
                name_id: measure_name_id(words.key),
                definition_id: measure_definition_id(words.key),
            })
            .collect(),
        end_reasons: EndKind::ALL
            .iter()
            .map(|&kind| EndWording {
                kind,
                words: kind.words(),
                words_id: end_words_id(kind),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every measure's plain name and every end reason has its message in every console
    /// language (the console words them by these ids).
    #[test]
    fn every_measure_and_end_reason_has_words_in_every_console_language() {
        for tag in i18n::LANGUAGES {
            let text = i18n::console_catalogue(tag).unwrap();
            let has = |id: &str| text.lines().any(|l| l.starts_with(&format!("{id} =")));
            for m in &MEASURES {
                let id = measure_name_id(m.key);
                assert!(has(&id), "{tag}: no {id}");
            }
            for k in EndKind::ALL {
                let id = end_words_id(k);
                assert!(has(&id), "{tag}: no {id}");
            }
        }
        assert_eq!(
            end_words_id(EndKind::WheelUnplugged),
            "words-end-wheel-unplugged"
        );
    }

    /// Issue 42: every measure of the words table has its definition in every console
    /// language, so a measure added without one (by any branch) fails here.
    #[test]
    fn every_measure_has_its_definition_in_every_console_language() {
        for tag in i18n::LANGUAGES {
            let text = i18n::console_catalogue(tag).unwrap();
            for m in &MEASURES {
                let id = measure_definition_id(m.key);
                let line = text.lines().find(|l| l.starts_with(&format!("{id} =")));
                let worded = line.is_some_and(|l| l.len() > id.len() + 12);
                assert!(worded, "{tag}: no definition {id} for {}", m.key);
            }
        }
        assert_eq!(
            measure_definition_id("pct_in_lane"),
            "words-definition-pct-in-lane"
        );
    }
}
