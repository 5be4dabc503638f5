//! A regimen's TOML error in plain words (issue 29): the line and the field, and what is wrong,
//! instead of the parser's raw message.

use hub_store::refusal::{Code, Why};

/// A regimen text the TOML reader refuses: its plain words and the line they are about.
#[derive(Debug, PartialEq)]
pub(crate) struct TomlProblem {
    /// The line and the field, and what is wrong, in plain (English) words.
    pub(crate) words: String,
    /// The 1-based line, when the reader knows it.
    pub(crate) line: Option<usize>,
}

impl TomlProblem {
    /// Why, for the console's words in any language.
    pub(crate) fn why(&self) -> Why {
        match self.line {
            Some(line) => Why::new(Code::RegimenText).with("line", line),
            None => Why::new(Code::RegimenUnreadable),
        }
    }
}

/// The plain-words refusal of `text` when it is not a regimen the TOML reader accepts (its
/// syntax or a field's type or name), naming the line and the field; `None` when it reads (the
/// regimen's own bounds are checked after, and their messages already name the field).
pub(crate) fn toml_problem(text: &str) -> Option<TomlProblem> {
    let err = toml::from_str::<regimen::Regimen>(text).err()?;
    let what = plain_message(err.message());
    let Some(span) = err.span() else {
        return Some(TomlProblem {
            words: format!("The regimen text cannot be read: {what}."),
            line: None,
        });
    };
    let start = span.start.min(text.len());
    // An error in a table points at its header: find the line the message is about in the
    // table's lines (up to the next header).
    let at = clue(err.message())
        .and_then(|c| {
            let mut offset = start;
            let mut lines = text[start..].split_inclusive('\n');
            let header = lines.next().map_or(0, str::len);
            offset += header;
            let mut body = lines.take_while(|l| !l.trim_start().starts_with('['));
            body.find_map(|l| {
                let here = offset;
                offset += l.len();
                let (key, value) = l.split_once('=')?;
                (key.trim() == c || value.trim() == c).then_some(here)
            })
        })
        .unwrap_or(start);
    let line_no = text[..at].matches('\n').count() + 1;
    let line = text.lines().nth(line_no - 1).unwrap_or("").trim();
    let section = text[..at]
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| l.starts_with('['))
        .filter(|l| *l != line)
        .map(|l| format!(" in {l}"))
        .unwrap_or_default();
    let field = line
        .split_once('=')
        .map(|(k, _)| k.trim())
        .filter(|k| !k.is_empty() && !k.starts_with('['));
    let words = match field {
        Some(field) => format!("Line {line_no}, the field \"{field}\"{section}: {what}."),
        None => format!("Line {line_no} (\"{line}\"){section}: {what}."),
    };
    Some(TomlProblem {
        words,
        line: Some(line_no),
    })
}

/// What in the message names the line: an unknown field's name, or the value as written of
/// the wrong type or kind (`"long"`, `3`, `"sinus"`).
fn clue(raw: &str) -> Option<String> {
    let first = raw.lines().next()?;
    if let Some(rest) = first.strip_prefix("unknown field `") {
        return rest.split('`').next().map(str::to_owned);
    }
    if let Some(rest) = first.strip_prefix("unknown variant `") {
        return rest.split('`').next().map(|v| format!("\"{v}\""));
    }
    let value = first
        .strip_prefix("invalid type: ")?
        .split(", expected ")
        .next()?;
    if let Some(s) = value.strip_prefix("string ") {
        return Some(s.to_owned());
    }
    value.split('`').nth(1).map(str::to_owned)
}

/// What a value of the type `expected` names looks like, in a therapist's words.
fn wanted(expected: &str) -> &str {
    match expected {
        e if e.contains("f64") || e.contains("f32") => "a number (e.g. 30.0)",
        e if e.contains("u32") || e.contains("u64") || e.contains("integer") => {
            "a whole number (e.g. 3)"
        }
        e if e.contains("bool") => "true or false",
        e if e.contains("string") => "a word in quotes (e.g. \"sine\")",
        e if e.contains("sequence") => "a list (each exercise under [[exercise]], two brackets)",
        e => e,
    }
}

/// The parser's message in a therapist's words: its first line, with the type names a
/// therapist does not write (`f64`, `u32`, a string "…") said plainly.
fn plain_message(raw: &str) -> String {
    let first = raw
        .lines()
        .next()
        .unwrap_or(raw)
        .trim()
        .trim_end_matches('.');
    if let Some(rest) = first.strip_prefix("unknown field ") {
        let name = rest.split(',').next().unwrap_or(rest).trim_matches('`');
        return format!("there is no setting called \"{name}\" (check its spelling)");
    }
    if let Some(rest) = first.strip_prefix("missing field ") {
        return format!("the setting \"{}\" is needed", rest.trim_matches('`'));
    }
    if let Some((_, expected)) = first
        .strip_prefix("invalid type: ")
        .and_then(|r| r.split_once(", expected "))
    {
        return format!("this should be {}", wanted(expected));
    }
    if let Some(rest) = first.strip_prefix("unknown variant ") {
        let (name, known) = rest.split_once(", expected one of ").unwrap_or((rest, ""));
        return format!(
            "\"{}\" is not a kind this station knows (it knows {})",
            name.trim_matches('`'),
            known.replace('`', "")
        );
    }
    match first {
        f if f.starts_with("invalid string") || f.starts_with("string values must be quoted") => {
            "a word needs quotes around it (e.g. kind = \"sine\")".to_owned()
        }
        f if f.starts_with("unexpected key or value") => {
            "one setting per line, and a decimal number takes a point (30.5, not 30,5)".to_owned()
        }
        f if f.starts_with("expected `.`, `=`") || f.starts_with("expected `=`") => {
            "a setting is written as name = value".to_owned()
        }
        other => format!("the text does not read as TOML ({other})"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mistyped_value_names_its_line_and_field_in_plain_words() {
        let text =
            "sessions_per_week = 3\n\n[[exercise]]\nkind = \"sine\"\nduration_s = \"long\"\n";
        let msg = toml_problem(text).unwrap().words;
        assert!(
            msg.starts_with("Line 5, the field \"duration_s\" in [[exercise]]"),
            "{msg}"
        );
        assert!(msg.contains("a number"), "{msg}");
        assert!(!msg.contains("f64"), "{msg}");
    }

    #[test]
    fn a_misspelt_setting_is_named_with_its_line() {
        let text = "[[exercise]]\nkind = \"sine\"\namplitud_m = 3.0\n";
        let msg = toml_problem(text).unwrap().words;
        assert!(msg.contains("Line 3"), "{msg}");
        assert!(msg.contains("no setting called \"amplitud_m\""), "{msg}");
    }

    #[test]
    fn a_readable_regimen_has_no_toml_problem() {
        assert_eq!(toml_problem("[[exercise]]\nkind = \"sine\"\n"), None);
    }

    #[test]
    fn an_unknown_kind_is_named_on_its_line_with_the_kinds_known() {
        let msg = toml_problem("[[exercise]]\nkind = \"sinus\"\n")
            .unwrap()
            .words;
        assert!(msg.starts_with("Line 2, the field \"kind\""), "{msg}");
        assert!(
            msg.contains("\"sinus\" is not a kind") && msg.contains("slalom"),
            "{msg}"
        );
    }
}
