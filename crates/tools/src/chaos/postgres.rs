//! A throwaway PostgreSQL server the chaos day owns: `initdb` into a temporary directory, then
//! `pg_ctl start`, `pg_ctl stop -m immediate` (a crash: no checkpoint, clients cut off) and
//! `pg_ctl start` again, as `scripts/with-postgres.sh` does. The binaries are taken from
//! `$TELEREHAB_PG_BINDIR`, else the newest `/usr/lib/postgresql/*/bin`. Run as root, the server
//! runs as the `postgres` OS user (initdb refuses root).

use anyhow::{Context, bail};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The server's `max_connections` (two hubs' pools and the checks; a server restored from its
/// backup needs at least as many).
pub(super) const MAX_CONNECTIONS: u32 = 200;

/// The server: its binaries, cluster directory and port.
#[derive(Debug)]
pub struct Postgres {
    bindir: PathBuf,
    /// Owns the cluster; removed on drop.
    dir: tempfile::TempDir,
    port: u16,
    /// `runuser -u postgres --` when running as root.
    as_user: Vec<String>,
    /// The server's version, e.g. `16.4`.
    pub version: String,
}

/// The directory holding `initdb` and `pg_ctl`.
pub(super) fn bindir() -> anyhow::Result<PathBuf> {
    if let Some(dir) = std::env::var_os("TELEREHAB_PG_BINDIR").filter(|d| !d.is_empty()) {
        return Ok(PathBuf::from(dir));
    }
    let mut candidates: Vec<(u32, PathBuf)> = std::fs::read_dir("/usr/lib/postgresql")
        .context("no /usr/lib/postgresql (install postgresql or set TELEREHAB_PG_BINDIR)")?
        .filter_map(Result::ok)
        .filter_map(|e| {
            let major = e.file_name().to_str()?.parse::<u32>().ok()?;
            Some((major, e.path().join("bin")))
        })
        .filter(|(_, bin)| bin.join("initdb").exists())
        .collect();
    candidates.sort();
    candidates
        .pop()
        .map(|(_, bin)| bin)
        .context("no initdb under /usr/lib/postgresql/*/bin")
}

/// The version `postgres --version` in `bindir` says (e.g. `15.18`), `?` if it says none.
pub(super) fn server_version(bindir: &Path) -> String {
    std::process::Command::new(bindir.join("postgres"))
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| {
            String::from_utf8_lossy(&o.stdout)
                .split_whitespace()
                .nth(2)
                .map(str::to_owned)
        })
        .unwrap_or_else(|| "?".into())
}

/// `(uid, gid)` of the `postgres` OS user when this process is root; `None` otherwise.
pub(super) fn postgres_owner() -> anyhow::Result<Option<(u32, u32)>> {
    // /proc/self belongs to the process's effective user.
    let euid = std::os::unix::fs::MetadataExt::uid(&std::fs::metadata("/proc/self")?);
    if euid != 0 {
        return Ok(None);
    }
    let id = |flag: &str| {
        std::process::Command::new("id")
            .args([flag, "postgres"])
            .output()
            .ok()
            .filter(|o| o.status.success())
            .and_then(|o| {
                String::from_utf8_lossy(&o.stdout)
                    .trim()
                    .parse::<u32>()
                    .ok()
            })
    };
    match (id("-u"), id("-g")) {
        (Some(u), Some(g)) => Ok(Some((u, g))),
        _ => bail!("running as root but there is no `postgres` OS user to run the server"),
    }
}

/// `runuser -u postgres --` when this process is root (PostgreSQL refuses root), else nothing.
pub(super) fn as_postgres_user() -> anyhow::Result<Vec<String>> {
    Ok(if postgres_owner()?.is_some() {
        ["runuser", "-u", "postgres", "--"]
            .map(String::from)
            .to_vec()
    } else {
        Vec::new()
    })
}

/// Where one PostgreSQL server of the day runs: the one server, or a node of the cluster.
#[derive(Debug, Clone)]
pub(super) struct PgNode {
    /// Its data directory.
    pub data: PathBuf,
    /// Its TCP port (and its socket's number).
    pub port: u16,
    /// The directory of its Unix socket.
    pub socket_dir: PathBuf,
}

/// A free TCP port on loopback (free when asked; the caller binds it soon after).
pub(super) fn free_port() -> anyhow::Result<u16> {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").context("no free port")?;
    Ok(listener.local_addr()?.port())
}

/// `program` to be run as the server's user: behind `as_user` (`runuser -u postgres --` when
/// root), else as it is.
pub(super) fn command_as(
    as_user: &[String],
    program: impl AsRef<std::ffi::OsStr>,
) -> tokio::process::Command {
    match as_user.split_first() {
        Some((first, rest)) => {
            let mut c = tokio::process::Command::new(first);
            c.args(rest).arg(program);
            c
        }
        None => tokio::process::Command::new(program),
    }
}

/// Runs `program args` (as the server's user), failing with the tail of its output.
pub(super) async fn run_as(
    as_user: &[String],
    program: &Path,
    args: &[&str],
) -> anyhow::Result<()> {
    let mut command = command_as(as_user, program);
    let out = tokio::time::timeout(
        Duration::from_secs(60),
        command.args(args).kill_on_drop(true).output(),
    )
    .await
    .with_context(|| format!("{} did not finish within 60 s", program.display()))?
    .with_context(|| format!("cannot run {}", program.display()))?;
    if !out.status.success() {
        bail!("{} {}: {}", program.display(), out.status, last_lines(&out));
    }
    Ok(())
}

impl Postgres {
    /// Makes a cluster and starts it. An error here means "PostgreSQL unavailable".
    pub async fn start_new() -> anyhow::Result<Self> {
        let bindir = bindir()?;
        let dir = tempfile::Builder::new()
            .prefix("telerehab-chaos-pg.")
            .tempdir()
            .context("cannot make the cluster's directory")?;
        if let Some((uid, _)) = postgres_owner()? {
            std::os::unix::fs::chown(dir.path(), Some(uid), None)
                .context("cannot give the cluster's directory to the postgres user")?;
        }
        let as_user = as_postgres_user()?;
        let version = server_version(&bindir);
        let pg = Self {
            port: free_port()?,
            bindir,
            dir,
            as_user,
            version,
        };
        let data = pg.data();
        run_as(
            &pg.as_user,
            &pg.bindir.join("initdb"),
            &[
                "-D",
                path_str(&data)?,
                "-U",
                "postgres",
                "--auth=trust",
                "-E",
                "UTF8",
                "--no-sync",
            ],
        )
        .await?;
        pg.start().await?;
        Ok(pg)
    }

    /// The cluster's data directory.
    fn data(&self) -> PathBuf {
        self.dir.path().join("data")
    }

    /// Where the server runs: data directory, port, socket.
    pub(super) fn node(&self) -> PgNode {
        PgNode {
            data: self.data(),
            port: self.port,
            socket_dir: self.dir.path().to_owned(),
        }
    }

    /// The directory of `initdb`, `pg_ctl`, `psql`.
    pub(super) fn bin(&self) -> &Path {
        &self.bindir
    }

    /// Appends `lines` to the cluster's `postgresql.conf` (later lines win) and restarts the
    /// server in order so that settings read only at start (`archive_mode`) take effect.
    pub(super) async fn configure(&self, lines: &str) -> anyhow::Result<()> {
        use std::io::Write;
        let conf = self.data().join("postgresql.conf");
        let mut file = std::fs::OpenOptions::new()
            .append(true)
            .open(&conf)
            .with_context(|| format!("cannot open {}", conf.display()))?;
        writeln!(file, "\n{lines}").with_context(|| format!("cannot write {}", conf.display()))?;
        drop(file);
        self.stop().await?;
        self.start().await
    }

    /// The database URL.
    pub fn url(&self) -> String {
        format!("postgres://postgres@127.0.0.1:{}/postgres", self.port)
    }

    async fn pg_ctl(&self, args: &[&str]) -> anyhow::Result<()> {
        let data = self.data();
        let mut all = vec!["-D", path_str(&data)?];
        all.extend_from_slice(args);
        run_as(&self.as_user, &self.bindir.join("pg_ctl"), &all).await
    }

    /// Starts the server and waits until it accepts connections.
    pub async fn start(&self) -> anyhow::Result<()> {
        let log = self.dir.path().join("server.log");
        let options = format!(
            "-c listen_addresses=127.0.0.1 -p {} -k {} -c fsync=off -c max_connections={MAX_CONNECTIONS}",
            self.port,
            path_str(self.dir.path())?
        );
        self.pg_ctl(&[
            "-l",
            path_str(&log)?,
            "-w",
            "-t",
            "30",
            "-o",
            &options,
            "start",
        ])
        .await
    }

    /// Crashes the server: `pg_ctl stop -m immediate` (no checkpoint; recovery at restart).
    pub async fn kill(&self) -> anyhow::Result<()> {
        self.pg_ctl(&["-w", "-t", "30", "-m", "immediate", "stop"])
            .await
    }

    /// Stops the server in order.
    pub async fn stop(&self) -> anyhow::Result<()> {
        self.pg_ctl(&["-w", "-t", "30", "-m", "fast", "stop"]).await
    }
}

pub(super) fn path_str(p: &Path) -> anyhow::Result<&str> {
    p.to_str()
        .with_context(|| format!("{} is not UTF-8", p.display()))
}

/// The last `n` lines of a log file, ` / `-joined (empty when it cannot be read).
pub(crate) fn log_tail(path: &Path, n: usize) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join(" / ")
}

/// A failed command's last four lines of output (stderr, then stdout), joined by " / ".
pub(crate) fn last_lines(out: &std::process::Output) -> String {
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stderr),
        String::from_utf8_lossy(&out.stdout)
    );
    let tail: Vec<&str> = text.lines().rev().take(4).collect();
    tail.into_iter().rev().collect::<Vec<_>>().join(" / ")
}
