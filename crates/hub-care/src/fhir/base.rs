//! The clinic's FHIR address: the canonical base of the hub's own code systems, questionnaire
//! and identifier systems (`hub.toml`'s `fhir_base`, e.g. `https://fhir.clinic.example/telerehab`;
//! without it `https://NAME/fhir` of the hub's first certificate name). A canonical address
//! names things: nothing needs to answer there, but it must be the clinic's own and stay the
//! same, since every exported code is known by it.

use std::fmt;

use hub_store::HubError;

/// A checked FHIR canonical base: `http(s)://host[:port][/path]`, no query, fragment, spaces
/// or `|` (FHIR's version separator), no trailing `/`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FhirBase(String);

impl FhirBase {
    /// `text` as a base; the error names what is wrong and where it came from (`from`:
    /// "hub.toml's fhir_base").
    pub fn parse(text: &str, from: &str) -> Result<Self, HubError> {
        let bad = |why: &str| {
            HubError::Config(format!(
                "{from} {text:?} is not a FHIR address: {why} (write it like https://fhir.clinic.example/telerehab)"
            ))
        };
        let (scheme, rest) = ["https://", "http://"]
            .iter()
            .find_map(|s| text.strip_prefix(s).map(|rest| (*s, rest)))
            .ok_or_else(|| bad("it must start with https:// or http://"))?;
        let rest = rest.trim_end_matches('/');
        let trimmed = format!("{scheme}{rest}");
        if let Some(c) = trimmed.chars().find(|c| {
            c.is_whitespace()
                || c.is_control()
                || matches!(c, '?' | '#' | '|' | '"' | '<' | '>' | '\\')
        }) {
            return Err(bad(&format!("it holds {c:?}")));
        }
        let host = rest.split('/').next().unwrap_or_default();
        let name = host.rsplit_once(':').map_or(host, |(h, port)| {
            if port.chars().all(|c| c.is_ascii_digit()) {
                h
            } else {
                host
            }
        });
        if name.is_empty() || name.starts_with('.') || name.ends_with('.') || name.contains("..") {
            return Err(bad("it names no host"));
        }
        if rest.contains("//") {
            return Err(bad("it has an empty path segment (//)"));
        }
        Ok(Self(trimmed))
    }

    /// The default of a hub whose first certificate name is `name`: `https://NAME/fhir`.
    /// An IPv6 literal is bracketed (`https://[::1]/fhir`).
    pub fn of_hub_name(name: &str) -> Result<Self, HubError> {
        let host = if name.contains(':') && !name.starts_with('[') {
            format!("[{name}]")
        } else {
            name.to_owned()
        };
        Self::parse(
            &format!("https://{host}/fhir"),
            "the hub's certificate name",
        )
    }

    /// The canonical URL of the hub's code system `name` (`…/CodeSystem/measures`).
    pub fn code_system(&self, name: &str) -> String {
        format!("{}/CodeSystem/{name}", self.0)
    }

    /// The canonical URL of the hub's questionnaire `name`.
    pub fn questionnaire(&self, name: &str) -> String {
        format!("{}/Questionnaire/{name}", self.0)
    }

    /// The system of the hub's identifiers of kind `name` (`…/sid/pseudonym`).
    pub fn identifiers(&self, name: &str) -> String {
        format!("{}/sid/{name}", self.0)
    }
}

impl fmt::Display for FhirBase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::FhirBase;

    #[test]
    fn a_fhir_base_is_an_http_address_without_query_or_trailing_slash() {
        let b = FhirBase::parse("https://fhir.clinic.example/telerehab/", "test").unwrap();
        assert_eq!(
            b.code_system("measures"),
            "https://fhir.clinic.example/telerehab/CodeSystem/measures"
        );
        assert!(FhirBase::parse("http://10.0.0.5:8080/fhir", "test").is_ok());
        for (bad, why) in [
            ("fhir.clinic.example", "https://"),
            ("ftp://fhir.clinic.example", "https://"),
            ("https://", "no host"),
            ("https://fhir clinic", "' '"),
            ("https://fhir.clinic.example/x?y=1", "'?'"),
            ("https://fhir.clinic.example/a|1", "'|'"),
            ("https://fhir.clinic.example//x", "//"),
        ] {
            let e = FhirBase::parse(bad, "hub.toml's fhir_base")
                .unwrap_err()
                .to_string();
            assert!(e.contains(why) && e.contains("fhir_base"), "{bad}: {e}");
        }
    }
}
