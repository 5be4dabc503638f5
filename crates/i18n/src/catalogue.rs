//! One language's messages: the embedded `.ftl` files of its folder in one Fluent bundle,
//! with English behind it for a message the language lacks.

use crate::UnknownLanguage;
use crate::message::{MessageInfo, info};
use fluent_bundle::concurrent::FluentBundle;
use fluent_bundle::{FluentArgs, FluentResource};
use fluent_syntax::ast;
use rust_embed::RustEmbed;
use unic_langid::LanguageIdentifier;

/// Every catalogue file, embedded: `<language>/<area>.ftl`.
#[derive(RustEmbed)]
#[folder = "locales/"]
struct Files;

/// One language's messages.
pub struct Catalogue {
    tag: String,
    bundle: FluentBundle<FluentResource>,
    /// English, for a message this language lacks (none for English itself).
    fallback: Option<Box<Catalogue>>,
}

/// Whose words a catalogue holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Words {
    /// The patient's (`locales/`).
    Patient,
    /// The therapist console's (`console/`).
    Console,
}

impl Catalogue {
    /// The patient's catalogue of `tag` (`de`, `de-AT`, [`crate::PSEUDO`]).
    pub fn load(tag: &str) -> Result<Self, UnknownLanguage> {
        Self::load_words(tag, Words::Patient)
    }

    /// The console's catalogue of `tag`, for what the hub writes for a clinician in their
    /// language (a spreadsheet's words).
    pub fn console(tag: &str) -> Result<Self, UnknownLanguage> {
        Self::load_words(tag, Words::Console)
    }

    /// The console's catalogue of `tag`, English for none or a language the console lacks
    /// (what the hub writes for a clinician: a spreadsheet, a mail).
    pub fn console_or_english(tag: Option<&str>) -> Self {
        tag.and_then(|t| Self::console(t).ok()).unwrap_or_else(|| {
            Self::load_words(crate::FALLBACK, Words::Console)
                .expect("English is one of the embedded languages")
        })
    }

    fn load_words(tag: &str, words: Words) -> Result<Self, UnknownLanguage> {
        let unknown = || UnknownLanguage(tag.to_string());
        let pseudo = tag.eq_ignore_ascii_case(crate::PSEUDO);
        let id: LanguageIdentifier = tag.parse().map_err(|_| unknown())?;
        let folder = if pseudo {
            crate::FALLBACK
        } else {
            crate::LANGUAGES
                .iter()
                .copied()
                .find(|l| id.language.as_str() == *l)
                .ok_or_else(unknown)?
        };
        let mut bundle = FluentBundle::new_concurrent(vec![id]);
        // No invisible isolation marks around arguments: the window's fonts would draw them.
        bundle.set_use_isolating(false);
        if pseudo {
            bundle.set_transform(Some(crate::pseudo::transform));
        }
        for (_, resource) in resources(folder, words) {
            // A message defined twice keeps its first definition; the tests forbid it.
            bundle.add_resource_overriding(resource);
        }
        let fallback = (folder != crate::FALLBACK || pseudo)
            .then(|| Catalogue::load_words(crate::FALLBACK, words).map(Box::new))
            .transpose()?;
        Ok(Self {
            tag: if pseudo {
                crate::PSEUDO.into()
            } else {
                tag.into()
            },
            bundle,
            fallback: fallback.filter(|_| !pseudo),
        })
    }

    /// The language tag this catalogue was loaded for.
    pub fn tag(&self) -> &str {
        &self.tag
    }

    /// The message `id` (or `id.attribute`) with `args`; English when this language lacks
    /// it; `[id]` when no catalogue has it.
    pub fn message(&self, id: &str, args: Option<&FluentArgs>) -> String {
        if let Some(text) = self.format(id, args) {
            return text;
        }
        match &self.fallback {
            Some(english) => english.message(id, args),
            None => format!("[{id}]"),
        }
    }

    /// Whether this language itself (not its fallback) has `id`.
    pub fn has(&self, id: &str) -> bool {
        let (message, attribute) = split(id);
        self.bundle
            .get_message(message)
            .is_some_and(|m| match attribute {
                None => m.value().is_some(),
                Some(a) => m.get_attribute(a).is_some(),
            })
    }

    /// Whether this language or the English behind it has `id` (what [`Catalogue::message`]
    /// words rather than showing `[id]`).
    pub fn words(&self, id: &str) -> bool {
        self.has(id) || self.fallback.as_ref().is_some_and(|f| f.has(id))
    }

    fn format(&self, id: &str, args: Option<&FluentArgs>) -> Option<String> {
        let (message, attribute) = split(id);
        let m = self.bundle.get_message(message)?;
        let pattern = match attribute {
            None => m.value()?,
            Some(a) => m.get_attribute(a)?.value(),
        };
        let mut errors = Vec::new();
        let text = self.bundle.format_pattern(pattern, args, &mut errors);
        Some(text.into_owned())
    }

    /// Every message and attribute of `language`'s files, in file order.
    pub fn messages_of(language: &str) -> Vec<MessageInfo> {
        let mut out = Vec::new();
        for (file, resource) in resources(language, Words::Patient) {
            for entry in resource.entries() {
                let ast::Entry::Message(m) = entry else {
                    continue;
                };
                let id = m.id.name;
                if let Some(value) = &m.value {
                    out.push(info(id.to_string(), &file, value));
                }
                for a in &m.attributes {
                    out.push(info(format!("{id}.{}", a.id.name), &file, &a.value));
                }
            }
        }
        out
    }
}

fn split(id: &str) -> (&str, Option<&str>) {
    match id.split_once('.') {
        Some((m, a)) => (m, Some(a)),
        None => (id, None),
    }
}

/// The parsed files of one language's folder, by name. A file that does not parse is a
/// build mistake the tests catch ([`parse_errors`]); its good entries are kept.
fn resources(language: &str, words: Words) -> Vec<(String, FluentResource)> {
    let names = match words {
        Words::Patient => {
            let prefix = format!("{language}/");
            let mut names: Vec<String> = Files::iter()
                .filter(|p| p.starts_with(&prefix) && p.ends_with(".ftl"))
                .map(|p| p.into_owned())
                .collect();
            names.sort();
            names
        }
        Words::Console => crate::console_files(language),
    };
    names
        .into_iter()
        .filter_map(|name| {
            let text = match words {
                Words::Patient => String::from_utf8_lossy(&Files::get(&name)?.data).into_owned(),
                Words::Console => crate::console_file(&name)?,
            };
            let resource = FluentResource::try_new(text).unwrap_or_else(|(r, _)| r);
            Some((name, resource))
        })
        .collect()
}

/// The files of `language` that do not parse, with Fluent's errors (for the tests).
pub fn parse_errors(language: &str) -> Vec<String> {
    let prefix = format!("{language}/");
    Files::iter()
        .filter(|p| p.starts_with(&prefix))
        .filter_map(|name| {
            let file = Files::get(&name)?;
            let text = String::from_utf8_lossy(&file.data).into_owned();
            FluentResource::try_new(text)
                .err()
                .map(|(_, errors)| format!("{name}: {errors:?}"))
        })
        .collect()
}
