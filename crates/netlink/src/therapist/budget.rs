//! Budgets for connections that have not proven who they are yet, shared by the hub's station
//! port and its web port: a cap per remote address and one in all, and refusals counted and
//! reported at a bounded rate instead of one line each.
//!
//! Every counted connection is protected from eviction for [`EVICTION_GRACE`] after it is given
//! its slot and again after each step it completes (its TLS handshake, a request head): only a
//! connection that has made no progress for a whole grace — a stalled one — may be evicted,
//! and the oldest stalled one goes first. A newcomer at an address whose slots are all
//! protected is not dropped and drops no one: it waits in that address's line (first come,
//! first served, at most a cap's worth) until a slot frees or a stalled one can be evicted
//! for it; only beyond the line is it refused. At the cap over all addresses the oldest stalled
//! connection anywhere goes, or, if none has stalled, the oldest of the address holding the
//! most (a newcomer from a lighter address displaces a heavier one's, never the reverse: a
//! newcomer from the heaviest displaces its own address's oldest).
//!
//! Why this shape: the connections of one address (a shared NAT, a clinic LAN) look alike
//! until they make progress, so no choice among them at arrival can tell a flooder from a
//! slow handshake. Evicting the oldest let a client reopening its connections thousands of
//! times a second push out any handshake slower than a cap's worth of its reconnects (a
//! 25 ms path: none got through); evicting the newest or a random one fails the same way;
//! refusing newcomers outright lets a holder of a cap's worth lock its address out. A grace
//! protects a handshake while it runs (2 s covers TLS over a path of 1 s round trip), and the
//! line keeps a flooder's reconnects from jumping ahead of a client that came first: with up
//! to twice the cap of connections a flooder gets no more turns than anyone else at its
//! address, and no other address is affected at all. Beyond that, a client holding more
//! connections than the line takes can still starve its own address — nothing at the
//! connection level tells its connections from a neighbour's — but never another address.

use std::collections::{BTreeMap, BTreeSet, HashMap, VecDeque};
use std::fmt::Write as _;
use std::net::IpAddr;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use tokio::sync::{Notify, oneshot};

/// How often refusals are summarised (one line per interval at most).
pub const REFUSAL_LOG_INTERVAL: Duration = Duration::from_secs(10);

/// Refusals described one by one per interval before the rest are only counted.
pub const REFUSAL_DETAILS_PER_INTERVAL: u32 = 20;

/// How long a connection is protected from eviction after it gets its slot and after each step
/// it completes: enough for a TLS handshake (about one round trip after the accept) over a
/// path of up to 1 s round trip, with room for a lost packet on shorter ones.
pub const EVICTION_GRACE: Duration = Duration::from_secs(2);

/// Caps on connections not yet authenticated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GateLimits {
    /// Most such connections from all addresses, waiting in line included.
    pub max_total: usize,
    /// Most such connections from one remote address holding a slot; as many more may wait in
    /// its line.
    pub max_per_address: usize,
    /// How long a connection is protected from eviction after it gets a slot and after each
    /// step it completes ([`EVICTION_GRACE`] on the hub's ports).
    pub grace: Duration,
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
    /// Every counted connection (holding a slot or waiting in line), oldest first.
    entries: BTreeMap<u64, Entry>,
    per_address: HashMap<IpAddr, Address>,
}

/// One address's connections.
#[derive(Debug, Default)]
struct Address {
    /// Connections holding a slot, oldest first.
    slots: BTreeSet<u64>,
    /// Connections waiting for a slot, first come first.
    line: VecDeque<u64>,
    /// Wakes the line when a slot frees or its head changes.
    turn: Arc<Notify>,
}

#[derive(Debug)]
struct Entry {
    ip: IpAddr,
    /// Whether it waits in its address's line (holds no slot yet).
    waiting: bool,
    /// How to tell it that it was evicted; `None` while it waits and once it may no longer be
    /// evicted (see [`Ticket::hold`]).
    evict: Option<oneshot::Sender<()>>,
    /// Until when it may not be evicted (its last progress + the grace).
    protected_until: Instant,
}

impl Entry {
    fn evictable(&self, now: Instant) -> bool {
        self.evict.is_some() && self.protected_until <= now
    }
}

/// What a connection waiting in line should do next.
enum Turn {
    /// It holds a slot now; its eviction signal.
    Admitted(oneshot::Receiver<()>),
    /// Wait for the line to move, or until this instant (when a slot's grace ends).
    Wait(Option<Instant>),
}

impl GateState {
    fn remove(&mut self, id: u64) -> Option<Entry> {
        let entry = self.entries.remove(&id)?;
        if let Some(address) = self.per_address.get_mut(&entry.ip) {
            address.slots.remove(&id);
            address.line.retain(|&w| w != id);
            address.turn.notify_waiters();
            if address.slots.is_empty() && address.line.is_empty() {
                self.per_address.remove(&entry.ip);
            }
        }
        Some(entry)
    }

    fn slots_of(&self, ip: IpAddr) -> usize {
        self.per_address.get(&ip).map_or(0, |a| a.slots.len())
    }

    fn line_of(&self, ip: IpAddr) -> usize {
        self.per_address.get(&ip).map_or(0, |a| a.line.len())
    }

    /// Evicts the oldest stalled connection (from `ip` only, if given); false if none.
    fn evict_stalled(&mut self, ip: Option<IpAddr>, now: Instant) -> bool {
        let evictable = |id: &u64| self.entries.get(id).is_some_and(|e| e.evictable(now));
        let victim = match ip {
            Some(ip) => self
                .per_address
                .get(&ip)
                .and_then(|a| a.slots.iter().copied().find(|id| evictable(id))),
            None => self.entries.keys().copied().find(|id| evictable(id)),
        };
        victim.is_some_and(|id| self.evict(id))
    }

    /// Under the global cap with nobody stalled: evicts the oldest connection that is not held
    /// among the addresses holding the most, if they hold at least as many as `newcomer`'s
    /// address will with the newcomer (a fair share between addresses), else the oldest of the
    /// newcomer's own address; false if there is none. A lighter address never loses a
    /// connection to a heavier one.
    fn evict_from_heaviest(&mut self, newcomer: IpAddr) -> bool {
        let count = |a: &Address| a.slots.len() + a.line.len();
        let theirs = self.per_address.get(&newcomer).map_or(0, count);
        let most = self
            .per_address
            .iter()
            .filter(|(ip, _)| **ip != newcomer)
            .map(|(_, a)| count(a))
            .max()
            .unwrap_or(0);
        let heavy = |ip: &IpAddr| {
            if most > theirs {
                *ip != newcomer && self.per_address.get(ip).is_some_and(|a| count(a) == most)
            } else {
                *ip == newcomer
            }
        };
        let victim = self
            .entries
            .iter()
            .find(|(_, e)| !e.waiting && e.evict.is_some() && heavy(&e.ip))
            .map(|(id, _)| *id);
        victim.is_some_and(|id| self.evict(id))
    }

    /// Uncounts `id` and tells it that it was evicted.
    fn evict(&mut self, id: u64) -> bool {
        let Some(entry) = self.remove(id) else {
            return false;
        };
        if let Some(tell) = entry.evict {
            let _ = tell.send(());
        }
        true
    }

    /// When the first of `ip`'s protected slots may be evicted; `None` if all are held.
    fn next_lapse(&self, ip: IpAddr) -> Option<Instant> {
        let address = self.per_address.get(&ip)?;
        address
            .slots
            .iter()
            .filter_map(|id| self.entries.get(id))
            .filter(|e| e.evict.is_some())
            .map(|e| e.protected_until)
            .min()
    }

    /// Counts a new connection from `ip`: in a slot (its eviction signal) or in line.
    fn insert(&mut self, ip: IpAddr, waiting: bool, grace: Duration) -> (u64, Eviction) {
        let id = self.next_id;
        self.next_id += 1;
        let (evict, eviction) = if waiting {
            (None, Eviction(None))
        } else {
            let (tell, evicted) = oneshot::channel();
            (Some(tell), Eviction(Some(evicted)))
        };
        self.entries.insert(
            id,
            Entry {
                ip,
                waiting,
                evict,
                protected_until: Instant::now() + grace,
            },
        );
        let address = self.per_address.entry(ip).or_default();
        if waiting {
            address.line.push_back(id);
        } else {
            address.slots.insert(id);
        }
        (id, eviction)
    }
}

/// One connection counted by a [`ConnectionGate`]; uncounted when dropped.
#[derive(Debug)]
pub struct Ticket {
    gate: Arc<ConnectionGate>,
    id: u64,
    eviction: Eviction,
    /// The line's wake-ups while it waits for a slot; `None` once it holds one.
    line: Option<Arc<Notify>>,
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
    /// Waits until this connection holds a slot (at once unless it was put in its address's
    /// line). Serve nothing before: a waiting connection has not been given any work.
    /// Cancel-safe.
    pub async fn wait_turn(&mut self) {
        while let Some(line) = self.line.clone() {
            let notified = line.notified();
            tokio::pin!(notified);
            notified.as_mut().enable();
            let turn = self.gate.take_turn(self.id);
            match turn {
                Turn::Admitted(evicted) => {
                    self.eviction = Eviction(Some(evicted));
                    self.line = None;
                }
                Turn::Wait(Some(until)) => {
                    tokio::select! {
                        () = notified => {}
                        () = tokio::time::sleep_until(until.into()) => {}
                    }
                }
                Turn::Wait(None) => notified.await,
            }
        }
    }

    /// Whether it still waits in line for a slot.
    pub fn waiting(&self) -> bool {
        self.line.is_some()
    }

    /// Waits until this connection is evicted to make room for a newer one.
    /// Cancel-safe.
    pub async fn evicted(&mut self) {
        self.eviction.wait().await;
    }

    /// The eviction signal, separately from the ticket (which may then move elsewhere). Take it
    /// after [`Self::wait_turn`]: a connection in line has none yet.
    pub fn eviction(&mut self) -> Eviction {
        std::mem::replace(&mut self.eviction, Eviction(None))
    }

    /// The connection completed a step (its TLS handshake, a request head): protected from
    /// eviction for another grace.
    pub fn progress(&mut self) {
        let grace = self.gate.limits.grace;
        let mut state = self.gate.lock();
        if let Some(entry) = state.entries.get_mut(&self.id)
            && !entry.waiting
        {
            entry.protected_until = Instant::now() + grace;
        }
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

    /// Counts a new connection from `ip`. It gets a slot if its address has one free (or one
    /// held by a stalled connection, which is evicted) and nobody of its address waits;
    /// otherwise it joins the address's line ([`Ticket::wait_turn`]). When all addresses
    /// together are at `max_total`, the oldest stalled connection anywhere is evicted, or if
    /// none has stalled, the oldest not held of the addresses holding the most (when they hold
    /// at least as many as the newcomer's will; else of the newcomer's own address). `None`
    /// (counted as a refusal) when there is no room: the address's line is full, or the total
    /// is reached and every connection is held.
    pub fn admit(self: &Arc<Self>, ip: IpAddr) -> Option<Ticket> {
        let ip = address_of(ip);
        let now = Instant::now();
        let cap = self.limits.max_per_address;
        let mut state = self.lock();
        let must_wait = |state: &GateState| state.slots_of(ip) >= cap || state.line_of(ip) > 0;
        if state.line_of(ip) == 0 && state.slots_of(ip) >= cap && state.evict_stalled(Some(ip), now)
        {
            self.refusals
                .count("evicted: stalled past its grace, from the same address");
        }
        if must_wait(&state) && state.line_of(ip) >= cap {
            self.refusals
                .count("refused: per-address cap and its line full, none stalled");
            return None;
        }
        if state.entries.len() >= self.limits.max_total {
            if state.evict_stalled(None, now) {
                self.refusals
                    .count("evicted: stalled past its grace (global cap)");
            } else if state.evict_from_heaviest(ip) {
                self.refusals
                    .count("evicted: from the address holding the most (global cap)");
            } else {
                self.refusals
                    .count("refused: global cap, every connection held");
                return None;
            }
        }
        let waiting = must_wait(&state);
        let line = waiting.then(|| state.per_address.entry(ip).or_default().turn.clone());
        let (id, eviction) = state.insert(ip, waiting, self.limits.grace);
        Some(Ticket {
            gate: self.clone(),
            id,
            eviction,
            line,
        })
    }

    /// Gives the connection `id` a slot if it heads its address's line and a slot is free or
    /// held by a stalled connection (evicted for it).
    fn take_turn(&self, id: u64) -> Turn {
        let now = Instant::now();
        let mut state = self.lock();
        let Some(ip) = state.entries.get(&id).filter(|e| e.waiting).map(|e| e.ip) else {
            // Not waiting (cannot happen for a ticket in line): nothing to wait for.
            let (_, evicted) = oneshot::channel();
            return Turn::Admitted(evicted);
        };
        let heads = state
            .per_address
            .get(&ip)
            .is_some_and(|a| a.line.front() == Some(&id));
        if !heads {
            return Turn::Wait(None);
        }
        if state.slots_of(ip) >= self.limits.max_per_address {
            if !state.evict_stalled(Some(ip), now) {
                return Turn::Wait(state.next_lapse(ip));
            }
            self.refusals
                .count("evicted: stalled past its grace, for the next in line");
        }
        let (tell, evicted) = oneshot::channel();
        if let Some(entry) = state.entries.get_mut(&id) {
            entry.waiting = false;
            entry.evict = Some(tell);
            entry.protected_until = now + self.limits.grace;
        }
        if let Some(address) = state.per_address.get_mut(&ip) {
            address.line.pop_front();
            address.slots.insert(id);
            // The next in line looks again.
            address.turn.notify_waiters();
        }
        Turn::Admitted(evicted)
    }

    /// Connections counted now (from all addresses, waiting in line included).
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
    async fn a_full_address_evicts_its_own_oldest_stalled_connection_only() {
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: 10,
                max_per_address: 2,
                grace: Duration::ZERO,
            },
            "test",
        );
        let mut first = gate.admit(ip(1)).unwrap();
        let _second = gate.admit(ip(1)).unwrap();
        let mut other = gate.admit(ip(2)).unwrap();
        let _third = gate.admit(ip(1)).unwrap();
        tokio::time::timeout(Duration::from_secs(1), first.evicted())
            .await
            .expect("the oldest stalled one from 127.0.0.1 is evicted");
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

    /// Whether the eviction signal has fired already (polled once, no waiting).
    async fn is_evicted(t: &mut Ticket) -> bool {
        tokio::time::timeout(Duration::ZERO, t.evicted())
            .await
            .is_ok()
    }

    #[tokio::test]
    async fn a_flood_from_one_address_evicts_no_connection_within_its_grace_and_waits_in_line() {
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: 100,
                max_per_address: 2,
                grace: Duration::from_secs(60),
            },
            "test",
        );
        let mut slow = gate.admit(ip(1)).unwrap();
        let mut other = gate.admit(ip(1)).unwrap();
        let flood: Vec<_> = (0..1000).filter_map(|_| gate.admit(ip(1))).collect();
        assert_eq!(
            flood.len(),
            2,
            "a cap's worth waits in line, the rest is refused"
        );
        assert!(flood.iter().all(Ticket::waiting));
        assert!(!is_evicted(&mut slow).await, "protected within its grace");
        assert!(!is_evicted(&mut other).await);
        assert!(
            !gate.admit(ip(2)).unwrap().waiting(),
            "another address is not affected"
        );
        let summary = gate.refusals().take_summary_now().unwrap();
        assert_eq!(summary.count, 998, "{summary}");
        // A slot that frees goes to the head of the line.
        let mut flood = flood;
        drop(other);
        tokio::time::timeout(Duration::from_secs(5), flood[0].wait_turn())
            .await
            .expect("the head of the line gets the freed slot");
        assert!(flood[1].waiting());
    }

    #[tokio::test]
    async fn the_line_is_served_in_arrival_order_and_takes_slots_only_from_stalled_connections() {
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: 100,
                max_per_address: 2,
                grace: Duration::from_millis(200),
            },
            "test",
        );
        let mut oldest = gate.admit(ip(1)).unwrap();
        let mut stalled = gate.admit(ip(1)).unwrap();
        let mut first = gate.admit(ip(1)).unwrap();
        assert!(first.waiting());
        tokio::time::timeout(Duration::from_secs(5), first.wait_turn())
            .await
            .expect("the first in line gets a stalled one's slot after its grace");
        assert!(
            is_evicted(&mut oldest).await,
            "the oldest stalled one was evicted"
        );
        // Newcomers queue behind one another; a reconnect does not jump the line.
        let mut second = gate.admit(ip(1)).unwrap();
        let mut third = gate.admit(ip(1)).unwrap();
        tokio::select! {
            () = second.wait_turn() => {}
            () = third.wait_turn() => panic!("the third in line went before the second"),
            () = tokio::time::sleep(Duration::from_secs(5)) => panic!("the line did not move"),
        }
        assert!(is_evicted(&mut stalled).await);
        assert!(third.waiting());
    }

    #[tokio::test]
    async fn at_the_global_cap_a_newcomer_displaces_the_address_holding_the_most() {
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: 4,
                max_per_address: 10,
                grace: Duration::from_secs(60),
            },
            "test",
        );
        let mut light = gate.admit(ip(1)).unwrap();
        let mut heavy: Vec<_> = (0..3).map(|_| gate.admit(ip(2)).unwrap()).collect();
        let newcomer = gate
            .admit(ip(3))
            .expect("room made from the heaviest address");
        assert!(!newcomer.waiting());
        assert!(is_evicted(&mut heavy[0]).await, "its oldest goes");
        assert!(
            !is_evicted(&mut light).await,
            "the lighter address keeps its one"
        );
        // The heavier address cannot displace a lighter one's: it displaces its own oldest.
        let _again = gate.admit(ip(2)).expect("room made from its own address");
        assert!(is_evicted(&mut heavy[1]).await);
        assert!(!is_evicted(&mut light).await);
        let summary = gate.refusals().take_summary_now().unwrap();
        assert!(summary.reasons.contains("holding the most"), "{summary}");
        // All held: nothing to evict.
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: 1,
                max_per_address: 10,
                grace: Duration::from_secs(60),
            },
            "test",
        );
        let mut held = gate.admit(ip(1)).unwrap();
        held.hold();
        assert!(gate.admit(ip(1)).is_none());
        assert!(gate.admit(ip(2)).is_none());
    }

    #[tokio::test]
    async fn held_connections_are_never_evicted_and_a_full_gate_of_them_refuses() {
        let gate = ConnectionGate::new(
            GateLimits {
                max_total: 2,
                max_per_address: 10,
                grace: Duration::ZERO,
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
                grace: Duration::ZERO,
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
