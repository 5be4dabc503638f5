//! The human-readable part of each exported resource (`text`, status `generated`): an XHTML
//! `div` of the resource's own facts, in words from the console's catalogue (`fhir.ftl`,
//! `scales.ftl`) and the station's (the check-in's questions and answers). The export is in
//! English, as its codes' names are.

use i18n::{Catalogue, FluentArgs};
use serde_json::{Value, json};

/// The language the export is written in.
pub const LANGUAGE: &str = "en";

/// The words of one export: the console's (clinicians') and the station's (the patient's).
pub struct Words {
    console: Catalogue,
    patient: Catalogue,
}

impl Words {
    /// The export's words ([`LANGUAGE`]).
    pub fn new() -> Self {
        Self {
            console: Catalogue::console_or_english(Some(LANGUAGE)),
            patient: Catalogue::load(LANGUAGE).unwrap_or_else(|_| {
                unreachable!("{LANGUAGE} is one of the embedded station languages")
            }),
        }
    }

    /// The console's message `id` with `args`.
    pub fn say(&self, id: &str, args: &[(&'static str, String)]) -> String {
        self.console.message(id, Some(&fluent(args)))
    }

    /// The station's message `id` (the words the patient saw).
    pub fn patient(&self, id: &str) -> String {
        self.patient.message(id, None)
    }
}

impl Default for Words {
    fn default() -> Self {
        Self::new()
    }
}

fn fluent(args: &[(&'static str, String)]) -> FluentArgs<'static> {
    let mut f = FluentArgs::new();
    for (name, value) in args {
        f.set(*name, value.clone());
    }
    f
}

/// A moment as a narrative says it: `2026-11-21 09:30` (UTC, the words say so).
pub fn when(ms: i64) -> String {
    let iso = crate::db::iso_utc(ms);
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

/// A narrative of paragraphs `lines` and, if `rows` is not empty, a two-column table headed
/// `head` (each cell escaped).
pub fn narrative(
    lines: &[String],
    head: Option<(String, String)>,
    rows: &[(String, String)],
) -> Value {
    let mut div = format!(
        "<div xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"{LANGUAGE}\" xml:lang=\"{LANGUAGE}\">"
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

/// A narrative of the one sentence `line`.
pub fn sentence(line: String) -> Value {
    narrative(&[line], None, &[])
}

#[cfg(test)]
mod tests {
    use super::{Words, narrative};

    #[test]
    fn a_narrative_is_an_escaped_xhtml_div_of_catalogue_words() {
        let words = Words::new();
        let said = words.say("fhir-patient", &[("pseudonym", "P-<1>&".to_owned())]);
        assert!(said.contains("P-<1>&") && !said.starts_with('['), "{said}");
        let n = narrative(
            &[said],
            Some(("a".into(), "b".into())),
            &[("x\"".into(), "1".into())],
        );
        let div = n["div"].as_str().unwrap();
        assert!(
            div.starts_with("<div xmlns=\"http://www.w3.org/1999/xhtml\""),
            "{div}"
        );
        assert!(
            div.contains("P-&lt;1&gt;&amp;") && div.contains("<td>x&quot;</td>"),
            "{div}"
        );
        assert_eq!(n["status"], "generated");
        assert!(!words.patient("checkin-pain-question").starts_with('['));
    }
}
