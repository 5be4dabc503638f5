//! Clinical scales (migration 0013): the standard assessments a therapist takes at the clinic
//! — Fugl-Meyer upper extremity motor, Action Research Arm Test, Box and Block Test — with the
//! date each was taken, charted beside the station's measures.

use serde::{Deserialize, Serialize};

use super::{Db, col, new_id};
use crate::error::HubError;
use crate::refusal::{Code, Why};

/// Most entries [`Db::scales_of`] returns (the newest; listed oldest first).
pub const MAX_SCALES_LISTED: i64 = 1_000;

/// The earliest assessment date accepted (`YYYY-MM-DD`): an older one is a typo.
pub const EARLIEST_ASSESSED_ON: &str = "1990-01-01";

/// One number of a scale: its field in the API, what it is in words, its unit and bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct ScaleField {
    /// The field's name in the API and the database.
    pub field: &'static str,
    /// What it is, in words.
    pub label: &'static str,
    /// Its unit in words (`points`, `blocks per minute`).
    pub unit: &'static str,
    /// The smallest score.
    pub min: i64,
    /// The largest score.
    pub max: i64,
}

/// A clinical scale the hub records.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct ScaleDef {
    /// Its key in the API (`fugl_meyer_ue`, `arat`, `box_and_block`).
    pub key: &'static str,
    /// Its name in words.
    pub name: &'static str,
    /// Its numbers (every one required).
    pub fields: &'static [ScaleField],
}

const fn field(
    field: &'static str,
    label: &'static str,
    unit: &'static str,
    max: i64,
) -> ScaleField {
    ScaleField {
        field,
        label,
        unit,
        min: 0,
        max,
    }
}

/// The scales recorded, with their bounds.
pub const SCALES: [ScaleDef; 3] = [
    ScaleDef {
        key: "fugl_meyer_ue",
        name: "Fugl-Meyer Assessment, upper extremity motor",
        fields: &[field(
            "score",
            "Fugl-Meyer upper extremity motor score",
            "points",
            66,
        )],
    },
    ScaleDef {
        key: "arat",
        name: "Action Research Arm Test",
        fields: &[field(
            "score",
            "Action Research Arm Test score",
            "points",
            57,
        )],
    },
    ScaleDef {
        key: "box_and_block",
        name: "Box and Block Test",
        fields: &[
            field(
                "affected_blocks_per_min",
                "Box and Block Test, affected side",
                "blocks per minute",
                150,
            ),
            field(
                "unaffected_blocks_per_min",
                "Box and Block Test, unaffected side",
                "blocks per minute",
                150,
            ),
        ],
    },
];

/// Every number field of any scale.
const ALL_FIELDS: [&str; 3] = [
    "score",
    "affected_blocks_per_min",
    "unaffected_blocks_per_min",
];

/// The scale `key`, if the hub records it.
pub fn scale_def(key: &str) -> Option<&'static ScaleDef> {
    SCALES.iter().find(|s| s.key == key)
}

/// An assessment as a therapist sends it (`POST /api/patients/{id}/scales`): numbers as JSON
/// numbers, checked by [`check_scale`].
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NewScale {
    /// Which scale: `fugl_meyer_ue`, `arat` or `box_and_block`.
    pub scale: String,
    /// The day it was taken, `YYYY-MM-DD`.
    pub assessed_on: String,
    /// Fugl-Meyer (0–66) or ARAT (0–57) score, points.
    #[serde(default)]
    pub score: Option<f64>,
    /// Box and Block Test, affected side, blocks in one minute (0–150).
    #[serde(default)]
    pub affected_blocks_per_min: Option<f64>,
    /// Box and Block Test, unaffected side, blocks in one minute (0–150).
    #[serde(default)]
    pub unaffected_blocks_per_min: Option<f64>,
}

impl NewScale {
    fn value(&self, field: &str) -> Option<f64> {
        match field {
            "score" => self.score,
            "affected_blocks_per_min" => self.affected_blocks_per_min,
            "unaffected_blocks_per_min" => self.unaffected_blocks_per_min,
            _ => None,
        }
    }
}

/// A recorded assessment.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ScaleEntry {
    /// Its identifier (`c-` and 16 hex digits).
    pub id: String,
    /// The patient assessed.
    pub patient_id: String,
    /// Which scale (a [`SCALES`] key).
    pub scale: String,
    /// The scale's name in words.
    pub scale_name: String,
    /// The day it was taken, `YYYY-MM-DD`.
    pub assessed_on: String,
    /// Fugl-Meyer or ARAT score, points (`null` for the Box and Block Test).
    pub score: Option<i64>,
    /// Box and Block Test, affected side, blocks per minute.
    pub affected_blocks_per_min: Option<i64>,
    /// Box and Block Test, unaffected side, blocks per minute.
    pub unaffected_blocks_per_min: Option<i64>,
    /// The therapist who recorded it.
    pub therapist_id: String,
    /// Their e-mail, when the account still exists.
    pub therapist_email: Option<String>,
    /// When it was recorded, ms since the Unix epoch.
    pub created_at_ms: i64,
}

impl ScaleEntry {
    /// The entry in a few words for the audit log: `fugl_meyer_ue of 2026-11-20: score 34`.
    pub fn words(&self) -> String {
        let numbers: Vec<String> = [
            ("score", self.score),
            ("affected_blocks_per_min", self.affected_blocks_per_min),
            ("unaffected_blocks_per_min", self.unaffected_blocks_per_min),
        ]
        .iter()
        .filter_map(|(name, v)| v.map(|v| format!("{name} {v}")))
        .collect();
        format!(
            "{} of {}: {}",
            self.scale,
            self.assessed_on,
            numbers.join(", ")
        )
    }
}

/// The checked numbers of an assessment: [score, affected, unaffected].
type Scores = [Option<i64>; 3];

/// Checks `new` against its scale's bounds and its date against `today` (`YYYY-MM-DD`, UTC):
/// the field at fault ([`HubError::Invalid`]) and why, in words naming its range, or the
/// numbers to store. A date may be one day after `today` (the clinic's day may be ahead of UTC).
pub fn check_scale(new: &NewScale, now_ms: i64) -> Result<Scores, HubError> {
    let Some(def) = scale_def(&new.scale) else {
        let keys: Vec<&str> = SCALES.iter().map(|s| s.key).collect();
        return Err(HubError::refused(
            "scale",
            format!(
                "{:?} is not a scale the hub records: one of {}",
                clipped(&new.scale),
                keys.join(", ")
            ),
            Why::field(Code::NotOneOf, "scale"),
        ));
    };
    check_assessed_on(&new.assessed_on, now_ms).map_err(|(e, code)| {
        HubError::refused("assessed_on", e, Why::field(code, "assessed_on"))
    })?;
    let mut scores: Scores = [None; 3];
    for (slot, name) in ALL_FIELDS.iter().enumerate() {
        let value = new.value(name);
        let Some(f) = def.fields.iter().find(|f| f.field == *name) else {
            if value.is_some() {
                return Err(HubError::refused(
                    ALL_FIELDS[slot],
                    format!("{name} is not a number of the {}", def.name),
                    Why::field(Code::FieldRefused, ALL_FIELDS[slot]),
                ));
            }
            continue;
        };
        let range = format!("a whole number from {} to {} {}", f.min, f.max, f.unit);
        let Some(v) = value else {
            return Err(HubError::refused(
                f.field,
                format!("{} is missing: {range}", f.label),
                Why::field(Code::Missing, f.field),
            ));
        };
        if !v.is_finite() || v.fract() != 0.0 || v < f.min as f64 || v > f.max as f64 {
            return Err(HubError::refused(
                f.field,
                format!("{} must be {range}; {v} is out of range", f.label),
                Why::field(Code::OutOfRange, f.field)
                    .with("min", f.min)
                    .with("max", f.max),
            ));
        }
        scores[slot] = Some(v as i64);
    }
    Ok(scores)
}

/// At most the first 40 characters of a value sent, for an error that quotes it (a body may
/// hold 64 KiB).
fn clipped(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((at, _)) => format!("{}…", &text[..at]),
        None => text.to_owned(),
    }
}

/// Checks an assessment date: `YYYY-MM-DD`, a real day, from [`EARLIEST_ASSESSED_ON`] to the
/// day after `now_ms`'s (UTC).
fn check_assessed_on(text: &str, now_ms: i64) -> Result<(), (String, Code)> {
    let days = parse_date(text).ok_or_else(|| {
        let words = format!(
            "{:?} is not a date: write the day the scale was taken as YYYY-MM-DD",
            clipped(text)
        );
        (words, Code::BadDate)
    })?;
    let earliest = parse_date(EARLIEST_ASSESSED_ON).unwrap_or(0);
    let today = now_ms.div_euclid(DAY_MS);
    if days < earliest {
        let words =
            format!("{text} is before {EARLIEST_ASSESSED_ON}: write the day the scale was taken");
        return Err((words, Code::BadDate));
    }
    if days > today + 1 {
        let words = format!(
            "{text} is in the future (today is {}): write the day the scale was taken",
            date_of_days(today)
        );
        return Err((words, Code::FutureDate));
    }
    Ok(())
}

/// One UTC day, ms.
pub const DAY_MS: i64 = 24 * 60 * 60 * 1000;
/// Days since 1970-01-01 of a `YYYY-MM-DD` date that exists (four-digit year, two-digit month
/// and day: the form the console sends; the calendar is jiff's).
pub(crate) fn parse_date(text: &str) -> Option<i64> {
    let b = text.as_bytes();
    let digits = |r: std::ops::Range<usize>| b[r].iter().all(u8::is_ascii_digit);
    if b.len() != 10
        || b[4] != b'-'
        || b[7] != b'-'
        || !digits(0..4)
        || !digits(5..7)
        || !digits(8..10)
    {
        return None;
    }
    let date: jiff::civil::Date = text.parse().ok()?;
    let days = date.since(EPOCH).ok()?.get_days();
    Some(i64::from(days))
}

/// 1970-01-01, the day the millisecond clock counts from.
const EPOCH: jiff::civil::Date = jiff::civil::date(1970, 1, 1);

/// `YYYY-MM-DD` of the day `days` after 1970-01-01 (clamped to the calendar's range).
fn date_of_days(days: i64) -> String {
    let days = days.clamp(-3_000_000, 3_000_000);
    EPOCH
        .checked_add(jiff::Span::new().days(days))
        .unwrap_or(EPOCH)
        .strftime("%Y-%m-%d")
        .to_string()
}

/// `ms` (since the Unix epoch) as ISO 8601 UTC to the second: `2026-11-18T14:10:00Z`.
pub fn iso_utc(ms: i64) -> String {
    let at = jiff::Timestamp::from_millisecond(ms).unwrap_or(if ms < 0 {
        jiff::Timestamp::MIN
    } else {
        jiff::Timestamp::MAX
    });
    at.strftime("%Y-%m-%dT%H:%M:%SZ").to_string()
}

/// `ms` (since the Unix epoch) as its UTC day, `2026-11-21`: the alerts' dates and the
/// spreadsheets' file names.
pub fn day_of(ms: i64) -> String {
    let mut day = iso_utc(ms);
    day.truncate(10);
    day
}

const SCALE_COLUMNS: &str = "c.id, c.patient_id, c.scale, c.assessed_on, c.score, \
    c.affected_blocks_per_min, c.unaffected_blocks_per_min, c.therapist_id, t.email, \
    c.created_at_ms";

fn entry_of(row: &sqlx::any::AnyRow) -> Result<ScaleEntry, HubError> {
    let scale: String = col(row, "scale")?;
    Ok(ScaleEntry {
        id: col(row, "id")?,
        patient_id: col(row, "patient_id")?,
        scale_name: scale_def(&scale).map_or_else(|| scale.clone(), |d| d.name.to_owned()),
        scale,
        assessed_on: col(row, "assessed_on")?,
        score: col(row, "score")?,
        affected_blocks_per_min: col(row, "affected_blocks_per_min")?,
        unaffected_blocks_per_min: col(row, "unaffected_blocks_per_min")?,
        therapist_id: col(row, "therapist_id")?,
        therapist_email: col(row, "email")?,
        created_at_ms: col(row, "created_at_ms")?,
    })
}

impl Db {
    /// Stores `therapist_id`'s assessment `new` of patient `patient_id`, checked with
    /// [`check_scale`] (an invalid one is [`HubError::Invalid`] naming the field and its
    /// range).
    pub async fn add_scale(
        &self,
        patient_id: &str,
        therapist_id: &str,
        new: &NewScale,
        now_ms: i64,
    ) -> Result<ScaleEntry, HubError> {
        let [score, affected, unaffected] = check_scale(new, now_ms)?;
        let id = new_id("c-")?;
        sqlx::query(
            "INSERT INTO clinical_scales (id, patient_id, scale, assessed_on, score, \
             affected_blocks_per_min, unaffected_blocks_per_min, therapist_id, created_at_ms) \
             VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9)",
        )
        .bind(&id)
        .bind(patient_id)
        .bind(&new.scale)
        .bind(&new.assessed_on)
        .bind(score)
        .bind(affected)
        .bind(unaffected)
        .bind(therapist_id)
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("storing a clinical scale"))?;
        self.scale(patient_id, &id)
            .await?
            .ok_or_else(|| HubError::not_found("clinical scale", id))
    }

    /// Patient `patient_id`'s assessment `id`, if any.
    pub async fn scale(&self, patient_id: &str, id: &str) -> Result<Option<ScaleEntry>, HubError> {
        let row = sqlx::query(sqlx::AssertSqlSafe(format!(
            "SELECT {SCALE_COLUMNS} FROM clinical_scales c \
             LEFT JOIN therapists t ON t.id = c.therapist_id \
             WHERE c.patient_id = $1 AND c.id = $2"
        )))
        .bind(patient_id)
        .bind(id)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a clinical scale"))?;
        row.as_ref().map(entry_of).transpose()
    }

    /// Patient `patient_id`'s newest [`MAX_SCALES_LISTED`] assessments, oldest first (by the
    /// day taken, then when recorded).
    pub async fn scales_of(&self, patient_id: &str) -> Result<Vec<ScaleEntry>, HubError> {
        let rows = sqlx::query(sqlx::AssertSqlSafe(format!(
            "SELECT {SCALE_COLUMNS} FROM clinical_scales c \
             LEFT JOIN therapists t ON t.id = c.therapist_id WHERE c.patient_id = $1 \
             ORDER BY c.assessed_on DESC, c.created_at_ms DESC, c.id DESC \
             LIMIT {MAX_SCALES_LISTED}"
        )))
        .bind(patient_id)
        .fetch_all(self.pool())
        .await
        .map_err(HubError::db("reading clinical scales"))?;
        rows.iter().rev().map(entry_of).collect()
    }

    /// Deletes patient `patient_id`'s assessment `id` (a mistaken entry); returns what was
    /// deleted, `None` when there was no such entry.
    pub async fn delete_scale(
        &self,
        patient_id: &str,
        id: &str,
    ) -> Result<Option<ScaleEntry>, HubError> {
        let Some(entry) = self.scale(patient_id, id).await? else {
            return Ok(None);
        };
        let done = sqlx::query("DELETE FROM clinical_scales WHERE patient_id = $1 AND id = $2")
            .bind(patient_id)
            .bind(id)
            .execute(self.pool())
            .await
            .map_err(HubError::db("deleting a clinical scale"))?;
        // Two deletes of one entry at once: only the one that removed it says so.
        Ok((done.rows_affected() > 0).then_some(entry))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_round_trip_and_impossible_days_are_refused() {
        for text in ["1970-01-01", "2000-02-29", "2026-11-18", "2024-12-31"] {
            let days = parse_date(text).unwrap();
            assert_eq!(date_of_days(days), text);
        }
        assert_eq!(parse_date("1970-01-02"), Some(1));
        for bad in [
            "2026-02-29",
            "2026-13-01",
            "2026-00-10",
            "2026-1-01",
            "26-11-18x",
            "+026-11-18",
        ] {
            assert_eq!(parse_date(bad), None, "{bad}");
        }
        assert_eq!(iso_utc(1_795_253_400_000), "2026-11-21T09:30:00Z");
        assert_eq!(iso_utc(-1), "1969-12-31T23:59:59Z");
        assert_eq!(date_of_days(-1), "1969-12-31");
    }

    #[test]
    fn leap_days_and_year_ends_follow_the_gregorian_calendar() {
        // Leap days: every fourth year, not a century unless it divides by 400.
        for (text, exists) in [
            ("2024-02-29", true),
            ("2000-02-29", true),
            ("2023-02-29", false),
            ("2100-02-29", false),
            ("2026-02-30", false),
        ] {
            assert_eq!(parse_date(text).is_some(), exists, "{text}");
        }
        let leap = parse_date("2024-02-29").unwrap();
        assert_eq!(date_of_days(leap + 1), "2024-03-01");
        assert_eq!(
            parse_date("2024-12-31").unwrap() - parse_date("2024-01-01").unwrap(),
            365
        );
        assert_eq!(
            parse_date("2026-12-31").unwrap() - parse_date("2026-01-01").unwrap(),
            364
        );
        // Year end: the last millisecond of 2026 and the first of 2027.
        let new_year_ms = parse_date("2027-01-01").unwrap() * DAY_MS;
        assert_eq!(iso_utc(new_year_ms - 1), "2026-12-31T23:59:59Z");
        assert_eq!(day_of(new_year_ms - 1), "2026-12-31");
        assert_eq!(day_of(new_year_ms), "2027-01-01");
        assert_eq!(
            date_of_days(parse_date("2026-12-31").unwrap() + 1),
            "2027-01-01"
        );
    }
}
