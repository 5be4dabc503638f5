//! Why the hub refused, in any language (issue 40): every refusal the console can meet carries
//! a [`Code`] and the arguments it names ([`Why`]), beside the hub's English sentence. The
//! console words it from its catalogue (`api-why-<code>` in `crates/i18n/console/<lang>/api.ftl`),
//! so a German therapist reads why in German; API clients and logs keep the English.
//!
//! The list of codes is closed: a code without words in the catalogue, or words naming an
//! argument the code does not give, fails `crates/hub/tests/refusal_words.rs`.

use serde::Serialize;
use serde_json::{Map, Value};

macro_rules! codes {
    ($($(#[$doc:meta])* $name:ident => $code:literal [$($arg:literal),*],)*) => {
        /// A reason the hub refuses a request for; its words are the console's `api-why-<code>`.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[non_exhaustive]
        pub enum Code {
            $($(#[$doc])* $name,)*
        }

        impl Code {
            /// Every code, for the test that each has words in every language.
            pub const ALL: &'static [Code] = &[$(Code::$name,)*];

            /// The code as the console's catalogue names it (`api-why-<code>`).
            pub const fn as_str(self) -> &'static str {
                match self {
                    $(Code::$name => $code,)*
                }
            }

            /// The arguments the code gives its words.
            pub const fn args(self) -> &'static [&'static str] {
                match self {
                    $(Code::$name => &[$($arg),*],)*
                }
            }
        }
    };
}

codes! {
    /// A field was not accepted, for a reason with no words of its own (a value no form sends).
    FieldRefused => "field-refused" ["field"],
    /// A text field is empty.
    Empty => "empty" ["field"],
    /// A text field is longer than allowed (`max` characters).
    TooLong => "too-long" ["field", "max"],
    /// A text field holds control characters.
    ControlCharacters => "control-characters" ["field"],
    /// A required field is missing.
    Missing => "missing" ["field"],
    /// A field's value is not one the hub knows (a sort, a scale, a setting).
    NotOneOf => "not-one-of" ["field"],
    /// A number outside `[min, max]`.
    OutOfRange => "out-of-range" ["field", "min", "max"],
    /// A date that is not a real day, or not one the field allows.
    BadDate => "bad-date" ["field"],
    /// A date in the future where a past one is needed.
    FutureDate => "future-date" ["field"],
    /// An identifier in the address that cannot be one (`field` names which).
    BadId => "bad-id" ["field"],
    /// An e-mail address that does not look like one.
    BadEmail => "bad-email" [],
    /// A pseudonym with characters other than letters, digits, `.`, `_`, `-`, or too long.
    BadPseudonym => "bad-pseudonym" ["max"],
    /// A password with invisible characters.
    PasswordInvisible => "password-invisible" [],
    /// A password shorter than `min` characters (or longer than the hub keeps).
    PasswordLength => "password-length" ["min"],
    /// A password of mostly spaces.
    PasswordSpaces => "password-spaces" [],
    /// A password that is the account's e-mail.
    PasswordEmail => "password-email" [],
    /// One of the most common passwords.
    PasswordCommon => "password-common" [],
    /// A character or short group repeated.
    PasswordRepeated => "password-repeated" ["min"],
    /// A run of consecutive letters or digits.
    PasswordSequence => "password-sequence" [],
    /// Too easy to guess.
    PasswordGuessable => "password-guessable" [],
    /// The new password is the current one.
    PasswordSame => "password-same" [],
    /// A snooze that ends in the past.
    SnoozePast => "snooze-past" [],
    /// The named thing (`what`: patient, station, session, therapist, scale) does not exist,
    /// or is not this therapist's to see.
    NotFound => "not-found" ["what"],
    /// The named thing (`what`) already exists.
    AlreadyExists => "already-exists" ["what"],
    /// No such endpoint.
    NoEndpoint => "no-endpoint" [],
    /// Wrong e-mail or password (the same for both, and for a revoked account).
    LoginRefused => "login-refused" [],
    /// Not logged in, or the login has ended.
    LogInFirst => "log-in-first" [],
    /// A one-time password must be changed before anything else.
    OneTimePassword => "one-time-password" [],
    /// For administrators only.
    AdminOnly => "admin-only" [],
    /// A therapist adds patients into their own care only.
    OwnCareOnly => "own-care-only" [],
    /// No therapist has the e-mail given.
    NoTherapistEmail => "no-therapist-email" [],
    /// Too many tries, or too much queued: wait `seconds`.
    Throttled => "throttled" ["seconds"],
    /// The alert has cleared since it was shown.
    AlertGone => "alert-gone" [],
    /// Something new happened since the alert was shown.
    AlertChanged => "alert-changed" [],
    /// A regimen sent neither as text nor as fields (or as both), or fields of the wrong shape.
    RegimenShape => "regimen-shape" [],
    /// The regimen's text cannot be read at `line`.
    RegimenText => "regimen-text" ["line"],
    /// The regimen's text cannot be read (no line known).
    RegimenUnreadable => "regimen-unreadable" [],
    /// Exercise number `exercise` has a value outside its allowed range.
    RegimenExercise => "regimen-exercise" ["exercise"],
    /// Exercise number `exercise` asks more force than the patient's wheel gives (`max_nm`).
    AboveWheel => "above-wheel" ["exercise", "max_nm"],
    /// The session's recording has not fully arrived.
    RecordingNotArrived => "recording-not-arrived" [],
    /// The session's recording cannot be read on the hub.
    RecordingUnreadable => "recording-unreadable" [],
    /// The recording (`mb`) is larger than the hub replays (`max_mb`).
    RecordingTooLarge => "recording-too-large" ["mb", "max_mb"],
    /// A replay asked for is still being prepared.
    ReplayPending => "replay-pending" [],
    /// The hub is busy preparing other replays.
    ReplayBusy => "replay-busy" [],
    /// At most `max` live streams at once (per login or per therapist).
    LiveStreams => "live-streams" ["max"],
    /// A language the console has no words for.
    UnknownLanguage => "unknown-language" [],
    /// A time zone the hub does not know.
    UnknownTimeZone => "unknown-time-zone" [],
    /// A body that is not JSON of the expected shape.
    BodyMalformed => "body-malformed" [],
    /// A body larger than the hub accepts.
    BodyTooLarge => "body-too-large" [],
    /// A body that is not sent as JSON.
    BodyNotJson => "body-not-json" [],
    /// Something failed on the hub (its log has the details).
    Internal => "internal" [],
}

/// Why a request was refused: a [`Code`] and its arguments, as the console reads it
/// (`{"code": "too-long", "args": {"field": "text", "max": 2000}}`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Why {
    #[serde(serialize_with = "code_str")]
    code: Code,
    #[serde(skip_serializing_if = "Map::is_empty")]
    args: Map<String, Value>,
}

fn code_str<S: serde::Serializer>(code: &Code, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(code.as_str())
}

impl Why {
    /// `code`, its arguments to follow ([`Why::with`]).
    pub fn new(code: Code) -> Self {
        Self {
            code,
            args: Map::new(),
        }
    }

    /// `code` naming `field` (the JSON or form field refused).
    pub fn field(code: Code, field: &str) -> Self {
        Self::new(code).with("field", field)
    }

    /// Adds argument `name` (one of [`Code::args`]; others are dropped, so the catalogue never
    /// meets an argument it was not written for).
    pub fn with(mut self, name: &'static str, value: impl Into<Value>) -> Self {
        debug_assert!(
            self.code.args().contains(&name),
            "{name} is not an argument of {}",
            self.code.as_str()
        );
        if self.code.args().contains(&name) {
            self.args.insert(name.to_owned(), value.into());
        }
        self
    }

    /// The code.
    pub fn code(&self) -> Code {
        self.code
    }

    /// The arguments given.
    pub fn args(&self) -> &Map<String, Value> {
        &self.args
    }
}

/// Why `text` was refused as `field` of at most `max_chars` characters, in the order the
/// hub's and the protocol's text checks refuse: empty, too long, control characters.
pub fn of_text(field: &str, text: &str, max_chars: usize) -> Why {
    if text.trim().is_empty() {
        Why::field(Code::Empty, field)
    } else if text.chars().count() > max_chars {
        Why::field(Code::TooLong, field).with("max", max_chars)
    } else {
        Why::field(Code::ControlCharacters, field)
    }
}

/// Why a regimen the reader refused after its text was read: the exercise whose value is out
/// of range, else unreadable.
pub fn of_regimen(e: &regimen::RegimenError) -> Why {
    match e {
        regimen::RegimenError::Invalid { index, .. } => {
            Why::new(Code::RegimenExercise).with("exercise", *index)
        }
        _ => Why::new(Code::RegimenUnreadable),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_why_serialises_as_its_code_and_arguments() {
        let why = Why::field(Code::TooLong, "text").with("max", 2000);
        assert_eq!(
            serde_json::to_value(&why).unwrap(),
            serde_json::json!({"code": "too-long", "args": {"field": "text", "max": 2000}})
        );
        assert_eq!(
            serde_json::to_value(Why::new(Code::LogInFirst)).unwrap(),
            serde_json::json!({"code": "log-in-first"})
        );
    }

    #[test]
    fn every_code_is_named_once() {
        let mut names: Vec<&str> = Code::ALL.iter().map(|c| c.as_str()).collect();
        names.sort_unstable();
        let before = names.len();
        names.dedup();
        assert_eq!(names.len(), before, "two codes share a name");
    }
}
