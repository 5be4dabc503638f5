//! The `telerehab hub serve` processes of a chaos day, each kept running by a supervisor
//! (as systemd would restart it): killed on command (SIGKILL, or SIGTERM and a wait for the
//! clean stop) and started again on the same ports after a pause; a hub that exits on its own
//! (e.g. started while PostgreSQL is down) is started again after a second.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::Stdio;
use std::time::Duration;

use tokio::sync::{mpsc, oneshot};

/// How a hub is killed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Signal {
    /// SIGKILL: the process vanishes.
    Kill,
    /// SIGTERM: the hub stops in order (it must within [`TERM_WITHIN`]).
    Term,
}

/// How long a hub may take to stop on SIGTERM before it counts as not stopping (and is killed).
pub const TERM_WITHIN: Duration = Duration::from_secs(10);

/// How to start one hub.
#[derive(Debug, Clone)]
pub struct HubSpec {
    /// The `telerehab` binary.
    pub exe: PathBuf,
    /// Its data directory (the clinic's, shared by every hub, or a copy of its own with `--s3`).
    pub data: PathBuf,
    /// The database URL (`--db`); `None`: the one the clinic's `hub.toml` names.
    pub db: Option<String>,
    /// Stations' address.
    pub stations: SocketAddr,
    /// Console address.
    pub web: SocketAddr,
    /// Where its output goes (appended).
    pub log: PathBuf,
}

/// What happened to a hub over the day.
#[derive(Debug, Default, Clone)]
pub struct HubStats {
    /// Processes started.
    pub starts: u32,
    /// Exits nobody asked for, with the last line of the log at each.
    pub own_exits: Vec<String>,
    /// SIGTERMs it did not obey within [`TERM_WITHIN`].
    pub slow_stops: u32,
    /// Errors starting the process.
    pub spawn_errors: Vec<String>,
}

enum Command {
    Kill(Signal, Duration, oneshot::Sender<bool>),
    Stop,
}

/// A supervised hub.
pub struct Hub {
    tx: mpsc::Sender<Command>,
    task: tokio::task::JoinHandle<HubStats>,
    /// Its stations' address.
    pub stations: SocketAddr,
    /// Its console's address (its `/readyz`).
    pub web: SocketAddr,
}

impl Hub {
    /// Starts the hub and its supervisor.
    pub fn start(spec: HubSpec) -> Self {
        let (tx, rx) = mpsc::channel(8);
        let (stations, web) = (spec.stations, spec.web);
        let task = tokio::spawn(supervise(spec, rx));
        Self {
            tx,
            task,
            stations,
            web,
        }
    }

    /// Kills the hub with `signal`, restarting it `down` later; false if it was not running.
    pub async fn kill(&self, signal: Signal, down: Duration) -> bool {
        let (reply, answer) = oneshot::channel();
        if self
            .tx
            .send(Command::Kill(signal, down, reply))
            .await
            .is_err()
        {
            return false;
        }
        answer.await.unwrap_or(false)
    }

    /// Stops the hub (SIGTERM) for good and says what happened to it.
    pub async fn stop(self) -> HubStats {
        let _ = self.tx.send(Command::Stop).await;
        self.task.await.unwrap_or_default()
    }
}

fn spawn(spec: &HubSpec) -> std::io::Result<tokio::process::Child> {
    let log = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&spec.log)?;
    let (stations, web) = (spec.stations.to_string(), spec.web.to_string());
    tokio::process::Command::new(&spec.exe)
        .args(["hub", "serve", "--data"])
        .arg(&spec.data)
        .args(spec.db.iter().flat_map(|db| ["--db", db.as_str()]))
        .args(["--stations", &stations, "--web", &web])
        .args(["--max-connections", "4096"])
        .args(["--max-connections-per-address", "4096"])
        .stdin(Stdio::null())
        .stdout(Stdio::from(log.try_clone()?))
        .stderr(Stdio::from(log))
        .kill_on_drop(true)
        .spawn()
}

fn last_log_line(spec: &HubSpec) -> String {
    std::fs::read_to_string(&spec.log)
        .ok()
        .and_then(|t| {
            t.lines()
                .rev()
                .find(|l| !l.trim().is_empty())
                .map(str::to_owned)
        })
        .unwrap_or_default()
}

/// Sleeps `d` while answering commands; true if told to stop.
async fn down_for(rx: &mut mpsc::Receiver<Command>, d: Duration) -> bool {
    let until = tokio::time::Instant::now() + d;
    loop {
        tokio::select! {
            () = tokio::time::sleep_until(until) => return false,
            cmd = rx.recv() => match cmd {
                None | Some(Command::Stop) => return true,
                Some(Command::Kill(_, _, reply)) => { let _ = reply.send(false); }
            },
        }
    }
}

/// SIGTERM, then waits up to [`TERM_WITHIN`]; false if it had to be killed.
async fn terminate(child: &mut tokio::process::Child) -> bool {
    if let Some(pid) = child.id() {
        let _ = tokio::process::Command::new("kill")
            .args(["-TERM", &pid.to_string()])
            .status()
            .await;
    }
    if tokio::time::timeout(TERM_WITHIN, child.wait())
        .await
        .is_ok()
    {
        return true;
    }
    let _ = child.kill().await;
    false
}

async fn supervise(spec: HubSpec, mut rx: mpsc::Receiver<Command>) -> HubStats {
    let mut stats = HubStats::default();
    loop {
        let mut child = match spawn(&spec) {
            Ok(c) => c,
            Err(e) => {
                stats.spawn_errors.push(e.to_string());
                if down_for(&mut rx, Duration::from_secs(1)).await {
                    return stats;
                }
                continue;
            }
        };
        stats.starts += 1;
        let command = tokio::select! {
            _ = child.wait() => None,
            cmd = rx.recv() => Some(cmd),
        };
        let down = match command {
            None => {
                stats.own_exits.push(last_log_line(&spec));
                Duration::from_secs(1)
            }
            Some(None | Some(Command::Stop)) => {
                if !terminate(&mut child).await {
                    stats.slow_stops += 1;
                }
                return stats;
            }
            Some(Some(Command::Kill(signal, down, reply))) => {
                match signal {
                    Signal::Kill => {
                        let _ = child.kill().await;
                    }
                    Signal::Term => {
                        if !terminate(&mut child).await {
                            stats.slow_stops += 1;
                        }
                    }
                }
                let _ = reply.send(true);
                down
            }
        };
        if down_for(&mut rx, down).await {
            return stats;
        }
    }
}
