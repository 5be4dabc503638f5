//! Reading a configuration or regimen written by another version of telerehab, leniently.
//!
//! A recording keeps the station configuration and the regimen it ran with as TOML, and a
//! recording must replay for as long as it is kept. Our types refuse unknown fields (a typo in a
//! configuration a person writes must be named, not ignored), so a field renamed or removed
//! since the recording was made would refuse the whole file. [`from_toml_lenient`] reads such a
//! text anyway: a field this version does not know is dropped, a field it needs and the text
//! lacks takes its default, and every such change is reported in plain words for the reader
//! to show. What is left is then parsed (and validated by the caller) as usual.

use serde::Serialize;
use serde::de::DeserializeOwned;

/// Most fields one text may have dropped or defaulted before it is refused as not ours.
const MAX_REPAIRS: usize = 64;

/// A text read leniently: the value, and what had to be dropped or defaulted to read it.
#[derive(Debug, Clone, PartialEq)]
pub struct Lenient<T> {
    /// The value read.
    pub value: T,
    /// One line per field dropped or defaulted, naming the field (`arm.geometry.foo`).
    pub notes: Vec<String>,
}

/// Reads `text` as a `T`, dropping the fields `T` does not know and giving the fields it
/// needs and `text` lacks their value in `defaults` (the TOML of a default `T`, if there is
/// one). `Err` when the text is not TOML, a field has a value of the wrong type, or more than
/// a few dozen fields had to be repaired (then it is not a text of ours).
pub fn from_toml_lenient<T: DeserializeOwned>(
    text: &str,
    defaults: Option<&toml::Table>,
) -> Result<Lenient<T>, String> {
    let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| e.to_string())?;
    let mut notes = Vec::new();
    loop {
        let value = toml::Value::Table(table.clone());
        let error = match serde_path_to_error::deserialize::<_, T>(value) {
            Ok(value) => return Ok(Lenient { value, notes }),
            Err(e) => e,
        };
        if notes.len() >= MAX_REPAIRS {
            return Err(format!(
                "{error} (after {MAX_REPAIRS} fields dropped or defaulted)"
            ));
        }
        let mut parent = path_of(error.path());
        let message = error.inner().to_string();
        let repaired = if let Some(field) = quoted_after(&message, "unknown field `") {
            // The path ends at the unknown key itself.
            if parent.last() == Some(&Step::Key(field.clone())) {
                parent.pop();
            }
            remove(&mut table, &parent, &field).then(|| {
                format!(
                    "`{}` is not a field of this version: ignored",
                    dotted(&parent, &field)
                )
            })
        } else if let Some(field) = quoted_after(&message, "missing field `") {
            let default = defaults.and_then(|d| get(d, &parent, &field)).cloned();
            default.and_then(|v| {
                let shown = v.to_string();
                insert(&mut table, &parent, &field, v).then(|| {
                    format!(
                        "`{}` is absent (renamed or added since): the default {shown} is used",
                        dotted(&parent, &field)
                    )
                })
            })
        } else {
            None
        };
        match repaired {
            Some(note) => notes.push(note),
            None => return Err(format!("{}: {message}", error.path())),
        }
    }
}

/// One step into a TOML document: a table's key or an array's index.
#[derive(Debug, Clone, PartialEq)]
enum Step {
    Key(String),
    Index(usize),
}

fn path_of(path: &serde_path_to_error::Path) -> Vec<Step> {
    use serde_path_to_error::Segment;
    path.iter()
        .filter_map(|s| match s {
            Segment::Map { key } => Some(Step::Key(key.clone())),
            Segment::Seq { index } => Some(Step::Index(*index)),
            Segment::Enum { .. } | Segment::Unknown => None,
        })
        .collect()
}

fn dotted(parent: &[Step], field: &str) -> String {
    let mut out = String::new();
    for step in parent {
        match step {
            Step::Key(k) => {
                out.push_str(k);
                out.push('.');
            }
            Step::Index(i) => {
                if out.ends_with('.') {
                    out.pop();
                }
                out.push_str(&format!("[{i}]."));
            }
        }
    }
    out.push_str(field);
    out
}

/// The name in backquotes right after `prefix` in `message`.
fn quoted_after(message: &str, prefix: &str) -> Option<String> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    Some(rest[..rest.find('`')?].to_owned())
}

fn table_at<'a>(table: &'a mut toml::Table, path: &[Step]) -> Option<&'a mut toml::Table> {
    let mut here = table;
    let mut steps = path.iter();
    let Some(first) = steps.next() else {
        return Some(here);
    };
    let mut value = match first {
        Step::Key(k) => here.get_mut(k)?,
        Step::Index(_) => return None,
    };
    for step in steps {
        value = match step {
            Step::Key(k) => value.as_table_mut()?.get_mut(k)?,
            Step::Index(i) => value.as_array_mut()?.get_mut(*i)?,
        };
    }
    here = value.as_table_mut()?;
    Some(here)
}

fn remove(table: &mut toml::Table, parent: &[Step], field: &str) -> bool {
    table_at(table, parent).is_some_and(|t| t.remove(field).is_some())
}

fn insert(table: &mut toml::Table, parent: &[Step], field: &str, value: toml::Value) -> bool {
    table_at(table, parent).is_some_and(|t| t.insert(field.to_owned(), value).is_none())
}

fn get<'a>(table: &'a toml::Table, parent: &[Step], field: &str) -> Option<&'a toml::Value> {
    let mut value: Option<&toml::Value> = None;
    let mut here = table;
    for step in parent {
        let next = match step {
            Step::Key(k) => here.get(k)?,
            Step::Index(i) => value?.as_array()?.get(*i)?,
        };
        if let Some(t) = next.as_table() {
            here = t;
        }
        value = Some(next);
    }
    here.get(field)
}

/// The TOML table of `value` (for [`from_toml_lenient`]'s defaults).
pub fn defaults_of<T: Serialize>(value: &T) -> Option<toml::Table> {
    toml::Table::try_from(value).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Default, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Geometry {
        upper_arm_m: f64,
        forearm_m: f64,
    }

    #[derive(Debug, Default, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Arm {
        geometry: Geometry,
        #[serde(default)]
        names: Vec<Geometry>,
    }

    #[derive(Debug, Default, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Config {
        arm: Arm,
        #[serde(default)]
        seed: u64,
    }

    fn defaults() -> toml::Table {
        let mut c = Config::default();
        c.arm.geometry.forearm_m = 0.25;
        defaults_of(&c).unwrap()
    }

    #[test]
    fn a_text_of_this_version_reads_with_no_notes() {
        let text = "seed = 3\n[arm.geometry]\nupper_arm_m = 0.3\nforearm_m = 0.2\n";
        let r: Lenient<Config> = from_toml_lenient(text, Some(&defaults())).unwrap();
        assert_eq!(r.value.seed, 3);
        assert!(r.notes.is_empty(), "{:?}", r.notes);
    }

    #[test]
    fn unknown_fields_anywhere_are_dropped_and_named() {
        let text = "gone = 1\n[arm]\nold_name = true\n[arm.geometry]\nupper_arm_m = 0.3\n\
                    forearm_m = 0.2\nwrist_m = 0.1\n[[arm.names]]\nupper_arm_m = 1.0\n\
                    forearm_m = 2.0\nextra = 5\n[removed_section]\nx = 1\n";
        let r: Lenient<Config> = from_toml_lenient(text, Some(&defaults())).unwrap();
        assert_eq!(r.value.arm.geometry.upper_arm_m, 0.3);
        assert_eq!(r.value.arm.names[0].forearm_m, 2.0);
        let all = r.notes.join("\n");
        for name in [
            "`gone`",
            "`arm.old_name`",
            "`arm.geometry.wrist_m`",
            "`arm.names[0].extra`",
            "`removed_section`",
        ] {
            assert!(all.contains(name), "{name} not in {all}");
        }
        assert_eq!(r.notes.len(), 5);
    }

    #[test]
    fn a_renamed_field_takes_its_default_and_says_so() {
        let text = "[arm.geometry]\nupper_arm_m = 0.3\nlower_arm_m = 0.2\n";
        let r: Lenient<Config> = from_toml_lenient(text, Some(&defaults())).unwrap();
        assert_eq!(r.value.arm.geometry.forearm_m, 0.25);
        assert_eq!(r.notes.len(), 2, "{:?}", r.notes);
        assert!(
            r.notes
                .iter()
                .any(|n| n.contains("`arm.geometry.forearm_m` is absent"))
        );
    }

    #[test]
    fn a_wrong_type_or_not_toml_is_still_an_error_naming_the_field() {
        let e = from_toml_lenient::<Config>("seed = \"x\"\n", Some(&defaults())).unwrap_err();
        assert!(e.contains("seed"), "{e}");
        assert!(from_toml_lenient::<Config>("[[[", None).is_err());
        let missing = from_toml_lenient::<Config>("[arm.geometry]\nupper_arm_m = 1.0\n", None);
        assert!(missing.unwrap_err().contains("forearm_m"));
    }
}
