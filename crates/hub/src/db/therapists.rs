//! Therapist accounts (argon2id password hashes, lockout) and console login sessions.

use std::sync::OnceLock;

use argon2::Argon2;
use argon2::password_hash::{PasswordHasher, PasswordVerifier};
use serde::Serialize;
use sqlx::any::AnyRow;

use super::{Db, col, new_id, random_bytes, sha256_hex};
use crate::error::HubError;

/// Failed logins in a row that lock an account.
pub const MAX_FAILED_LOGINS: i64 = 5;

/// How long a locked account stays locked, ms (15 minutes).
pub const LOCKOUT_MS: i64 = 15 * 60 * 1000;

/// Shortest password accepted, characters.
pub const MIN_PASSWORD_CHARS: usize = 10;

/// Longest password accepted, bytes (argon2 hashes any length; this bounds the work).
pub const MAX_PASSWORD_BYTES: usize = 1024;

/// What a therapist account may do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum Role {
    /// Sees every patient and the audit log.
    Admin,
    /// Sees their own patients.
    Therapist,
}

impl Role {
    /// The role's name as stored (`admin` or `therapist`).
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Admin => "admin",
            Self::Therapist => "therapist",
        }
    }

    fn parse(text: &str) -> Result<Self, HubError> {
        match text {
            "admin" => Ok(Self::Admin),
            "therapist" => Ok(Self::Therapist),
            other => Err(HubError::Corrupt(format!("unknown role {other:?}"))),
        }
    }
}

/// A therapist account (the password hash never leaves the database layer).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Therapist {
    /// Identifier, `t-` + 16 hex digits.
    pub id: String,
    /// Login email, lowercase.
    pub email: String,
    /// What the account may do.
    pub role: Role,
    /// Creation time, ms since the Unix epoch.
    pub created_at_ms: i64,
}

impl Therapist {
    /// True for an administrator.
    pub fn is_admin(&self) -> bool {
        self.role == Role::Admin
    }

    /// The actor name of this therapist in the audit log, `therapist:<id>`.
    pub fn actor(&self) -> String {
        format!("therapist:{}", self.id)
    }

    fn from_row(row: &AnyRow) -> Result<Self, HubError> {
        Ok(Self {
            id: col(row, "id")?,
            email: col(row, "email")?,
            role: Role::parse(&col::<String>(row, "role")?)?,
            created_at_ms: col(row, "created_at_ms")?,
        })
    }
}

/// Lowercased, checked email address.
fn normalise_email(email: &str) -> Result<String, HubError> {
    let email = email.trim().to_lowercase();
    let ok = email.len() <= 254
        && !email.chars().any(|c| c.is_whitespace() || c.is_control())
        && email
            .split_once('@')
            .is_some_and(|(local, domain)| !local.is_empty() && !domain.is_empty());
    if ok {
        Ok(email)
    } else {
        Err(HubError::invalid(
            "email",
            "must look like name@domain, at most 254 characters, no spaces",
        ))
    }
}

/// A password a therapist may choose: at least [`MIN_PASSWORD_CHARS`] characters, at most
/// [`MAX_PASSWORD_BYTES`] bytes.
fn check_new_password(password: &str) -> Result<(), HubError> {
    if password.chars().count() < MIN_PASSWORD_CHARS || password.len() > MAX_PASSWORD_BYTES {
        return Err(HubError::invalid(
            "password",
            format!(
                "must have at least {MIN_PASSWORD_CHARS} characters and at most \
                 {MAX_PASSWORD_BYTES} bytes"
            ),
        ));
    }
    Ok(())
}

fn hash_password(password: &str) -> Result<String, HubError> {
    Argon2::default()
        .hash_password(password.as_bytes())
        .map(|h| h.to_string())
        .map_err(|e| HubError::PasswordHash(e.to_string()))
}

/// A valid hash of a random password, verified against when the email is unknown so that
/// unknown and known emails take the same time.
fn dummy_hash() -> &'static str {
    static DUMMY: OnceLock<String> = OnceLock::new();
    DUMMY.get_or_init(|| {
        hash_password("no account has this password, it only costs time").unwrap_or_default()
    })
}

fn password_matches(password: &str, hash: &str) -> bool {
    Argon2::default()
        .verify_password(password.as_bytes(), hash)
        .is_ok()
}

const THERAPIST_COLUMNS: &str = "id, email, role, created_at_ms";

impl Db {
    /// Creates a therapist account; the password (≥ 10 characters) is stored as an argon2id
    /// PHC string.
    pub async fn add_therapist(
        &self,
        email: &str,
        password: &str,
        role: Role,
        now_ms: i64,
    ) -> Result<Therapist, HubError> {
        let email = normalise_email(email)?;
        check_new_password(password)?;
        let hash = hash_password(password)?;
        let id = new_id("t-")?;
        sqlx::query(
            "INSERT INTO therapists (id, email, password_hash, role, created_at_ms, \
             failed_logins) VALUES ($1, $2, $3, $4, $5, 0)",
        )
        .bind(&id)
        .bind(&email)
        .bind(&hash)
        .bind(role.as_str())
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(|e| {
            if HubError::is_unique_violation(&e) {
                HubError::AlreadyExists {
                    what: "therapist",
                    id: email.clone(),
                }
            } else {
                HubError::db("adding a therapist")(e)
            }
        })?;
        Ok(Therapist {
            id,
            email,
            role,
            created_at_ms: now_ms,
        })
    }

    /// The therapist whose `column` (`id` or `email`, never input) equals `value`, if any.
    async fn therapist_where(
        &self,
        column: &'static str,
        value: &str,
    ) -> Result<Option<Therapist>, HubError> {
        let sql = sqlx::AssertSqlSafe(format!(
            "SELECT {THERAPIST_COLUMNS} FROM therapists WHERE {column} = $1"
        ));
        let row = sqlx::query(sql)
            .bind(value)
            .fetch_optional(self.pool())
            .await
            .map_err(HubError::db("reading a therapist"))?;
        row.as_ref().map(Therapist::from_row).transpose()
    }

    /// The therapist with this id, if any.
    pub async fn therapist(&self, id: &str) -> Result<Option<Therapist>, HubError> {
        self.therapist_where("id", id).await
    }

    /// The therapist with this e-mail (compared lowercased, as stored), if any.
    pub async fn therapist_by_email(&self, email: &str) -> Result<Option<Therapist>, HubError> {
        self.therapist_where("email", &email.trim().to_lowercase())
            .await
    }

    /// Checks a login. [`MAX_FAILED_LOGINS`] failures in a row lock the account for
    /// [`LOCKOUT_MS`]; while locked even the right password is refused. Every refusal is the
    /// same [`HubError::LoginRefused`], whether or not the email exists.
    pub async fn verify_login(
        &self,
        email: &str,
        password: &str,
        now_ms: i64,
    ) -> Result<Therapist, HubError> {
        let Ok(email) = normalise_email(email) else {
            password_matches(password, dummy_hash());
            return Err(HubError::LoginRefused);
        };
        let row = sqlx::query(
            "SELECT id, email, role, created_at_ms, password_hash, locked_until_ms \
             FROM therapists WHERE email = $1",
        )
        .bind(&email)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a login"))?;
        let Some(row) = row else {
            password_matches(password, dummy_hash());
            return Err(HubError::LoginRefused);
        };
        let therapist = Therapist::from_row(&row)?;
        let hash: String = col(&row, "password_hash")?;
        let locked_until: Option<i64> = col(&row, "locked_until_ms")?;
        let matches = password.len() <= MAX_PASSWORD_BYTES && password_matches(password, &hash);
        if locked_until.is_some_and(|until| now_ms < until) {
            return Err(HubError::LoginRefused);
        }
        if matches {
            sqlx::query(
                "UPDATE therapists SET failed_logins = 0, locked_until_ms = NULL WHERE id = $1",
            )
            .bind(&therapist.id)
            .execute(self.pool())
            .await
            .map_err(HubError::db("recording a login"))?;
            return Ok(therapist);
        }
        let failures: i64 = sqlx::query_scalar(
            "UPDATE therapists SET failed_logins = failed_logins + 1 WHERE id = $1 \
             RETURNING failed_logins",
        )
        .bind(&therapist.id)
        .fetch_one(self.pool())
        .await
        .map_err(HubError::db("recording a failed login"))?;
        if failures >= MAX_FAILED_LOGINS {
            sqlx::query(
                "UPDATE therapists SET failed_logins = 0, locked_until_ms = $2 WHERE id = $1",
            )
            .bind(&therapist.id)
            .bind(now_ms.saturating_add(LOCKOUT_MS))
            .execute(self.pool())
            .await
            .map_err(HubError::db("locking an account"))?;
            tracing::warn!(therapist = %therapist.id, "account locked after failed logins");
        }
        Err(HubError::LoginRefused)
    }

    /// Changes the password of the therapist with `email` (the one-time password `hub init`
    /// printed, or any other): `current` is checked as a login is (failures count towards the
    /// lockout), the new one as at account creation and different from `current`. Every other
    /// login session of the account ends (`keep_token` stays logged in).
    pub async fn change_password(
        &self,
        email: &str,
        current: &str,
        new: &str,
        keep_token: &str,
        now_ms: i64,
    ) -> Result<(), HubError> {
        let therapist = self.verify_login(email, current, now_ms).await?;
        check_new_password(new)?;
        if new == current {
            return Err(HubError::invalid(
                "password",
                "the new password must differ from the current one",
            ));
        }
        let hash = hash_password(new)?;
        let mut tx = self
            .pool()
            .begin()
            .await
            .map_err(HubError::db("starting a transaction"))?;
        sqlx::query("UPDATE therapists SET password_hash = $2 WHERE id = $1")
            .bind(&therapist.id)
            .bind(&hash)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("changing a password"))?;
        sqlx::query("DELETE FROM web_sessions WHERE therapist_id = $1 AND token_hash <> $2")
            .bind(&therapist.id)
            .bind(sha256_hex(keep_token.as_bytes()))
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("ending other login sessions"))?;
        tx.commit()
            .await
            .map_err(HubError::db("committing a password change"))
    }

    /// Starts a console login session for `therapist_id` lasting `ttl_ms`; returns the bearer
    /// token (64 hex digits, 256 random bits). Only its SHA-256 is stored.
    pub async fn create_web_session(
        &self,
        therapist_id: &str,
        now_ms: i64,
        ttl_ms: i64,
    ) -> Result<String, HubError> {
        let token = super::hex(&random_bytes::<32>()?);
        sqlx::query(
            "INSERT INTO web_sessions (token_hash, therapist_id, created_at_ms, expires_at_ms) \
             VALUES ($1, $2, $3, $4)",
        )
        .bind(sha256_hex(token.as_bytes()))
        .bind(therapist_id)
        .bind(now_ms)
        .bind(now_ms.saturating_add(ttl_ms))
        .execute(self.pool())
        .await
        .map_err(HubError::db("creating a login session"))?;
        Ok(token)
    }

    /// The therapist logged in with `token`, if the session exists and has not expired.
    pub async fn web_session(
        &self,
        token: &str,
        now_ms: i64,
    ) -> Result<Option<Therapist>, HubError> {
        let row = sqlx::query(
            "SELECT t.id, t.email, t.role, t.created_at_ms FROM web_sessions w \
             JOIN therapists t ON t.id = w.therapist_id \
             WHERE w.token_hash = $1 AND w.expires_at_ms > $2",
        )
        .bind(sha256_hex(token.as_bytes()))
        .bind(now_ms)
        .fetch_optional(self.pool())
        .await
        .map_err(HubError::db("reading a login session"))?;
        row.as_ref().map(Therapist::from_row).transpose()
    }

    /// Ends the login session of `token` (and purges expired sessions).
    pub async fn delete_web_session(&self, token: &str, now_ms: i64) -> Result<(), HubError> {
        sqlx::query("DELETE FROM web_sessions WHERE token_hash = $1 OR expires_at_ms <= $2")
            .bind(sha256_hex(token.as_bytes()))
            .bind(now_ms)
            .execute(self.pool())
            .await
            .map_err(HubError::db("ending a login session"))?;
        Ok(())
    }
}
