//! The crate's error type.

use crate::refusal::{Code, Why};

/// Why a pairing code was not accepted (see [`crate::Db::pair_station`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum PairRefusal {
    /// No code with this value was ever issued.
    Unknown,
    /// The code was issued but its time to live has passed.
    Expired,
    /// The code has already been redeemed once (codes are single use).
    Used,
}

impl std::fmt::Display for PairRefusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Unknown => "unknown pairing code",
            Self::Expired => "the pairing code has expired; ask the clinic for a new one",
            Self::Used => "the pairing code has already been used; ask the clinic for a new one",
        })
    }
}

/// Errors of the hub's database layer and API. The message names the problem and, for input,
/// the offending field and what is allowed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum HubError {
    /// An input value is malformed (the message names the field and the allowed form).
    #[error("invalid {field}: {reason}")]
    Invalid {
        /// The field or argument.
        field: &'static str,
        /// What is wrong and what is allowed.
        reason: String,
        /// The same for the console's words in any language.
        why: Why,
    },
    /// The named thing does not exist.
    #[error("{what} {id:?} does not exist")]
    NotFound {
        /// Kind of thing (patient, station, session, therapist).
        what: &'static str,
        /// Its identifier.
        id: String,
    },
    /// The thing already exists (unique email, pseudonym, station id, fingerprint).
    #[error("{what} {id:?} already exists")]
    AlreadyExists {
        /// Kind of thing.
        what: &'static str,
        /// Its identifier.
        id: String,
    },
    /// Login refused. Deliberately the same for an unknown email, a wrong password and a
    /// revoked account, so the answer does not reveal which accounts exist.
    #[error("login refused: wrong email or password")]
    LoginRefused,
    /// Too many attempts (login throttling) or too much work queued (the password hashing
    /// pool is full): nothing was evaluated; the same request may succeed after
    /// `retry_after_ms`. Answered 429 with `Retry-After`.
    #[error("{reason}; try again in {} s", (.retry_after_ms + 999) / 1000)]
    Throttled {
        /// What is throttled, for people.
        reason: String,
        /// How long to wait, ms.
        retry_after_ms: i64,
    },
    /// A pairing code was refused.
    #[error("pairing refused: {0}")]
    Pair(PairRefusal),
    /// The station's access has been revoked by the clinic.
    #[error("station {0:?} has been revoked")]
    StationRevoked(String),
    /// A Hello or Summary conflicts with what is stored (session of another station, patient
    /// mismatch, sequence number jump); the message says what.
    #[error("refused: {0}")]
    Conflict(String),
    /// The database could not be opened, migrated or queried.
    #[error("database error while {context}: {source}")]
    Database {
        /// What was being done.
        context: String,
        /// The driver's error.
        source: sqlx::Error,
    },
    /// A file-system operation failed.
    #[error("{context}: {source}")]
    Io {
        /// What was being done.
        context: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Password hashing failed (not a wrong password: that is [`HubError::LoginRefused`]).
    #[error("password hashing failed: {0}")]
    PasswordHash(String),
    /// TLS or server configuration refused.
    #[error("server configuration error: {0}")]
    Config(String),
    /// A stored value could not be decoded (a damaged row).
    #[error("stored data is damaged: {0}")]
    Corrupt(String),
}

impl HubError {
    /// `field` refused for `reason`, for which the console has no words of its own (a value
    /// only a hand-made request or a station sends): [`Code::FieldRefused`].
    pub fn invalid(field: &'static str, reason: impl Into<String>) -> Self {
        Self::refused(field, reason, Why::field(Code::FieldRefused, field))
    }

    /// `field` refused for `reason`, worded for the console by `why`.
    pub fn refused(field: &'static str, reason: impl Into<String>, why: Why) -> Self {
        Self::Invalid {
            field,
            reason: reason.into(),
            why,
        }
    }

    /// Why, for the console's words in any language ([`crate::refusal`]); `None` for a
    /// failure on the hub's side.
    pub fn why(&self) -> Option<Why> {
        Some(match self {
            Self::Invalid { why, .. } => why.clone(),
            Self::NotFound { what, .. } => Why::new(Code::NotFound).with("what", *what),
            Self::AlreadyExists { what, .. } => Why::new(Code::AlreadyExists).with("what", *what),
            Self::LoginRefused => Why::new(Code::LoginRefused),
            Self::Throttled { retry_after_ms, .. } => {
                Why::new(Code::Throttled).with("seconds", (retry_after_ms + 999) / 1000)
            }
            _ => return None,
        })
    }

    /// [`HubError::NotFound`]: no `what` with id `id`.
    pub fn not_found(what: &'static str, id: impl Into<String>) -> Self {
        Self::NotFound {
            what,
            id: id.into(),
        }
    }

    /// A mapper of I/O errors that says what was being done to which path: `what path`.
    pub fn io_at(what: &str, path: &std::path::Path) -> impl Fn(std::io::Error) -> Self + use<> {
        let context = format!("{what} {}", path.display());
        move |e| Self::io(context.clone(), e)
    }

    /// [`HubError::Io`]: `source` met while doing `context`.
    pub fn io(context: impl Into<String>, source: std::io::Error) -> Self {
        Self::Io {
            context: context.into(),
            source,
        }
    }

    /// A closure turning a driver error into [`HubError::Database`] naming `context`.
    pub fn db(context: &'static str) -> impl FnOnce(sqlx::Error) -> Self {
        move |source| Self::Database {
            context: context.to_owned(),
            source,
        }
    }

    /// True for a unique or primary-key violation (on either backend).
    pub(crate) fn is_unique_violation(e: &sqlx::Error) -> bool {
        matches!(e, sqlx::Error::Database(d) if d.is_unique_violation())
    }

    /// A closure turning an INSERT's driver error into [`HubError::AlreadyExists`] (`what`
    /// `id`) for a unique violation, else [`HubError::Database`] naming `context`.
    pub(crate) fn inserting(
        what: &'static str,
        id: &str,
        context: &'static str,
    ) -> impl FnOnce(sqlx::Error) -> Self + use<> {
        let id = id.to_owned();
        move |e| {
            if Self::is_unique_violation(&e) {
                Self::AlreadyExists { what, id }
            } else {
                Self::db(context)(e)
            }
        }
    }
}
