//! Therapist accounts (argon2id password hashes, a password policy, one-time passwords that
//! must be changed), logins (throttled: see the `logins` module for the design) and console
//! login sessions.

use std::net::IpAddr;
use std::sync::OnceLock;

use argon2::Argon2;
use argon2::password_hash::{PasswordHasher, PasswordVerifier};
use serde::Serialize;
use sqlx::any::AnyRow;

use super::logins::{ACCOUNT_RULE, ADDRESS_RULE, account_key, address_key, device_key, place_key};
use super::{Db, col, new_id, random_bytes, sha256_hex};
use crate::error::HubError;
use crate::refusal::{Code, Why};

mod language;
mod passwords;

pub use passwords::{
    COMMON_PASSWORDS, MAX_PASSWORD_BYTES, MIN_DISTINCT_CHARS, MIN_GUESSES_LOG10,
    MIN_PASSWORD_CHARS, check_new_password,
};

/// Failed logins of an account before its attempts are delayed (see
/// [`super::ACCOUNT_FREE_FAILURES`]; there is no lock anyone could keep up).
pub const MAX_FAILED_LOGINS: i64 = super::logins::ACCOUNT_FREE_FAILURES;

/// Longest wait a run of failed logins can impose, ms (15 minutes, on the failing address;
/// an account's own delay stops at [`super::ACCOUNT_MAX_DELAY_MS`]).
pub const LOCKOUT_MS: i64 = super::logins::ADDRESS_MAX_DELAY_MS;

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
    /// True while the account's password is a one-time password (`hub init`, `hub therapist
    /// add`): the console must change it before anything else.
    pub must_change_password: bool,
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
            must_change_password: col::<i64>(row, "must_change_password")? != 0,
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
        Err(HubError::refused(
            "email",
            "must look like name@domain, at most 254 characters, no spaces",
            Why::new(Code::BadEmail),
        ))
    }
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

/// The throttle a login's attempt went through besides its address's (see `super::logins`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Lane {
    /// The browser's device cookie.
    Device,
    /// A familiar place of the account, without a device cookie.
    Place,
    /// The account-wide throttle: a new browser at a new address, or a guesser.
    Account,
}

const THERAPIST_COLUMNS: &str = "id, email, role, created_at_ms, must_change_password";

/// One login attempt: who it claims to be and where it comes from.
#[derive(Debug, Clone, Copy)]
pub struct LoginAttempt<'a> {
    /// The e-mail typed.
    pub email: &'a str,
    /// The password typed.
    pub password: &'a str,
    /// The client's address, throttled on its own; `None` when unknown (only the account's
    /// or device's throttle applies).
    pub address: Option<IpAddr>,
    /// The browser's device cookie, if it sent one.
    pub device: Option<&'a str>,
}

impl<'a> LoginAttempt<'a> {
    /// An attempt from an unknown address without a device cookie (the command line, tests).
    pub fn new(email: &'a str, password: &'a str) -> Self {
        Self {
            email,
            password,
            address: None,
            device: None,
        }
    }
}

/// A successful login.
#[derive(Debug, Clone)]
pub struct LoginOk {
    /// Who logged in.
    pub therapist: Therapist,
    /// True if the attempt carried a valid device cookie of this account (no new one needed).
    pub known_device: bool,
}

impl Db {
    /// Creates a therapist account; the password must pass [`check_new_password`] and is
    /// stored as an argon2id PHC string (hashed on the bounded pool).
    pub async fn add_therapist(
        &self,
        email: &str,
        password: &str,
        role: Role,
        now_ms: i64,
    ) -> Result<Therapist, HubError> {
        let email = normalise_email(email)?;
        check_new_password(password, &email)?;
        let owned = password.to_owned();
        let hash = self.hashing().run(move || hash_password(&owned)).await??;
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
        .map_err(HubError::inserting(
            "therapist",
            &email,
            "adding a therapist",
        ))?;
        Ok(Therapist {
            id,
            email,
            role,
            created_at_ms: now_ms,
            must_change_password: false,
        })
    }

    /// Marks the account's password as one-time (`hub init`, `hub therapist add`): it must
    /// be changed at the first login before anything else is served.
    pub async fn require_password_change(&self, therapist_id: &str) -> Result<(), HubError> {
        let done = sqlx::query("UPDATE therapists SET must_change_password = 1 WHERE id = $1")
            .bind(therapist_id)
            .execute(self.pool())
            .await
            .map_err(HubError::db("marking a one-time password"))?;
        if done.rows_affected() == 0 {
            return Err(HubError::not_found("therapist", therapist_id));
        }
        Ok(())
    }

    /// Revokes a therapist: no more logins, every login session, device cookie and live
    /// stream of theirs ends (streams within a second).
    pub async fn revoke_therapist(&self, therapist_id: &str, now_ms: i64) -> Result<(), HubError> {
        let mut tx = self
            .pool()
            .begin()
            .await
            .map_err(HubError::db("starting a transaction"))?;
        let done = sqlx::query(
            "UPDATE therapists SET revoked_at_ms = $2 WHERE id = $1 AND revoked_at_ms IS NULL",
        )
        .bind(therapist_id)
        .bind(now_ms)
        .execute(&mut *tx)
        .await
        .map_err(HubError::db("revoking a therapist"))?;
        for table in ["web_sessions", "login_devices"] {
            sqlx::query(sqlx::AssertSqlSafe(format!(
                "DELETE FROM {table} WHERE therapist_id = $1"
            )))
            .bind(therapist_id)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("ending a revoked therapist's logins"))?;
        }
        tx.commit()
            .await
            .map_err(HubError::db("committing a revocation"))?;
        if done.rows_affected() == 0 && self.therapist(therapist_id).await?.is_none() {
            return Err(HubError::not_found("therapist", therapist_id));
        }
        Ok(())
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

    /// Every therapist account not revoked, by e-mail.
    pub async fn therapists(&self) -> Result<Vec<Therapist>, HubError> {
        let sql = sqlx::AssertSqlSafe(format!(
            "SELECT {THERAPIST_COLUMNS} FROM therapists WHERE revoked_at_ms IS NULL ORDER BY email"
        ));
        let rows = sqlx::query(sql)
            .fetch_all(self.pool())
            .await
            .map_err(HubError::db("listing therapists"))?;
        rows.iter().map(Therapist::from_row).collect()
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

    /// Checks a login from an unknown address without a device cookie; see [`Db::login`].
    pub async fn verify_login(
        &self,
        email: &str,
        password: &str,
        now_ms: i64,
    ) -> Result<Therapist, HubError> {
        Ok(self
            .login(LoginAttempt::new(email, password), now_ms)
            .await?
            .therapist)
    }

    /// Checks a login. Before any hashing the attempt is reserved, atomically, on the
    /// address's throttle and on one of the account's lanes: with a valid device cookie the
    /// device's, else from a familiar place (an address the account logged in from before) the
    /// place's, else the account-wide one; [`HubError::Throttled`] while either's delay runs,
    /// or when the hashing pool is full. A wrong password, an unknown e-mail and a revoked
    /// account are the same [`HubError::LoginRefused`], in the same time. A success clears the
    /// device's or the place's failures, or only gives its attempt back on the account-wide
    /// lane (which fades with time only), gives the address its attempt back, and makes the
    /// address a familiar place of the account.
    pub async fn login(&self, attempt: LoginAttempt<'_>, now_ms: i64) -> Result<LoginOk, HubError> {
        // A full pool refuses before any other work: a flood costs this check only.
        let ticket = self.hashing().ticket()?;
        let email = normalise_email(attempt.email).ok();
        let address = match attempt.address {
            Some(ip) => Some(
                self.reserve_attempt(&address_key(ip), ADDRESS_RULE, now_ms)
                    .await?,
            ),
            None => None,
        };
        let give_back_address = || async {
            if let Some(a) = &address {
                self.give_back(a, now_ms).await?;
            }
            Ok::<(), HubError>(())
        };
        let known_device = match (attempt.device, &email) {
            (Some(token), Some(email)) => self.device_of(token, email, now_ms).await?,
            _ => false,
        };
        let account = account_key(email.as_deref().unwrap_or("(not an e-mail address)"));
        let place = attempt.address.map(address_key);
        let familiar = match (&place, &email, known_device) {
            (Some(place), Some(_), false) => {
                self.is_familiar_place(&account, place, now_ms).await?
            }
            _ => false,
        };
        let (lane, gate_key) = match (known_device, attempt.device, &place) {
            (true, Some(token), _) => (Lane::Device, device_key(token)),
            (false, _, Some(place)) if familiar => (Lane::Place, place_key(&account, place)),
            _ => (Lane::Account, account.clone()),
        };
        let gate = match self.reserve_attempt(&gate_key, ACCOUNT_RULE, now_ms).await {
            Ok(g) => g,
            Err(e) => {
                give_back_address().await?;
                return Err(e);
            }
        };
        let row = match &email {
            Some(email) => sqlx::query(
                "SELECT id, email, role, created_at_ms, must_change_password, password_hash, \
                 revoked_at_ms FROM therapists WHERE email = $1",
            )
            .bind(email)
            .fetch_optional(self.pool())
            .await
            .map_err(HubError::db("reading a login"))?,
            None => None,
        };
        let (therapist, hash, revoked) = match &row {
            Some(row) => (
                Some(Therapist::from_row(row)?),
                Some(col::<String>(row, "password_hash")?),
                col::<Option<i64>>(row, "revoked_at_ms")?.is_some(),
            ),
            None => (None, None, false),
        };
        let password = attempt.password.to_owned();
        let checked = ticket
            .run(move || {
                let matches = |hash: &str| {
                    password.len() <= MAX_PASSWORD_BYTES && password_matches(&password, hash)
                };
                match &hash {
                    Some(hash) => matches(hash),
                    None => matches(dummy_hash()),
                }
            })
            .await;
        let matches = match checked {
            Ok(m) => m,
            Err(e) => {
                // Nothing was evaluated: both attempts go back.
                self.give_back(&gate, now_ms).await?;
                give_back_address().await?;
                return Err(e);
            }
        };
        match therapist {
            Some(therapist) if matches && !revoked => {
                match lane {
                    // The browser's or the place's own count starts again.
                    Lane::Device | Lane::Place => self.clear_throttle(&gate_key).await?,
                    // The account-wide count is shared with whoever guesses from elsewhere: a
                    // success only gives its own attempt back (no failure counted), so it
                    // never hands an attacker a fresh allowance; the count fades with time
                    // only ([`super::THROTTLE_FORGET_MS`]).
                    Lane::Account => self.give_back(&gate, now_ms).await?,
                }
                give_back_address().await?;
                if let Some(place) = &place {
                    self.remember_place(&account, place, now_ms).await?;
                }
                Ok(LoginOk {
                    therapist,
                    known_device,
                })
            }
            _ => Err(HubError::LoginRefused),
        }
    }

    /// Changes the password of the therapist with `email` (see [`Db::change_password_from`]);
    /// returns the new login token.
    pub async fn change_password(
        &self,
        email: &str,
        current: &str,
        new: &str,
        now_ms: i64,
        ttl_ms: i64,
    ) -> Result<String, HubError> {
        self.change_password_from(LoginAttempt::new(email, current), new, now_ms, ttl_ms)
            .await
    }

    /// Changes a password: the current one is checked as a login is (throttled, failures
    /// count), the new one must pass [`check_new_password`] and differ from it. Every login
    /// session of the account ends, the one making the change too: the returned token (a new
    /// session lasting `ttl_ms`) replaces it. A one-time password is no longer one.
    pub async fn change_password_from(
        &self,
        attempt: LoginAttempt<'_>,
        new: &str,
        now_ms: i64,
        ttl_ms: i64,
    ) -> Result<String, HubError> {
        let therapist = self.login(attempt, now_ms).await?.therapist;
        check_new_password(new, &therapist.email)?;
        if new == attempt.password {
            return Err(HubError::refused(
                "password",
                "the new password must differ from the current one",
                Why::new(Code::PasswordSame),
            ));
        }
        let owned = new.to_owned();
        let hash = self.hashing().run(move || hash_password(&owned)).await??;
        let mut tx = self
            .pool()
            .begin()
            .await
            .map_err(HubError::db("starting a transaction"))?;
        sqlx::query(
            "UPDATE therapists SET password_hash = $2, must_change_password = 0 WHERE id = $1",
        )
        .bind(&therapist.id)
        .bind(&hash)
        .execute(&mut *tx)
        .await
        .map_err(HubError::db("changing a password"))?;
        sqlx::query("DELETE FROM web_sessions WHERE therapist_id = $1")
            .bind(&therapist.id)
            .execute(&mut *tx)
            .await
            .map_err(HubError::db("ending the login sessions"))?;
        let token = super::hex(&random_bytes::<32>()?);
        insert_web_session(&mut tx, &token, &therapist.id, now_ms, ttl_ms).await?;
        tx.commit()
            .await
            .map_err(HubError::db("committing a password change"))?;
        Ok(token)
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
        let mut conn = self
            .pool()
            .acquire()
            .await
            .map_err(HubError::db("creating a login session"))?;
        insert_web_session(&mut conn, &token, therapist_id, now_ms, ttl_ms).await?;
        Ok(token)
    }

    /// The therapist logged in with `token`, if the session exists, has not expired and the
    /// therapist is not revoked. Live streams ask this again every second.
    pub async fn web_session(
        &self,
        token: &str,
        now_ms: i64,
    ) -> Result<Option<Therapist>, HubError> {
        let row = sqlx::query(
            "SELECT t.id, t.email, t.role, t.created_at_ms, t.must_change_password \
             FROM web_sessions w JOIN therapists t ON t.id = w.therapist_id \
             WHERE w.token_hash = $1 AND w.expires_at_ms > $2 AND t.revoked_at_ms IS NULL",
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

async fn insert_web_session(
    conn: &mut sqlx::AnyConnection,
    token: &str,
    therapist_id: &str,
    now_ms: i64,
    ttl_ms: i64,
) -> Result<(), HubError> {
    sqlx::query(
        "INSERT INTO web_sessions (token_hash, therapist_id, created_at_ms, expires_at_ms) \
         VALUES ($1, $2, $3, $4)",
    )
    .bind(sha256_hex(token.as_bytes()))
    .bind(therapist_id)
    .bind(now_ms)
    .bind(now_ms.saturating_add(ttl_ms))
    .execute(conn)
    .await
    .map_err(HubError::db("creating a login session"))?;
    Ok(())
}
