//! What a paired station may send, held to what a real station produces: summaries at most
//! twice a station's rate (paced per station across all its connections), start times near
//! the hub's clock, summary times finite, increasing and within a session's longest length,
//! and recording bytes and upload announcements paced per station across its connections.

use std::collections::HashMap;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Summaries per second of a session's own time (`t_s`) a station may send: a station sends
/// one `LiveSummary` every 100 ms of its session (10 per second), so twice that. A session's
/// `seq` beyond this many a second of its `t_s` plus [`SUMMARY_BURST`] is refused
/// ([`check_summary_count`]).
pub const SUMMARY_RATE_PER_S: f64 = 20.0;

/// Summaries per second of the hub's clock taken from one station over all its connections:
/// what a station delivering its queue produces. Live it sends 10 a second; after an outage
/// its store-and-forward sends what was queued as fast as the link takes it, so the pace is
/// set by the backlog a patient's day leaves: an hour offline (36 000 summaries) drains in
/// 3 minutes beside the live session, and a queued 10-minute session in 27 s. One connection
/// is held back to this pace, not refused; a flood stores at most this many a second (it
/// stored 4 452 a second before issue 44), and a session at most
/// [`SUMMARY_RATE_PER_S`] a second of its own time.
pub const SUMMARY_PACE_PER_S: f64 = 200.0;

/// Summaries a station may send at once above [`SUMMARY_PACE_PER_S`] (and above
/// [`SUMMARY_RATE_PER_S`] a second of a session's time): a minute of a station's production,
/// so what a minute's outage (or a session run faster than real time, `--speed max`) left
/// queued is delivered at once, not held back.
pub const SUMMARY_BURST: f64 = 600.0;

/// Longest a summary is held back by the station's pace: 50 summaries' worth. One connection
/// is only paced (it waits 5 ms a summary at most); a station whose summaries would wait
/// longer sends on several connections at once, and is refused: `Error` frame, connection
/// closed.
pub const MAX_SUMMARY_WAIT: Duration = Duration::from_millis(250);

/// Longest a recording chunk's answer is held back by the station's upload pace; beyond,
/// the chunk is refused (a station uploads one recording at a time).
pub const MAX_UPLOAD_WAIT: Duration = Duration::from_secs(5);

/// Upload announcements (`UploadStart`) a second taken from one station over all its
/// connections beyond [`UPLOAD_START_BURST`]. Each costs the hub a look in its recording store
/// and a note in the database; a station announces each recording once per connection, and
/// uploads one at a time, so one a second never slows a real station's queue (its recordings
/// take far longer than a second each to send). Held back to this pace on one connection;
/// refused beyond [`MAX_UPLOAD_WAIT`] (a station announcing on many connections at once).
pub const UPLOAD_START_PACE_PER_S: f64 = 1.0;

/// Upload announcements a station may make at once above [`UPLOAD_START_PACE_PER_S`]: a month
/// offline at a session a day leaves about 30 recordings queued.
pub const UPLOAD_START_BURST: f64 = 30.0;

/// How far ahead of the hub's clock a session's start may be, ms (a station's clock that is
/// off by a few minutes).
pub const MAX_START_AHEAD_MS: u64 = 5 * 60 * 1000;

/// The earliest session start taken, ms since the Unix epoch: 2025-01-01T00:00:00Z, before any
/// station of this software existed. A station whose clock reads earlier (a flat clock battery
/// reads 1970 or 2000) is refused with a message saying to check its clock. A fixed date, not
/// an age, so that what a station kept while offline for months is still taken.
pub const EARLIEST_START_MS: u64 = 1_735_689_600_000;

/// Longest a session's summaries may reach, s (`t_s`): three times the longest session a
/// regimen plans (2 h of exercise), for pauses.
pub const MAX_SESSION_S: f64 = 6.0 * 3600.0;

/// Slack between a summary's `t_s` and the time since the session's start by the hub's clock,
/// s (a station's clock off by up to [`MAX_START_AHEAD_MS`]).
pub const CLOCK_SLACK_S: f64 = 300.0;

/// A recording's `.part` file not written for this long is removed when its station next
/// uploads, s (a station that comes back later uploads that recording again from its start).
pub const STALE_PART_S: u64 = 7 * 24 * 60 * 60;

/// Checks a session's start (ms since the Unix epoch, station clock) against the hub's clock
/// `now_ms`: at most [`MAX_START_AHEAD_MS`] ahead, and not before [`EARLIEST_START_MS`].
pub fn check_start(started_unix_ms: u64, now_ms: u64) -> Result<(), String> {
    if started_unix_ms > now_ms.saturating_add(MAX_START_AHEAD_MS) {
        return Err(format!(
            "the session's start time {} is {} minutes ahead of the hub's clock (at most {} \
             allowed); check the station's clock",
            iso(started_unix_ms),
            (started_unix_ms - now_ms) / 60_000,
            MAX_START_AHEAD_MS / 60_000
        ));
    }
    if started_unix_ms < EARLIEST_START_MS {
        return Err(format!(
            "the session's start time {} is before {}, earlier than any session this hub takes; \
             check the station's clock",
            iso(started_unix_ms),
            iso(EARLIEST_START_MS)
        ));
    }
    Ok(())
}

/// Checks a summary's time `t_s` (s since the session's start): finite, not negative, not
/// before the session's last stored summary (`last_t_s`), at most [`MAX_SESSION_S`], and not
/// past the time since the session's start by the hub's clock (with [`CLOCK_SLACK_S`]).
pub fn check_summary_time(
    t_s: f64,
    last_t_s: Option<f64>,
    started_unix_ms: u64,
    now_ms: u64,
) -> Result<(), String> {
    if !t_s.is_finite() || t_s < 0.0 {
        return Err(format!(
            "summary time t_s = {t_s} s: must be a finite number of seconds, 0 or more"
        ));
    }
    if t_s > MAX_SESSION_S {
        return Err(format!(
            "summary time t_s = {t_s} s is past the longest session the hub takes \
             ({MAX_SESSION_S} s)"
        ));
    }
    if let Some(last) = last_t_s
        && t_s < last
    {
        return Err(format!(
            "summary time t_s = {t_s} s goes back before the last stored summary's ({last} s)"
        ));
    }
    let elapsed_s = now_ms.saturating_sub(started_unix_ms) as f64 / 1000.0;
    if t_s > elapsed_s + CLOCK_SLACK_S {
        return Err(format!(
            "summary time t_s = {t_s} s is later than the session can have reached: it started \
             {elapsed_s:.0} s ago by the hub's clock"
        ));
    }
    Ok(())
}

/// Checks that a session's summary `seq` at time `t_s` is no more than a station produces in
/// that time: [`SUMMARY_RATE_PER_S`] a second of session time plus [`SUMMARY_BURST`] (a
/// station numbers its summaries from 0, one every 100 ms of its session).
pub fn check_summary_count(seq: u64, t_s: f64) -> Result<(), String> {
    let most = SUMMARY_RATE_PER_S * t_s.max(0.0) + SUMMARY_BURST;
    if seq as f64 > most {
        return Err(format!(
            "summary seq {seq} at t_s = {t_s} s: more summaries than a station produces in that \
             time (at most {SUMMARY_RATE_PER_S} a second of the session, plus {SUMMARY_BURST})"
        ));
    }
    Ok(())
}

/// `ms` since the Unix epoch as a UTC date `YYYY-MM-DD`, for messages (days to civil date,
/// H. Hinnant's algorithm).
fn iso(ms: u64) -> String {
    let days = i64::try_from(ms / 86_400_000).unwrap_or(i64::MAX / 2) + 719_468;
    let era = days / 146_097;
    let doe = days - era * 146_097;
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

/// Paces per key (a station) across all its connections: a generic cell-rate limiter (each
/// unit of cost is due `1 / rate` s after the previous one, `burst` units may come early).
#[derive(Debug, Default)]
pub struct Pacer {
    state: Mutex<PacerState>,
}

#[derive(Debug, Default)]
struct PacerState {
    /// Per key, when its next unit is due if it had no burst allowance.
    due: HashMap<String, Instant>,
    /// Forget keys whose due time has passed once the table is this large.
    clean_at: usize,
}

impl Pacer {
    /// Reserves `cost` units for `key` at `rate` units/s with `burst` units early: how long
    /// to wait before taking them, or `None` (nothing reserved) if that would be longer than
    /// `max_wait`.
    pub fn reserve(
        &self,
        key: &str,
        cost: f64,
        rate: f64,
        burst: f64,
        max_wait: Duration,
    ) -> Option<Duration> {
        let now = Instant::now();
        let mut state = self
            .state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if state.due.len() > state.clean_at {
            state.due.retain(|_, due| *due > now);
            state.clean_at = (state.due.len() * 2).max(1024);
        }
        let rate = rate.max(f64::MIN_POSITIVE);
        let start = state.due.get(key).copied().unwrap_or(now).max(now);
        let early = Duration::from_secs_f64(burst / rate);
        let wait = (start + Duration::from_secs_f64(cost / rate))
            .checked_duration_since(now + early)
            .unwrap_or_default();
        if wait > max_wait {
            return None;
        }
        let due = start + Duration::from_secs_f64(cost / rate);
        match state.due.get_mut(key) {
            Some(d) => *d = due,
            None => {
                state.due.insert(key.to_owned(), due);
            }
        }
        Some(wait)
    }

    /// [`Pacer::reserve`], then waits until the units are due: false (nothing reserved, no
    /// wait) if that would be longer than `max_wait`.
    pub async fn take(
        &self,
        key: &str,
        cost: f64,
        rate: f64,
        burst: f64,
        max_wait: Duration,
    ) -> bool {
        match self.reserve(key, cost, rate, burst, max_wait) {
            Some(wait) => {
                if !wait.is_zero() {
                    tokio::time::sleep(wait).await;
                }
                true
            }
            None => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NOW: u64 = 1_796_000_000_000;

    #[test]
    fn a_start_a_few_minutes_ahead_or_months_behind_is_taken_the_year_2302_is_not() {
        assert!(check_start(NOW + 60_000, NOW).is_ok());
        assert!(check_start(NOW - 90 * 86_400_000, NOW).is_ok());
        let far = check_start(10_505_000_000_000, NOW).unwrap_err();
        assert!(far.contains("2302") && far.contains("ahead"), "{far}");
        assert!(
            check_start(0, NOW)
                .unwrap_err()
                .contains("before 2025-01-01")
        );
        assert_eq!(iso(0), "1970-01-01");
        assert_eq!(iso(1_795_253_400_000), "2026-11-21");
    }

    #[test]
    fn summary_times_must_be_finite_increasing_and_within_the_session() {
        let start = NOW - 60_000;
        assert!(check_summary_time(0.0, None, start, NOW).is_ok());
        assert!(check_summary_time(59.9, Some(59.8), start, NOW).is_ok());
        assert!(check_summary_time(f64::NAN, None, start, NOW).is_err());
        assert!(check_summary_time(f64::INFINITY, None, start, NOW).is_err());
        assert!(check_summary_time(-0.1, None, start, NOW).is_err());
        assert!(check_summary_time(1e308, None, start, NOW).is_err());
        assert!(check_summary_time(10.0, Some(20.0), start, NOW).is_err());
        // Ahead of what a minute-old session can have reached, past the clock's slack.
        assert!(check_summary_time(60.0 + CLOCK_SLACK_S + 1.0, None, start, NOW).is_err());
    }

    #[test]
    fn a_station_produces_at_most_twenty_summaries_a_second_of_its_session() {
        assert!(check_summary_count(600, 0.0).is_ok());
        assert!(check_summary_count(600, 60.0).is_ok());
        assert!(check_summary_count(1_800, 60.0).is_ok());
        let e = check_summary_count(1_801, 60.0).unwrap_err();
        assert!(e.contains("more summaries than a station produces"), "{e}");
    }

    #[test]
    fn the_pacer_lets_a_burst_through_then_paces_and_refuses_a_long_wait() {
        let p = Pacer::default();
        let max = Duration::from_secs(1);
        for _ in 0..10 {
            assert_eq!(p.reserve("a", 1.0, 10.0, 10.0, max), Some(Duration::ZERO));
        }
        let w = p.reserve("a", 1.0, 10.0, 10.0, max).unwrap();
        assert!(w > Duration::from_millis(50), "{w:?}");
        // Another key has its own allowance.
        assert_eq!(p.reserve("b", 1.0, 10.0, 10.0, max), Some(Duration::ZERO));
        // Ten more on "a" would wait > 1 s: refused, nothing reserved.
        let mut refused = 0;
        for _ in 0..20 {
            if p.reserve("a", 1.0, 10.0, 10.0, max).is_none() {
                refused += 1;
            }
        }
        assert!(refused >= 9, "{refused}");
    }
}
