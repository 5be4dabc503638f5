//! The patient's and the clinician's words, from Project Fluent catalogues.
//!
//! Every sentence a person reads or hears comes from `locales/<language>/<area>.ftl`: one
//! folder a language ([`LANGUAGES`]), one file an area of the product (the first-run pages,
//! the session's screens, the check-in, …), all embedded in the binary. A message is asked
//! for by its id with [`tr!`]; Fluent chooses plurals and formats numbers per language.
//!
//! The language in force is process-wide ([`use_language`], [`current`]): the station shows
//! one patient's screens at a time. Which language that is — the prescription's, the one
//! chosen on the first-run page, else the system's ([`system_language`]) — is the caller's
//! choice, made with [`negotiate`]. [`PSEUDO`] is an accented, 40 % longer English that
//! layout tests render to find clipped or overlapping text.
//!
//! A message missing from a language falls back to English; one missing from English shows
//! its id in brackets (`[today-title]`), never an empty page. The crate's tests check that
//! every language has every English message with the same arguments.

mod catalogue;
mod console;
mod language;
mod message;
mod pseudo;

pub use catalogue::{Catalogue, parse_errors};
pub use console::{
    console_catalogue, console_file, console_files, console_messages_of, console_tags,
};
pub use fluent_bundle::{FluentArgs, FluentValue};
pub use language::{negotiate, system_language, system_language_from};
pub use message::MessageInfo;

use std::sync::{Arc, OnceLock, RwLock};

/// The languages the catalogues are written in, English first (the fallback).
///
/// German and Spanish are the first markets' languages; Mandarin Chinese (simplified) is the
/// language of the largest stroke population in the world and the one that exercises what a
/// Latin-script catalogue would not: fonts beyond Latin, lines without spaces, a tonal voice.
pub const LANGUAGES: &[&str] = &["en", "de", "es", "zh"];

/// The fallback language: every message exists in it.
pub const FALLBACK: &str = "en";

/// The pseudo-locale: English with every letter accented and every text 40 % longer, for
/// layout tests (the tag Android uses for the same purpose).
pub const PSEUDO: &str = "en-XA";

/// A language tag the catalogues do not have.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownLanguage(pub String);

impl std::fmt::Display for UnknownLanguage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "no words for the language \"{}\"; the languages are {}",
            self.0,
            LANGUAGES.join(", ")
        )
    }
}

impl std::error::Error for UnknownLanguage {}

fn slot() -> &'static RwLock<Arc<Catalogue>> {
    static CURRENT: OnceLock<RwLock<Arc<Catalogue>>> = OnceLock::new();
    CURRENT.get_or_init(|| {
        let first = negotiate(system_language().as_deref());
        RwLock::new(Arc::new(Catalogue::load(first).unwrap_or_else(|_| {
            Catalogue::load(FALLBACK).expect("the English catalogue is embedded")
        })))
    })
}

/// The catalogue in force (at first the system's language, else English).
pub fn current() -> Arc<Catalogue> {
    slot().read().unwrap_or_else(|e| e.into_inner()).clone()
}

/// Puts `tag` (one of [`LANGUAGES`] or [`PSEUDO`], a region allowed: `de-AT`) in force for
/// the whole process.
pub fn use_language(tag: &str) -> Result<(), UnknownLanguage> {
    let catalogue = Arc::new(Catalogue::load(tag)?);
    *slot().write().unwrap_or_else(|e| e.into_inner()) = catalogue;
    Ok(())
}

/// A message of the catalogue in force: `tr!("today-title")`, or with arguments
/// `tr!("rest-left", seconds = 30)` (an argument is anything `Into<FluentValue>`: text and
/// numbers).
#[macro_export]
macro_rules! tr {
    ($id:expr) => {
        $crate::current().message($id, None)
    };
    ($id:expr, $($name:ident = $value:expr),+ $(,)?) => {{
        let mut args = $crate::FluentArgs::new();
        $( args.set(stringify!($name), $value); )+
        $crate::current().message($id, Some(&args))
    }};
}
