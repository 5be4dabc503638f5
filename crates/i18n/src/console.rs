//! The therapist console's words: `console/<language>/<area>.ftl`, a root apart from the
//! station's `locales/` (clinicians' words are plain and clinical, not the patient's grade 6,
//! and the station's bundle never loads them). The hub serves one language's files as one
//! Fluent text ([`console_catalogue`]); the browser formats them with Fluent's JS package.

use std::borrow::Cow;

use fluent_syntax::ast;
use rust_embed::RustEmbed;

use crate::{MessageInfo, UnknownLanguage};

/// Every console catalogue file, embedded: `<language>/<area>.ftl`.
#[derive(RustEmbed)]
#[folder = "console/"]
struct ConsoleFiles;

/// The tags the console's catalogues are served for: the languages and the pseudo-locale.
pub fn console_tags() -> impl Iterator<Item = &'static str> {
    crate::LANGUAGES.iter().copied().chain([crate::PSEUDO])
}

/// The console's file names of `language` (`de/caseload.ftl`), sorted.
pub fn console_files(language: &str) -> Vec<String> {
    let prefix = format!("{language}/");
    let mut names: Vec<String> = ConsoleFiles::iter()
        .filter(|p| p.starts_with(&prefix) && p.ends_with(".ftl"))
        .map(Cow::into_owned)
        .collect();
    names.sort();
    names
}

/// The text of one console file (`en/app.ftl`), if embedded.
pub fn console_file(name: &str) -> Option<String> {
    ConsoleFiles::get(name).map(|f| String::from_utf8_lossy(&f.data).into_owned())
}

/// Every message and attribute of the console's files of `language`, in file order (for the
/// tests: every language has every English message with its arguments), and the files that
/// do not parse with Fluent's errors.
pub fn console_messages_of(language: &str) -> (Vec<MessageInfo>, Vec<String>) {
    let mut out = Vec::new();
    let mut errors = Vec::new();
    for name in console_files(language) {
        let text = console_file(&name).unwrap_or_default();
        let resource = match fluent_syntax::parser::parse(text.as_str()) {
            Ok(r) => r,
            Err((r, e)) => {
                errors.push(format!("{name}: {e:?}"));
                r
            }
        };
        for entry in &resource.body {
            let ast::Entry::Message(m) = entry else {
                continue;
            };
            let id = m.id.name;
            if let Some(value) = &m.value {
                out.push(crate::message::info(id.to_string(), &name, value));
            }
            for a in &m.attributes {
                out.push(crate::message::info(
                    format!("{id}.{}", a.id.name),
                    &name,
                    &a.value,
                ));
            }
        }
    }
    (out, errors)
}

/// The console's whole catalogue of `tag` (exactly one of [`crate::LANGUAGES`] or
/// [`crate::PSEUDO`]): every file of its folder, in name order, one after the other. The
/// pseudo-locale is the English files with the pseudo transform (accents, 40 % longer) applied
/// to the text of message values and attributes (never to ids, variables, selectors or variant
/// keys).
pub fn console_catalogue(tag: &str) -> Result<String, UnknownLanguage> {
    let pseudo = tag == crate::PSEUDO;
    let language = if pseudo {
        crate::FALLBACK
    } else {
        crate::LANGUAGES
            .iter()
            .copied()
            .find(|l| *l == tag)
            .ok_or_else(|| UnknownLanguage(tag.to_string()))?
    };
    let mut out = String::new();
    for name in console_files(language) {
        let text = console_file(&name).unwrap_or_default();
        out.push_str(&format!("## {name}\n"));
        if pseudo {
            out.push_str(&pseudo_ftl(text));
        } else {
            out.push_str(&text);
        }
        if !out.ends_with('\n') {
            out.push('\n');
        }
    }
    Ok(out)
}

/// `text` (Fluent) with every message's and term's text accented and lengthened.
fn pseudo_ftl(text: String) -> String {
    let mut resource = match fluent_syntax::parser::parse(text) {
        Ok(r) => r,
        Err((r, _)) => r,
    };
    for entry in &mut resource.body {
        let (value, attributes) = match entry {
            ast::Entry::Message(m) => (m.value.as_mut(), &mut m.attributes),
            ast::Entry::Term(t) => (Some(&mut t.value), &mut t.attributes),
            _ => continue,
        };
        if let Some(p) = value {
            pseudo_pattern(p);
        }
        for a in attributes {
            pseudo_pattern(&mut a.value);
        }
    }
    fluent_syntax::serializer::serialize(&resource)
}

fn pseudo_pattern(pattern: &mut ast::Pattern<String>) {
    for element in &mut pattern.elements {
        match element {
            ast::PatternElement::TextElement { value } => {
                *value = crate::pseudo::transform(value).into_owned();
            }
            ast::PatternElement::Placeable { expression } => pseudo_expression(expression),
        }
    }
}

fn pseudo_expression(expression: &mut ast::Expression<String>) {
    match expression {
        ast::Expression::Select { variants, .. } => {
            for v in variants {
                pseudo_pattern(&mut v.value);
            }
        }
        ast::Expression::Inline(ast::InlineExpression::Placeable { expression }) => {
            pseudo_expression(expression);
        }
        ast::Expression::Inline(_) => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pseudo_catalogue_changes_text_but_not_ids_variables_or_variant_keys() {
        let out = pseudo_ftl(
            "caseload-more = { $count ->\n    [one] one more\n   *[other] { $count } more\n }\napp-x = Log in\n    .title = Log in now\n"
                .to_string(),
        );
        assert!(out.contains("caseload-more ="), "{out}");
        assert!(out.contains("[one] öñé ɱöřé~~~"), "{out}");
        assert!(out.contains("{ $count }"), "{out}");
        assert!(out.contains("app-x = Ľöĝ îñ~~"), "{out}");
        assert!(out.contains(".title = Ľöĝ îñ ñöŵ~~~~"), "{out}");
        assert!(fluent_syntax::parser::parse(out).is_ok());
    }

    #[test]
    fn an_unknown_tag_is_refused_with_the_languages_named() {
        let e = console_catalogue("fr").unwrap_err();
        assert!(e.to_string().contains("en, de, es, zh"));
        assert!(console_catalogue("de-AT").is_err());
    }
}
