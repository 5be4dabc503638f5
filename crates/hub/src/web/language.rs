//! The therapist's console language (issue 40): `GET /api/me/language` and
//! `PUT /api/me/language`. Kept per therapist on the hub, so it follows them to any browser;
//! until they choose, the console takes the best match of the browser's languages.

use axum::Json;
use axum::extract::State;
use axum::extract::rejection::JsonRejection;
use serde::{Deserialize, Serialize};

use super::Says as _;
use super::auth::Authed;
use super::{ApiError, AppState};
use hub_store::refusal::{Code, Why};

/// Answer of `GET`/`PUT /api/me/language`.
#[derive(Serialize)]
pub(crate) struct Language {
    /// The language the therapist chose, `null` when they never chose (the console then
    /// follows the browser).
    language: Option<String>,
    /// The console's languages, English first (the pseudo-locale `en-XA` is accepted too).
    languages: &'static [&'static str],
}

/// Body of `PUT /api/me/language`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LanguageChoice {
    /// One of the languages, the pseudo-locale, or `null` to follow the browser again.
    language: Option<String>,
}

/// `GET /api/me/language`: the logged-in therapist's console language.
pub(crate) async fn get_language(
    State(state): State<AppState>,
    Authed(therapist): Authed,
) -> Result<Json<Language>, ApiError> {
    let language = state.db.therapist_language(&therapist.id).await?;
    Ok(Json(Language {
        language,
        languages: i18n::LANGUAGES,
    }))
}

/// `PUT /api/me/language`: keeps the therapist's choice (400 naming the languages for one the
/// console does not have, nothing changed); audited `change_language` with old → new.
pub(crate) async fn put_language(
    State(state): State<AppState>,
    Authed(therapist): Authed,
    body: Result<Json<LanguageChoice>, JsonRejection>,
) -> Result<Json<Language>, ApiError> {
    let Json(choice) = body?;
    if let Some(tag) = &choice.language
        && !i18n::console_tags().any(|t| t == tag.as_str())
    {
        return Err(ApiError::BadRequest(Why::new(Code::UnknownLanguage).says(
            format!(
                "{} (or {} to test layouts; null follows the browser); nothing was changed",
                i18n::UnknownLanguage(tag.clone()),
                i18n::PSEUDO
            ),
        )));
    }
    let before = state.db.therapist_language(&therapist.id).await?;
    state
        .db
        .set_therapist_language(&therapist.id, choice.language.as_deref())
        .await?;
    let words = |l: &Option<String>| l.clone().unwrap_or_else(|| "the browser's".to_owned());
    state
        .audit(
            &therapist.actor(),
            "change_language",
            &therapist.id,
            &format!("{} → {}", words(&before), words(&choice.language)),
        )
        .await?;
    Ok(Json(Language {
        language: choice.language,
        languages: i18n::LANGUAGES,
    }))
}
