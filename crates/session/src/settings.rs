//! The patient's settings: `settings.toml` in the station's home (the platform's configuration
//! directory, `~/.config/telerehab` on Linux; never the working directory). Optional; a
//! clinic's installation may write it to fill in its address for the pairing page.
//!
//! ```toml
//! clinic_address = "clinic.example.org:7878"   # shown on the pairing page
//! fullscreen = true                             # the patient's window fills the screen
//! language = "de"                               # chosen on the first-run page
//! ```

use anyhow::Context;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The patient's settings.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// The clinic hub's address for stations, filled in on the pairing page.
    pub clinic_address: Option<String>,
    /// The patient's window fills the screen (F11 toggles it).
    pub fullscreen: bool,
    /// The language the patient chose on the first-run page (a tag of
    /// [`i18n::LANGUAGES`]); `None` until chosen (the first-run page then asks). The
    /// prescription's wins over it ([`crate::language::choose`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub language: Option<String>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            clinic_address: None,
            fullscreen: true,
            language: None,
        }
    }
}

/// The settings file's name in the station's home.
pub const FILE: &str = "settings.toml";

impl Settings {
    /// The settings in `home_dir`, or the defaults when there is no file; a file that cannot
    /// be read is an error naming it and the problem.
    pub fn load(home_dir: &Path) -> anyhow::Result<Self> {
        let path = home_dir.join(FILE);
        match std::fs::read_to_string(&path) {
            Ok(text) => toml::from_str(&text)
                .with_context(|| format!("the settings file {} is not valid", path.display())),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Self::default()),
            Err(e) => Err(e).with_context(|| format!("cannot read {}", path.display())),
        }
    }
}

impl Settings {
    /// Writes the settings to `home_dir` (replacing the file at once: a crash leaves the old
    /// one or the new one, never half of one).
    pub fn save(&self, home_dir: &Path) -> anyhow::Result<()> {
        let path = home_dir.join(FILE);
        let text = toml::to_string(self).context("cannot write the settings")?;
        std::fs::create_dir_all(home_dir)
            .with_context(|| format!("cannot create {}", home_dir.display()))?;
        let tmp = home_dir.join(format!("{FILE}.new"));
        std::fs::write(&tmp, text).with_context(|| format!("cannot write {}", tmp.display()))?;
        std::fs::rename(&tmp, &path).with_context(|| format!("cannot replace {}", path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_file_gives_full_screen_and_no_address() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(Settings::load(dir.path()).unwrap(), Settings::default());
        assert!(Settings::default().fullscreen);
    }

    #[test]
    fn a_clinic_address_is_read_and_a_typo_is_named() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join(FILE),
            "clinic_address = \"hub.example:7878\"\n",
        )
        .unwrap();
        let s = Settings::load(dir.path()).unwrap();
        assert_eq!(s.clinic_address.as_deref(), Some("hub.example:7878"));
        std::fs::write(dir.path().join(FILE), "fulscreen = false\n").unwrap();
        let err = format!("{:#}", Settings::load(dir.path()).unwrap_err());
        assert!(
            err.contains("settings.toml") && err.contains("fulscreen"),
            "{err}"
        );
    }

    #[test]
    fn the_language_chosen_is_saved_with_the_other_settings_and_read_back() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join(FILE),
            "clinic_address = \"hub.example:7878\"\n",
        )
        .unwrap();
        let mut s = Settings::load(dir.path()).unwrap();
        assert_eq!(s.language, None);
        s.language = Some("de".into());
        s.save(dir.path()).unwrap();
        let back = Settings::load(dir.path()).unwrap();
        assert_eq!(back.language.as_deref(), Some("de"));
        assert_eq!(back.clinic_address.as_deref(), Some("hub.example:7878"));
    }
}
