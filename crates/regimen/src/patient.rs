//! How the station meets this patient: the `[patient]` table the therapist prescribes with
//! the exercises — the language of the screens and the voice, the side of space the patient
//! neglects, the spoken words, what happens after a rest.
//!
//! ```toml
//! [patient]
//! language = "de"          # one of the station's languages (i18n::LANGUAGES)
//! neglected_side = "left"  # none | left | right
//! speech = true            # read each page's main sentence aloud
//! speech_volume_pct = 80   # 0–100
//! start_after_rest_s = 10  # absent: the next exercise waits for the patient
//! ```

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Longest countdown after a rest before the next exercise starts by itself, s.
pub const MAX_START_AFTER_REST_S: f64 = 60.0;

/// The side of space a patient neglects after a stroke.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum NeglectedSide {
    /// No neglect: the screens are laid out as usual.
    #[default]
    None,
    /// The patient neglects the left side of space.
    Left,
    /// The patient neglects the right side of space.
    Right,
}

/// The `[patient]` table: settings that travel with the prescription.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PatientSettings {
    /// The language of the patient's screens and voice (`en`, `de`, `es`, `zh`); absent: the
    /// one chosen on the station, else the computer's own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub language: Option<String>,
    /// The side of space the patient neglects: the station keeps what matters away from it
    /// and draws attention into it.
    #[serde(default)]
    pub neglected_side: NeglectedSide,
    /// Read each page's main sentence aloud (default on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speech: Option<bool>,
    /// The voice's volume, % (0–100; default 80).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0, max = 100))]
    pub speech_volume_pct: Option<u8>,
    /// After a rest, start the next exercise after this countdown, s (0–60); absent: wait
    /// for the patient to press a wheel button.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0, max = MAX_START_AFTER_REST_S))]
    pub start_after_rest_s: Option<f64>,
}

impl PatientSettings {
    /// Speech on unless the therapist turned it off.
    pub fn speech_on(&self) -> bool {
        self.speech.unwrap_or(true)
    }

    /// The voice's volume, 0–1.
    pub fn speech_volume(&self) -> f64 {
        f64::from(self.speech_volume_pct.unwrap_or(80).min(100)) / 100.0
    }

    /// Checks the settings; the message names the field and what is allowed.
    pub fn validate(&self) -> Result<(), String> {
        if let Some(lang) = &self.language
            && i18n::Catalogue::load(lang).is_err()
        {
            return Err(format!(
                "patient.language = \"{lang}\": allowed {}",
                i18n::LANGUAGES.join(", ")
            ));
        }
        if let Some(v) = self.speech_volume_pct
            && v > 100
        {
            return Err(format!("patient.speech_volume_pct = {v}, allowed 0 to 100"));
        }
        if let Some(s) = self.start_after_rest_s
            && !(0.0..=MAX_START_AFTER_REST_S).contains(&s)
        {
            return Err(format!(
                "patient.start_after_rest_s = {s}, allowed 0 to {MAX_START_AFTER_REST_S}"
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patient_settings_refuse_an_unknown_language_and_out_of_range_numbers() {
        let ok = PatientSettings {
            language: Some("de".into()),
            neglected_side: NeglectedSide::Left,
            ..Default::default()
        };
        assert!(ok.validate().is_ok());
        let klingon = PatientSettings {
            language: Some("tlh".into()),
            ..Default::default()
        };
        assert!(klingon.validate().unwrap_err().contains("patient.language"));
        let long = PatientSettings {
            start_after_rest_s: Some(f64::NAN),
            ..Default::default()
        };
        assert!(long.validate().is_err());
        assert!(ok.speech_on());
        assert!((ok.speech_volume() - 0.8).abs() < 1e-12);
    }
}
