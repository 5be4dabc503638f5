//! Budgets for connections that have not proven who they are yet, shared by the hub's station
//! port and its web port: a cap per remote address and one in all, and refusals counted and
//! reported at a bounded rate instead of one line each.
//!
//! A connection over either cap replaces the OLDEST connection still waiting (its TLS
//! handshake or first message) rather than being turned away: idle junk is always older than a
//! station or browser that has just connected, so holding connections open cannot lock anyone
//! out; an attacker would have to open a whole cap's worth of new connections during a
//! legitimate handshake (a few milliseconds) to push it out.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt::Write as _;
use std::net::IpAddr;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use tokio::sync::oneshot;

/// How often refusals are summarised (one line per interval at most).
pub const REFUSAL_LOG_INTERVAL: Duration = Duration::from_secs(10);

/// Refusals described one by one per interval before the rest are only counted.
pub const REFUSAL_DETAILS_PER_INTERVAL: u32 = 20;

/// Caps on connections not yet authenticated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GateLimits {
    /// Most such connections from all addresses.
    pub max_total: usize,
    /// Most such connections from one remote address.
    pub max_per_address: usize,
}

/// Counts connections not yet authenticated, per address and in all, within [`GateLimits`].
#[derive(Debug)]
pub struct ConnectionGate {
    limits: GateLimits,
    state: Mutex<GateState>,
    refusals: RefusalLog,
}

#[derive(Debug, Default)]
struct GateState {
    next_id: u64,
    /// Every counted connection, oldest first.
    entries: BTreeMap<u64, Entry>,
    per_address: HashMap<IpAddr, BTreeSet<u64>>,
}

#[derive(Debug)]
struct Entry {
    ip: IpAddr,
    /// How to tell it that it was evicted; `None` once it may no longer be (see
    /// [`Ticket::hold`]).
    evict: Option<oneshot::Sender<()>>,
}

impl GateState {
    fn remove(&mut self, id: u64) -> Option<Entry> {
        let entry = self.entries.remove(&id)?;
        if let Some(ids) = self.per_address.get_mut(&entry.ip) {
            ids.remove(&id);
            if ids.is_empty() {
                self.per_address.remove(&entry.ip);
            }
        }
        Some(entry)
    }

    /// Evicts the oldest evictable connection (from `ip` only, if given); false if none.
    fn evict_oldest(&mut self, ip: Option<IpAddr>) -> bool {
        let evictable = |id: &u64| self.entries.get(id).is_some_and(|e| e.evict.is_some());
        let victim = match ip {
            Some(ip) => self
                .per_address
                .get(&ip)
                .and_then(|ids| ids.iter().copied().find(|id| evictable(id))),
            None => self.entries.keys().copied().find(|id| evictable(id)),
        };
        let Some(entry) = victim.and_then(|id| self.remove(id)) else {
            return false;
        };
        if let Some(tell) = entry.evict {
            let _ = tell.send(());
        }
        true
    }
}

/// One connection counted by a [`ConnectionGate`]; uncounted when dropped.
#[derive(Debug)]
pub struct Ticket {
    gate: Arc<ConnectionGate>,
    id: u64,
    eviction: Eviction,
}

/// Resolves when its connection is evicted to make room for a newer one (never if it is not).
#[derive(Debug)]
pub struct Eviction(Option<oneshot::Receiver<()>>);

impl Eviction {
    /// Waits until the connection is evicted.
    /// Cancel-safe: a wait dropped before it resolves loses nothing.
    pub async fn wait(&mut self) {
        if let Some(rx) = self.0.as_mut() {
            let told = rx.await.is_ok();
            self.0 = None;
            if told {
                return;
            }
            // Uncounted without eviction (authenticated, or the gate let it go).
        }
        std::future::pending::<()>().await;
    }
}

impl Ticket {
    /// Waits until this connection is evicted to make room for a newer one.
    /// Cancel-safe.
    pub async fn evicted(&mut self) {
        self.eviction.wait().await;
    }

    /// The eviction signal, separately from the ticket (which may then move elsewhere).
    pub fn eviction(&mut self) -> Eviction {
        std::mem::replace(&mut self.eviction, Eviction(None))
    }

    /// Keeps the connection counted but no longer evictable: it has sent its first message and
    /// is being admitted (or paired), a short phase with its own deadlines.
    pub fn hold(&mut self) {
        let mut state = self.gate.lock();
        if let Some(entry) = state.entries.get_mut(&self.id) {
            entry.evict = None;
        }
        self.eviction = Eviction(None);
    }
}

impl Drop for Ticket {
    fn drop(&mut self) {
        self.gate.lock().remove(self.id);
    }
}

impl ConnectionGate {
    /// A gate with these caps; `what` names the port in refusal summaries.
    pub fn new(limits: GateLimits, what: &'static str) -> Arc<Self> {
        Arc::new(Self {
            limits,
            state: Mutex::new(GateState::default()),
            refusals: RefusalLog::new(what),
        })
    }

    /// The caps.
    pub fn limits(&self) -> GateLimits {
        self.limits
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, GateState> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Counts a new connection from `ip`, evicting the oldest waiting connection from that
    /// address (or from all) when a cap is reached. `None` (counted as a refusal) only when
    /// every counted connection is past its first message and cannot be evicted.
    pub fn admit(self: &Arc<Self>, ip: IpAddr) -> Option<Ticket> {
        let ip = address_of(ip);
        let mut state = self.lock();
        let from_ip = state.per_address.get(&ip).map_or(0, BTreeSet::len);
        if from_ip >= self.limits.max_per_address {
            if !state.evict_oldest(Some(ip)) {
                self.refusals
                    .count("refused: per-address cap, none evictable");
                return None;
            }
            self.refusals
                .count("evicted: oldest waiting from the same address");
        }
        if state.entries.len() >= self.limits.max_total {
            if !state.evict_oldest(None) {
                self.refusals.count("refused: global cap, none evictable");
                return None;
            }
            self.refusals.count("evicted: oldest waiting (global cap)");
        }
        let id = state.next_id;
        state.next_id += 1;
        let (tell, evicted) = oneshot::channel();
        state.entries.insert(
            id,
            Entry {
                ip,
                evict: Some(tell),
            },
        );
        state.per_address.entry(ip).or_default().insert(id);
        Some(Ticket {
            gate: self.clone(),
            id,
            eviction: Eviction(Some(evicted)),
        })
    }

    /// Connections counted now (from all addresses).
    pub fn waiting(&self) -> usize {
        self.lock().entries.len()
    }

    /// The refusal log of this port.
    pub fn refusals(&self) -> &RefusalLog {
        &self.refusals
    }
}

/// Counts refusals by reason and summarises them at most once per [`REFUSAL_LOG_INTERVAL`].
#[derive(Debug)]
pub struct RefusalLog {
    what: &'static str,
    window: Mutex<Window>,
}

#[derive(Debug)]
struct Window {
    started: Instant,
    counts: BTreeMap<&'static str, u64>,
    details: u32,
}

/// One interval's refusals.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RefusalSummary {
    /// Refusals counted (not described one by one).
    pub count: u64,
    /// The interval, s.
    pub interval_s: u64,
    /// `N reason, M reason, …`, most frequent first.
    pub reasons: String,
}

impl std::fmt::Display for RefusalSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "refused {} connections in the last {} s ({})",
            self.count, self.interval_s, self.reasons
        )
    }
}

impl RefusalLog {
    /// An empty log; `what` names the port.
    pub fn new(what: &'static str) -> Self {
        Self {
            what,
            window: Mutex::new(Window {
                started: Instant::now(),
                counts: BTreeMap::new(),
                details: 0,
            }),
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Window> {
        self.window.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Counts one refusal, reported only in the next summary.
    pub fn count(&self, reason: &'static str) {
        *self.lock().counts.entry(reason).or_insert(0) += 1;
    }

    /// Whether this refusal may be described on its own line: true for the first
    /// [`REFUSAL_DETAILS_PER_INTERVAL`] of an interval; the rest are only counted.
    pub fn detail(&self, reason: &'static str) -> bool {
        let mut window = self.lock();
        if window.details < REFUSAL_DETAILS_PER_INTERVAL {
            window.details += 1;
            true
        } else {
            *window.counts.entry(reason).or_insert(0) += 1;
            false
        }
    }

    /// The summary of the interval that has ended, if anything was counted in it; `None`
    /// before [`REFUSAL_LOG_INTERVAL`] has passed. Starts a new interval.
    pub fn take_summary(&self) -> Option<RefusalSummary> {
        self.take(false)
    }

    /// As [`Self::take_summary`] even if the interval has not ended (at shutdown).
    pub fn take_summary_now(&self) -> Option<RefusalSummary> {
        self.take(true)
    }

    fn take(&self, now: bool) -> Option<RefusalSummary> {
        let mut window = self.lock();
        let elapsed = window.started.elapsed();
        // Slack for a ticker that fires a little early.
        if !now && elapsed + Duration::from_millis(500) < REFUSAL_LOG_INTERVAL {
            return None;
        }
        window.started = Instant::now();
        window.details = 0;
        let counts = std::mem::take(&mut window.counts);
        drop(window);
        let count: u64 = counts.values().sum();
        if count == 0 {
            return None;
        }
        let mut sorted: Vec<_> = counts.into_iter().collect();
        sorted.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        let mut reasons = String::from(self.what);
        for (reason, n) in sorted {
            let _ = write!(reasons, "; {n} {reason}");
        }
        Some(RefusalSummary {
            count,
            interval_s: elapsed.as_secs().max(1),
            reasons,
        })
    }
}

/// The address a connection is counted under: itself for IPv4 (and IPv4-mapped IPv6), its
/// /64 for IPv6 (one host holds a whole /64, so changing address within it must not buy a
/// fresh per-address allowance).
fn address_of(ip: IpAddr) -> IpAddr {
    match ip {
        IpAddr::V4(_) => ip,
        IpAddr::V6(v6) => match v6.to_ipv4_mapped() {
            Some(v4) => IpAddr::V4(v4),
            None => {
                let s = v6.segments();
                IpAddr::from([s[0], s[1], s[2], s[3], 0, 0, 0, 0])
            }
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ip(last: u8) -> IpAddr {
        IpAddr::from([127, 0, 0, last])
    }

    #[tokio::test]
    async fn a_full_address_evicts_its_own_oldest_waiting_connection_only() {
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: 10,
                max_per_address: 2,
            },
            "test",
        );
        let mut first = gate.admit(ip(1)).unwrap();
        let _second = gate.admit(ip(1)).unwrap();
        let mut other = gate.admit(ip(2)).unwrap();
        let _third = gate.admit(ip(1)).unwrap();
        tokio::time::timeout(Duration::from_secs(1), first.evicted())
            .await
            .expect("the oldest from 127.0.0.1 is evicted");
        assert!(
            tokio::time::timeout(Duration::from_millis(50), other.evicted())
                .await
                .is_err(),
            "another address keeps its connection"
        );
        assert_eq!(gate.waiting(), 3);
        let summary = gate.refusals().take_summary_now().unwrap();
        assert_eq!(summary.count, 1);
        assert!(summary.reasons.contains("same address"), "{summary}");
    }

    #[tokio::test]
    async fn held_connections_are_never_evicted_and_a_full_gate_of_them_refuses() {
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: 2,
                max_per_address: 10,
            },
            "test",
        );
        let mut a = gate.admit(ip(1)).unwrap();
        a.hold();
        let mut b = gate.admit(ip(2)).unwrap();
        let _c = gate.admit(ip(3)).unwrap();
        tokio::time::timeout(Duration::from_secs(1), b.evicted())
            .await
            .expect("the oldest evictable one goes, not the held one");
        let mut c2 = gate.admit(ip(4)).unwrap();
        c2.hold();
        // Both counted connections are held now: nothing can be evicted.
        assert!(gate.admit(ip(5)).is_none());
        drop(a);
        assert!(gate.admit(ip(5)).is_some(), "a released slot is free again");
    }

    #[test]
    fn refusal_details_are_bounded_per_interval_and_the_rest_summarised() {
        let log = RefusalLog::new("station port");
        let described = (0..1000).filter(|_| log.detail("TLS handshake")).count();
        assert_eq!(described, REFUSAL_DETAILS_PER_INTERVAL as usize);
        assert!(log.take_summary().is_none(), "the interval has not ended");
        let summary = log.take_summary_now().unwrap();
        assert_eq!(
            summary.count,
            1000 - u64::from(REFUSAL_DETAILS_PER_INTERVAL)
        );
        assert!(summary.to_string().starts_with("refused 980 connections"));
        assert!(
            log.take_summary_now().is_none(),
            "a new interval starts empty"
        );
    }

    #[tokio::test]
    async fn ipv6_addresses_of_one_slash_64_share_their_per_address_cap() {
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: 10,
                max_per_address: 2,
            },
            "test",
        );
        let a: IpAddr = "2001:db8:1:2::1".parse().unwrap();
        let b: IpAddr = "2001:db8:1:2:ffff::9".parse().unwrap();
        let elsewhere: IpAddr = "2001:db8:1:3::1".parse().unwrap();
        let mut first = gate.admit(a).unwrap();
        let _second = gate.admit(b).unwrap();
        let mut other = gate.admit(elsewhere).unwrap();
        // A third address of the same /64 replaces its oldest, not a connection elsewhere.
        let _third = gate.admit("2001:db8:1:2::77".parse().unwrap()).unwrap();
        tokio::time::timeout(Duration::from_secs(1), first.evicted())
            .await
            .expect("the oldest of the /64 is evicted");
        assert!(
            tokio::time::timeout(Duration::from_millis(50), other.evicted())
                .await
                .is_err(),
            "another /64 keeps its connection"
        );
    }
}
