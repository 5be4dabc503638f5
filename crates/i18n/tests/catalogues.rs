//! Every language has every English message, with the same arguments, and every file parses.

use i18n::{Catalogue, FALLBACK, LANGUAGES, PSEUDO};
use std::collections::BTreeMap;

fn by_id(language: &str) -> BTreeMap<String, Vec<String>> {
    let mut out = BTreeMap::new();
    for m in Catalogue::messages_of(language) {
        let previous = out.insert(m.id.clone(), m.variables);
        assert!(previous.is_none(), "{language}: {} is defined twice", m.id);
    }
    out
}

#[test]
fn every_catalogue_file_parses() {
    for language in LANGUAGES {
        let errors = i18n::parse_errors(language);
        assert!(errors.is_empty(), "{errors:#?}");
    }
}

#[test]
fn every_language_has_every_english_message_with_its_arguments() {
    let english = by_id(FALLBACK);
    assert!(!english.is_empty());
    for language in LANGUAGES.iter().filter(|l| **l != FALLBACK) {
        let theirs = by_id(language);
        for (id, variables) in &english {
            let Some(their_variables) = theirs.get(id) else {
                panic!("{language} lacks {id}");
            };
            // A translation may leave out a number its grammar does not need (Chinese has
            // no plural), never use one English does not pass.
            for v in their_variables {
                assert!(
                    variables.contains(v),
                    "{language} {id} uses ${v}, which the station does not pass"
                );
            }
        }
        for id in theirs.keys() {
            assert!(
                english.contains_key(id),
                "{language} has {id}, English does not"
            );
        }
    }
}

#[test]
fn plurals_and_arguments_follow_the_language() {
    let de = Catalogue::load("de").unwrap();
    let mut args = i18n::FluentArgs::new();
    args.set("minutes", 1);
    assert_eq!(de.message("common-minutes", Some(&args)), "1 Minute");
    args.set("minutes", 5);
    assert_eq!(de.message("common-minutes", Some(&args)), "5 Minuten");
}

#[test]
fn a_missing_message_falls_back_to_english_then_shows_its_id() {
    let zh = Catalogue::load("zh-CN").unwrap();
    assert_eq!(zh.message("common-yes", None), "是");
    assert_eq!(zh.message("no-such-message", None), "[no-such-message]");
    assert!(Catalogue::load("xx").is_err());
}

#[test]
fn the_pseudo_locale_is_accented_english() {
    let pseudo = Catalogue::load(PSEUDO).unwrap();
    let yes = pseudo.message("common-yes", None);
    assert_ne!(yes, "Yes");
    assert!(yes.starts_with('Ý'), "{yes}");
}

#[test]
fn the_macro_formats_in_the_language_in_force() {
    i18n::use_language("es").unwrap();
    assert_eq!(i18n::tr!("common-minutes", minutes = 2), "2 minutos");
    assert_eq!(i18n::tr!("common-yes"), "Sí");
    assert!(i18n::use_language("klingon").is_err());
    assert_eq!(i18n::current().tag(), "es");
}

/// The console's catalogues (`console/<language>/<area>.ftl`): every file parses, every id
/// starts with its file's area, every language has every English message and uses no argument
/// the console does not pass.
#[test]
fn every_console_language_has_every_english_message_with_its_arguments() {
    let of = |language: &str| {
        let (messages, errors) = i18n::console_messages_of(language);
        assert!(errors.is_empty(), "{errors:#?}");
        let mut out = BTreeMap::new();
        for m in messages {
            let area = m.file.rsplit('/').next().unwrap().trim_end_matches(".ftl");
            assert!(
                m.id.starts_with(&format!("{area}-")),
                "{}: {} does not start with its area {area}-",
                m.file,
                m.id
            );
            let previous = out.insert(m.id.clone(), m.variables);
            assert!(previous.is_none(), "{language}: {} is defined twice", m.id);
        }
        out
    };
    let english = of(FALLBACK);
    assert!(english.len() > 100, "{}", english.len());
    for language in LANGUAGES.iter().filter(|l| **l != FALLBACK) {
        let theirs = of(language);
        for (id, variables) in &english {
            let their_variables = theirs
                .get(id)
                .unwrap_or_else(|| panic!("console {language} lacks {id}"));
            for v in their_variables {
                assert!(
                    variables.contains(v),
                    "console {language} {id} uses ${v}, which the console does not pass"
                );
            }
        }
        for id in theirs.keys() {
            assert!(
                english.contains_key(id),
                "console {language} has {id}, English does not"
            );
        }
    }
}

#[test]
fn the_consoles_pseudo_locale_is_the_english_catalogue_accented() {
    let en = i18n::console_catalogue("en").unwrap();
    let pseudo = i18n::console_catalogue(PSEUDO).unwrap();
    assert!(en.contains("app-login-title = Log in"));
    assert!(
        pseudo.contains("app-login-title = Ľöĝ îñ~~"),
        "{}",
        &pseudo[..300]
    );
    assert!(i18n::console_catalogue("xx").is_err());
}
