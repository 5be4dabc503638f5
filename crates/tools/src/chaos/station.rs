//! A simulated station of the chaos day: the station's own link code in-process (netlink's
//! store-and-forward link, the on-disk summary queue and the upload queue of
//! [`station::link`]) without the physics. It pairs once, then runs its sessions — a summary every
//! 100 ms, each appended to its home's queue before it is sent, the session ended with `Bye`,
//! a small recording queued and uploaded — failing over to the other hub when its hub stops
//! acknowledging. "Killing" it drops its future (every await point is a possible crash point);
//! it restarts from its home directory, as `telerehab run` would: pairing, session counter,
//! queued summaries and queued uploads all come from disk.
//!
//! What each station produced is written to the [`Ledger`] in the same synchronous step as
//! its queue file, so the ledger is exactly what the station owes the hub.

use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use hub::db::Db;
use netlink::pairing::PairError;
use netlink::{ClientTls, Hello, PROTOCOL_VERSION, StationLink, StationLinkConfig, Summary};
use rand::{RngCore, SeedableRng};

use station::home::{Home, Pairing};
use station::link::{queue, uploads};

/// A station's session as the station saw it.
#[derive(Debug, Clone, Default)]
pub struct SessionLedger {
    /// Its id.
    pub session_id: String,
    /// Summaries produced (seq 0 to `produced - 1`), each in the queue file before sending.
    pub produced: u64,
    /// Its recording's SHA-256 and size, once written and queued for upload.
    pub recording: Option<(String, u64)>,
}

/// One station's day.
#[derive(Debug, Clone, Default)]
pub struct StationLedger {
    /// Its patient.
    pub patient_id: String,
    /// The pairing code it holds now.
    pub code: String,
    /// Its id, once paired (its credential saved).
    pub station_id: Option<String>,
    /// Its sessions.
    pub sessions: Vec<SessionLedger>,
    /// When it finished its day, s after the start.
    pub finished_s: Option<f64>,
    /// What it is doing (for a stuck station).
    pub phase: String,
    /// Times killed.
    pub kills: u32,
    /// Switches to the other hub.
    pub failovers: u64,
    /// New pairing codes it needed.
    pub codes_reissued: u32,
    /// Pairing attempts refused by the per-address rate limit.
    pub pairing_rate_limited: u32,
    /// The last error it saw.
    pub last_error: Option<String>,
}

/// The shape of every station's day.
#[derive(Debug, Clone)]
pub struct DayPlan {
    /// Sessions per station.
    pub sessions: u32,
    /// Length of a session, s.
    pub session_s: f64,
    /// Pause between sessions, s.
    pub gap_s: f64,
    /// Summaries per second.
    pub rate_hz: f64,
    /// When each station is switched on, s after the start.
    pub start_s: Vec<f64>,
    /// The seed (recordings' bytes).
    pub seed: u64,
}

/// What the stations share: the hubs, the ledger, the clinic's front desk.
pub struct World {
    /// Where stations connect: each hub's station address, or the one balancer in front of
    /// them all.
    pub hubs: Vec<SocketAddr>,
    /// Every station's ledger.
    pub ledger: Mutex<Vec<StationLedger>>,
    /// The clinic's database, for new pairing codes (the front desk).
    pub desk: Db,
    /// The day.
    pub plan: DayPlan,
    /// The start of the day.
    pub t0: Instant,
    /// Stations' homes live under here.
    pub homes: std::path::PathBuf,
}

/// How long a link with unacknowledged summaries and no progress waits before the station
/// switches hubs.
const FAILOVER_AFTER: Duration = Duration::from_secs(4);

impl World {
    fn with<R>(&self, i: usize, f: impl FnOnce(&mut StationLedger) -> R) -> R {
        let mut ledger = self
            .ledger
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        f(&mut ledger[i])
    }

    fn note(&self, i: usize, phase: &str) {
        self.with(i, |l| phase.clone_into(&mut l.phase));
    }

    fn error(&self, i: usize, e: impl std::fmt::Display) {
        self.with(i, |l| l.last_error = Some(e.to_string()));
    }

    fn addr(&self, hub: usize) -> String {
        self.hubs[hub % self.hubs.len()].to_string()
    }

    /// A station's home.
    pub fn home(&self, i: usize) -> Home {
        Home::at(self.homes.join(format!("station-{i:03}")))
    }
}

/// Runs station `i`'s day from whatever its home holds; returns when the day is done.
pub async fn run(world: Arc<World>, i: usize) {
    let home = world.home(i);
    let start = world.t0 + Duration::from_secs_f64(world.plan.start_s[i]);
    tokio::time::sleep_until(start.into()).await;
    let mut hub = i % 2;
    let pairing = loop {
        match home.pairing() {
            Ok(Some(p)) => break p,
            Ok(None) => {
                world.note(i, "pairing");
                pair(&world, i, &home, &mut hub).await;
            }
            Err(e) => {
                world.error(i, format!("{e:#}"));
                tokio::time::sleep(Duration::from_secs(1)).await;
            }
        }
    };
    let tls = home.client_tls(&pairing);
    loop {
        let next = next_session(&home);
        world.note(i, "delivering its queue");
        let empty = flush_backlog(&world, i, &home, &tls, &mut hub).await;
        if next < world.plan.sessions {
            let p = &world.plan;
            let due = start + Duration::from_secs_f64(f64::from(next) * (p.session_s + p.gap_s));
            tokio::time::sleep_until(due.into()).await;
            if let Err(e) = set_next_session(&home, next + 1) {
                world.error(i, format!("{e:#}"));
                tokio::time::sleep(Duration::from_secs(1)).await;
                continue;
            }
            world.note(i, &format!("session {next}"));
            if let Err(e) = session(&world, i, (&home, &pairing, &tls), next, &mut hub).await {
                world.error(i, format!("{e:#}"));
            }
        } else if empty {
            let t = world.t0.elapsed().as_secs_f64();
            world.with(i, |l| {
                l.finished_s = Some(t);
                "done".clone_into(&mut l.phase);
            });
            return;
        } else {
            tokio::time::sleep(Duration::from_millis(300)).await;
        }
    }
}

/// The next session's number, kept in the home (`chaos-day.txt`).
fn next_session(home: &Home) -> u32 {
    std::fs::read_to_string(home.dir().join("chaos-day.txt"))
        .ok()
        .and_then(|t| t.trim().parse().ok())
        .unwrap_or(0)
}

fn set_next_session(home: &Home, n: u32) -> anyhow::Result<()> {
    session::files::write_private(&home.dir().join("chaos-day.txt"), n.to_string().as_bytes())
}

/// Pairs with the code in the ledger: another hub when one is unreachable, a pause when the
/// per-address limit refuses, a new code from the front desk when the code is refused (used
/// up by a pairing whose answer was lost, or by a database that failed half-way).
async fn pair(world: &World, i: usize, home: &Home, hub: &mut usize) {
    let mut refusals = 0;
    loop {
        let code = world.with(i, |l| l.code.clone());
        let addr = world.addr(*hub);
        match netlink::pairing::pair(&addr, &code, Duration::from_secs(10)).await {
            Ok(credential) => {
                let now = crate::chaos::unix_ms();
                match home.save_pairing(&addr, &credential, now) {
                    Ok(p) => {
                        world.with(i, |l| l.station_id = Some(p.station_id));
                        return;
                    }
                    Err(e) => world.error(i, format!("{e:#}")),
                }
            }
            Err(PairError::Refused(m)) if m.contains("too many pairing attempts") => {
                world.with(i, |l| l.pairing_rate_limited += 1);
                *hub += 1;
                tokio::time::sleep(Duration::from_secs(3)).await;
                continue;
            }
            Err(PairError::Refused(m)) => {
                world.error(i, format!("pairing refused: {m}"));
                refusals += 1;
                if refusals >= 2 {
                    refusals = 0;
                    let patient = world.with(i, |l| l.patient_id.clone());
                    let code = new_code(world, &patient).await;
                    world.with(i, |l| {
                        l.code = code;
                        l.codes_reissued += 1;
                    });
                }
            }
            Err(e) => {
                world.error(i, format!("pairing: {e}"));
                *hub += 1;
            }
        }
        tokio::time::sleep(Duration::from_millis(500)).await;
    }
}

/// A new pairing code from the front desk (retried while the database is down).
pub async fn new_code(world: &World, patient_id: &str) -> String {
    loop {
        let now = i64::try_from(crate::chaos::unix_ms()).unwrap_or(i64::MAX);
        match world
            .desk
            .create_pairing_code(patient_id, now, 3_600_000)
            .await
        {
            Ok(code) => return code,
            Err(_) => tokio::time::sleep(Duration::from_millis(500)).await,
        }
    }
}

/// Delivers queued sessions and uploads queued recordings; true if nothing is left. A hub
/// that fails is swapped for the other.
async fn flush_backlog(
    world: &World,
    i: usize,
    home: &Home,
    tls: &ClientTls,
    hub: &mut usize,
) -> bool {
    let dir = home.queue_dir();
    let queued = match queue::pending(&dir) {
        Ok(q) => q,
        Err(e) => {
            world.error(i, format!("{e:#}"));
            return false;
        }
    };
    if !queued.is_empty() {
        let timeout = Duration::from_secs(4);
        let addr = world.addr(*hub);
        match queue::deliver_sessions(queued, &dir, &addr, Some(tls.clone()), timeout).await {
            Ok(r) if r.delivered == r.sessions => {}
            Ok(r) => {
                world.error(i, r.last_error.unwrap_or_else(|| "not delivered".into()));
                failover(world, i, hub);
                return false;
            }
            Err(e) => {
                world.error(i, format!("{e:#}"));
                return false;
            }
        }
    }
    let udir = home.uploads_dir();
    let waiting = std::fs::read_dir(&udir).map_or(0, |d| {
        d.filter_map(Result::ok)
            .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
            .count()
    });
    if waiting == 0 {
        return true;
    }
    world.note(i, "uploading");
    let addr = world.addr(*hub);
    let r = uploads::upload_all(&udir, &addr, Some(tls), 4_000_000, Duration::from_secs(8)).await;
    if r.remaining > 0 {
        world.error(i, r.last_error.unwrap_or_else(|| "upload left".into()));
        failover(world, i, hub);
        return false;
    }
    true
}

fn failover(world: &World, i: usize, hub: &mut usize) {
    *hub += 1;
    world.with(i, |l| l.failovers += 1);
}

fn link(
    world: &World,
    hub: usize,
    tls: &ClientTls,
    hello: &Hello,
) -> anyhow::Result<(netlink::SummarySender, StationLink)> {
    let mut config =
        StationLinkConfig::new(world.addr(hub).as_str(), Some(tls.clone()), hello.clone());
    config.channel_capacity = 100_000;
    config.reconnect = netlink::Backoff {
        initial_ms: 100,
        max_ms: 1_000,
    };
    Ok(StationLink::spawn(
        &tokio::runtime::Handle::current(),
        config,
    )?)
}

/// One session: summaries at the plan's rate, then `Bye`, then the recording queued.
async fn session(
    world: &World,
    i: usize,
    (home, pairing, tls): (&Home, &Pairing, &ClientTls),
    n: u32,
    hub: &mut usize,
) -> anyhow::Result<()> {
    let session_id = format!("chaos-{i:03}-s{n:02}");
    let hello = Hello {
        protocol_version: PROTOCOL_VERSION,
        min_protocol_version: None,
        wheel: None,
        station_id: pairing.station_id.clone(),
        patient_id: pairing.patient_id.clone(),
        session_id: session_id.clone(),
        exercise: "sine-road".into(),
        started_unix_ms: crate::chaos::unix_ms(),
        software_version: "telerehab hub chaos".into(),
    };
    let mut file = queue::QueueFile::create(&home.queue_dir(), &hello)?;
    let index = world.with(i, |l| {
        l.sessions.push(SessionLedger {
            session_id: session_id.clone(),
            ..SessionLedger::default()
        });
        l.sessions.len() - 1
    });
    let (mut sender, mut current) = link(world, *hub, tls, &hello)?;
    let count = (world.plan.session_s * world.plan.rate_hz).round().max(1.0) as u64;
    let mut every = tokio::time::interval(Duration::from_secs_f64(1.0 / world.plan.rate_hz));
    let mut all: Vec<Summary> = Vec::with_capacity(usize::try_from(count).unwrap_or(0));
    let (mut acked, mut progress_at) = (0, Instant::now());
    for seq in 0..count {
        every.tick().await;
        let summary = Summary::example(&session_id, seq);
        // The queue file and the ledger in one synchronous step: a kill falls before or after.
        file.push(&summary);
        if let Some(e) = &file.error {
            anyhow::bail!("the summary queue failed: {e}");
        }
        world.with(i, |l| l.sessions[index].produced = seq + 1);
        let _ = sender.send(summary.clone());
        all.push(summary);
        let stats = current.stats();
        if stats.acked > acked || stats.pending == 0 {
            (acked, progress_at) = (stats.acked, Instant::now());
        } else if progress_at.elapsed() > FAILOVER_AFTER {
            failover(world, i, hub);
            (sender, current) = link(world, *hub, tls, &hello)?;
            for s in &all {
                let _ = sender.send(s.clone());
            }
            (acked, progress_at) = (0, Instant::now());
        }
    }
    drop(sender);
    let stats = current.finish(Duration::from_secs(3)).await;
    if stats.pending == 0 && stats.bye_acknowledged {
        file.delivered();
    } else {
        // Left in the queue: delivered by the backlog, from the other hub.
        failover(world, i, hub);
    }
    record(world, i, home, &hello, n, index)
}

/// Writes the session's recording (seeded bytes, 8 to 64 KiB) and queues its upload.
fn record(
    world: &World,
    i: usize,
    home: &Home,
    hello: &Hello,
    n: u32,
    index: usize,
) -> anyhow::Result<()> {
    let mut rng =
        rand_chacha::ChaCha8Rng::seed_from_u64(world.plan.seed ^ ((i as u64) << 20) ^ u64::from(n));
    let size = 8_192 + (rng.next_u32() % 57_345) as usize;
    let mut bytes = vec![0u8; size];
    rng.fill_bytes(&mut bytes);
    let dir = home.recordings_dir();
    station::home::private_dir(&dir)?;
    let path = dir.join(format!("{}.mcap", hello.session_id));
    session::files::write_private(&path, &bytes)?;
    let (size, sha) = netlink::upload::file_sha256(&path)?;
    world.with(i, |l| l.sessions[index].recording = Some((sha, size)));
    uploads::enqueue(&home.uploads_dir(), hello, &path)
}
