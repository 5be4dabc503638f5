//! The restore drill of `telerehab hub chaos --drill` (issue 45): the day's PostgreSQL is backed
//! up with PostgreSQL's own tool, pgBackRest (Debian's `pgbackrest`), into an S3 object store,
//! and restored at the end of the day into a fresh data directory, as docs/DEPLOY.md tells a
//! clinic network to do it.
//!
//! - **The store**: a SeaweedFS (`weed mini`, `~/.local/bin/weed` or `$TELEREHAB_WEED`) of the
//!   drill's own with a bucket `backups`, serving S3 over HTTPS only to pgBackRest (2.45 speaks
//!   S3 over HTTPS only) with a certificate for `localhost` from a CA made at run time
//!   (`netlink::pki`), which pgBackRest verifies (`repo1-storage-ca-file`).
//! - **The repository** is encrypted (`repo1-cipher-type=aes-256-cbc`, a passphrase made per
//!   run), as a clinic's must be.
//! - **Each PostgreSQL machine has its own pgBackRest configuration** (`pg1-path` its own data
//!   directory), as pgBackRest is set up on every database host.
//! - **Before the day**: `archive_command = 'pgbackrest … archive-push %p'` on every server.
//!   One server: `archive_mode = on` in its `postgresql.conf` (restart). A Patroni cluster
//!   (`--patroni`): the command in each node's `postgresql.parameters` before the cluster
//!   starts, with `archive_mode = always`, so the replica archives every segment it receives
//!   too: a segment the primary filled but had not archived when its machine went is in the
//!   archive all the same (pgBackRest takes a segment it already holds with the same checksum
//!   as done). Then `stanza-create` and a full `backup` in the background while the day starts,
//!   each on the node that leads then (Patroni's REST API says which, as a clinic's nightly job
//!   asks `GET /primary` before it backs up), retried on the new leader when a kill cuts it off.
//!   Every WAL segment the day fills is archived, across failovers and their timelines.
//! - **After the day** ([`Drill::run`], the hubs stopped, the database still up): the live
//!   database's counts (on the leader) (summaries, sessions, recordings, audit rows, patients, stations) and a
//!   digest of every summary; `pgbackrest check` (switches the WAL segment and waits until it is
//!   archived); then, timed, `pgbackrest restore --type=default` (the full backup plus every
//!   archived segment to the end) into a fresh data directory, a second postmaster on it on
//!   another port (`archive_mode = off`: it must not push its new timeline into the day's
//!   repository; no synchronous standby to wait for), the wait until recovery has ended
//!   (`pg_is_in_recovery()` false: it follows the archive's timelines to the latest and
//!   promotes itself at its end) and the same counts read from it. They must be equal: every
//!   acknowledged summary survives the restore; a difference is a violation.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, bail};

use super::patroni::{self, Patroni};
use super::postgres::{
    MAX_CONNECTIONS, PgNode, Postgres, as_postgres_user, command_as, free_port, log_tail, path_str,
    postgres_owner, run_as,
};

/// The stanza (pgBackRest's name for one cluster's backups).
const STANZA: &str = "chaos";
/// The bucket of the backups.
const BUCKET: &str = "backups";
/// The path of the repository in the bucket.
const REPO_PATH: &str = "/telerehab";
/// The name the store's certificate carries and pgBackRest connects to (2.45 checks DNS names
/// only, not IP addresses; `localhost` is 127.0.0.1 where SeaweedFS listens).
const STORE_HOST: &str = "localhost";
/// How long SeaweedFS may take to answer after its start (a loaded 2-core machine).
const STORE_WITHIN: Duration = Duration::from_secs(90);
/// The longest one pgBackRest command may take (a large backup or restore).
const COMMAND_WITHIN: Duration = Duration::from_secs(1800);
/// The longest the restored server may take to end its recovery.
const RECOVERY_WITHIN: Duration = Duration::from_secs(600);
/// How often a full backup cut off by a PostgreSQL kill is tried again.
const BACKUP_TRIES: u32 = 6;

/// What the drill measured and compared.
#[derive(Debug, Clone, Default)]
pub struct Figures {
    /// The full backup's `pgbackrest backup`, s (the attempt that succeeded).
    pub backup_s: f64,
    /// Attempts the full backup needed (a PostgreSQL kill cuts one off).
    pub backup_attempts: u32,
    /// The database's size as the full backup saw it, bytes.
    pub database_bytes: u64,
    /// The full backup in the store (compressed), bytes.
    pub backup_bytes: u64,
    /// The archived WAL in the store (compressed), bytes.
    pub wal_bytes: u64,
    /// WAL segments archived.
    pub wal_segments: u64,
    /// `pgbackrest check` before the restore (WAL switched and archived), s.
    pub check_s: f64,
    /// `pgbackrest restore` alone, s.
    pub restore_command_s: f64,
    /// `pgbackrest restore` started → the restored database answering with its counts, s.
    pub restore_s: f64,
    /// The live database's counts.
    pub live: Counts,
    /// The restored database's counts.
    pub restored: Counts,
}

/// What is compared: rows of the tables that hold what the stations and the clinic did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Counts {
    /// `(table, rows)`.
    pub rows: Vec<(String, u64)>,
    /// MD5 over every summary (session, sequence number, MD5 of its body), in key order.
    pub summaries_md5: String,
}

/// The tables counted, in the report's order.
const TABLES: [&str; 6] = [
    "summaries",
    "sessions",
    "recordings",
    "audit_log",
    "patients",
    "stations",
];

/// One statement giving every count and the digest, `|`-separated.
fn counts_sql() -> String {
    let mut parts: Vec<String> = TABLES
        .iter()
        .map(|t| format!("(SELECT count(*) FROM {t})::text"))
        .collect();
    parts.push(
        "(SELECT coalesce(md5(string_agg(session_id || ':' || seq || ':' || md5(body), ',' \
         ORDER BY session_id, seq)), '') FROM summaries)"
            .into(),
    );
    format!("SELECT {}", parts.join(" || '|' || "))
}

fn parse_counts(line: &str) -> anyhow::Result<Counts> {
    let fields: Vec<&str> = line.trim().split('|').collect();
    if fields.len() != TABLES.len() + 1 {
        bail!("unexpected answer to the counts: {line:?}");
    }
    let mut rows = Vec::with_capacity(TABLES.len());
    for (t, f) in TABLES.iter().zip(&fields) {
        rows.push((
            (*t).to_owned(),
            f.parse().with_context(|| format!("count of {t}: {f:?}"))?,
        ));
    }
    Ok(Counts {
        rows,
        summaries_md5: fields[TABLES.len()].to_owned(),
    })
}

impl std::fmt::Display for Counts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let rows: Vec<String> = self.rows.iter().map(|(t, n)| format!("{t} {n}")).collect();
        let md5 = self.summaries_md5.get(..8).unwrap_or("-");
        write!(f, "{}, summaries MD5 {md5}…", rows.join(", "))
    }
}

/// The files SeaweedFS is started with.
struct StoreFiles {
    s3_json: PathBuf,
    cert: PathBuf,
    key: PathBuf,
}

/// How often SeaweedFS is started on new ports when it exits before its HTTPS port opens (a
/// port taken between [`free_port`] and its bind makes it panic).
const STORE_STARTS: u32 = 3;

/// Starts SeaweedFS in `dir` (data in `store/`, log `weed.log`) and waits until its HTTPS port
/// accepts connections: the process and that port.
async fn start_store(dir: &Path, files: &StoreFiles) -> anyhow::Result<(Child, u16)> {
    let binary = super::store::weed_binary();
    let log_path = dir.join("weed.log");
    let mut last = String::new();
    for _ in 0..STORE_STARTS {
        let https_port = free_port()?;
        let mut args = super::store::mini_args(&dir.join("store"), &files.s3_json, BUCKET)?;
        args.extend([
            format!("-s3.port={}", free_port()?),
            format!("-s3.port.https={https_port}"),
            format!("-s3.cert.file={}", path_str(&files.cert)?),
            format!("-s3.key.file={}", path_str(&files.key)?),
        ]);
        let log = std::fs::File::create(&log_path)?;
        let mut weed = Command::new(&binary)
            .args(&args)
            .stdin(Stdio::null())
            .stdout(log.try_clone()?)
            .stderr(log)
            .spawn()
            .with_context(|| {
                format!(
                    "cannot start SeaweedFS ({}); scripts/setup.sh installs it",
                    binary.display()
                )
            })?;
        let started = Instant::now();
        loop {
            if let Ok(Some(status)) = weed.try_wait() {
                last = format!("SeaweedFS exited ({status}): {}", weed_log(&log_path));
                break;
            }
            if tokio::net::TcpStream::connect(("127.0.0.1", https_port))
                .await
                .is_ok()
            {
                return Ok((weed, https_port));
            }
            if started.elapsed() > STORE_WITHIN {
                let _ = weed.kill();
                let _ = weed.wait();
                bail!(
                    "SeaweedFS did not open its HTTPS port within {STORE_WITHIN:?}: {}",
                    weed_log(&log_path)
                );
            }
            tokio::time::sleep(Duration::from_millis(250)).await;
        }
    }
    bail!("{last} ({STORE_STARTS} starts)")
}

/// SeaweedFS's log: its first line saying `panic` or `F` (fatal) and its last lines.
fn weed_log(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let fatal = text
        .lines()
        .find(|l| l.starts_with("panic") || l.starts_with('F'))
        .unwrap_or("");
    format!("{fatal} … {}", log_tail(path, 4))
}

/// The database the drill backs up: one server, or a Patroni cluster (whichever node leads).
#[derive(Clone, Copy)]
pub(super) enum Target<'a> {
    /// The day's one server.
    Server(&'a Postgres),
    /// The day's cluster.
    Cluster(&'a Patroni),
}

impl Target<'_> {
    /// Where each server runs, by node (one for a single server).
    fn nodes(&self) -> Vec<PgNode> {
        match self {
            Self::Server(pg) => vec![pg.node()],
            Self::Cluster(c) => c.nodes(),
        }
    }

    /// The directory of `pg_ctl` and `psql`.
    fn bin(&self) -> PathBuf {
        match self {
            Self::Server(pg) => pg.bin().to_owned(),
            Self::Cluster(c) => c.bin().to_owned(),
        }
    }

    fn leader(&self) -> Leader {
        match self {
            Self::Server(_) => Leader::Server,
            Self::Cluster(c) => Leader::Cluster(c.members()),
        }
    }
}

/// Finds the node that leads now, from a task of its own.
#[derive(Debug, Clone)]
enum Leader {
    /// The one server is node 0.
    Server,
    /// A cluster's Patroni REST APIs say which.
    Cluster(patroni::Members),
}

impl Leader {
    /// The node leading now; during a failover, the one that leads once it is over.
    async fn now(&self) -> anyhow::Result<usize> {
        let Self::Cluster(members) = self else {
            return Ok(0);
        };
        let began = Instant::now();
        loop {
            if let Some(k) = members.leader().await {
                return Ok(k);
            }
            if began.elapsed() > patroni::FAILOVER_WITHIN {
                bail!(
                    "no node of the cluster leads after {:?}",
                    patroni::FAILOVER_WITHIN
                );
            }
            tokio::time::sleep(Duration::from_millis(200)).await;
        }
    }
}

/// The store, the repository's configuration and the backup under way.
#[derive(Debug)]
pub struct Drill {
    /// The configurations, CA, store data, logs and the restore; removed on drop.
    dir: tempfile::TempDir,
    /// The SeaweedFS; killed on drop.
    weed: Option<Child>,
    /// Every configuration's `[global]` section: the repository in the store.
    global: String,
    /// `runuser -u postgres --` when running as root.
    as_user: Vec<String>,
    /// The full backup in the background: (its time, attempts).
    backup: Option<tokio::task::JoinHandle<anyhow::Result<(Duration, u32)>>>,
}

impl Drop for Drill {
    fn drop(&mut self) {
        if let Some(mut weed) = self.weed.take() {
            let _ = weed.kill();
            let _ = weed.wait();
        }
    }
}

/// Runs `pgbackrest --config=… --stanza=chaos args` (as the server's user): its stdout, or an
/// error with the tail of what it said.
async fn pgbackrest(as_user: &[String], config: &Path, args: &[&str]) -> anyhow::Result<String> {
    let mut command = command_as(as_user, "pgbackrest");
    command
        .arg(format!("--config={}", path_str(config)?))
        .arg(format!("--stanza={STANZA}"))
        .args(args)
        .stdin(Stdio::null())
        .kill_on_drop(true);
    let what = format!("pgbackrest {}", args.join(" "));
    let out = tokio::time::timeout(COMMAND_WITHIN, command.output())
        .await
        .with_context(|| format!("{what} did not finish within {COMMAND_WITHIN:?}"))?
        .with_context(|| format!("cannot run {what} (scripts/setup.sh installs pgbackrest)"))?;
    if !out.status.success() {
        bail!(
            "{what}: {}: {}",
            out.status,
            super::postgres::last_lines(&out)
        );
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// `psql -At -c sql` (of `bin`, as the server's user) on the server at `socket_dir`:`port`: its
/// one line of output.
async fn psql(
    bin: &Path,
    as_user: &[String],
    socket_dir: &Path,
    port: u16,
    sql: &str,
) -> anyhow::Result<String> {
    let psql = bin.join("psql");
    let mut command = command_as(as_user, &psql);
    let port = port.to_string();
    command
        .args([
            "-X",
            "-A",
            "-t",
            "-q",
            "-v",
            "ON_ERROR_STOP=1",
            "-U",
            "postgres",
        ])
        .args(["-d", "postgres", "-h", path_str(socket_dir)?, "-p", &port])
        .args(["-c", sql])
        .stdin(Stdio::null())
        .kill_on_drop(true);
    let out = tokio::time::timeout(Duration::from_secs(120), command.output())
        .await
        .context("psql did not answer within 120 s")?
        .context("cannot run psql")?;
    if !out.status.success() {
        bail!(
            "psql on port {port}: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

/// Gives `path` to the `postgres` OS user (when running as root).
fn give(path: &Path, owner: Option<(u32, u32)>) -> anyhow::Result<()> {
    if let Some((uid, gid)) = owner {
        std::os::unix::fs::chown(path, Some(uid), Some(gid))
            .with_context(|| format!("cannot give {} to the postgres user", path.display()))?;
    }
    Ok(())
}

fn write_private(path: &Path, text: &str, owner: Option<(u32, u32)>) -> anyhow::Result<()> {
    use std::os::unix::fs::OpenOptionsExt;
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(path)
        .with_context(|| format!("cannot create {}", path.display()))?;
    f.write_all(text.as_bytes())
        .with_context(|| format!("cannot write {}", path.display()))?;
    give(path, owner)
}

impl Drill {
    /// Starts the store (its CA and certificate made now) and writes the repository's part of
    /// the configuration; [`Drill::archive_command`] then says what each server archives with
    /// and [`Drill::begin`] starts the backups. An error here means "drill unavailable".
    pub async fn start() -> anyhow::Result<Self> {
        let owner = postgres_owner()?;
        let dir = tempfile::Builder::new()
            .prefix("telerehab-chaos-drill.")
            .tempdir()
            .context("cannot make the drill's directory")?;
        give(dir.path(), owner)?;
        std::fs::create_dir(dir.path().join("store"))?;
        // The store's CA and certificate, made now.
        let ca = netlink::pki::ClinicCa::create("chaos drill store")
            .context("cannot make the store's CA")?;
        let server = ca
            .issue_server(&[STORE_HOST.to_owned()])
            .context("cannot make the store's certificate")?;
        let ca_file = dir.path().join("ca.pem");
        std::fs::write(&ca_file, &ca.pem().cert_pem)?;
        let cert_file = dir.path().join("store.pem");
        std::fs::write(&cert_file, &server.cert_pem)?;
        let key_file = dir.path().join("store-key.pem");
        write_private(&key_file, &server.key_pem, None)?;
        // The store's one identity.
        let access_key = format!("drill{}", &patroni::password()[..12]);
        let secret_key = patroni::password();
        let identities = serde_json::json!({
            "identities": [{
                "name": "pgbackrest",
                "credentials": [{"accessKey": access_key, "secretKey": secret_key}],
                "actions": ["Admin", "Read", "Write", "List", "Tagging"]
            }]
        });
        let s3_json = dir.path().join("s3.json");
        write_private(&s3_json, &identities.to_string(), None)?;
        let files = StoreFiles {
            s3_json,
            cert: cert_file,
            key: key_file,
        };
        let (weed, https_port) = start_store(dir.path(), &files).await?;
        let global = format!(
            "[global]\n\
             repo1-type=s3\n\
             repo1-path={REPO_PATH}\n\
             repo1-s3-bucket={BUCKET}\n\
             repo1-s3-endpoint={STORE_HOST}\n\
             repo1-storage-port={https_port}\n\
             repo1-s3-region=us-east-1\n\
             repo1-s3-uri-style=path\n\
             repo1-s3-key={access_key}\n\
             repo1-s3-key-secret={secret_key}\n\
             repo1-storage-ca-file={ca}\n\
             repo1-retention-full=2\n\
             repo1-cipher-type=aes-256-cbc\n\
             repo1-cipher-pass={cipher_pass}\n\
             compress-type=lz4\n\
             start-fast=y\n\
             archive-timeout=60\n\
             log-level-console=warn\n\
             log-level-file=info\n",
            ca = path_str(&ca_file)?,
            cipher_pass = patroni::password(),
        );
        Ok(Self {
            dir,
            weed: Some(weed),
            global,
            as_user: as_postgres_user()?,
            backup: None,
        })
    }

    /// Node `k`'s pgBackRest configuration (`pg1-path` its own data directory).
    fn config(&self, k: usize) -> PathBuf {
        self.dir.path().join(format!("pgbackrest-{k}.conf"))
    }

    /// What node `k`'s PostgreSQL archives each WAL segment with.
    pub fn archive_command(&self, k: usize) -> anyhow::Result<String> {
        Ok(format!(
            "pgbackrest --config={} --stanza={STANZA} archive-push %p",
            path_str(&self.config(k))?
        ))
    }

    /// Writes each node's configuration, turns on WAL archiving on a single server (a
    /// restart; a cluster was started with it), creates the stanza and starts the full backup
    /// in the background.
    pub async fn begin(&mut self, target: Target<'_>) -> anyhow::Result<()> {
        let owner = postgres_owner()?;
        let nodes = target.nodes();
        // pgBackRest refuses `archive_mode = always` unless told that the archivers may be
        // several: the replica's segments are the primary's byte for byte (streamed), and one
        // it pushes again is taken as done when its checksum is the same; one that differed
        // would fail its archive-push and stop that node's archiving, which the counts after
        // the restore would show.
        let several_archivers = match target {
            Target::Server(_) => "",
            Target::Cluster(_) => "archive-mode-check=n\n",
        };
        for (k, node) in nodes.iter().enumerate() {
            // Each machine's own log, lock and spool directories.
            let own = self.dir.path().join(format!("node{k}"));
            for sub in ["", "log", "lock", "spool"] {
                std::fs::create_dir_all(own.join(sub))?;
                give(&own.join(sub), owner)?;
            }
            let conf = format!(
                "{global}\
                 {several_archivers}\
                 log-path={log}\n\
                 lock-path={lock}\n\
                 spool-path={spool}\n\
                 \n\
                 [{STANZA}]\n\
                 pg1-path={data}\n\
                 pg1-port={port}\n\
                 pg1-socket-path={socket}\n\
                 pg1-user=postgres\n",
                global = self.global,
                log = path_str(&own.join("log"))?,
                lock = path_str(&own.join("lock"))?,
                spool = path_str(&own.join("spool"))?,
                data = path_str(&node.data)?,
                port = node.port,
                socket = path_str(&node.socket_dir)?,
            );
            write_private(&self.config(k), &conf, owner)?;
        }
        if let Target::Server(pg) = target {
            // archive_mode is read at start only: `configure` restarts.
            pg.configure(&format!(
                "# The restore drill (telerehab hub chaos --drill): WAL into the object store.\n\
                 wal_level = replica\n\
                 archive_mode = on\n\
                 archive_command = '{}'\n",
                self.archive_command(0)?
            ))
            .await
            .context("cannot turn on WAL archiving")?;
        }
        let leader = target.leader();
        self.wait_stanza(&leader).await?;
        let as_user = self.as_user.clone();
        let configs: Vec<PathBuf> = (0..nodes.len()).map(|k| self.config(k)).collect();
        self.backup = Some(tokio::spawn(async move {
            let mut attempts = 0;
            loop {
                attempts += 1;
                let started = Instant::now();
                let tried = match leader.now().await {
                    Ok(k) => pgbackrest(&as_user, &configs[k], &["--type=full", "backup"])
                        .await
                        .map(drop),
                    Err(e) => Err(e),
                };
                match tried {
                    Ok(()) => return Ok((started.elapsed(), attempts)),
                    Err(e) if attempts >= BACKUP_TRIES => {
                        return Err(e.context(format!("the full backup, {attempts} attempts")));
                    }
                    Err(_) => tokio::time::sleep(Duration::from_secs(3)).await,
                }
            }
        }));
        Ok(())
    }

    fn log_tail(&self) -> String {
        weed_log(&self.dir.path().join("weed.log"))
    }

    /// Creates the stanza on the leader (SeaweedFS makes the bucket shortly after its port
    /// opens: retried).
    async fn wait_stanza(&self, leader: &Leader) -> anyhow::Result<()> {
        let started = Instant::now();
        loop {
            let k = leader.now().await?;
            match pgbackrest(&self.as_user, &self.config(k), &["stanza-create"]).await {
                Ok(_) => return Ok(()),
                Err(e) if started.elapsed() > STORE_WITHIN => {
                    bail!(
                        "the backup store did not take the stanza within {STORE_WITHIN:?}: \
                         {e:#}; SeaweedFS: {}",
                        self.log_tail()
                    )
                }
                Err(_) => tokio::time::sleep(Duration::from_millis(500)).await,
            }
        }
    }

    /// The drill, at the end of the day with the hubs stopped and the database running: counts
    /// on the leader, check, restore into a fresh data directory, a second server on it,
    /// counts again.
    pub async fn run(mut self, target: Target<'_>) -> anyhow::Result<Figures> {
        let mut f = Figures::default();
        let (backup, attempts) = self
            .backup
            .take()
            .context("no backup was started")?
            .await
            .context("the backup task")??;
        f.backup_s = backup.as_secs_f64();
        f.backup_attempts = attempts;
        let bin = target.bin();
        let k = target.leader().now().await?;
        let leader = &target.nodes()[k];
        let sql = counts_sql();
        f.live =
            parse_counts(&psql(&bin, &self.as_user, &leader.socket_dir, leader.port, &sql).await?)?;
        let config = self.config(k);
        let t = Instant::now();
        pgbackrest(&self.as_user, &config, &["check"]).await?;
        f.check_s = t.elapsed().as_secs_f64();
        self.sizes(&config, &mut f).await?;
        // The restore, into a directory of its own.
        let owner = postgres_owner()?;
        let restore = self.dir.path().join("restore");
        std::fs::create_dir(&restore)?;
        give(&restore, owner)?;
        let data = restore.join("data");
        let port = free_port()?;
        let started = Instant::now();
        pgbackrest(
            &self.as_user,
            &config,
            &[
                &format!("--pg1-path={}", path_str(&data)?),
                "--type=default",
                "restore",
            ],
        )
        .await?;
        f.restore_command_s = started.elapsed().as_secs_f64();
        let pg_ctl = bin.join("pg_ctl");
        // Not archiving into the day's repository, and no synchronous standby to wait for
        // (a cluster's settings come with its data directory); the command line wins over both
        // configuration files.
        let options = format!(
            "-c listen_addresses=127.0.0.1 -p {port} -k {} -c fsync=off \
             -c max_connections={MAX_CONNECTIONS} -c archive_mode=off \
             -c synchronous_standby_names=''",
            path_str(&restore)?
        );
        let log = restore.join("server.log");
        let (data_s, log_s) = (path_str(&data)?, path_str(&log)?);
        run_as(
            &self.as_user,
            &pg_ctl,
            &[
                "-D", data_s, "-l", log_s, "-w", "-t", "600", "-o", &options, "start",
            ],
        )
        .await
        .with_context(|| format!("starting the restored server: {}", log_tail(&log, 6)))?;
        let answered = async {
            let waiting = Instant::now();
            loop {
                let recovering = psql(
                    &bin,
                    &self.as_user,
                    &restore,
                    port,
                    "SELECT pg_is_in_recovery()",
                )
                .await?;
                if recovering == "f" {
                    break;
                }
                if waiting.elapsed() > RECOVERY_WITHIN {
                    bail!("the restored server still recovers after {RECOVERY_WITHIN:?}");
                }
                tokio::time::sleep(Duration::from_millis(100)).await;
            }
            parse_counts(&psql(&bin, &self.as_user, &restore, port, &sql).await?)
        }
        .await;
        f.restore_s = started.elapsed().as_secs_f64();
        let stopped = run_as(
            &self.as_user,
            &pg_ctl,
            &["-D", data_s, "-w", "-t", "60", "-m", "immediate", "stop"],
        )
        .await;
        f.restored =
            answered.with_context(|| format!("the restored database: {}", log_tail(&log, 6)))?;
        stopped.context("stopping the restored server")?;
        Ok(f)
    }

    /// The full backup's and the archived WAL's sizes in the store (read with `config`).
    async fn sizes(&self, config: &Path, f: &mut Figures) -> anyhow::Result<()> {
        let info: serde_json::Value = serde_json::from_str(
            &pgbackrest(&self.as_user, config, &["--output=json", "info"]).await?,
        )
        .context("pgbackrest info's JSON")?;
        let last = &info[0]["backup"]
            .as_array()
            .and_then(|b| b.last())
            .context("pgbackrest info lists no backup")?["info"];
        f.database_bytes = last["size"].as_u64().unwrap_or(0);
        f.backup_bytes = last["repository"]["size"].as_u64().unwrap_or(0);
        let listing: serde_json::Value = serde_json::from_str(
            &pgbackrest(
                &self.as_user,
                config,
                &[
                    "--output=json",
                    "--recurse",
                    "repo-ls",
                    &format!("archive/{STANZA}"),
                ],
            )
            .await?,
        )
        .context("pgbackrest repo-ls's JSON")?;
        if let Some(files) = listing.as_object() {
            for (name, entry) in files {
                if entry["type"] == "file" && is_segment(name) {
                    f.wal_segments += 1;
                    f.wal_bytes += entry["size"].as_u64().unwrap_or(0);
                }
            }
        }
        Ok(())
    }
}

/// Whether a repository path names an archived WAL segment (`…/<24 hex digits>-<sha1>…`, not
/// `archive.info`, a timeline's `.history` or a backup's `.backup` label).
fn is_segment(path: &str) -> bool {
    let name = path.rsplit('/').next().unwrap_or(path);
    name.len() > 24
        && name.as_bytes()[..24].iter().all(u8::is_ascii_hexdigit)
        && name.as_bytes()[24] == b'-'
}

/// Prints the drill's figures; the number of violations (a difference, or the drill failed).
pub fn report(result: &anyhow::Result<Figures>) -> usize {
    let mb = |b: u64| b as f64 / 1e6;
    match result {
        Ok(f) => {
            println!(
                "restore drill: full backup {:.1} s ({} attempt{}; database {:.1} MB, in the store \
                 {:.1} MB), WAL archived {} segments, {:.1} MB in the store; check {:.1} s; \
                 restore {:.1} s (pgbackrest restore {:.1} s, then recovery to the end of the \
                 archive and the counts)",
                f.backup_s,
                f.backup_attempts,
                if f.backup_attempts == 1 { "" } else { "s" },
                mb(f.database_bytes),
                mb(f.backup_bytes),
                f.wal_segments,
                mb(f.wal_bytes),
                f.check_s,
                f.restore_s,
                f.restore_command_s,
            );
            println!("restore drill: live     {}", f.live);
            println!("restore drill: restored {}", f.restored);
            if f.live == f.restored {
                println!("restore drill: OK — the restored database equals the live one");
                0
            } else {
                println!(
                    "VIOLATION: the restored database differs from the live one (live {}; \
                     restored {})",
                    f.live, f.restored
                );
                1
            }
        }
        Err(e) => {
            println!("VIOLATION: the restore drill failed: {e:#}");
            1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_parse_and_compare_row_by_row() {
        let a = parse_counts("10|2|2|7|1|1|abcdef0123\n").unwrap();
        assert_eq!(a.rows[0], ("summaries".to_owned(), 10));
        assert_eq!(a.summaries_md5, "abcdef0123");
        let b = parse_counts("9|2|2|7|1|1|abcdef0123").unwrap();
        assert_ne!(a, b, "a lost summary is a difference");
        assert!(parse_counts("1|2|3").is_err());
        assert!(is_segment(
            "15-1/0000000100000000/000000010000000000000006-d6e7331e4770347f2492ecf8a49a570f9d5aa25b.lz4"
        ));
        assert!(!is_segment("archive.info"));
        assert!(!is_segment(
            "15-1/0000000100000000/000000010000000000000005.00000028.backup"
        ));
        assert!(counts_sql().starts_with("SELECT (SELECT count(*) FROM summaries)"));
    }
}
