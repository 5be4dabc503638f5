//! Summaries, stored exactly once, many per statement.
//!
//! A busy hub commits many stations' summaries in one transaction (group commit). Each
//! statement costs a round trip (to the PostgreSQL server, or to sqlx's SQLite worker thread:
//! two thread wake-ups), so a batch is written in *rounds* of a few statements each rather
//! than two statements per summary: round `k` takes the `k`-th summary of every session in the
//! batch (so a round holds at most one summary per session), and
//!
//! 1. one `UPDATE sessions … FROM (VALUES …) … RETURNING` advances `last_seq` of every session
//!    whose summary is the next acceptable one (the same rule as one summary at a time: above
//!    the last stored, at most `MAX_SEQ_STEP` past it) — the conditional update decides, and
//!    takes the row locks, so two hubs on one PostgreSQL never both store a summary;
//! 2. one multi-row `INSERT INTO summaries` stores the summaries whose session advanced;
//! 3. only if some were refused, one `SELECT` reads those sessions' `last_seq` to say why
//!    (duplicate, unknown session, or a jump too far).
//!
//! Both backends accept `UPDATE … FROM` with `RETURNING` (SQLite ≥ 3.35, PostgreSQL ≥ 9.5) and
//! name a `VALUES` list's columns `column1`, `column2`.

use std::collections::{HashMap, HashSet, VecDeque};

use netlink::Summary;
use netlink::frame::MAX_SEQ_STEP;
use netlink::store::Appended;
use sqlx::{Any, Row, Transaction};

use super::{Db, to_i64};
use crate::error::HubError;

/// Most summaries one statement carries. Statements carry a power of two of rows (a round of
/// 37 is written as 32 + 4 + 1), so a connection prepares at most a handful of distinct
/// statements and its statement cache always hits; and sqlx's SQLite driver binds parameters
/// in time quadratic in their number (it looks each one's name up), which 64 rows × 5 values
/// keep negligible, where 1 000 rows spent most of the hub's CPU in the binding.
const MAX_ROWS_PER_STATEMENT: usize = 64;

/// Splits `items` into pieces whose lengths are powers of two, at most
/// [`MAX_ROWS_PER_STATEMENT`].
fn power_of_two_pieces<T>(mut items: &[T]) -> impl Iterator<Item = &[T]> {
    std::iter::from_fn(move || {
        if items.is_empty() {
            return None;
        }
        let len = MAX_ROWS_PER_STATEMENT.min(1 << items.len().ilog2());
        let (piece, rest) = items.split_at(len);
        items = rest;
        Some(piece)
    })
}

/// A summary that passed validation, with its place in the batch.
struct Checked<'a> {
    index: usize,
    summary: &'a Summary,
    seq: i64,
    body: String,
}

fn check(summary: &Summary) -> Result<(i64, String), HubError> {
    summary
        .validate()
        .map_err(|reason| HubError::invalid("summary", reason))?;
    let seq = to_i64("seq", summary.seq)?;
    let body =
        serde_json::to_string(summary).map_err(|e| HubError::invalid("summary", e.to_string()))?;
    Ok((seq, body))
}

/// `($first, $first+1, …), …` — `rows` tuples of `width` numbered placeholders.
fn placeholders(rows: usize, width: usize, first: usize) -> String {
    let mut sql = String::with_capacity(rows * width * 6);
    for r in 0..rows {
        if r > 0 {
            sql.push_str(", ");
        }
        sql.push('(');
        for c in 0..width {
            if c > 0 {
                sql.push_str(", ");
            }
            sql.push('$');
            sql.push_str(&(first + r * width + c).to_string());
        }
        sql.push(')');
    }
    sql
}

impl Db {
    /// Stores a summary exactly once: only if its `seq` is above the last one stored for its
    /// session (as netlink's file store does), so duplicates and stale reorderings are
    /// [`Appended::Duplicate`]. Refused: an invalid summary, an unknown session, `seq` above
    /// `i64::MAX`, and a jump beyond netlink's `MAX_SEQ_STEP`.
    pub async fn store_summary(
        &self,
        summary: &Summary,
        now_ms: i64,
    ) -> Result<Appended, HubError> {
        self.store_summaries(std::slice::from_ref(summary), now_ms)
            .await?
            .pop()
            .unwrap_or_else(|| Err(HubError::Corrupt("no result for one summary".into())))
    }

    /// Stores `summaries` (of any sessions, in any order) in ONE transaction — group commit —
    /// each by the rule of [`Self::store_summary`], with the outcome it would have had stored
    /// one by one in this order; one result per summary, in order. A database error fails the
    /// whole batch (nothing of it is stored).
    pub async fn store_summaries(
        &self,
        summaries: &[Summary],
        now_ms: i64,
    ) -> Result<Vec<Result<Appended, HubError>>, HubError> {
        let step = to_i64("MAX_SEQ_STEP", MAX_SEQ_STEP)?;
        let mut results: Vec<Option<Result<Appended, HubError>>> =
            summaries.iter().map(|_| None).collect();
        // Each session's valid summaries in batch order.
        let mut queues: Vec<VecDeque<Checked<'_>>> = Vec::new();
        let mut queue_of: HashMap<&str, usize> = HashMap::new();
        for (index, summary) in summaries.iter().enumerate() {
            match check(summary) {
                Ok((seq, body)) => {
                    let q = *queue_of.entry(&summary.session_id).or_insert_with(|| {
                        queues.push(VecDeque::new());
                        queues.len() - 1
                    });
                    queues[q].push_back(Checked {
                        index,
                        summary,
                        seq,
                        body,
                    });
                }
                Err(e) => results[index] = Some(Err(e)),
            }
        }
        let mut tx = self
            .pool()
            .begin()
            .await
            .map_err(HubError::db("starting a transaction"))?;
        loop {
            let round: Vec<Checked<'_>> =
                queues.iter_mut().filter_map(VecDeque::pop_front).collect();
            if round.is_empty() {
                break;
            }
            for chunk in power_of_two_pieces(&round) {
                for (index, outcome) in store_round(&mut tx, chunk, step, now_ms).await? {
                    results[index] = Some(outcome);
                }
            }
        }
        tx.commit()
            .await
            .map_err(HubError::db("committing summaries"))?;
        Ok(results
            .into_iter()
            .map(|r| r.unwrap_or_else(|| Err(HubError::Corrupt("a summary had no outcome".into()))))
            .collect())
    }

    /// The summary `seq` of session `session_id`, if stored.
    pub async fn summary(&self, session_id: &str, seq: u64) -> Result<Option<Summary>, HubError> {
        let body: Option<String> =
            sqlx::query_scalar("SELECT body FROM summaries WHERE session_id = $1 AND seq = $2")
                .bind(session_id)
                .bind(to_i64("seq", seq)?)
                .fetch_optional(self.pool())
                .await
                .map_err(HubError::db("reading a summary"))?;
        body.map(|b| {
            serde_json::from_str(&b)
                .map_err(|e| HubError::Corrupt(format!("summary of {session_id:?}: {e}")))
        })
        .transpose()
    }

    /// A session's stored summaries in sequence order.
    pub async fn summaries_of(&self, session_id: &str) -> Result<Vec<Summary>, HubError> {
        let bodies: Vec<String> =
            sqlx::query_scalar("SELECT body FROM summaries WHERE session_id = $1 ORDER BY seq")
                .bind(session_id)
                .fetch_all(self.pool())
                .await
                .map_err(HubError::db("reading summaries"))?;
        bodies
            .iter()
            .map(|b| {
                serde_json::from_str(b)
                    .map_err(|e| HubError::Corrupt(format!("summary of {session_id:?}: {e}")))
            })
            .collect()
    }
}

/// One round (at most one summary per session): advance, insert, explain the refusals.
async fn store_round(
    tx: &mut Transaction<'static, Any>,
    round: &[Checked<'_>],
    step: i64,
    now_ms: i64,
) -> Result<Vec<(usize, Result<Appended, HubError>)>, HubError> {
    let advanced = advance(tx, round, step).await?;
    let (stored, refused): (Vec<&Checked<'_>>, Vec<&Checked<'_>>) = round
        .iter()
        .partition(|c| advanced.contains(c.summary.session_id.as_str()));
    insert(tx, &stored, now_ms).await?;
    let mut outcomes: Vec<(usize, Result<Appended, HubError>)> = stored
        .iter()
        .map(|c| (c.index, Ok(Appended::Stored)))
        .collect();
    if refused.is_empty() {
        return Ok(outcomes);
    }
    let last = last_seqs(tx, &refused).await?;
    outcomes.extend(refused.iter().map(|c| {
        let id = &c.summary.session_id;
        let outcome = match last.get(id.as_str()) {
            None => Err(HubError::not_found("session", id)),
            Some(Some(last)) if c.seq <= *last => Ok(Appended::Duplicate),
            Some(last) => Err(HubError::Conflict(format!(
                "summary seq {} jumps more than {MAX_SEQ_STEP} past the last stored ({last:?}) \
                 in session {id:?}",
                c.seq
            ))),
        };
        (c.index, outcome)
    }));
    Ok(outcomes)
}

/// Advances `last_seq` of every session whose summary in `round` is acceptable; returns their
/// ids.
async fn advance(
    tx: &mut Transaction<'static, Any>,
    round: &[Checked<'_>],
    step: i64,
) -> Result<HashSet<String>, HubError> {
    let sql = sqlx::AssertSqlSafe(format!(
        "UPDATE sessions SET last_seq = v.column2 FROM (VALUES {}) AS v \
         WHERE sessions.session_id = v.column1 AND \
         ((sessions.last_seq IS NULL AND v.column2 <= $1) OR \
          (sessions.last_seq < v.column2 AND v.column2 - sessions.last_seq <= $1 + 1)) \
         RETURNING sessions.session_id",
        placeholders(round.len(), 2, 2)
    ));
    let mut query = sqlx::query(sql).bind(step);
    for c in round {
        query = query.bind(c.summary.session_id.as_str()).bind(c.seq);
    }
    let rows = query
        .fetch_all(&mut **tx)
        .await
        .map_err(HubError::db("advancing sessions"))?;
    rows.iter()
        .map(|row| {
            row.try_get::<String, _>(0)
                .map_err(|e| HubError::Corrupt(format!("advanced session id: {e}")))
        })
        .collect()
}

/// Inserts `stored` in one statement.
async fn insert(
    tx: &mut Transaction<'static, Any>,
    stored: &[&Checked<'_>],
    now_ms: i64,
) -> Result<(), HubError> {
    if stored.is_empty() {
        return Ok(());
    }
    let sql = sqlx::AssertSqlSafe(format!(
        "INSERT INTO summaries (session_id, seq, t_s, body, stored_at_ms) VALUES {} \
         ON CONFLICT (session_id, seq) DO NOTHING",
        placeholders(stored.len(), 5, 1)
    ));
    let mut query = sqlx::query(sql);
    for c in stored {
        query = query
            .bind(c.summary.session_id.as_str())
            .bind(c.seq)
            .bind(c.summary.t_s)
            .bind(c.body.as_str())
            .bind(now_ms);
    }
    query
        .execute(&mut **tx)
        .await
        .map_err(HubError::db("storing summaries"))?;
    Ok(())
}

/// `last_seq` of the sessions of `refused` that exist (absent: unknown session).
async fn last_seqs(
    tx: &mut Transaction<'static, Any>,
    refused: &[&Checked<'_>],
) -> Result<HashMap<String, Option<i64>>, HubError> {
    let list = (1..=refused.len())
        .map(|i| format!("${i}"))
        .collect::<Vec<_>>()
        .join(", ");
    let sql = sqlx::AssertSqlSafe(format!(
        "SELECT session_id, last_seq FROM sessions WHERE session_id IN ({list})"
    ));
    let mut query = sqlx::query(sql);
    for c in refused {
        query = query.bind(c.summary.session_id.as_str());
    }
    let rows = query
        .fetch_all(&mut **tx)
        .await
        .map_err(HubError::db("reading sessions"))?;
    rows.iter()
        .map(|row| {
            let id: String = super::col(row, "session_id")?;
            let last: Option<i64> = super::col(row, "last_seq")?;
            Ok((id, last))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounds_are_split_into_powers_of_two_up_to_the_most_per_statement() {
        let items: Vec<usize> = (0..141).collect();
        let lens: Vec<usize> = power_of_two_pieces(&items).map(<[usize]>::len).collect();
        assert_eq!(lens, [64, 64, 8, 4, 1]);
        let joined: Vec<usize> = power_of_two_pieces(&items).flatten().copied().collect();
        assert_eq!(joined, items);
        assert_eq!(power_of_two_pieces::<u8>(&[]).count(), 0);
    }

    #[test]
    fn placeholders_number_rows_in_order() {
        assert_eq!(placeholders(2, 2, 2), "($2, $3), ($4, $5)");
        assert_eq!(placeholders(1, 3, 1), "($1, $2, $3)");
    }
}
