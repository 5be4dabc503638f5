//! The human-readable part of each exported resource (`text`, status `generated`): an XHTML
//! `div` of the resource's own facts, in words from the console's catalogue (`fhir.ftl`,
//! `scales.ftl`, `words.ftl`, `progress.ftl`) and the station's (the check-in's questions and
//! answers), in the language the export is asked in (the therapist's: `hub export --fhir
//! --lang de`, the console's download in the logged-in therapist's language), which each
//! resource names in `language` and each narrative in its `lang`.

use i18n::Catalogue;
use serde_json::{Value, json};

use crate::sheet_words::SheetWords;
use hub_store::HubError;

/// The words of one export, in one language: the console's (clinicians') and the station's
/// (the patient's).
pub struct Words {
    console: SheetWords,
    patient: Catalogue,
    language: &'static str,
}

impl Words {
    /// The export's words in `tag` (one of [`i18n::LANGUAGES`], a region allowed: `de-AT`
    /// reads `de`); English for none. A language without catalogues is refused, naming it and
    /// the languages there are.
    pub fn of(tag: Option<&str>) -> Result<Self, HubError> {
        let tag = tag.map(str::trim).filter(|t| !t.is_empty());
        let language = match tag {
            None => i18n::FALLBACK,
            Some(t) => {
                let lower = t.to_ascii_lowercase();
                i18n::LANGUAGES
                    .iter()
                    .copied()
                    .find(|l| lower == *l || lower.starts_with(&format!("{l}-")))
                    .ok_or_else(|| {
                        let short: String = t.chars().take(32).collect();
                        HubError::invalid("lang", i18n::UnknownLanguage(short).to_string())
                    })?
            }
        };
        Ok(Self {
            console: SheetWords::of(Some(language)),
            patient: Catalogue::load(language).unwrap_or_else(|_| {
                unreachable!("{language} is one of the embedded station languages")
            }),
            language,
        })
    }

    /// The English export's words.
    pub fn english() -> Self {
        Self::of(None).unwrap_or_else(|_| unreachable!("English is always there"))
    }

    /// The language the words are in (`de`): each resource's `language`.
    pub fn language(&self) -> &'static str {
        self.language
    }

    /// The console's message `id` with `args`.
    pub fn say(&self, id: &str, args: &[(&'static str, String)]) -> String {
        self.console.t(id, args)
    }

    /// The console's message `id` when the catalogue (or English behind it) has it.
    pub fn say_if(&self, id: &str, args: &[(&'static str, String)]) -> Option<String> {
        self.console.has(id).then(|| self.say(id, args))
    }

    /// Measure `key`'s plain name with its unit in these words (`Zeit in der Spur (%)`); a
    /// measure the words table lacks by its name with spaces.
    pub fn measure(&self, key: &str) -> String {
        self.console.measure(key)
    }

    /// A session's exercises in order in these words (`Sinusstraße, dann …`) from their short
    /// names; `named` (the hub's English) when they are unknown.
    pub fn exercises(&self, shorts: &[String], named: &str) -> String {
        self.console.exercises(shorts, named)
    }

    /// The station's message `id` (the words the patient saw).
    pub fn patient(&self, id: &str) -> String {
        self.patient.message(id, None)
    }

    /// A narrative of paragraphs `lines` and, if `rows` is not empty, a two-column table
    /// headed `head` (each cell escaped), marked as written in these words' language.
    pub fn narrative(
        &self,
        lines: &[String],
        head: Option<(String, String)>,
        rows: &[(String, String)],
    ) -> Value {
        narrative_in(self.language, lines, head, rows)
    }

    /// A narrative of the one sentence `line`.
    pub fn sentence(&self, line: String) -> Value {
        self.narrative(&[line], None, &[])
    }
}

/// A moment as a narrative says it: `2026-11-21 09:30` (UTC, the words say so).
pub fn when(ms: i64) -> String {
    let iso = hub_store::db::iso_utc(ms);
    iso.get(..16).unwrap_or(&iso).replace('T', " ")
}

/// `s` with XML's special characters escaped.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// A narrative in `language` of paragraphs `lines` and, if `rows` is not empty, a two-column
/// table headed `head` (each cell escaped).
fn narrative_in(
    language: &str,
    lines: &[String],
    head: Option<(String, String)>,
    rows: &[(String, String)],
) -> Value {
    let mut div = format!(
        "<div xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"{language}\" xml:lang=\"{language}\">"
    );
    for l in lines {
        div.push_str(&format!("<p>{}</p>", escape(l)));
    }
    if !rows.is_empty() {
        div.push_str("<table>");
        if let Some((a, b)) = head {
            div.push_str(&format!(
                "<tr><th>{}</th><th>{}</th></tr>",
                escape(&a),
                escape(&b)
            ));
        }
        for (a, b) in rows {
            div.push_str(&format!(
                "<tr><td>{}</td><td>{}</td></tr>",
                escape(a),
                escape(b)
            ));
        }
        div.push_str("</table>");
    }
    div.push_str("</div>");
    json!({ "status": "generated", "div": div })
}

#[cfg(test)]
mod tests {
    use super::Words;

    #[test]
    fn a_narrative_is_an_escaped_xhtml_div_of_catalogue_words() {
        let words = Words::english();
        let said = words.say("fhir-patient", &[("pseudonym", "P-<1>&".to_owned())]);
        assert!(said.contains("P-<1>&") && !said.starts_with('['), "{said}");
        let n = words.narrative(
            &[said],
            Some(("a".into(), "b".into())),
            &[("x\"".into(), "1".into())],
        );
        let div = n["div"].as_str().unwrap();
        assert!(
            div.starts_with("<div xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\""),
            "{div}"
        );
        assert!(
            div.contains("P-&lt;1&gt;&amp;") && div.contains("<td>x&quot;</td>"),
            "{div}"
        );
        assert_eq!(n["status"], "generated");
        assert!(!words.patient("checkin-pain-question").starts_with('['));
    }

    #[test]
    fn an_export_in_german_says_its_words_in_german_and_names_its_language() {
        let de = Words::of(Some("de-AT")).unwrap();
        let en = Words::english();
        assert_eq!(de.language(), "de");
        let args = [("pseudonym", "P-1".to_owned())];
        assert_ne!(de.say("fhir-patient", &args), en.say("fhir-patient", &args));
        assert_ne!(
            de.patient("checkin-pain-question"),
            en.patient("checkin-pain-question")
        );
        assert_ne!(de.measure("pct_in_lane"), en.measure("pct_in_lane"));
        let div = de.sentence("Hallo".into())["div"]
            .as_str()
            .unwrap()
            .to_owned();
        assert!(div.contains("lang=\"de\" xml:lang=\"de\""), "{div}");
        let e = Words::of(Some("xx")).err().unwrap().to_string();
        assert!(e.contains("\"xx\"") && e.contains("en, de, es, zh"), "{e}");
    }
}
