//! The clinic's pairing card: a small file the clinic prepares before lending the station
//! (on a USB stick, or put in the patient's home folder), so the patient never types an
//! address. The first-run page looks for it and pairs with one press of a wheel button.
//!
//! ```toml
//! # telerehab-pairing.toml
//! clinic_address = "clinic.example.org:7878"
//! code = "7KQ2-M9XD"        # optional: without it the code is chosen with the wheel
//! ```

use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The card's file name.
pub const FILE: &str = "telerehab-pairing.toml";

/// What the clinic's card says.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairingCard {
    /// The clinic hub's address for stations, `host` or `host:port`.
    pub clinic_address: String,
    /// The one-time pairing code, if the clinic wrote it on the card.
    #[serde(default)]
    pub code: Option<String>,
}

/// What looking for the card found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Found {
    /// No card anywhere.
    Nothing,
    /// A card, read.
    Card(PathBuf, PairingCard),
    /// A card that cannot be read: where, and why (for the log; the page says it plainly).
    Unreadable(PathBuf, String),
}

/// Where the card is looked for, in order: the station's home, the user's home folder, and
/// every removable medium mounted under `/media/<user>/`, `/run/media/<user>/` or `/media/`.
pub fn places(station_home: &Path) -> Vec<PathBuf> {
    let mut out = vec![station_home.to_path_buf()];
    if let Some(home) = std::env::var_os("HOME").filter(|h| !h.is_empty()) {
        out.push(PathBuf::from(home));
    }
    let user = std::env::var("USER").unwrap_or_default();
    let mut media = Vec::new();
    if !user.is_empty() {
        media.push(PathBuf::from("/media").join(&user));
        media.push(PathBuf::from("/run/media").join(&user));
    }
    media.push(PathBuf::from("/media"));
    for dir in media {
        if let Ok(entries) = std::fs::read_dir(&dir) {
            let mut mounted: Vec<PathBuf> = entries
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| p.is_dir())
                .collect();
            mounted.sort();
            out.extend(mounted);
        }
    }
    out
}

/// The first card in `places`.
pub fn find(places: &[PathBuf]) -> Found {
    for dir in places {
        let path = dir.join(FILE);
        match std::fs::read_to_string(&path) {
            Ok(text) => {
                return match toml::from_str::<PairingCard>(&text) {
                    Ok(card) if !card.clinic_address.trim().is_empty() => Found::Card(path, card),
                    Ok(_) => Found::Unreadable(path, "it names no clinic address".into()),
                    Err(e) => Found::Unreadable(path, e.to_string()),
                };
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Found::Unreadable(path, e.to_string()),
        }
    }
    Found::Nothing
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_card_found_is_read_and_a_broken_one_is_named() {
        let a = tempfile::tempdir().unwrap();
        let b = tempfile::tempdir().unwrap();
        let places = vec![a.path().to_path_buf(), b.path().to_path_buf()];
        assert_eq!(find(&places), Found::Nothing);
        std::fs::write(
            b.path().join(FILE),
            "clinic_address = \"hub.example:7878\"\ncode = \"7KQ2-M9XD\"\n",
        )
        .unwrap();
        let Found::Card(path, card) = find(&places) else {
            panic!("no card")
        };
        assert_eq!(path, b.path().join(FILE));
        assert_eq!(card.code.as_deref(), Some("7KQ2-M9XD"));
        std::fs::write(a.path().join(FILE), "clinic = 1\n").unwrap();
        assert!(matches!(find(&places), Found::Unreadable(p, _) if p == a.path().join(FILE)));
    }
}
