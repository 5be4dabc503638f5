//! Which language: negotiation against [`crate::LANGUAGES`] and the system's own setting.

use unic_langid::LanguageIdentifier;

/// The first of `requested` (language tags, most wanted first: `de-AT`, `zh_CN.UTF-8`, …)
/// the catalogues have, by language; [`crate::PSEUDO`] when asked for; else English.
pub fn negotiate<'a>(requested: impl IntoIterator<Item = &'a str>) -> &'static str {
    for tag in requested {
        let tag = clean(tag);
        if tag.eq_ignore_ascii_case(crate::PSEUDO) {
            return crate::PSEUDO;
        }
        let Ok(id) = tag.parse::<LanguageIdentifier>() else {
            continue;
        };
        if let Some(lang) = crate::LANGUAGES
            .iter()
            .find(|l| id.language.as_str() == **l)
        {
            return lang;
        }
    }
    crate::FALLBACK
}

/// `de_DE.UTF-8@euro` → `de-DE`.
fn clean(tag: &str) -> String {
    let tag = tag.split(['.', '@']).next().unwrap_or("");
    tag.replace('_', "-")
}

/// The system's language for messages, as desktop programs read it: the first set of
/// `LC_ALL`, `LC_MESSAGES`, `LANG` (POSIX order); `C` and `POSIX` mean none.
pub fn system_language() -> Option<String> {
    system_language_from(|name| std::env::var(name).ok())
}

/// [`system_language`] over a given environment (for tests).
pub fn system_language_from(env: impl Fn(&str) -> Option<String>) -> Option<String> {
    ["LC_ALL", "LC_MESSAGES", "LANG"]
        .into_iter()
        .filter_map(env)
        .find(|v| !v.is_empty())
        .filter(|v| !matches!(v.as_str(), "C" | "POSIX") && !v.starts_with("C."))
        .map(|v| clean(&v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negotiation_takes_the_first_language_the_catalogues_have() {
        assert_eq!(negotiate(["fr-FR", "de-AT", "es"]), "de");
        assert_eq!(negotiate(["zh_CN.UTF-8"]), "zh");
        assert_eq!(negotiate(["fr", "xx-not a tag"]), "en");
        assert_eq!(negotiate(["en-XA"]), crate::PSEUDO);
    }

    #[test]
    fn system_language_follows_posix_precedence_and_ignores_the_c_locale() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |k: &str| {
                vars.iter()
                    .find(|(n, _)| *n == k)
                    .map(|(_, v)| v.to_string())
            }
        };
        assert_eq!(
            system_language_from(env(&[("LANG", "es_ES.UTF-8"), ("LC_MESSAGES", "de_DE")])),
            Some("de-DE".into())
        );
        assert_eq!(
            system_language_from(env(&[("LC_ALL", "C.UTF-8"), ("LANG", "de_DE")])),
            None
        );
        assert_eq!(system_language_from(env(&[])), None);
    }
}
