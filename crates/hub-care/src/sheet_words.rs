//! What the hub writes for a clinician outside the console, in the therapist's language
//! (issue 40): a spreadsheet's plain header line, the exercises, how each session ended, yes /
//! no and the check-in's "how hard it felt", and the FHIR export's narratives
//! ([`crate::fhir`]), from the console's catalogue (`sheet.ftl`, `words.ftl`, `progress.ftl`,
//! `fhir.ftl`), as the console's screens say them. The technical header line and the numbers
//! stay as they are, for whoever joins the file to other data. Outside `web`, so that the FHIR
//! export reads the same words without a module cycle.

use metrics::words::{EndKind, measure_words};

/// The console catalogue id of measure `key`'s plain name: `words-measure-pct-in-lane`.
pub fn measure_name_id(key: &str) -> String {
    format!("words-measure-{}", key.replace('_', "-"))
}

/// The console catalogue id of measure `key`'s definition: `words-definition-pct-in-lane`.
pub fn measure_definition_id(key: &str) -> String {
    format!("words-definition-{}", key.replace('_', "-"))
}

/// The console catalogue id of end kind `kind`'s wording: `words-end-wheel-unplugged`.
pub fn end_words_id(kind: EndKind) -> String {
    let key = serde_json::to_value(kind)
        .ok()
        .and_then(|v| v.as_str().map(str::to_owned))
        .unwrap_or_default();
    format!("words-end-{}", key.replace('_', "-"))
}

/// The words of one spreadsheet, in one language.
pub struct SheetWords {
    catalogue: i18n::Catalogue,
}

impl SheetWords {
    /// The console's words in `tag` (one of the console's languages or the pseudo-locale),
    /// English for any other.
    pub fn of(tag: Option<&str>) -> Self {
        Self {
            catalogue: i18n::Catalogue::console_or_english(tag),
        }
    }

    /// The console's message `id` with `args`.
    pub fn t(&self, id: &str, args: &[(&'static str, String)]) -> String {
        let mut fluent = i18n::FluentArgs::new();
        for (name, value) in args {
            fluent.set(*name, value.clone());
        }
        self.catalogue.message(id, Some(&fluent))
    }

    /// Whether the catalogue (or English behind it) words `id`.
    pub fn has(&self, id: &str) -> bool {
        self.catalogue.words(id)
    }

    /// A fixed column's plain header (`sheet-col-<key>`); the local start names its zone.
    pub fn column(&self, key: &str, zone: &str) -> String {
        self.t(&format!("sheet-col-{key}"), &[("zone", zone.to_owned())])
    }

    /// A measure's plain header with its unit (`Time in lane (%)`); a measure the table
    /// lacks by its name with spaces.
    pub fn measure(&self, key: &str) -> String {
        let Some(m) = measure_words(key).filter(|_| self.has(&measure_name_id(key))) else {
            return key.replace('_', " ");
        };
        let name = self.measure_name(key);
        if m.unit.is_empty() {
            name
        } else {
            self.t(
                "words-name-unit",
                &[("name", name), ("unit", m.unit.to_owned())],
            )
        }
    }

    /// A measure's plain name without its unit (`Time in lane`); a measure the catalogue
    /// lacks by its name with spaces.
    pub fn measure_name(&self, key: &str) -> String {
        let id = measure_name_id(key);
        if self.has(&id) {
            self.t(&id, &[])
        } else {
            key.replace('_', " ")
        }
    }

    /// How a session ended, in the one wording; "; the recording stopped early" when it did.
    pub fn ended(&self, kind: EndKind, recording_stopped_early: bool) -> String {
        let words = self.t(&end_words_id(kind), &[]);
        if recording_stopped_early {
            self.t("words-end-recording-stopped", &[("end", words)])
        } else {
            words
        }
    }

    /// The exercises of a session in order (`Sine road, then Dial sine`) from their short
    /// names; `named` (the hub's English) when they are unknown.
    pub fn exercises(&self, shorts: &[String], named: &str) -> String {
        let mut names = shorts.iter().map(|s| {
            let id = format!("words-exercise-{s}");
            if self.has(&id) {
                self.t(&id, &[])
            } else {
                s.replace('-', " ")
            }
        });
        let Some(first) = names.next() else {
            return named.to_owned();
        };
        names.fold(first, |first, next| {
            self.t("words-exercises-then", &[("first", first), ("next", next)])
        })
    }

    /// Yes or no.
    pub fn yes_no(&self, yes: bool) -> String {
        self.t(if yes { "sheet-yes" } else { "sheet-no" }, &[])
    }

    /// The check-in's "how hard it felt" (`too_hard`), in words.
    pub fn felt(&self, felt: &str) -> String {
        let id = format!("progress-felt-{}", felt.replace('_', "-"));
        if self.has(&id) {
            self.t(&id, &[])
        } else {
            felt.replace('_', " ")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_german_sheet_says_its_words_in_german_and_an_unknown_language_in_english() {
        let de = SheetWords::of(Some("de"));
        let en = SheetWords::of(Some("xx"));
        for words in [&de, &en] {
            for key in [
                "session",
                "exercises",
                "ended",
                "as-prescribed",
                "pain",
                "effort",
            ] {
                assert!(!words.column(key, "UTC").starts_with('['), "{key}");
            }
        }
        assert_ne!(de.column("ended", "UTC"), en.column("ended", "UTC"));
        assert!(
            de.column("started-local", "Europe/Berlin")
                .contains("Europe/Berlin")
        );
        assert_ne!(de.yes_no(true), en.yes_no(true));
        assert_ne!(de.felt("too_hard"), en.felt("too_hard"));
        assert_ne!(
            de.ended(EndKind::WheelUnplugged, false),
            en.ended(EndKind::WheelUnplugged, false)
        );
        assert_ne!(de.measure("pct_in_lane"), en.measure("pct_in_lane"));
        assert!(
            en.measure("pct_in_lane").ends_with("(%)"),
            "{}",
            en.measure("pct_in_lane")
        );
        assert_eq!(en.measure("a_new_measure"), "a new measure");
        let shorts = ["sine-road".to_owned(), "dial-sine".to_owned()];
        let two = de.exercises(&shorts, "Sine road, then Dial sine");
        assert!(!two.contains("then"), "{two}");
        assert_eq!(
            en.exercises(&[], "A regimen of 2 exercises"),
            "A regimen of 2 exercises"
        );
    }
}
