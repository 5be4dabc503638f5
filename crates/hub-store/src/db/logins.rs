//! What keeps logins from being turned against therapists or the clinic: throttling with
//! growing delays per client address, per account and per device cookie; a bounded pool for
//! password hashing; and rate-limited audit entries for refusals (per source, per account and
//! in all).
//!
//! # Why growing delays and not a lock (OWASP Authentication Cheat Sheet)
//!
//! The cheat sheet's "Protect Against Automated Attacks" section asks for a limit on failed
//! attempts per account, but warns that an account lockout lets anyone deny a user service by
//! failing on purpose, and that the counter must not be bypassable by spreading guesses over
//! time or addresses. It names as mitigations a lockout that grows (exponential back-off)
//! instead of a fixed one, throttling by source as well as by account, and *device cookies*,
//! which let a browser that logged in before skip the account-wide throttle. The hub combines
//! the three:
//!
//! - **Per address** (IPv4 address, IPv6 /64): [`ADDRESS_FREE_FAILURES`] failures, then each
//!   further attempt waits `1 s · 2^(n − 5)` up to [`ADDRESS_MAX_DELAY_MS`] (15 min). This
//!   carries most of the weight: a guessing address quickly gets one guess per 15 minutes,
//!   whatever accounts it tries.
//! - **Per account** (keyed by the e-mail's hash, whether or not the account exists, so the
//!   answers reveal nothing): [`ACCOUNT_FREE_FAILURES`] failures, then `1 s · 2^(n − 5)` up to
//!   only [`ACCOUNT_MAX_DELAY_MS`] (1 min). It bounds guessing spread over many addresses to
//!   about 60 guesses an hour per account, yet can never shut the therapist out for longer
//!   than a minute at a time; the console shows the wait and retries.
//! - **Per device**: a browser that logged in to the account before holds a device cookie
//!   (HttpOnly, 90 days); its attempts are throttled by their own counter (same rule as the
//!   account) *instead of* the account's, so an attacker elsewhere who keeps the account's
//!   delay up does not lock out the therapist's own browser at all.
//! - **Per familiar place**: without a device cookie (a new browser, cookies cleared), an
//!   attempt from an address the account logged in from before (kept 90 days, the
//!   [`MAX_PLACES_PER_ACCOUNT`] most recent: the clinic, home) is throttled by that place's own
//!   counter instead of the account's — the "familiar location" of Microsoft's smart lockout.
//!   An attacker there is held by the address throttle besides.
//!
//! A correct password from an address and a device that have not failed is therefore subject
//! only to the account's delay (at most a minute), or to nothing with the device cookie or
//! from a familiar place. Only a new browser at a new address shares the account-wide delay
//! with a guesser rotating addresses, and waits at most a minute at a time for it.
//!
//! A success clears the count of the device's or the place's throttle it went through. On the
//! account-wide throttle it only gives its own attempt back (it was not a failure): that count
//! is shared with whoever guesses from elsewhere, and clearing it handed a rotating attacker a
//! fresh allowance at every login of the therapist (issue 44: 21 guesses evaluated in 150 s
//! against the 60 an hour documented). It fades with time only: failures are forgotten after
//! [`THROTTLE_FORGET_MS`] without one. A success also gives the address its attempt back and
//! makes it a familiar place of the account.
//!
//! Every attempt is *reserved* before any hashing by one conditional upsert per key
//! (`… ON CONFLICT DO UPDATE SET failures = failures + 1, next_allowed_ms = … WHERE
//! next_allowed_ms <= now RETURNING failures`): parallel guesses cannot all pass a check made
//! before the counter moves, so of 100 sent at once at most the free allowance is evaluated.

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, Sender};
use std::sync::{Arc, Mutex, OnceLock};

use super::{Db, hex, random_bytes, sha256_hex};
use crate::error::HubError;

/// Failed logins from one address before its attempts are delayed.
pub const ADDRESS_FREE_FAILURES: i64 = 5;
/// Longest delay between attempts from one address, ms (15 minutes).
pub const ADDRESS_MAX_DELAY_MS: i64 = 15 * 60 * 1000;
/// Failed logins of one account (or device) before its attempts are delayed.
pub const ACCOUNT_FREE_FAILURES: i64 = 5;
/// Longest delay between attempts on one account (or device), ms (1 minute).
pub const ACCOUNT_MAX_DELAY_MS: i64 = 60 * 1000;
/// First delay once the free failures are used up, ms; it doubles with each failure.
pub const BASE_DELAY_MS: i64 = 1000;
/// Failures are forgotten after this long without one, ms (24 hours).
pub const THROTTLE_FORGET_MS: i64 = 24 * 60 * 60 * 1000;
/// Lifetime of a device cookie, ms (90 days); a familiar place is forgotten after as long
/// without a success from it.
pub const DEVICE_TTL_MS: i64 = 90 * 24 * 60 * 60 * 1000;
/// Familiar places kept per account (the most recent successes).
pub const MAX_PLACES_PER_ACCOUNT: i64 = 16;
/// Password checks that may wait for a busy hashing thread; more are answered 429 at once.
pub const HASH_QUEUE: usize = 8;
/// Refusals of one source (a client address, a station) written to the audit log per minute;
/// the rest are counted and written as one `refusals_suppressed` entry when the minute is
/// over.
pub const REFUSAL_AUDITS_PER_MINUTE: u32 = 20;
/// Refusals concerning one account (the e-mail a login tried, the therapist refused) written
/// per minute, whatever their sources: rotating addresses get no fresh allowance.
pub const REFUSAL_AUDITS_PER_ACCOUNT_PER_MINUTE: u32 = 20;
/// Refusals written per minute in all, whatever their sources and accounts.
pub const REFUSAL_AUDITS_TOTAL_PER_MINUTE: u32 = 100;
/// The refusal limiter's key of the window counting every refusal.
const ALL_REFUSALS: &str = "all sources";

const MINUTE_MS: i64 = 60_000;
/// Sources tracked by the refusal limiter; beyond, refusals share one `other` source.
const MAX_REFUSAL_SOURCES: usize = 10_000;

/// A throttle's rule: `free` failures, then delays doubling from [`BASE_DELAY_MS`] to `max_ms`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Rule {
    free: i64,
    max_ms: i64,
}

/// The per-address rule.
pub(crate) const ADDRESS_RULE: Rule = Rule {
    free: ADDRESS_FREE_FAILURES,
    max_ms: ADDRESS_MAX_DELAY_MS,
};
/// The per-account and per-device rule.
pub(crate) const ACCOUNT_RULE: Rule = Rule {
    free: ACCOUNT_FREE_FAILURES,
    max_ms: ACCOUNT_MAX_DELAY_MS,
};

impl Rule {
    /// The wait after the `failures`-th failure, ms.
    pub(crate) fn delay_ms(self, failures: i64) -> i64 {
        if failures < self.free {
            return 0;
        }
        let doublings = u32::try_from(failures - self.free)
            .unwrap_or(u32::MAX)
            .min(40);
        BASE_DELAY_MS
            .saturating_mul(1_i64 << doublings)
            .min(self.max_ms)
    }

    /// `CASE` over the SQL integer expression `n` giving [`Rule::delay_ms`]`(n)` (the table is
    /// short: the delay reaches its cap after a few doublings).
    fn case_sql(self, n: &str) -> String {
        let mut sql = format!("CASE WHEN {n} < {} THEN 0", self.free);
        let mut k = self.free;
        loop {
            let d = self.delay_ms(k);
            if d >= self.max_ms {
                break;
            }
            sql.push_str(&format!(" WHEN {n} = {k} THEN {d}"));
            k += 1;
        }
        sql.push_str(&format!(" ELSE {} END", self.max_ms));
        sql
    }
}

/// The throttle key of a client address: the address itself for IPv4, its /64 for IPv6 (one
/// host usually holds a whole /64).
pub fn address_key(ip: IpAddr) -> String {
    match ip {
        IpAddr::V4(v4) => format!("addr:{v4}"),
        IpAddr::V6(v6) => match v6.to_ipv4_mapped() {
            Some(v4) => format!("addr:{v4}"),
            None => {
                let s = v6.segments();
                format!("addr:{:x}:{:x}:{:x}:{:x}::/64", s[0], s[1], s[2], s[3])
            }
        },
    }
}

/// The throttle key of a login e-mail (hashed: attackers' typing is not stored).
pub(crate) fn account_key(email: &str) -> String {
    format!("acct:{}", &sha256_hex(email.as_bytes())[..32])
}

/// The throttle key of a device cookie.
pub(crate) fn device_key(token: &str) -> String {
    format!("dev:{}", &sha256_hex(token.as_bytes())[..32])
}

/// The throttle key of an account's familiar place: the account's key and an address key.
pub(crate) fn place_key(account_key: &str, address_key: &str) -> String {
    let both = format!("{account_key}|{address_key}");
    format!("place:{}", &sha256_hex(both.as_bytes())[..32])
}

type Job = Box<dyn FnOnce() + Send>;

/// A fixed set of low-priority threads for argon2 with bounded admission: password checks run
/// off the async workers (which serve the stations) and can never pile up.
pub(crate) struct HashPool {
    sender: OnceLock<Sender<Job>>,
    /// Checks admitted and not finished (running or queued).
    admitted: Arc<AtomicUsize>,
}

/// A place in the hashing pool, taken before any other work of a login (so a full pool
/// costs a refused client nothing but this check); released when dropped.
pub(crate) struct HashTicket<'a> {
    pool: &'a HashPool,
    place: Place,
}

/// One of the pool's places, given back when dropped: by the ticket if it is never used, else
/// by the job on the hashing thread once it has run (a client that goes away mid-wait does not
/// free a place its queued check still holds).
struct Place(Arc<AtomicUsize>);

impl Drop for Place {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::AcqRel);
    }
}

impl HashPool {
    fn new() -> Self {
        Self {
            sender: OnceLock::new(),
            admitted: Arc::new(AtomicUsize::new(0)),
        }
    }

    /// One thread fewer than the machine has cores (at least one), so password checks never
    /// take every core from the stations.
    pub(crate) fn threads() -> usize {
        std::thread::available_parallelism()
            .map_or(1, std::num::NonZeroUsize::get)
            .saturating_sub(1)
            .max(1)
    }

    fn sender(&self) -> &Sender<Job> {
        self.sender.get_or_init(|| {
            let (tx, rx) = std::sync::mpsc::channel::<Job>();
            let rx = Arc::new(Mutex::new(rx));
            for i in 0..Self::threads() {
                let rx = Arc::clone(&rx);
                let spawned = std::thread::Builder::new()
                    .name(format!("hub-argon2-{i}"))
                    .spawn(move || hash_worker(&rx));
                if let Err(e) = spawned {
                    tracing::error!("cannot start a password hashing thread: {e}");
                }
            }
            tx
        })
    }

    /// A place for one password check; [`HubError::Throttled`] at once when every thread is
    /// busy and [`HASH_QUEUE`] checks already wait.
    pub(crate) fn ticket(&self) -> Result<HashTicket<'_>, HubError> {
        let limit = Self::threads() + HASH_QUEUE;
        let admitted = self
            .admitted
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| {
                (n < limit).then_some(n + 1)
            });
        match admitted {
            Ok(_) => Ok(HashTicket {
                pool: self,
                place: Place(Arc::clone(&self.admitted)),
            }),
            Err(_) => Err(HubError::Throttled {
                reason: "the hub is busy checking other passwords".to_owned(),
                retry_after_ms: 1000,
            }),
        }
    }

    /// Takes a ticket and runs `job` with it (see [`HashTicket::run`]).
    pub(crate) async fn run<T: Send + 'static>(
        &self,
        job: impl FnOnce() -> T + Send + 'static,
    ) -> Result<T, HubError> {
        self.ticket()?.run(job).await
    }
}

impl HashTicket<'_> {
    /// Runs `job` on a hashing thread, in turn.
    pub(crate) async fn run<T: Send + 'static>(
        self,
        job: impl FnOnce() -> T + Send + 'static,
    ) -> Result<T, HubError> {
        let (tx, rx) = tokio::sync::oneshot::channel();
        let Self { pool, place } = self;
        let boxed: Job = Box::new(move || {
            let _ = tx.send(job());
            drop(place);
        });
        pool.sender().send(boxed).map_err(|_| {
            HubError::PasswordHash("no password hashing thread is running".to_owned())
        })?;
        rx.await
            .map_err(|_| HubError::PasswordHash("the password hashing thread failed".to_owned()))
    }
}

fn hash_worker(rx: &Mutex<Receiver<Job>>) {
    lower_priority();
    loop {
        let job = match rx.lock() {
            Ok(guard) => guard.recv(),
            Err(_) => return,
        };
        match job {
            Ok(job) => job(),
            Err(_) => return, // the pool was dropped
        }
    }
}

/// Batch scheduling at about nice 10: the stations' and the console's threads come first.
fn lower_priority() {
    #[cfg(target_os = "linux")]
    {
        use thread_priority::{
            NormalThreadSchedulePolicy, ThreadPriority, ThreadPriorityValue, ThreadSchedulePolicy,
            set_thread_priority_and_policy, thread_native_id,
        };
        let Ok(value) = ThreadPriorityValue::try_from(25u8) else {
            return;
        };
        if let Err(e) = set_thread_priority_and_policy(
            thread_native_id(),
            ThreadPriority::Crossplatform(value),
            ThreadSchedulePolicy::Normal(NormalThreadSchedulePolicy::Batch),
        ) {
            tracing::debug!("password hashing thread keeps its priority: {e:?}");
        }
    }
}

/// One source's refusals in the current minute.
#[derive(Debug)]
struct RefusalWindow {
    start_ms: i64,
    written: u32,
    suppressed: u64,
}

/// Per-process state of a [`Db`]'s login guards.
pub(crate) struct Guards {
    pub(crate) hashing: HashPool,
    refusals: Mutex<HashMap<String, RefusalWindow>>,
}

impl std::fmt::Debug for Guards {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Guards").finish_non_exhaustive()
    }
}

impl Guards {
    pub(crate) fn new() -> Self {
        Self {
            hashing: HashPool::new(),
            refusals: Mutex::new(HashMap::new()),
        }
    }
}

/// An attempt reserved on one throttle key.
#[derive(Debug, Clone)]
pub(crate) struct Reserved {
    key: String,
    rule: Rule,
}

impl Db {
    /// Reserves one attempt on `key`: counts it as a failure in advance and starts the delay
    /// that failure earns. `Err(Throttled)` (nothing changed) while the key's delay runs.
    pub(crate) async fn reserve_attempt(
        &self,
        key: &str,
        rule: Rule,
        now_ms: i64,
    ) -> Result<Reserved, HubError> {
        let failures = "CASE WHEN login_throttle.updated_at_ms < $3 THEN 0 \
                        ELSE login_throttle.failures END";
        let sql = format!(
            "INSERT INTO login_throttle (key, failures, next_allowed_ms, updated_at_ms) \
             VALUES ($1, 1, $2 + {first}, $2) \
             ON CONFLICT (key) DO UPDATE SET failures = {failures} + 1, \
             next_allowed_ms = $2 + {delay}, updated_at_ms = $2 \
             WHERE login_throttle.next_allowed_ms <= $2 RETURNING failures",
            first = rule.delay_ms(1),
            delay = rule.case_sql(&format!("({failures} + 1)")),
        );
        let row: Option<i64> = sqlx::query_scalar(sqlx::AssertSqlSafe(sql))
            .bind(key)
            .bind(now_ms)
            .bind(now_ms.saturating_sub(THROTTLE_FORGET_MS))
            .fetch_optional(self.pool())
            .await
            .map_err(HubError::db("reserving a login attempt"))?;
        if row.is_some() {
            return Ok(Reserved {
                key: key.to_owned(),
                rule,
            });
        }
        let next: Option<i64> =
            sqlx::query_scalar("SELECT next_allowed_ms FROM login_throttle WHERE key = $1")
                .bind(key)
                .fetch_optional(self.pool())
                .await
                .map_err(HubError::db("reading a login throttle"))?;
        let what = if key.starts_with("addr:") {
            "too many failed logins from this address"
        } else {
            "too many failed logins for this account"
        };
        Err(HubError::Throttled {
            reason: what.to_owned(),
            retry_after_ms: next.map_or(1000, |n| n.saturating_sub(now_ms).max(1)),
        })
    }

    /// Gives a reserved attempt back (it was not a failure): one failure less, and no delay
    /// if that brings the key under its free allowance.
    pub(crate) async fn give_back(&self, reserved: &Reserved, now_ms: i64) -> Result<(), HubError> {
        let sql = format!(
            "UPDATE login_throttle SET failures = failures - 1, \
             next_allowed_ms = CASE WHEN failures - 1 < {free} THEN $2 ELSE next_allowed_ms END \
             WHERE key = $1 AND failures > 0",
            free = reserved.rule.free
        );
        sqlx::query(sqlx::AssertSqlSafe(sql))
            .bind(&reserved.key)
            .bind(now_ms)
            .execute(self.pool())
            .await
            .map_err(HubError::db("giving back a login attempt"))?;
        Ok(())
    }

    /// Clears a key's failures (a successful login clears its account's and device's).
    pub(crate) async fn clear_throttle(&self, key: &str) -> Result<(), HubError> {
        sqlx::query("DELETE FROM login_throttle WHERE key = $1")
            .bind(key)
            .execute(self.pool())
            .await
            .map_err(HubError::db("clearing a login throttle"))?;
        Ok(())
    }

    /// Forgets throttles without a failure for [`THROTTLE_FORGET_MS`], expired device
    /// cookies and familiar places (the table of guessed e-mails cannot grow without bound); `hub serve` calls it
    /// every `hub::clinic::HOUSEKEEPING`, whether or not anyone logs in.
    pub async fn purge_throttles(&self, now_ms: i64) -> Result<(), HubError> {
        sqlx::query(
            "DELETE FROM login_throttle WHERE updated_at_ms < $1 AND next_allowed_ms <= $2",
        )
        .bind(now_ms.saturating_sub(THROTTLE_FORGET_MS))
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("purging login throttles"))?;
        sqlx::query("DELETE FROM login_devices WHERE expires_at_ms <= $1")
            .bind(now_ms)
            .execute(self.pool())
            .await
            .map_err(HubError::db("purging device cookies"))?;
        sqlx::query("DELETE FROM login_places WHERE last_success_ms <= $1")
            .bind(now_ms.saturating_sub(DEVICE_TTL_MS))
            .execute(self.pool())
            .await
            .map_err(HubError::db("purging familiar places"))?;
        Ok(())
    }

    /// The failures counted on a throttle key (0 if none): for tests and operators.
    pub async fn throttle_failures(&self, key: &str) -> Result<i64, HubError> {
        let n: Option<i64> =
            sqlx::query_scalar("SELECT failures FROM login_throttle WHERE key = $1")
                .bind(key)
                .fetch_optional(self.pool())
                .await
                .map_err(HubError::db("reading a login throttle"))?;
        Ok(n.unwrap_or(0))
    }

    /// True if the account with throttle key `account_key` logged in successfully from the
    /// address with key `address_key` within [`DEVICE_TTL_MS`].
    pub(crate) async fn is_familiar_place(
        &self,
        account_key: &str,
        address_key: &str,
        now_ms: i64,
    ) -> Result<bool, HubError> {
        let n: i64 = sqlx::query_scalar(
            "SELECT COUNT(*) FROM login_places WHERE account_key = $1 AND address_key = $2 \
             AND last_success_ms > $3",
        )
        .bind(account_key)
        .bind(address_key)
        .bind(now_ms.saturating_sub(DEVICE_TTL_MS))
        .fetch_one(self.pool())
        .await
        .map_err(HubError::db("reading a familiar place"))?;
        Ok(n > 0)
    }

    /// Remembers a successful login of the account `account_key` from `address_key`, keeping
    /// the account's [`MAX_PLACES_PER_ACCOUNT`] most recent places.
    pub(crate) async fn remember_place(
        &self,
        account_key: &str,
        address_key: &str,
        now_ms: i64,
    ) -> Result<(), HubError> {
        sqlx::query(
            "INSERT INTO login_places (account_key, address_key, last_success_ms) \
             VALUES ($1, $2, $3) ON CONFLICT (account_key, address_key) \
             DO UPDATE SET last_success_ms = excluded.last_success_ms",
        )
        .bind(account_key)
        .bind(address_key)
        .bind(now_ms)
        .execute(self.pool())
        .await
        .map_err(HubError::db("remembering a familiar place"))?;
        sqlx::query(
            "DELETE FROM login_places WHERE account_key = $1 AND address_key NOT IN \
             (SELECT address_key FROM login_places WHERE account_key = $1 \
              ORDER BY last_success_ms DESC, address_key LIMIT $2)",
        )
        .bind(account_key)
        .bind(MAX_PLACES_PER_ACCOUNT)
        .execute(self.pool())
        .await
        .map_err(HubError::db("forgetting old familiar places"))?;
        Ok(())
    }

    /// A new device cookie for `therapist_id` (64 hex digits; only its SHA-256 is stored).
    pub async fn create_device(&self, therapist_id: &str, now_ms: i64) -> Result<String, HubError> {
        let token = hex(&random_bytes::<32>()?);
        sqlx::query(
            "INSERT INTO login_devices (token_hash, therapist_id, created_at_ms, expires_at_ms) \
             VALUES ($1, $2, $3, $4)",
        )
        .bind(sha256_hex(token.as_bytes()))
        .bind(therapist_id)
        .bind(now_ms)
        .bind(now_ms.saturating_add(DEVICE_TTL_MS))
        .execute(self.pool())
        .await
        .map_err(HubError::db("storing a device cookie"))?;
        Ok(token)
    }

    /// True if `token` is an unexpired device cookie of the account with this (normalised)
    /// e-mail.
    pub(crate) async fn device_of(
        &self,
        token: &str,
        email: &str,
        now_ms: i64,
    ) -> Result<bool, HubError> {
        let n: i64 = sqlx::query_scalar(
            "SELECT COUNT(*) FROM login_devices d JOIN therapists t ON t.id = d.therapist_id \
             WHERE d.token_hash = $1 AND t.email = $2 AND d.expires_at_ms > $3",
        )
        .bind(sha256_hex(token.as_bytes()))
        .bind(email)
        .bind(now_ms)
        .fetch_one(self.pool())
        .await
        .map_err(HubError::db("reading a device cookie"))?;
        Ok(n > 0)
    }

    /// Audits a refusal (a refused login, a 401, 403 or 404 on patient data, a rate limit, a
    /// refused station) without letting a flood fill the log; see
    /// [`Db::audit_account_refusal`] (this is one that concerns no account).
    pub async fn audit_refusal(
        &self,
        actor: &str,
        action: &str,
        target: &str,
        detail: &str,
        source: &str,
        now_ms: i64,
    ) -> Result<(), HubError> {
        self.audit_account_refusal(actor, action, target, detail, source, None, now_ms)
            .await
    }

    /// Audits a refusal without letting a flood fill the log: an entry is written only while
    /// its `source` (a client address, a station id) has written fewer than
    /// [`REFUSAL_AUDITS_PER_MINUTE`] this minute, its `account` (the e-mail a login tried, the
    /// refused therapist; `None`: none) fewer than [`REFUSAL_AUDITS_PER_ACCOUNT_PER_MINUTE`],
    /// and the hub fewer than [`REFUSAL_AUDITS_TOTAL_PER_MINUTE`]. Nothing is silently lost:
    /// a refusal not written is counted on the widest of these limits that is full, and each
    /// limit that counted some writes one `refusals_suppressed` entry (actor `hub`, target
    /// the source, `account …` or `all sources`, detail the count and the minute) once its
    /// minute is over — at the next refusal, or when the log is read
    /// ([`Db::flush_refusal_audits`]). A burst therefore writes at most the total a minute,
    /// plus a few summaries.
    #[allow(clippy::too_many_arguments)]
    pub async fn audit_account_refusal(
        &self,
        actor: &str,
        action: &str,
        target: &str,
        detail: &str,
        source: &str,
        account: Option<&str>,
        now_ms: i64,
    ) -> Result<(), HubError> {
        let (write, finished) = {
            let mut windows = self
                .guards
                .refusals
                .lock()
                .map_err(|_| HubError::Corrupt("refusal limiter poisoned".to_owned()))?;
            let finished = take_finished(&mut windows, now_ms);
            let account_key = account.map(|a| {
                let a: String = a.chars().take(254).collect();
                format!("account {a}")
            });
            // Widest first: the window a suppressed refusal is counted on.
            let mut keys: Vec<(String, u32)> =
                vec![(ALL_REFUSALS.to_owned(), REFUSAL_AUDITS_TOTAL_PER_MINUTE)];
            if let Some(k) = account_key {
                keys.push((k, REFUSAL_AUDITS_PER_ACCOUNT_PER_MINUTE));
            }
            keys.push((source.to_owned(), REFUSAL_AUDITS_PER_MINUTE));
            for (key, _) in &mut keys {
                if windows.len() >= MAX_REFUSAL_SOURCES && !windows.contains_key(key.as_str()) {
                    "other".clone_into(key);
                }
            }
            let full = keys
                .iter()
                .find(|(key, cap)| windows.get(key.as_str()).is_some_and(|w| w.written >= *cap));
            let write = match full {
                Some((key, _)) => {
                    window(&mut windows, key, now_ms).suppressed += 1;
                    false
                }
                None => {
                    for (key, _) in &keys {
                        window(&mut windows, key, now_ms).written += 1;
                    }
                    true
                }
            };
            (write, finished)
        };
        self.write_suppressed(finished, now_ms).await?;
        if write {
            let detail = if detail.is_empty() {
                format!("from {source}")
            } else {
                format!("{detail} (from {source})")
            };
            self.audit(actor, action, target, &detail, now_ms).await?;
        }
        Ok(())
    }

    /// Writes the `refusals_suppressed` entries of every source whose minute is over.
    pub async fn flush_refusal_audits(&self, now_ms: i64) -> Result<(), HubError> {
        let finished = {
            let mut windows = self
                .guards
                .refusals
                .lock()
                .map_err(|_| HubError::Corrupt("refusal limiter poisoned".to_owned()))?;
            take_finished(&mut windows, now_ms)
        };
        self.write_suppressed(finished, now_ms).await
    }

    async fn write_suppressed(
        &self,
        finished: Vec<(String, RefusalWindow)>,
        now_ms: i64,
    ) -> Result<(), HubError> {
        for (source, w) in finished {
            let who = if source == ALL_REFUSALS {
                "from all sources".to_owned()
            } else if let Some(account) = source.strip_prefix("account ") {
                format!("concerning the account {account}")
            } else {
                format!("from {source}")
            };
            let detail = format!(
                "{} more refusals {who} in the minute from {} ms were not recorded one by one \
                 (at most {REFUSAL_AUDITS_PER_MINUTE} a minute per source, \
                 {REFUSAL_AUDITS_PER_ACCOUNT_PER_MINUTE} per account, \
                 {REFUSAL_AUDITS_TOTAL_PER_MINUTE} in all)",
                w.suppressed, w.start_ms
            );
            self.audit("hub", "refusals_suppressed", &source, &detail, now_ms)
                .await?;
        }
        Ok(())
    }

    /// The password hashing pool of this database's hub.
    pub(crate) fn hashing(&self) -> &HashPool {
        &self.guards.hashing
    }
}

/// The limiter's window of `key`, opened at `now_ms` if it has none.
fn window<'a>(
    windows: &'a mut HashMap<String, RefusalWindow>,
    key: &str,
    now_ms: i64,
) -> &'a mut RefusalWindow {
    windows
        .entry(key.to_owned())
        .or_insert_with(|| RefusalWindow {
            start_ms: now_ms,
            written: 0,
            suppressed: 0,
        })
}

/// Removes the windows whose minute is over; returns those that suppressed something.
fn take_finished(
    windows: &mut HashMap<String, RefusalWindow>,
    now_ms: i64,
) -> Vec<(String, RefusalWindow)> {
    let over: Vec<String> = windows
        .iter()
        .filter(|(_, w)| now_ms >= w.start_ms.saturating_add(MINUTE_MS))
        .map(|(k, _)| k.clone())
        .collect();
    over.into_iter()
        .filter_map(|k| windows.remove_entry(&k))
        .filter(|(_, w)| w.suppressed > 0)
        .collect()
}
