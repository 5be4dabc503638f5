//! Which language the patient's screens speak, chosen once at start: a language forced for
//! tests and screenshots (`--language`, `TELEREHAB_LANGUAGE`), else the prescription's
//! (`[patient] language`), else the one chosen on the first-run page (the station's
//! settings), else the computer's own (`LC_ALL`, `LC_MESSAGES`, `LANG`), else English.
//! The words themselves live in the [`i18n`] catalogues.

use regimen::Regimen;
use std::sync::OnceLock;

/// The environment variable that forces a language (as `--language` does).
pub const ENV: &str = "TELEREHAB_LANGUAGE";

/// A language forced on the command line, kept for the whole process.
static FORCED: OnceLock<Option<String>> = OnceLock::new();

/// Forces `tag` (`de`, `zh-CN`, the pseudo-locale `en-XA`) for the whole process, over the
/// prescription and the first-run choice, and puts it in force now. An unknown tag is an
/// error naming the languages there are.
pub fn force(tag: &str) -> Result<(), i18n::UnknownLanguage> {
    i18n::use_language(tag)?;
    let _ = FORCED.set(Some(tag.to_owned()));
    Ok(())
}

/// The language forced with [`force`], if any.
pub fn forced() -> Option<&'static str> {
    FORCED.get().and_then(|t| t.as_deref())
}

/// Chooses the language of the patient's screens and puts it in force: the forced one
/// ([`force`]), else `regimen`'s `[patient] language`, else `chosen` (the first-run page's
/// choice), else the system's, else English. Returns the tag in force.
pub fn choose(regimen: Option<&Regimen>, chosen: Option<&str>) -> &'static str {
    let prescribed = prescribed(regimen);
    let system = i18n::system_language();
    let tag = pick(forced(), prescribed, chosen, system.as_deref());
    if let Err(e) = i18n::use_language(tag) {
        tracing::warn!(%e, "cannot use the chosen language; English instead");
        let _ = i18n::use_language(i18n::FALLBACK);
        return i18n::FALLBACK;
    }
    tracing::debug!(language = tag, "the patient's language");
    tag
}

/// The prescription's language (`[patient] language`), if it sets one.
fn prescribed(regimen: Option<&Regimen>) -> Option<&str> {
    regimen
        .and_then(|r| r.patient.as_ref())
        .and_then(|p| p.language.as_deref())
}

/// The first of the candidates, in order of precedence, that the catalogues have (a
/// prescription in a language without words falls through to the next).
fn pick(
    forced: Option<&str>,
    prescribed: Option<&str>,
    chosen: Option<&str>,
    system: Option<&str>,
) -> &'static str {
    [forced, prescribed, chosen, system]
        .into_iter()
        .flatten()
        .find_map(|asked| {
            let lang = i18n::negotiate([asked]);
            (lang != i18n::FALLBACK || asked_for_english(asked)).then_some(lang)
        })
        .unwrap_or(i18n::FALLBACK)
}

/// `tag` names English itself (not a language negotiation fell back from).
fn asked_for_english(tag: &str) -> bool {
    let tag = tag.to_ascii_lowercase();
    tag == "en" || tag.starts_with("en-") || tag.starts_with("en_")
}

/// [`choose`] with the first-run choice kept in the station's settings in `home_dir`.
pub fn choose_at(home_dir: Option<&std::path::Path>, regimen: Option<&Regimen>) -> &'static str {
    let chosen = home_dir
        .and_then(|d| crate::settings::Settings::load(d).ok())
        .and_then(|s| s.language);
    choose(regimen, chosen.as_deref())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_prescription_wins_over_the_first_run_choice_and_the_system() {
        assert_eq!(pick(None, Some("de"), Some("es"), Some("zh-CN")), "de");
        assert_eq!(pick(None, None, Some("es"), Some("zh-CN")), "es");
        assert_eq!(pick(None, None, None, Some("zh-CN")), "zh");
        assert_eq!(pick(None, None, None, None), "en");
    }

    #[test]
    fn a_forced_language_wins_and_may_be_the_pseudo_locale() {
        assert_eq!(pick(Some("en-XA"), Some("de"), None, None), i18n::PSEUDO);
        assert_eq!(pick(Some("es"), Some("de"), Some("zh"), None), "es");
    }

    #[test]
    fn a_language_without_words_falls_through_but_english_asked_for_is_kept() {
        assert_eq!(pick(None, Some("fr"), Some("es"), None), "es");
        assert_eq!(pick(None, Some("en-GB"), Some("es"), None), "en");
        assert_eq!(pick(None, Some("fr"), None, None), "en");
    }

    #[test]
    fn the_prescribed_language_is_read_from_the_patient_table() {
        let r = Regimen::from_toml(
            "[patient]\nlanguage = \"es\"\n\n[[exercise]]\nkind = \"sine\"\n",
            "test",
        )
        .unwrap();
        assert_eq!(prescribed(Some(&r)), Some("es"));
        let plain = Regimen::from_toml("[[exercise]]\nkind = \"sine\"\n", "test").unwrap();
        assert_eq!(prescribed(Some(&plain)), None);
        assert_eq!(prescribed(None), None);
    }
}
