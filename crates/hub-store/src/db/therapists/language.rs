//! The console's language a therapist chose (migration 0022): `None` until they choose.

use super::super::{Db, col};
use crate::error::HubError;

impl Db {
    /// The console language therapist `id` chose, if any.
    pub async fn therapist_language(&self, id: &str) -> Result<Option<String>, HubError> {
        let row = sqlx::query("SELECT language FROM therapists WHERE id = $1")
            .bind(id)
            .fetch_optional(self.pool())
            .await
            .map_err(HubError::db("reading a therapist's language"))?;
        match row {
            Some(r) => col(&r, "language"),
            None => Ok(None),
        }
    }

    /// Keeps `language` (a tag the caller checked; `None` to follow the browser again) as
    /// therapist `id`'s console language.
    pub async fn set_therapist_language(
        &self,
        id: &str,
        language: Option<&str>,
    ) -> Result<(), HubError> {
        sqlx::query("UPDATE therapists SET language = $1 WHERE id = $2")
            .bind(language)
            .bind(id)
            .execute(self.pool())
            .await
            .map_err(HubError::db("keeping a therapist's language"))?;
        Ok(())
    }
}
