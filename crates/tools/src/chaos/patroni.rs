//! A throwaway PostgreSQL that fails over, as docs/DEPLOY.md sets one up for a clinic network:
//! three etcd members, two Patroni nodes (a primary and a synchronous replica: `synchronous_mode: true`,
//! so a commit returns only once the replica has it) and a HAProxy in `mode tcp` whose health
//! check asks each node's Patroni REST API `GET /primary`, so the hubs' database URL is the
//! balancer's and always reaches the primary. All from Debian (`patroni`, `etcd-server`,
//! `haproxy`, `postgresql`), in a temporary directory, on free ports.
//!
//! The etcd members stand on three machines as docs/DEPLOY.md places them: one beside each
//! database node and a witness, so the cluster keeps its quorum (2 of 3) when one machine goes.
//! [`Patroni::kill_primary`] is the machine of the primary gone: its Patroni, its postmaster with
//! every backend and its etcd member SIGKILLed at once. The replica's Patroni sees the leader key
//! expire (`ttl` 10 s) on the two etcd members left and promotes; [`Patroni::first_write`] measures how long until a write through the
//! balancer is accepted again. [`Patroni::restart`] starts the killed node's etcd member and
//! Patroni again: the member rejoins its cluster from its data directory, and the node rejoins as
//! the replica (`pg_rewind`, or a new base backup when the rewind fails).
//!
//! As root, Patroni (and so PostgreSQL, which refuses root) runs as the `postgres` OS user.

use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};

use anyhow::{Context, bail};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::process::{Child, Command};
use tokio::sync::Mutex;

use super::postgres::{PgNode, bindir, free_port, path_str, postgres_owner, server_version};

/// Longest the cluster may take to elect a leader and stream to a synchronous replica.
const FORM_WITHIN: Duration = Duration::from_secs(60);
/// Longest a failover may take before the day counts it as failed (ttl 10 s + a loop or two).
pub const FAILOVER_WITHIN: Duration = Duration::from_secs(45);
/// The DCS key's time to live, s: how long a dead primary keeps the leadership.
const TTL_S: u32 = 10;
/// How often Patroni runs its loop, s.
const LOOP_WAIT_S: u32 = 1;
/// How long Patroni retries etcd and PostgreSQL before it demotes, s.
const RETRY_TIMEOUT_S: u32 = 3;
// Patroni wants loop_wait + 2 × retry_timeout within the ttl.
const _: () = assert!(LOOP_WAIT_S + 2 * RETRY_TIMEOUT_S <= TTL_S);

/// One Patroni node.
#[derive(Debug)]
struct Node {
    name: String,
    /// PostgreSQL's port.
    pg_port: u16,
    /// Patroni's REST API port.
    rest_port: u16,
    /// Its directory: configuration, data directory, log, socket.
    dir: PathBuf,
    /// The running Patroni, if any.
    child: Mutex<Option<Child>>,
}

impl Node {
    fn data(&self) -> PathBuf {
        self.dir.join("data")
    }
    fn config(&self) -> PathBuf {
        self.dir.join("patroni.yml")
    }

    /// Its machine gone: its Patroni and its postmaster with every backend SIGKILLed at once
    /// (Patroni starts the postmaster in a session of its own: found by its pid file).
    async fn kill(&self) {
        let mut slot = self.child.lock().await;
        let mut roots: Vec<u32> = slot.as_ref().and_then(Child::id).into_iter().collect();
        if let Some(pm) = std::fs::read_to_string(self.data().join("postmaster.pid"))
            .ok()
            .and_then(|s| s.lines().next()?.trim().parse::<u32>().ok())
        {
            roots.push(pm);
        }
        kill_all(&process_tree(&roots));
        if let Some(mut child) = slot.take() {
            let _ = child.wait().await;
        }
    }
}

/// etcd members: one on each database node's machine, and a witness.
const ETCD_MEMBERS: usize = 3;

/// The cluster and its balancer; every process is killed by [`Patroni::stop`] or on drop.
#[derive(Debug)]
pub struct Patroni {
    /// Owns every node's directory; removed on drop.
    dir: tempfile::TempDir,
    /// Each etcd member's (client, peer) ports; member `k < 2` stands on node `k`'s machine.
    etcd_ports: Vec<(u16, u16)>,
    /// The etcd members' processes, by member.
    etcd: Vec<Mutex<Option<Child>>>,
    haproxy: Option<Child>,
    nodes: Vec<Node>,
    /// The balancer's port: the hubs' database.
    port: u16,
    password: String,
    /// `(uid, gid)` of the `postgres` OS user when running as root.
    owner: Option<(u32, u32)>,
    /// The directory of the server's binaries (`pg_ctl`, `psql`).
    bindir: PathBuf,
    /// The server's version, e.g. `15.10`.
    pub version: String,
}

/// Asks the nodes' Patroni REST APIs who leads; cheap to clone into a task.
#[derive(Debug, Clone)]
pub(super) struct Members {
    /// Each node's (name, REST port), by node.
    nodes: Vec<(String, u16)>,
}

impl Members {
    /// The cluster as Patroni's REST API on any answering node sees it.
    async fn state(&self) -> Option<ClusterState> {
        for (_, rest_port) in &self.nodes {
            if let Ok((200, body)) = http_get(*rest_port, "/cluster").await
                && let Ok(json) = serde_json::from_str::<serde_json::Value>(&body)
            {
                return Some(ClusterState::from_json(&json, &self.nodes));
            }
        }
        None
    }

    /// The node that leads now, if any.
    pub(super) async fn leader(&self) -> Option<usize> {
        self.state().await.and_then(|c| c.leader)
    }
}

/// A password of 32 hex digits (safe in a URL and in YAML).
pub(super) fn password() -> String {
    use rand::Rng;
    let mut rng = rand::rng();
    (0..4)
        .map(|_| format!("{:08x}", rng.random::<u32>()))
        .collect()
}

/// Whether `program` is on the PATH.
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(program).is_file()))
}

/// `GET path` of an HTTP server on 127.0.0.1: (status, body). HTTP/1.0, so the server closes.
async fn http_get(port: u16, path: &str) -> anyhow::Result<(u16, String)> {
    let exchange = async {
        let mut s = tokio::net::TcpStream::connect(("127.0.0.1", port)).await?;
        s.write_all(format!("GET {path} HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n").as_bytes())
            .await?;
        let mut raw = Vec::new();
        s.read_to_end(&mut raw).await?;
        anyhow::Ok(String::from_utf8_lossy(&raw).into_owned())
    };
    let text = tokio::time::timeout(Duration::from_secs(2), exchange)
        .await
        .context("no answer within 2 s")??;
    let status = text
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .context("not an HTTP answer")?;
    let body = text
        .split_once("\r\n\r\n")
        .map_or("", |(_, b)| b)
        .to_owned();
    Ok((status, body))
}

/// Every process whose ancestry leads to one of `roots`, and the roots (`/proc`).
fn process_tree(roots: &[u32]) -> Vec<u32> {
    let mut parent = Vec::new();
    if let Ok(entries) = std::fs::read_dir("/proc") {
        for e in entries.filter_map(Result::ok) {
            let Some(pid) = e.file_name().to_str().and_then(|s| s.parse::<u32>().ok()) else {
                continue;
            };
            // "pid (comm) state ppid …"; comm may hold spaces and parentheses.
            let ppid = std::fs::read_to_string(e.path().join("stat"))
                .ok()
                .and_then(|s| {
                    let after = s.rsplit_once(')')?.1.to_owned();
                    after.split_whitespace().nth(1)?.parse::<u32>().ok()
                });
            if let Some(ppid) = ppid {
                parent.push((pid, ppid));
            }
        }
    }
    let mut tree: Vec<u32> = roots.to_vec();
    let mut k = 0;
    while k < tree.len() {
        let p = tree[k];
        tree.extend(
            parent
                .iter()
                .filter(|(pid, ppid)| *ppid == p && !tree.contains(pid))
                .map(|(pid, _)| *pid)
                .collect::<Vec<_>>(),
        );
        k += 1;
    }
    tree
}

/// SIGKILLs `pids` at once.
fn kill_all(pids: &[u32]) {
    if pids.is_empty() {
        return;
    }
    let _ = std::process::Command::new("kill")
        .arg("-KILL")
        .args(pids.iter().map(u32::to_string))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
}

impl Patroni {
    /// Starts etcd, two Patroni nodes and the balancer, and waits until there is a leader with a
    /// synchronous replica streaming and a write through the balancer is accepted. An error here
    /// means "Patroni unavailable".
    ///
    /// With `archive_command` (node → its command), every node archives its WAL with
    /// `archive_mode = always`: the replica too, so a segment the primary filled but had not
    /// archived when its machine went is in the archive all the same (module `drill`).
    pub async fn start_new(
        archive_command: Option<&dyn Fn(usize) -> anyhow::Result<String>>,
    ) -> anyhow::Result<Self> {
        for program in ["patroni", "etcd", "haproxy", "psql"] {
            if !on_path(program) {
                bail!(
                    "no `{program}` on the PATH (scripts/setup.sh installs patroni, \
                     etcd-server, haproxy and postgresql)"
                );
            }
        }
        let bindir = bindir()?;
        let owner = postgres_owner()?;
        let dir = tempfile::Builder::new()
            .prefix("telerehab-chaos-patroni.")
            .tempdir()
            .context("cannot make the cluster's directory")?;
        let version = server_version(&bindir);
        let mut cluster = Self {
            dir,
            etcd_ports: (0..ETCD_MEMBERS)
                .map(|_| Ok((free_port()?, free_port()?)))
                .collect::<anyhow::Result<_>>()?,
            etcd: (0..ETCD_MEMBERS).map(|_| Mutex::new(None)).collect(),
            haproxy: None,
            nodes: Vec::new(),
            port: free_port()?,
            password: password(),
            owner,
            bindir: bindir.clone(),
            version,
        };
        for m in 0..ETCD_MEMBERS {
            cluster.start_etcd(m).await?;
        }
        for m in 0..ETCD_MEMBERS {
            cluster.wait_etcd(m).await?;
        }
        let replication = password();
        for k in 0..2 {
            let node = Node {
                name: format!("pg{k}"),
                pg_port: free_port()?,
                rest_port: free_port()?,
                dir: cluster.dir.path().join(format!("pg{k}")),
                child: Mutex::new(None),
            };
            std::fs::create_dir_all(&node.dir)?;
            let archive = archive_command.map(|f| f(k)).transpose()?;
            std::fs::write(
                node.config(),
                node_config(
                    &node,
                    &cluster.etcd_ports,
                    &bindir,
                    &cluster.password,
                    &replication,
                    archive.as_deref(),
                )?,
            )?;
            cluster.nodes.push(node);
        }
        cluster.give_to_postgres()?;
        // The first node bootstraps (initdb); the second then takes a base backup from it.
        cluster.restart(0).await?;
        cluster.wait(FORM_WITHIN, |c| c.leader.is_some()).await?;
        cluster.restart(1).await?;
        cluster.haproxy = Some(cluster.start_haproxy()?);
        cluster.wait_synchronous(FORM_WITHIN).await?;
        cluster
            .first_write(FORM_WITHIN)
            .await
            .context("no write accepted through the balancer")?;
        Ok(cluster)
    }

    /// Hands the cluster's directory to the `postgres` user (when root).
    fn give_to_postgres(&self) -> anyhow::Result<()> {
        let Some((uid, gid)) = self.owner else {
            return Ok(());
        };
        std::os::unix::fs::chown(self.dir.path(), Some(uid), Some(gid))?;
        for node in &self.nodes {
            std::os::unix::fs::chown(&node.dir, Some(uid), Some(gid))?;
            std::os::unix::fs::chown(node.config(), Some(uid), Some(gid))?;
        }
        Ok(())
    }

    fn log(&self, name: &str) -> anyhow::Result<std::fs::File> {
        std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(self.dir.path().join(name))
            .with_context(|| format!("cannot open {name}"))
    }

    /// Starts etcd member `m` (again, after a kill: it rejoins from its data directory).
    async fn start_etcd(&self, m: usize) -> anyhow::Result<()> {
        let mut slot = self.etcd[m].lock().await;
        if let Some(child) = slot.as_mut()
            && child.try_wait()?.is_none()
        {
            return Ok(());
        }
        let log = self.log(&format!("etcd{m}.log"))?;
        let url = |port: u16| format!("http://127.0.0.1:{port}");
        let (c, p) = (url(self.etcd_ports[m].0), url(self.etcd_ports[m].1));
        let cluster: Vec<String> = self
            .etcd_ports
            .iter()
            .enumerate()
            .map(|(k, &(_, peer))| format!("etcd{k}={}", url(peer)))
            .collect();
        let child = Command::new("etcd")
            .args(["--name", &format!("etcd{m}"), "--data-dir"])
            .arg(self.dir.path().join(format!("etcd{m}")))
            .args(["--listen-client-urls", &c, "--advertise-client-urls", &c])
            .args([
                "--listen-peer-urls",
                &p,
                "--initial-advertise-peer-urls",
                &p,
            ])
            .args(["--initial-cluster", &cluster.join(",")])
            .args(["--initial-cluster-state", "new", "--log-level", "warn"])
            .stdin(Stdio::null())
            .stdout(Stdio::from(log.try_clone()?))
            .stderr(Stdio::from(log))
            .kill_on_drop(true)
            .spawn()
            .context("cannot start etcd")?;
        *slot = Some(child);
        Ok(())
    }

    /// Waits until etcd member `m` says it is healthy (which needs a quorum of members).
    async fn wait_etcd(&self, m: usize) -> anyhow::Result<()> {
        let began = Instant::now();
        while !matches!(
            http_get(self.etcd_ports[m].0, "/health").await,
            Ok((200, _))
        ) {
            if began.elapsed() > Duration::from_secs(30) {
                bail!(
                    "etcd member {m} did not answer within 30 s: {}",
                    tail(&self.dir.path().join(format!("etcd{m}.log")))
                );
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
        Ok(())
    }

    /// SIGKILLs etcd member `m`.
    async fn kill_etcd(&self, m: usize) {
        if let Some(mut child) = self.etcd[m].lock().await.take() {
            let _ = child.kill().await;
        }
    }

    fn start_haproxy(&self) -> anyhow::Result<Child> {
        let cfg = self.dir.path().join("haproxy.cfg");
        std::fs::write(&cfg, haproxy_config(self.port, &self.nodes))?;
        let log = self.log("haproxy.log")?;
        Command::new("haproxy")
            .arg("-db")
            .arg("-f")
            .arg(&cfg)
            .stdin(Stdio::null())
            .stdout(Stdio::from(log.try_clone()?))
            .stderr(Stdio::from(log))
            .kill_on_drop(true)
            .spawn()
            .context("cannot start haproxy")
    }

    /// The database URL: the balancer, which passes the connection to the primary.
    pub fn url(&self) -> String {
        format!(
            "postgres://postgres:{}@127.0.0.1:{}/postgres",
            self.password, self.port
        )
    }

    /// Starts node `k`'s machine again (its etcd member, then its Patroni): after a kill it
    /// rejoins as the replica.
    pub async fn restart(&self, k: usize) -> anyhow::Result<()> {
        self.start_etcd(k).await?;
        let node = &self.nodes[k];
        let mut slot = node.child.lock().await;
        if let Some(child) = slot.as_mut()
            && child.try_wait()?.is_none()
        {
            return Ok(());
        }
        let log = self.log(&format!("{}.log", node.name))?;
        let mut command = Command::new("patroni");
        command
            .arg(node.config())
            .current_dir(&node.dir)
            .env("HOME", &node.dir)
            .stdin(Stdio::null())
            .stdout(Stdio::from(log.try_clone()?))
            .stderr(Stdio::from(log));
        if let Some((uid, gid)) = self.owner {
            command.uid(uid).gid(gid);
        }
        *slot = Some(command.spawn().context("cannot start patroni")?);
        Ok(())
    }

    /// Who leads, asked from anywhere (a task of its own).
    pub(super) fn members(&self) -> Members {
        Members {
            nodes: self
                .nodes
                .iter()
                .map(|n| (n.name.clone(), n.rest_port))
                .collect(),
        }
    }

    /// Where each node's PostgreSQL runs, by node.
    pub(super) fn nodes(&self) -> Vec<PgNode> {
        self.nodes
            .iter()
            .map(|n| PgNode {
                data: n.data(),
                port: n.pg_port,
                socket_dir: n.dir.clone(),
            })
            .collect()
    }

    /// The directory of the server's binaries.
    pub(super) fn bin(&self) -> &Path {
        &self.bindir
    }

    async fn state(&self) -> Option<ClusterState> {
        self.members().state().await
    }

    async fn wait(
        &self,
        within: Duration,
        done: impl Fn(&ClusterState) -> bool,
    ) -> anyhow::Result<()> {
        let began = Instant::now();
        loop {
            let state = self.state().await;
            if state.as_ref().is_some_and(&done) {
                return Ok(());
            }
            if began.elapsed() > within {
                bail!(
                    "the Patroni cluster did not form within {} s ({state:?}); {}",
                    within.as_secs(),
                    self.nodes
                        .iter()
                        .map(|n| format!(
                            "{}: {}",
                            n.name,
                            tail(&self.dir.path().join(format!("{}.log", n.name)))
                        ))
                        .collect::<Vec<_>>()
                        .join("; ")
                );
            }
            tokio::time::sleep(Duration::from_millis(200)).await;
        }
    }

    /// Waits until there is a leader and the other node streams as its synchronous standby.
    pub async fn wait_synchronous(&self, within: Duration) -> anyhow::Result<()> {
        self.wait(within, |c| c.leader.is_some() && c.sync_streaming.is_some())
            .await
    }

    /// The node that leads now, if any.
    pub async fn leader(&self) -> Option<usize> {
        self.members().leader().await
    }

    /// The primary's machine gone: its Patroni, its postmaster with every backend and its etcd
    /// member SIGKILLed at once. The node killed.
    pub async fn kill_primary(&self) -> anyhow::Result<usize> {
        let k = self.leader().await.context("no leader to kill")?;
        tokio::join!(self.nodes[k].kill(), self.kill_etcd(k));
        Ok(k)
    }

    /// Writes through the balancer until one is accepted (a new connection each try, as a hub's
    /// pool makes after its connections were cut); the time it took.
    pub async fn first_write(&self, within: Duration) -> anyhow::Result<Duration> {
        let began = Instant::now();
        let url = self.url();
        let sql = "CREATE TABLE IF NOT EXISTS chaos_probe (at_ms BIGINT NOT NULL); \
                   INSERT INTO chaos_probe VALUES (floor(extract(epoch FROM now()) * 1000))";
        loop {
            let out = Command::new("psql")
                .args(["-X", "-q", "-v", "ON_ERROR_STOP=1", &url, "-c", sql])
                .env("PGCONNECT_TIMEOUT", "2")
                .stdin(Stdio::null())
                .kill_on_drop(true)
                .output();
            let last = match tokio::time::timeout(Duration::from_secs(5), out).await {
                Ok(Ok(o)) if o.status.success() => return Ok(began.elapsed()),
                Ok(Ok(o)) => String::from_utf8_lossy(&o.stderr).trim().to_owned(),
                Ok(Err(e)) => e.to_string(),
                Err(_) => "psql did not finish within 5 s".into(),
            };
            if began.elapsed() > within {
                bail!("no write accepted within {} s: {last}", within.as_secs());
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }

    /// Kills everything (the data is thrown away with the directory).
    pub async fn stop(mut self) {
        self.kill_everything().await;
    }

    async fn kill_everything(&mut self) {
        for node in &self.nodes {
            node.kill().await;
        }
        if let Some(mut child) = self.haproxy.take() {
            let _ = child.kill().await;
        }
        for m in 0..self.etcd.len() {
            self.kill_etcd(m).await;
        }
    }
}

impl Drop for Patroni {
    fn drop(&mut self) {
        // What stop() did not get to: no PostgreSQL may outlive its removed directory.
        let mut roots = Vec::new();
        for node in &self.nodes {
            if let Ok(mut slot) = node.child.try_lock()
                && let Some(child) = slot.take()
            {
                roots.extend(child.id());
            }
            if let Some(pm) = std::fs::read_to_string(node.data().join("postmaster.pid"))
                .ok()
                .and_then(|s| s.lines().next()?.trim().parse::<u32>().ok())
            {
                roots.push(pm);
            }
        }
        kill_all(&process_tree(&roots));
    }
}

/// The last non-empty line of a log.
fn tail(path: &Path) -> String {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| {
            t.lines()
                .rev()
                .find(|l| !l.trim().is_empty())
                .map(str::to_owned)
        })
        .unwrap_or_default()
}

/// What `GET /cluster` says.
#[derive(Debug, Default)]
struct ClusterState {
    leader: Option<usize>,
    /// The node streaming as the leader's synchronous standby.
    sync_streaming: Option<usize>,
}

impl ClusterState {
    /// From `GET /cluster`'s answer, with `nodes`' (name, REST port) in node order.
    fn from_json(json: &serde_json::Value, nodes: &[(String, u16)]) -> Self {
        let mut state = Self::default();
        let members = json
            .get("members")
            .and_then(serde_json::Value::as_array)
            .map_or(&[][..], Vec::as_slice);
        for m in members {
            let field = |k: &str| m.get(k).and_then(serde_json::Value::as_str).unwrap_or("");
            let Some(k) = nodes.iter().position(|(name, _)| name == field("name")) else {
                continue;
            };
            match (field("role"), field("state")) {
                ("leader", "running") => state.leader = Some(k),
                // Patroni names a replica the synchronous standby only once the primary's
                // pg_stat_replication shows it streaming; 3.0.2 reports its state as
                // "running", later versions as "streaming".
                ("sync_standby", "running" | "streaming") => state.sync_streaming = Some(k),
                _ => {}
            }
        }
        state
    }
}

/// One node's Patroni configuration.
fn node_config(
    node: &Node,
    etcd_ports: &[(u16, u16)],
    bindir: &Path,
    superuser: &str,
    replication: &str,
    archive_command: Option<&str>,
) -> anyhow::Result<String> {
    let dir = path_str(&node.dir)?;
    let data = node.data();
    let data = path_str(&data)?;
    let bin = path_str(bindir)?;
    let (name, pg, rest) = (&node.name, node.pg_port, node.rest_port);
    let etcd_hosts: Vec<String> = etcd_ports
        .iter()
        .map(|(client, _)| format!("127.0.0.1:{client}"))
        .collect();
    let etcd_hosts = etcd_hosts.join(",");
    // YAML single quotes: a quote inside is doubled.
    let archive = archive_command.map_or(String::new(), |command| {
        format!(
            "    archive_mode: 'always'\n    archive_command: '{}'\n",
            command.replace('\'', "''")
        )
    });
    Ok(format!(
        "scope: telerehab-chaos
name: {name}
restapi:
  listen: 127.0.0.1:{rest}
  connect_address: 127.0.0.1:{rest}
etcd3:
  hosts: {etcd_hosts}
bootstrap:
  dcs:
    ttl: {TTL_S}
    loop_wait: {LOOP_WAIT_S}
    retry_timeout: {RETRY_TIMEOUT_S}
    maximum_lag_on_failover: 1048576
    synchronous_mode: true
    synchronous_mode_strict: false
    postgresql:
      use_pg_rewind: true
      remove_data_directory_on_rewind_failure: true
      parameters:
        wal_log_hints: 'on'
        max_connections: 200
        # A SIGKILL leaves the OS's page cache: no need to wait for the disk in a drill.
        fsync: 'off'
  initdb:
    - encoding: UTF8
postgresql:
  listen: 127.0.0.1:{pg}
  connect_address: 127.0.0.1:{pg}
  data_dir: {data}
  bin_dir: {bin}
  pgpass: {dir}/pgpass
  authentication:
    superuser:
      username: postgres
      password: {superuser}
    replication:
      username: replicator
      password: {replication}
  parameters:
    unix_socket_directories: {dir}
{archive}  pg_hba:
    - local all all trust
    - host replication replicator 127.0.0.1/32 md5
    - host all all 127.0.0.1/32 md5
tags:
  nofailover: false
  noloadbalance: false
  clonefrom: false
  nosync: false
"
    ))
}

/// The balancer: TCP passed to whichever node's Patroni answers `GET /primary` with 200;
/// connections to a node marked down are cut so clients reconnect to the new primary.
fn haproxy_config(port: u16, nodes: &[Node]) -> String {
    let servers: String = nodes
        .iter()
        .map(|n| {
            format!(
                "  server {} 127.0.0.1:{} check port {}\n",
                n.name, n.pg_port, n.rest_port
            )
        })
        .collect();
    format!(
        "global
  maxconn 2000
defaults
  mode tcp
  timeout connect 2s
  timeout client 30m
  timeout server 30m
  timeout check 1s
listen postgres
  bind 127.0.0.1:{port}
  option httpchk GET /primary
  http-check expect status 200
  default-server inter 500ms fall 2 rise 1 on-marked-down shutdown-sessions
{servers}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nodes() -> Vec<Node> {
        (0..2)
            .map(|k| Node {
                name: format!("pg{k}"),
                pg_port: 5432 + k,
                rest_port: 8008 + k,
                dir: PathBuf::from(format!("/tmp/x/pg{k}")),
                child: Mutex::new(None),
            })
            .collect()
    }

    #[test]
    fn the_cluster_is_formed_only_with_a_leader_and_a_synchronous_replica() {
        let nodes: Vec<(String, u16)> = nodes()
            .iter()
            .map(|n| (n.name.clone(), n.rest_port))
            .collect();
        let member = |name: &str, role: &str, state: &str| serde_json::json!({"name": name, "role": role, "state": state});
        let formed = |members: Vec<serde_json::Value>| {
            let c = ClusterState::from_json(&serde_json::json!({ "members": members }), &nodes);
            (c.leader, c.sync_streaming)
        };
        // Patroni 3.0.2 says "running" for a replica, later versions "streaming".
        assert_eq!(
            formed(vec![
                member("pg0", "leader", "running"),
                member("pg1", "sync_standby", "running")
            ]),
            (Some(0), Some(1))
        );
        assert_eq!(
            formed(vec![
                member("pg1", "leader", "running"),
                member("pg0", "sync_standby", "streaming")
            ]),
            (Some(1), Some(0))
        );
        // An asynchronous replica, one still starting, and a leader not running yet: not formed.
        assert_eq!(
            formed(vec![
                member("pg0", "leader", "running"),
                member("pg1", "replica", "streaming")
            ]),
            (Some(0), None)
        );
        assert_eq!(
            formed(vec![
                member("pg0", "leader", "starting"),
                member("pg1", "sync_standby", "starting"),
                member("other", "leader", "running")
            ]),
            (None, None)
        );
        assert_eq!(formed(vec![]), (None, None));
    }

    #[test]
    fn the_balancer_passes_only_to_the_node_whose_patroni_says_primary() {
        let cfg = haproxy_config(6000, &nodes());
        assert!(cfg.contains("bind 127.0.0.1:6000"), "{cfg}");
        assert!(cfg.contains("mode tcp"), "{cfg}");
        assert!(cfg.contains("option httpchk GET /primary"), "{cfg}");
        assert!(cfg.contains("on-marked-down shutdown-sessions"), "{cfg}");
        assert!(
            cfg.contains("server pg0 127.0.0.1:5432 check port 8008"),
            "{cfg}"
        );
        assert!(
            cfg.contains("server pg1 127.0.0.1:5433 check port 8009"),
            "{cfg}"
        );
    }

    #[test]
    fn a_node_is_configured_for_synchronous_replication_rewind_and_every_etcd_member() {
        let node = &nodes()[1];
        let cfg = node_config(
            node,
            &[(2379, 2380), (2479, 2480), (2579, 2580)],
            Path::new("/usr/lib/postgresql/15/bin"),
            "su",
            "rep",
            None,
        )
        .unwrap();
        for line in [
            "name: pg1",
            "  listen: 127.0.0.1:8009",
            "  hosts: 127.0.0.1:2379,127.0.0.1:2479,127.0.0.1:2579",
            "    ttl: 10",
            "    loop_wait: 1",
            "    retry_timeout: 3",
            "    synchronous_mode: true",
            "    synchronous_mode_strict: false",
            "      use_pg_rewind: true",
            "      remove_data_directory_on_rewind_failure: true",
            "  listen: 127.0.0.1:5433",
            "  data_dir: /tmp/x/pg1/data",
            "  bin_dir: /usr/lib/postgresql/15/bin",
            "      password: su",
            "      password: rep",
        ] {
            assert!(cfg.lines().any(|l| l == line), "no {line:?} in:\n{cfg}");
        }
    }

    #[test]
    fn a_node_archives_with_its_own_command_even_as_the_replica() {
        let node = &nodes()[0];
        let etcd = [(2379, 2380)];
        let bin = Path::new("/usr/lib/postgresql/15/bin");
        let plain = node_config(node, &etcd, bin, "su", "rep", None).unwrap();
        assert!(!plain.contains("archive"), "{plain}");
        let cfg = node_config(
            node,
            &etcd,
            bin,
            "su",
            "rep",
            Some("pgbackrest --config=/d/it's.conf archive-push %p"),
        )
        .unwrap();
        for line in [
            "    archive_mode: 'always'",
            "    archive_command: 'pgbackrest --config=/d/it''s.conf archive-push %p'",
        ] {
            assert!(cfg.lines().any(|l| l == line), "no {line:?} in:\n{cfg}");
        }
        // Under the node's own `postgresql.parameters`, before its pg_hba.
        let params = cfg.find("    unix_socket_directories:").unwrap();
        let archive = cfg.find("    archive_mode:").unwrap();
        let hba = cfg.find("  pg_hba:").unwrap();
        assert!(params < archive && archive < hba, "{cfg}");
    }

    #[test]
    fn a_process_tree_holds_the_grandchildren() {
        let mut child = std::process::Command::new("sh")
            .args(["-c", "sleep 30 & sleep 30 & wait"])
            .spawn()
            .unwrap();
        let root = child.id();
        let began = Instant::now();
        let mut tree = process_tree(&[root]);
        while tree.len() < 3 && began.elapsed() < Duration::from_secs(10) {
            std::thread::sleep(Duration::from_millis(20));
            tree = process_tree(&[root]);
        }
        assert_eq!(tree.len(), 3, "{tree:?}");
        assert_eq!(tree[0], root);
        kill_all(&tree);
        let _ = child.wait();
        // Each gone, or a zombie waiting for whoever adopted it to reap it.
        let alive = |pid: &u32| {
            std::fs::read_to_string(format!("/proc/{pid}/stat"))
                .ok()
                .and_then(|s| {
                    s.rsplit_once(')')
                        .map(|(_, rest)| rest.trim().starts_with('Z'))
                })
                .is_some_and(|zombie| !zombie)
        };
        let began = Instant::now();
        while tree.iter().any(alive) && began.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_millis(20));
        }
        let survivors: Vec<&u32> = tree.iter().filter(|p| alive(p)).collect();
        assert!(survivors.is_empty(), "outlived the kill: {survivors:?}");
    }
}
