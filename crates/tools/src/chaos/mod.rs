//! `telerehab hub chaos`: a compressed clinic day on N hubs (`--hubs`, default 2) sharing one
//! PostgreSQL database, with hubs (SIGKILL and SIGTERM), stations, the PostgreSQL server, the
//! recording store and the network killed or cut at random (seeded) and restored. At the end
//! every summary must be stored exactly once, every recording stored with the SHA-256 its
//! station computed, every station done within the deadline and every pairing and upload in
//! the audit log; the report lists each violation and the command fails if there is one.
//!
//! The PostgreSQL server is the command's own (see module `postgres`: `initdb` and `pg_ctl` from
//! `$TELEREHAB_PG_BINDIR` or `/usr/lib/postgresql/*/bin`); without one the command fails with
//! "PostgreSQL unavailable: …". With `--patroni` the database is a cluster that fails over
//! (module `patroni`: etcd, a Patroni-managed primary and synchronous replica, HAProxy in front),
//! a PostgreSQL kill is the primary's machine gone (Patroni and postmaster SIGKILLed), the
//! report gives each failover's time (killed → first write accepted on the new primary) and the
//! killed node rejoins as the replica. The hubs are `telerehab hub serve` child processes
//! (module `hubs`), each on its own ports; the stations run in this process (module `station`).
//!
//! Without `--s3` the hubs share one data directory (one CA, recordings on that shared disk)
//! and the stations connect to them directly. With `--s3` the day is a clinic network's: a
//! SeaweedFS of its own (module `store`; killed by SIGKILL and restarted on the same ports and
//! data by the `store` kind), each hub a data directory of its own (a copy of the clinic's
//! configuration and keys, `[recordings]` in the store; no shared disk), the stations
//! connecting through one HAProxy in front of the hubs (`hub::bench::balancer`: the station port
//! passed through as TCP so mutual TLS stays end to end, each hub's `/readyz` checked), and the
//! recordings verified at the end by reading them back from the store, not from a hub's disk.
//! The `partition` kind cuts one hub off from the database and the store (module `partition`:
//! TCP relays on loopback that go silent, never reset) for at least 8 s (`PARTITION_AT_LEAST`); its
//! own deadlines must bring it back, and its stations, failing over through the balancer, still
//! get every summary stored exactly once.

mod check;
mod drill;
pub(crate) mod hubs;
mod partition;
mod patroni;
mod postgres;
mod station;
mod store;

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{Context, bail};
use rand::{Rng, SeedableRng};
use tokio::sync::mpsc;

use hubs::{Hub, HubSpec, Signal};
use partition::Link;
use patroni::Patroni;
use postgres::Postgres;
use station::{DayPlan, StationLedger, World};
use store::Store;

/// `telerehab hub chaos`.
#[derive(Debug, Clone, clap::Args)]
pub struct ChaosArgs {
    /// Simulated stations.
    #[arg(long, default_value_t = 100)]
    pub stations: usize,
    /// Seed of every random choice (what is killed when, for how long; recordings' bytes).
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
    /// Length of the compressed day, s: stations switch on in its first 30 %, their sessions
    /// fill half of it, the chaos happens between 5 % and 80 % of it.
    #[arg(long, default_value_t = 600.0)]
    pub day_s: f64,
    /// Sessions per station.
    #[arg(long, default_value_t = 3)]
    pub sessions: u32,
    /// Kills over the day (each kind of `--kinds` at least once when there are as many);
    /// default one per 15 s of the day.
    #[arg(long)]
    pub events: Option<usize>,
    /// Every station must be done this long after the start, s; default 1.5 × the day.
    #[arg(long)]
    pub deadline_s: Option<f64>,
    /// Keep the clinic, the stations' homes and the hubs' logs here (default: a temporary
    /// directory, removed).
    #[arg(long, value_name = "DIR")]
    pub keep: Option<std::path::PathBuf>,
    /// The database is a Patroni cluster (etcd, a primary and a synchronous replica, HAProxy
    /// in front) instead of one server, and "kill PostgreSQL" kills the primary's machine
    /// (Patroni and postmaster SIGKILLed): the replica takes over, the killed node rejoins.
    #[arg(long)]
    pub patroni: bool,
    /// Hub processes (1 to 16).
    #[arg(long, default_value_t = 2)]
    pub hubs: usize,
    /// Recordings in an S3 store (a SeaweedFS of the day's own, killed by `store`), each hub
    /// with a data directory of its own (no shared disk) and the stations connecting through
    /// one HAProxy in front of the hubs; recordings are verified from the store at the end.
    #[arg(long)]
    pub s3: bool,
    /// The kinds of kill the day draws from (comma-separated); default every kind the
    /// configuration supports (`store` only with `--s3`).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub kinds: Vec<KillKind>,
    /// The restore drill: the database (with `--patroni`, whichever node leads) backed up with
    /// pgBackRest into an S3 store of its own (HTTPS) early in the day, WAL archived all day
    /// (by every node of a cluster), restored at the end into a fresh server whose counts must
    /// equal the live one's (module `drill`).
    #[arg(long)]
    pub drill: bool,
}

/// A kind of kill, as `--kinds` names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum KillKind {
    /// A hub SIGKILLed.
    HubKill,
    /// A hub SIGTERMed (it must stop in order).
    HubTerm,
    /// A station's process gone.
    Station,
    /// The PostgreSQL server crashed (`--patroni`: the primary's machine gone).
    Postgres,
    /// The S3 store SIGKILLed and restarted (`--s3`).
    Store,
    /// One hub cut off from the database and the store (module `partition`).
    Partition,
}

impl KillKind {
    fn kind(self) -> Kind {
        match self {
            Self::HubKill => Kind::Hub(Signal::Kill),
            Self::HubTerm => Kind::Hub(Signal::Term),
            Self::Station => Kind::Station,
            Self::Postgres => Kind::Postgres,
            Self::Store => Kind::Store,
            Self::Partition => Kind::Partition,
        }
    }
}

/// The day's database: one server, or a cluster that fails over.
enum Database {
    Single(Postgres),
    Patroni(Box<Patroni>),
}

impl Database {
    fn url(&self) -> String {
        match self {
            Self::Single(pg) => pg.url(),
            Self::Patroni(c) => c.url(),
        }
    }

    fn drill_target(&self) -> drill::Target<'_> {
        match self {
            Self::Single(pg) => drill::Target::Server(pg),
            Self::Patroni(c) => drill::Target::Cluster(c),
        }
    }

    fn describe(&self) -> String {
        match self {
            Self::Single(pg) => format!("PostgreSQL {}", pg.version),
            Self::Patroni(c) => format!(
                "PostgreSQL {} under Patroni (primary + synchronous replica, HAProxy)",
                c.version
            ),
        }
    }

    async fn stop(self) -> anyhow::Result<()> {
        match self {
            Self::Single(pg) => pg.stop().await,
            Self::Patroni(c) => {
                c.stop().await;
                Ok(())
            }
        }
    }
}

/// The shortest partition: longer than a station waits for acknowledgements before it tries
/// another hub (4 s), than the balancer takes to find the hub unready (a 2 s check every
/// 500 ms) and than the store's connect deadline (2 s), so a partition tests the hub's and the
/// stations' own deadlines, not only their patience.
const PARTITION_AT_LEAST: Duration = Duration::from_secs(8);

/// Now, ms since the Unix epoch.
pub fn unix_ms() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_millis()).unwrap_or(u64::MAX))
}

/// One kill in the day's schedule.
#[derive(Debug, Clone, Copy)]
enum Kind {
    Hub(Signal),
    Station,
    Postgres,
    Store,
    Partition,
}

/// The day's kills of `kinds`: (time s, kind, which, downtime s), in time order.
fn schedule(
    rng: &mut impl Rng,
    day_s: f64,
    n: usize,
    kinds: &[Kind],
) -> Vec<(f64, Kind, usize, f64)> {
    let mut first: Vec<Kind> = kinds.to_vec();
    // Every kind once (shuffled), then at random.
    for k in (1..first.len()).rev() {
        first.swap(k, rng.random_range(0..=k));
    }
    let mut events: Vec<(f64, Kind, usize, f64)> = (0..n)
        .map(|k| {
            let kind = first
                .get(k)
                .copied()
                .unwrap_or_else(|| kinds[rng.random_range(0..kinds.len())]);
            let at = day_s * rng.random_range(0.05..0.8);
            let down = (day_s * rng.random_range(0.003..0.015)).max(0.5);
            (at, kind, rng.random_range(0..usize::MAX), down)
        })
        .collect();
    events.sort_by(|a, b| a.0.total_cmp(&b.0));
    events
}

fn free_port() -> anyhow::Result<std::net::SocketAddr> {
    let l = std::net::TcpListener::bind("127.0.0.1:0").context("no free port")?;
    Ok(l.local_addr()?)
}

/// Runs the day and prints the report; an error if any promise was broken.
pub async fn run(args: ChaosArgs) -> anyhow::Result<()> {
    if !(1..=1000).contains(&args.stations) || !(1..=100).contains(&args.sessions) {
        bail!("--stations must be 1 to 1000 and --sessions 1 to 100");
    }
    if !(args.day_s.is_finite() && (5.0..=86_400.0).contains(&args.day_s)) {
        bail!("--day-s must be 5 to 86400");
    }
    if !(1..=16).contains(&args.hubs) {
        bail!("--hubs must be 1 to 16");
    }
    if args.kinds.contains(&KillKind::Store) && !args.s3 {
        bail!("--kinds store needs --s3 (the day's own S3 store)");
    }
    let deadline_s = args.deadline_s.unwrap_or(args.day_s * 1.5);
    let n_events = args.events.unwrap_or((args.day_s / 15.0).round() as usize);
    // The drill's store first: a cluster archives from its start.
    let mut drill = if args.drill {
        Some(
            drill::Drill::start()
                .await
                .map_err(|e| anyhow::anyhow!("restore drill unavailable: {e:#}"))?,
        )
    } else {
        None
    };
    let pg = if args.patroni {
        let archive = drill.as_ref().map(|d| move |k: usize| d.archive_command(k));
        Database::Patroni(Box::new(
            Patroni::start_new(
                archive
                    .as_ref()
                    .map(|f| f as &dyn Fn(usize) -> anyhow::Result<String>),
            )
            .await
            .map_err(|e| anyhow::anyhow!("Patroni unavailable: {e:#}"))?,
        ))
    } else {
        Database::Single(
            Postgres::start_new()
                .await
                .map_err(|e| anyhow::anyhow!("PostgreSQL unavailable: {e:#}"))?,
        )
    };
    let s3 = if args.s3 {
        match Store::start_new().await {
            Ok(s) => Some(s),
            Err(e) => {
                let _ = pg.stop().await;
                bail!("S3 store unavailable: {e:#}");
            }
        }
    } else {
        None
    };
    if let Some(d) = drill.as_mut()
        && let Err(e) = d.begin(pg.drill_target()).await
    {
        if let Some(s) = s3 {
            s.stop().await;
        }
        let _ = pg.stop().await;
        bail!("restore drill unavailable: {e:#}");
    }
    let tmp = tempfile::tempdir().context("cannot make the day's directory")?;
    let dir = args.keep.clone().unwrap_or_else(|| tmp.path().to_owned());
    let result = day(&args, &pg, s3.as_ref(), &dir, deadline_s, n_events).await;
    if let Some(s) = s3 {
        s.stop().await;
    }
    let drilled = match drill {
        Some(d) if result.is_ok() => Some(drill::report(&d.run(pg.drill_target()).await)),
        _ => None,
    };
    if let Err(e) = pg.stop().await {
        eprintln!("chaos: stopping PostgreSQL: {e:#}");
    }
    let violations = result? + drilled.unwrap_or(0);
    if violations > 0 {
        bail!("the chaos day broke {violations} promises (listed above)");
    }
    Ok(())
}

/// The clinic, its patients and their pairing codes.
async fn clinic(
    dir: &std::path::Path,
    url: &str,
    stations: usize,
) -> anyhow::Result<(hub::db::Db, Vec<StationLedger>)> {
    let clinic = hub::clinic::Clinic::at(dir.join("clinic"));
    let names = ["localhost".to_owned(), "127.0.0.1".to_owned()];
    let now = i64::try_from(unix_ms()).unwrap_or(i64::MAX);
    clinic
        .init("chaos@clinic.example", &names, Some(url), now)
        .await?;
    let db = clinic.open_db(Some(url)).await?;
    let mut ledger = Vec::with_capacity(stations);
    for i in 0..stations {
        let p = db.add_patient(&format!("CHAOS-{i:04}"), None, now).await?;
        let code = db.create_pairing_code(&p.id, now, 3_600_000).await?;
        ledger.push(StationLedger {
            patient_id: p.id,
            code,
            phase: "off".into(),
            ..StationLedger::default()
        });
    }
    Ok((db, ledger))
}

/// The kinds the configuration supports: every one, `store` only with an S3 store.
fn default_kinds(s3: bool) -> Vec<KillKind> {
    let mut kinds = vec![
        KillKind::HubKill,
        KillKind::HubTerm,
        KillKind::Station,
        KillKind::Postgres,
    ];
    if s3 {
        kinds.push(KillKind::Store);
    }
    kinds.push(KillKind::Partition);
    kinds
}

/// Hub `k`'s data directory: with an S3 store a copy of the clinic's configuration and keys of
/// its own (a hub machine's own disk) whose `hub.toml` puts recordings in the store reached at
/// `endpoint`; without, the clinic's directory itself (shared by every hub, recordings too).
fn hub_data(
    dir: &std::path::Path,
    k: usize,
    s3: Option<(&Store, &str)>,
) -> anyhow::Result<std::path::PathBuf> {
    let clinic = dir.join("clinic");
    let Some((store, endpoint)) = s3 else {
        return Ok(clinic);
    };
    let data = dir.join(format!("hub-{k}"));
    let status = std::process::Command::new("cp")
        .arg("-a")
        .arg(&clinic)
        .arg(&data)
        .status()
        .context("cp -a of the clinic's directory")?;
    if !status.success() {
        bail!("cannot copy the clinic's directory to {}", data.display());
    }
    let recordings = toml::to_string(&std::collections::BTreeMap::from([(
        "recordings",
        store.config(endpoint),
    )]))
    .context("hub.toml's [recordings]")?;
    let toml_path = data.join("hub.toml");
    let mut text = std::fs::read_to_string(&toml_path).context("reading hub.toml")?;
    text.push('\n');
    text.push_str(&recordings);
    std::fs::write(&toml_path, text).context("writing hub.toml")?;
    Ok(data)
}

/// Starts `n` supervised hubs on `url` (and the store `s3`), each through relays of its own that
/// a partition can silence when `partitions`; the hubs and their links.
async fn start_hubs(
    n: usize,
    url: &str,
    s3: Option<&Store>,
    dir: &std::path::Path,
    partitions: bool,
) -> anyhow::Result<(Vec<Hub>, Vec<Link>)> {
    let exe = std::env::current_exe().context("cannot find this executable")?;
    let mut hubs = Vec::new();
    let mut links = Vec::new();
    for k in 0..n {
        let link = Link::new();
        let (db_url, endpoint) = if partitions {
            let db_relay = link.relay(partition::upstream_of(url)?).await?;
            let endpoint = match s3 {
                Some(s) => Some(partition::through(
                    &s.endpoint,
                    link.relay(partition::upstream_of(&s.endpoint)?).await?,
                )?),
                None => None,
            };
            (partition::through(url, db_relay)?, endpoint)
        } else {
            (url.to_owned(), s3.map(|s| s.endpoint.clone()))
        };
        let data = hub_data(dir, k, s3.zip(endpoint.as_deref()))?;
        hubs.push(Hub::start(HubSpec {
            exe: exe.clone(),
            data,
            db: Some(db_url),
            stations: free_port()?,
            web: free_port()?,
            log: dir.join(format!("hub-{k}.log")),
        }));
        links.push(link);
    }
    Ok((hubs, links))
}

async fn day(
    args: &ChaosArgs,
    pg: &Database,
    s3: Option<&Store>,
    dir: &std::path::Path,
    deadline_s: f64,
    n_events: usize,
) -> anyhow::Result<usize> {
    let url = pg.url();
    let (db, ledger) = clinic(dir, &url, args.stations).await?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(args.seed);
    let chosen = if args.kinds.is_empty() {
        default_kinds(s3.is_some())
    } else {
        args.kinds.clone()
    };
    // Each hub reaches the database and the store through relays a partition can silence.
    let partitions = chosen.contains(&KillKind::Partition);
    let (hubs, links) = start_hubs(args.hubs, &url, s3, dir, partitions).await?;
    // With an S3 store the hubs share no disk: stations reach them through one balancer.
    let balancer = if s3.is_some() {
        let servers: Vec<_> = hubs.iter().map(|h| (h.stations, h.web)).collect();
        Some(hub::bench::balancer::Balancer::start_ready(&servers, args.stations).await?)
    } else {
        None
    };
    let p = args.sessions;
    let plan = DayPlan {
        sessions: p,
        session_s: args.day_s * 0.45 / f64::from(p),
        gap_s: args.day_s * 0.05 / f64::from(p),
        rate_hz: 10.0,
        start_s: (0..args.stations)
            .map(|_| rng.random_range(0.0..args.day_s * 0.3))
            .collect(),
        seed: args.seed,
    };
    let kinds: Vec<Kind> = chosen.iter().map(|k| k.kind()).collect();
    let events = schedule(&mut rng, args.day_s, n_events, &kinds);
    println!(
        "hub chaos: {} stations × {} sessions of {:.1} s at 10 Hz over a {} s day, seed {}, \
         {} hubs on {}, recordings {}, {} kills of {chosen:?}",
        args.stations,
        p,
        plan.session_s,
        args.day_s,
        args.seed,
        args.hubs,
        pg.describe(),
        if s3.is_some() {
            "in SeaweedFS (S3), each hub its own data directory, stations through HAProxy"
        } else {
            "on the hubs' shared data directory, stations connecting to the hubs directly"
        },
        events.len()
    );
    let world = Arc::new(World {
        hubs: balancer.as_ref().map_or_else(
            || hubs.iter().map(|h| h.stations).collect(),
            |b| vec![b.addr],
        ),
        ledger: Mutex::new(ledger),
        desk: db.clone(),
        plan,
        t0: Instant::now(),
        homes: dir.join("stations"),
    });
    let mut kills = Vec::with_capacity(args.stations);
    let mut runners = tokio::task::JoinSet::new();
    for i in 0..args.stations {
        let (tx, rx) = mpsc::unbounded_channel();
        kills.push(tx);
        runners.spawn(station_runner(world.clone(), i, rx));
    }
    let mut tally = Tally::default();
    let deadline = world.t0 + Duration::from_secs_f64(deadline_s);
    let mut events = events.into_iter().peekable();
    loop {
        let next = events
            .peek()
            .map(|e| world.t0 + Duration::from_secs_f64(e.0));
        tokio::select! {
            () = sleep_until_opt(next) => {
                if let Some(event) = events.next() {
                    act(event, (&world, &hubs, &links), (pg, s3), &kills, &mut tally).await;
                }
            }
            joined = runners.join_next() => if joined.is_none() { break },
            () = tokio::time::sleep_until(deadline.into()) => break,
        }
    }
    runners.abort_all();
    let recordings = before_check(pg, s3, dir, &mut tally).await;
    let ledger = world
        .ledger
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .clone();
    let verdict = check::check(&db, &ledger, recordings.as_ref()).await;
    let mut stats = Vec::new();
    for h in hubs {
        stats.push(h.stop().await);
    }
    if let Some(b) = balancer {
        b.stop().await;
    }
    db.close().await;
    Ok(report(&ledger, &verdict, &stats, &tally, deadline_s))
}

/// Makes sure the database's server and the store run for the end checks; a recording store
/// of the check's own on the S3 store, if there is one.
async fn before_check(
    pg: &Database,
    s3: Option<&Store>,
    dir: &std::path::Path,
    tally: &mut Tally,
) -> Option<hub::recordings::RecordingStore> {
    // The checks read the database: make sure its server runs.
    match pg {
        Database::Single(pg) if tally.pg_down => {
            let _ = pg.start().await;
        }
        Database::Single(_) => {}
        Database::Patroni(c) => {
            if let Err(e) = c.first_write(patroni::FAILOVER_WITHIN).await {
                tally
                    .errors
                    .push(format!("the database before the check: {e:#}"));
            }
        }
    }
    // … and the store, read through a recording store of the check's own.
    match s3 {
        Some(s) => {
            if tally.store_down
                && let Err(e) = s.restart().await
            {
                tally
                    .errors
                    .push(format!("the store before the check: {e:#}"));
            }
            match s.recordings(&dir.join("check")) {
                Ok(r) => Some(r),
                Err(e) => {
                    tally.errors.push(format!("{e:#}"));
                    None
                }
            }
        }
        None => None,
    }
}

async fn sleep_until_opt(at: Option<Instant>) {
    match at {
        Some(t) => tokio::time::sleep_until(t.into()).await,
        None => std::future::pending().await,
    }
}

/// Runs a station until its day is done; a message kills it (its future is dropped) and it
/// restarts from its home after the given pause.
async fn station_runner(world: Arc<World>, i: usize, mut kills: mpsc::UnboundedReceiver<Duration>) {
    loop {
        tokio::select! {
            () = station::run(world.clone(), i) => return,
            Some(down) = kills.recv() => {
                {
                    let mut l = world.ledger.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
                    l[i].kills += 1;
                    "killed".clone_into(&mut l[i].phase);
                }
                tokio::time::sleep(down).await;
            }
        }
    }
}

/// What the chaos did.
#[derive(Debug, Default)]
struct Tally {
    hub_kills: u32,
    hub_terms: u32,
    station_kills: u32,
    pg_kills: u32,
    store_kills: u32,
    /// Each store restart: started → it lists the bucket again, s.
    store_restarts_s: Vec<f64>,
    partitions: u32,
    store_down: bool,
    /// Each primary kill's failover: killed → first write accepted through the balancer, s.
    failovers_s: Vec<f64>,
    skipped: u32,
    pg_down: bool,
    errors: Vec<String>,
}

async fn act(
    (at, kind, which, down_s): (f64, Kind, usize, f64),
    (world, hubs, links): (&World, &[Hub], &[Link]),
    (pg, s3): (&Database, Option<&Store>),
    kills: &[mpsc::UnboundedSender<Duration>],
    tally: &mut Tally,
) {
    let down = Duration::from_secs_f64(down_s);
    let what = match kind {
        Kind::Hub(signal) => {
            let h = which % hubs.len();
            if hubs[h].kill(signal, down).await {
                match signal {
                    Signal::Kill => tally.hub_kills += 1,
                    Signal::Term => tally.hub_terms += 1,
                }
                format!("{signal:?} hub {h}")
            } else {
                tally.skipped += 1;
                format!("{signal:?} hub {h}: already down, skipped")
            }
        }
        Kind::Station => {
            let ledger = world
                .ledger
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            let running: Vec<usize> = (0..ledger.len())
                .filter(|&i| ledger[i].finished_s.is_none() && ledger[i].phase != "killed")
                .collect();
            drop(ledger);
            if running.is_empty() {
                tally.skipped += 1;
                "kill a station: none running, skipped".into()
            } else {
                let i = running[which % running.len()];
                let _ = kills[i].send(down);
                tally.station_kills += 1;
                format!("kill station {i}")
            }
        }
        Kind::Postgres => match pg {
            Database::Single(pg) => kill_single(pg, down, tally).await,
            Database::Patroni(c) => kill_primary(c, down, tally).await,
        },
        Kind::Store => match s3 {
            Some(s) => kill_store(s, down, tally).await,
            None => {
                tally.skipped += 1;
                "kill the store: no store, skipped".into()
            }
        },
        Kind::Partition => {
            let h = which % links.len();
            let cut = down.max(PARTITION_AT_LEAST);
            links[h].set_cut(true);
            tally.partitions += 1;
            tokio::time::sleep(cut).await;
            links[h].set_cut(false);
            format!(
                "partition hub {h} from the database and the store for {:.1} s",
                cut.as_secs_f64()
            )
        }
    };
    println!("  {at:6.1} s  {what}, down {down_s:.1} s");
}

/// Crashes the one server and starts it again `down` later.
async fn kill_single(pg: &Postgres, down: Duration, tally: &mut Tally) -> String {
    tally.pg_kills += 1;
    match pg.kill().await {
        Ok(()) => tally.pg_down = true,
        Err(e) => tally.errors.push(format!("killing PostgreSQL: {e:#}")),
    }
    tokio::time::sleep(down).await;
    match pg.start().await {
        Ok(()) => tally.pg_down = false,
        Err(e) => tally.errors.push(format!("restarting PostgreSQL: {e:#}")),
    }
    "kill PostgreSQL (pg_ctl stop -m immediate)".into()
}

/// SIGKILLs the store and starts it again `down` later on the same ports and data.
async fn kill_store(s: &Store, down: Duration, tally: &mut Tally) -> String {
    if let Err(e) = s.kill().await {
        tally.errors.push(format!("killing the store: {e:#}"));
        return "kill the store: failed".into();
    }
    tally.store_kills += 1;
    tally.store_down = true;
    tokio::time::sleep(down).await;
    let began = Instant::now();
    match s.restart().await {
        Ok(()) => {
            tally.store_down = false;
            let t = began.elapsed().as_secs_f64();
            tally.store_restarts_s.push(t);
            format!(
                "kill the S3 store (SeaweedFS SIGKILL): answering again {t:.1} s after its restart"
            )
        }
        Err(e) => {
            tally.errors.push(format!("restarting the store: {e:#}"));
            "kill the S3 store (SeaweedFS SIGKILL): not restarted".into()
        }
    }
}

/// Kills the primary's machine, measures the failover (killed → first write accepted through
/// the balancer), and starts the killed node again `down` after the kill (or after the
/// failover, if that took longer); waits until it streams as the synchronous replica again,
/// so the next kill finds two nodes.
async fn kill_primary(c: &Patroni, down: Duration, tally: &mut Tally) -> String {
    let killed_at = Instant::now();
    let k = match c.kill_primary().await {
        Ok(k) => k,
        Err(e) => {
            tally
                .errors
                .push(format!("killing the PostgreSQL primary: {e:#}"));
            return "kill PostgreSQL primary: failed".into();
        }
    };
    tally.pg_kills += 1;
    let failover = match c.first_write(patroni::FAILOVER_WITHIN).await {
        Ok(t) => {
            tally.failovers_s.push(t.as_secs_f64());
            format!("failover {:.1} s", t.as_secs_f64())
        }
        Err(e) => {
            tally.errors.push(format!("failover: {e:#}"));
            "no failover".into()
        }
    };
    tokio::time::sleep_until((killed_at + down).into()).await;
    let rejoin = Instant::now();
    let rejoined = match c.restart(k).await {
        Ok(()) => match c.wait_synchronous(patroni::FAILOVER_WITHIN).await {
            Ok(()) => format!(
                "node {k} back as synchronous replica after {:.1} s",
                rejoin.elapsed().as_secs_f64()
            ),
            Err(e) => {
                tally.errors.push(format!("node {k} rejoining: {e:#}"));
                format!("node {k} did not rejoin")
            }
        },
        Err(e) => {
            tally.errors.push(format!("restarting node {k}: {e:#}"));
            format!("node {k} not restarted")
        }
    };
    format!(
        "kill PostgreSQL primary node {k} (Patroni and postmaster SIGKILL): {failover}, {rejoined}"
    )
}

/// Prints the report; the number of violations.
fn report(
    ledger: &[StationLedger],
    v: &check::Verdict,
    hubs: &[hubs::HubStats],
    t: &Tally,
    deadline_s: f64,
) -> usize {
    let sum = |f: fn(&StationLedger) -> u64| ledger.iter().map(f).sum::<u64>();
    let own_exits: usize = hubs.iter().map(|h| h.own_exits.len()).sum();
    println!(
        "chaos: hub SIGKILL {}, hub SIGTERM {}, station kills {}, PostgreSQL kills {}, \
         store kills {}, partitions {}, skipped {}; hub starts {}, hub exits on their own {own_exits}",
        t.hub_kills,
        t.hub_terms,
        t.station_kills,
        t.pg_kills,
        t.store_kills,
        t.partitions,
        t.skipped,
        hubs.iter().map(|h| h.starts).sum::<u32>(),
    );
    if !t.failovers_s.is_empty() {
        let max = t.failovers_s.iter().copied().fold(0.0, f64::max);
        let mean = t.failovers_s.iter().sum::<f64>() / t.failovers_s.len() as f64;
        println!(
            "failover: {} primary kills, killed → first write accepted on the new primary \
             mean {mean:.1} s, max {max:.1} s",
            t.failovers_s.len()
        );
    }
    if !t.store_restarts_s.is_empty() {
        let max = t.store_restarts_s.iter().copied().fold(0.0, f64::max);
        println!(
            "store: {} kills, restart → answering again max {max:.1} s",
            t.store_restarts_s.len()
        );
    }
    println!(
        "stations: {} paired, {} done (slowest at {:.1} s, deadline {deadline_s:.0} s); \
         failovers {}, pairing codes reissued {}, pairings rate-limited {}",
        v.paired,
        v.finished,
        v.slowest_s,
        sum(|l| l.failovers),
        sum(|l| u64::from(l.codes_reissued)),
        sum(|l| u64::from(l.pairing_rate_limited)),
    );
    println!(
        "summaries: {} produced in {} sessions, {} stored exactly once, {} missing, {} extra",
        v.produced, v.sessions, v.stored_once, v.missing, v.extra
    );
    println!(
        "recordings: {} written, {} stored and SHA-256 verified {}",
        v.recordings, v.recordings_verified, v.verified_from
    );
    println!(
        "audit: {} station_paired, {} recording_uploaded entries",
        v.audited.0, v.audited.1
    );
    let mut violations: Vec<String> = v.violations.clone();
    for (k, h) in hubs.iter().enumerate() {
        if h.slow_stops > 0 {
            violations.push(format!(
                "hub {k} did not stop within {} s of SIGTERM {} times",
                hubs::TERM_WITHIN.as_secs(),
                h.slow_stops
            ));
        }
        for e in &h.spawn_errors {
            violations.push(format!("hub {k} could not be started: {e}"));
        }
        for e in h.own_exits.iter().take(3) {
            println!("note: hub {k} exited on its own (restarted): {e}");
        }
    }
    violations.extend(t.errors.iter().cloned());
    for line in violations.iter().take(30) {
        println!("VIOLATION: {line}");
    }
    if violations.len() > 30 {
        println!("… and {} more", violations.len() - 30);
    }
    println!(
        "verdict: {}",
        if violations.is_empty() {
            "OK — nothing lost, nothing duplicated, nobody stuck".to_owned()
        } else {
            format!("{} violations", violations.len())
        }
    );
    violations.len()
}
