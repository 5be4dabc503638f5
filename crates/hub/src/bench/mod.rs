//! The hub's load generator (`telerehab hub bench`): N stations, each with its own clinic
//! certificate and mutual-TLS connection, send a summary every `1/rate` s; the latency of each
//! summary is the time from its write to the hub's (cumulative) Ack, which the hub sends only
//! after the summary is committed to the database. At the end every station says Bye and waits
//! for the hub's reply, so "lost" counts summaries the hub never acknowledged.

pub mod balancer;

use std::collections::VecDeque;
use std::net::SocketAddr;
use std::path::Path;
use std::time::{Duration, Instant};

use netlink::pki::{ClinicCa, certificate_sha256_hex, first_certificate_der};
use netlink::{
    Bye, ClientTls, Frame, FrameDecoder, Hello, Identity, PROTOCOL_VERSION, Summary, encode_to_vec,
};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

use hub_store::HubError;
use hub_store::db::Db;

/// A provisioned station: its id, patient and TLS files.
#[derive(Debug, Clone)]
pub struct BenchStation {
    /// Station id.
    pub station_id: String,
    /// Its patient.
    pub patient_id: String,
    /// TLS to the hub with this station's certificate.
    pub tls: ClientTls,
}

/// Makes `n` patients and stations (certificates issued straight from the CA, as pairing
/// would), with their TLS files under `dir`.
pub async fn provision(
    db: &Db,
    ca: &ClinicCa,
    server_name: &str,
    n: usize,
    dir: &Path,
    now_ms: i64,
) -> Result<Vec<BenchStation>, HubError> {
    let io = |what: &str| {
        let what = what.to_owned();
        move |e| HubError::io(what.clone(), e)
    };
    std::fs::create_dir_all(dir).map_err(io("creating the bench directory"))?;
    let ca_path = dir.join("ca.crt");
    std::fs::write(&ca_path, &ca.pem().cert_pem).map_err(io("writing ca.crt"))?;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let patient = db
            .add_patient(&format!("BENCH-{i:05}"), None, now_ms)
            .await?;
        let key = rcgen::KeyPair::generate().map_err(|e| HubError::Config(e.to_string()))?;
        let csr = rcgen::CertificateParams::new(Vec::<String>::new())
            .and_then(|p| p.serialize_request(&key))
            .and_then(|c| c.pem())
            .map_err(|e| HubError::Config(e.to_string()))?;
        let station_id = format!("st-bench-{i:05}");
        let cert_pem = ca
            .sign_station(&csr, &station_id)
            .map_err(|e| HubError::Config(e.to_string()))?;
        let der = first_certificate_der(&cert_pem).map_err(|e| HubError::Config(e.to_string()))?;
        db.add_station(
            &station_id,
            &patient.id,
            &certificate_sha256_hex(&der),
            now_ms,
        )
        .await?;
        let cert_path = dir.join(format!("{station_id}.crt"));
        let key_path = dir.join(format!("{station_id}.key"));
        std::fs::write(&cert_path, cert_pem).map_err(io("writing a station certificate"))?;
        std::fs::write(&key_path, key.serialize_pem()).map_err(io("writing a station key"))?;
        out.push(BenchStation {
            station_id,
            patient_id: patient.id,
            tls: ClientTls {
                ca_pem_path: ca_path.clone(),
                server_name: server_name.to_owned(),
                identity: Some(Identity {
                    cert_pem_path: cert_path,
                    key_pem_path: key_path,
                }),
            },
        });
    }
    Ok(out)
}

/// What one station saw.
#[derive(Debug, Default)]
struct StationResult {
    connected: bool,
    sent: u64,
    acked: u64,
    /// Latency of each acknowledged summary, µs.
    latencies_us: Vec<u32>,
    error: Option<String>,
}

/// The load's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadReport {
    /// Stations that completed the TLS handshake and Hello.
    pub connected: usize,
    /// Summaries written.
    pub sent: u64,
    /// Summaries acknowledged (committed) by the end.
    pub acked: u64,
    /// Latency quantiles, ms: p50, p99, max.
    pub latency_ms: (f64, f64, f64),
    /// How long connecting every station took (TLS handshakes and Hellos, all at once), s;
    /// the load starts after it, so the latencies are those of a running clinic, not of a
    /// reconnection storm.
    pub connect_s: f64,
    /// The first station error, if any.
    pub first_error: Option<String>,
}

/// Runs `stations` against the hub at `addr` for `duration`, each sending at `rate_hz`
/// (start times spread over the first period) once every station has connected.
pub async fn load(
    addr: SocketAddr,
    stations: Vec<BenchStation>,
    rate_hz: f64,
    duration: Duration,
) -> LoadReport {
    load_run(addr, stations, rate_hz, duration, 0).await
}

/// [`load`] as run number `run` of several against one clinic: each run's sessions are new
/// (`bench-r<run>-<station>`), so no summary of one run is taken for a duplicate of another's.
pub async fn load_run(
    addr: SocketAddr,
    stations: Vec<BenchStation>,
    rate_hz: f64,
    duration: Duration,
    run: u32,
) -> LoadReport {
    let period = Duration::from_secs_f64(1.0 / rate_hz);
    let n = stations.len().max(1);
    let t0 = Instant::now();
    let (ready_tx, mut ready_rx) = tokio::sync::mpsc::channel::<()>(n);
    let (start_tx, start_rx) = tokio::sync::watch::channel(None::<Instant>);
    let tasks: Vec<_> = stations
        .into_iter()
        .enumerate()
        .map(|(i, st)| {
            let plan = Plan {
                offset: period.mul_f64(i as f64 / n as f64),
                period,
                duration,
                ready: ready_tx.clone(),
                start: start_rx.clone(),
                run,
            };
            tokio::spawn(one_station(addr, st, plan))
        })
        .collect();
    drop(ready_tx);
    // Every station says once that it connected or gave up (its sender drops).
    while ready_rx.recv().await.is_some() {}
    let connect_s = t0.elapsed().as_secs_f64();
    let _ = start_tx.send(Some(Instant::now() + Duration::from_millis(100)));
    let mut results = Vec::with_capacity(tasks.len());
    for t in tasks {
        results.push(t.await.unwrap_or_else(|e| StationResult {
            error: Some(format!("task failed: {e}")),
            ..StationResult::default()
        }));
    }
    let mut all: Vec<u32> = results
        .iter()
        .flat_map(|r| r.latencies_us.iter().copied())
        .collect();
    all.sort_unstable();
    let q = |p: f64| common::quantile(&all, p).map_or(f64::NAN, |us| f64::from(us) / 1000.0);
    LoadReport {
        connected: results.iter().filter(|r| r.connected).count(),
        sent: results.iter().map(|r| r.sent).sum(),
        acked: results.iter().map(|r| r.acked).sum(),
        latency_ms: (
            q(0.5),
            q(0.99),
            all.last().map_or(f64::NAN, |&m| f64::from(m) / 1000.0),
        ),
        connect_s,
        first_error: results.into_iter().find_map(|r| r.error),
    }
}

fn summary(session_id: &str, seq: u64) -> Summary {
    Summary::example(session_id, seq)
}

/// One station's part of the load.
struct Plan {
    /// Its first summary this long after the common start.
    offset: Duration,
    period: Duration,
    duration: Duration,
    /// Told (by a message, or by being dropped) once the station connected or failed to.
    ready: tokio::sync::mpsc::Sender<()>,
    /// The common start, once every station is ready.
    start: tokio::sync::watch::Receiver<Option<Instant>>,
    /// The run's number (part of the session id).
    run: u32,
}

async fn one_station(addr: SocketAddr, st: BenchStation, plan: Plan) -> StationResult {
    let mut result = StationResult::default();
    if let Err(e) = drive(addr, &st, plan, &mut result).await {
        result.error = Some(format!("{}: {e}", st.station_id));
    }
    result
}

async fn drive(
    addr: SocketAddr,
    st: &BenchStation,
    plan: Plan,
    result: &mut StationResult,
) -> Result<(), String> {
    let Plan {
        offset,
        period,
        duration,
        ready,
        mut start,
        run,
    } = plan;
    let (connector, name) = st.tls.connector().map_err(|e| e.to_string())?;
    let tcp = TcpStream::connect(addr).await.map_err(|e| e.to_string())?;
    let _ = tcp.set_nodelay(true);
    let tls = connector
        .connect(name, tcp)
        .await
        .map_err(|e| e.to_string())?;
    let (mut rd, mut wr) = tokio::io::split(tls);
    let session_id = if run == 0 {
        format!("bench-{}", st.station_id)
    } else {
        format!("bench-r{run}-{}", st.station_id)
    };
    let hello = Frame::Hello(Hello {
        protocol_version: PROTOCOL_VERSION,
        min_protocol_version: None,
        wheel: None,
        station_id: st.station_id.clone(),
        patient_id: st.patient_id.clone(),
        session_id: session_id.clone(),
        exercise: "sine-road".into(),
        started_unix_ms: netlink::frame::unix_ms_now(),
        software_version: "telerehab hub bench".into(),
    });
    let write = |f: &Frame| encode_to_vec(f).map_err(|e| e.to_string());
    wr.write_all(&write(&hello)?)
        .await
        .map_err(|e| e.to_string())?;
    result.connected = true;
    let _ = ready.send(()).await;
    drop(ready);
    let first = match start.wait_for(Option::is_some).await {
        Ok(t) => t.map_or_else(Instant::now, |t| t + offset),
        Err(_) => return Err("the load never started".into()),
    };
    let mut outstanding: VecDeque<(u64, Instant)> = VecDeque::new();
    let mut decoder = FrameDecoder::new();
    let mut buf = vec![0u8; 4096];
    let mut ticker = tokio::time::interval_at(first.into(), period);
    ticker.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let end = first + duration;
    let mut seq = 0u64;
    let mut bye_sent = false;
    let deadline = end + Duration::from_secs(15);
    loop {
        tokio::select! {
            _ = ticker.tick(), if !bye_sent => {
                if Instant::now() >= end {
                    let bye = Frame::Bye(Bye { session_id: session_id.clone(), reason: "bench done".into(), final_seq: seq.checked_sub(1), measures: Default::default(), hub_unix_ms: None, checkin: None, difficulty: None, exercises: Vec::new() });
                    wr.write_all(&write(&bye)?).await.map_err(|e| e.to_string())?;
                    bye_sent = true;
                    continue;
                }
                outstanding.push_back((seq, Instant::now()));
                wr.write_all(&write(&Frame::Summary(summary(&session_id, seq)))?).await.map_err(|e| e.to_string())?;
                result.sent += 1;
                seq += 1;
            }
            r = rd.read(&mut buf) => {
                let n = r.map_err(|e| e.to_string())?;
                if n == 0 {
                    return if bye_sent { Ok(()) } else { Err("the hub closed the connection".into()) };
                }
                decoder.extend(&buf[..n]);
                while let Some(frame) = decoder.next_frame().map_err(|e| e.to_string())? {
                    match frame {
                        Frame::Ack(ack) => {
                            let now = Instant::now();
                            while outstanding.front().is_some_and(|(s, _)| *s <= ack.seq) {
                                let (_, at) = outstanding.pop_front().unwrap_or((0, now));
                                let us = now.duration_since(at).as_micros();
                                result.latencies_us.push(u32::try_from(us).unwrap_or(u32::MAX));
                                result.acked += 1;
                            }
                        }
                        Frame::Bye(_) => return Ok(()),
                        Frame::Error(e) => return Err(format!("hub error: {}", e.message)),
                        _ => {}
                    }
                }
            }
            () = tokio::time::sleep_until(deadline.into()) => {
                return Err(format!("no Bye answer within 15 s; {} unacknowledged", outstanding.len()));
            }
        }
    }
}

/// CPU time (user + system, s) and peak resident memory (MiB) of process `pid`, from /proc.
pub fn process_usage(pid: u32) -> Option<(f64, f64)> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // Fields after the command name (which may hold spaces) start after the last ')'.
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    // /proc reports CPU times in USER_HZ, which the Linux ABI fixes at 100 per second.
    let hz = 100.0;
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let hwm_kb: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some((ticks / hz, hwm_kb / 1024.0))
}

/// Shared for the CLI: the load report and the hub's CPU/memory in one line set.
pub fn describe(
    report: &LoadReport,
    seconds: f64,
    rate_hz: f64,
    hub: Option<(f64, f64)>,
) -> String {
    let (p50, p99, max) = report.latency_ms;
    let mut s = format!(
        "stations connected {} (all at once, in {:.1} s; the load starts after)\nsummaries sent {} acknowledged {} unacknowledged 15 s after the end {}\nthroughput {:.0} summaries/s (target {:.0})\ningest latency p50 {p50:.2} ms p99 {p99:.2} ms max {max:.2} ms\n",
        report.connected,
        report.connect_s,
        report.sent,
        report.acked,
        report.sent.saturating_sub(report.acked),
        report.acked as f64 / seconds,
        report.connected as f64 * rate_hz,
    );
    if let Some((cpu_s, rss_mib)) = hub {
        s.push_str(&format!(
            "hub CPU {:.0} % of one core (every hub together), peak RSS {rss_mib:.0} MiB (the largest hub)\n",
            100.0 * cpu_s / seconds
        ));
    }
    if let Some(e) = &report.first_error {
        s.push_str(&format!("first error: {e}\n"));
    }
    s
}

/// CPU time (user + system, s) of `pid`, with that of its waited-for children when
/// `children` (a PostgreSQL postmaster's exited backends).
fn cpu_s(pid: u32, children: bool) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let field = |i: usize| fields.get(i).and_then(|f| f.parse::<f64>().ok());
    let mut ticks = field(11)? + field(12)?;
    if children {
        ticks += field(13)? + field(14)?;
    }
    // USER_HZ is 100 on Linux.
    Some(ticks / 100.0)
}

/// The parent of `pid`.
fn parent_of(pid: u32) -> Option<u32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    stat.rsplit_once(')')?
        .1
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()
}

/// The TCP port of a `postgres://…` URL (5432 if none is given).
pub fn postgres_port(url: &str) -> Option<u16> {
    let rest = url.split_once("://")?.1;
    let host_port = rest.rsplit_once('@').map_or(rest, |(_, h)| h);
    let host_port = host_port.split(['/', '?']).next()?;
    match host_port.rsplit_once(':') {
        Some((_, port)) if !port.contains(']') => port.parse().ok(),
        _ => Some(5432),
    }
}

/// The process listening on TCP `port` of this machine (from /proc/net/tcp{,6} and the
/// processes' descriptors), if visible to this user.
fn listener_pid(port: u16) -> Option<u32> {
    let hex_port = format!(":{port:04X}");
    let mut inodes = std::collections::HashSet::new();
    for table in ["/proc/net/tcp", "/proc/net/tcp6"] {
        let Ok(text) = std::fs::read_to_string(table) else {
            continue;
        };
        for line in text.lines().skip(1) {
            let f: Vec<&str> = line.split_whitespace().collect();
            // local_address, state 0A = LISTEN, inode.
            if f.len() > 9 && f[1].ends_with(&hex_port) && f[3] == "0A" {
                inodes.insert(format!("socket:[{}]", f[9]));
            }
        }
    }
    let procs = std::fs::read_dir("/proc").ok()?;
    for entry in procs.filter_map(Result::ok) {
        let Some(pid) = entry
            .file_name()
            .to_str()
            .and_then(|n| n.parse::<u32>().ok())
        else {
            continue;
        };
        let Ok(fds) = std::fs::read_dir(entry.path().join("fd")) else {
            continue;
        };
        for fd in fds.filter_map(Result::ok) {
            if let Ok(link) = std::fs::read_link(fd.path())
                && inodes.contains(link.to_string_lossy().as_ref())
            {
                return Some(pid);
            }
        }
    }
    None
}

/// The PostgreSQL server behind `url` (on this machine): its postmaster and the processes it
/// started, whose CPU [`postgres_cpu_s`] sums. `None` if it cannot be found.
pub fn postgres_server(url: &str) -> Option<u32> {
    listener_pid(postgres_port(url)?)
}

/// CPU time (s) of the PostgreSQL server whose postmaster is `postmaster`: itself with its
/// exited children, and every live process it started (backends, writers).
pub fn postgres_cpu_s(postmaster: u32) -> Option<f64> {
    let mut total = cpu_s(postmaster, true)?;
    for entry in std::fs::read_dir("/proc").ok()?.filter_map(Result::ok) {
        let Some(pid) = entry
            .file_name()
            .to_str()
            .and_then(|n| n.parse::<u32>().ok())
        else {
            continue;
        };
        if parent_of(pid) == Some(postmaster) {
            total += cpu_s(pid, false).unwrap_or(0.0);
        }
    }
    Some(total)
}

/// One run's figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunFigures {
    /// Ingest latency p50, ms.
    pub p50_ms: f64,
    /// Ingest latency p99, ms.
    pub p99_ms: f64,
    /// The hub's CPU, % of one core.
    pub hub_cpu_pct: f64,
    /// The PostgreSQL server's CPU, % of one core (`None` on SQLite).
    pub db_cpu_pct: Option<f64>,
    /// Summaries sent and not acknowledged.
    pub lost: u64,
    /// Summaries acknowledged (stored).
    pub acked: u64,
}

/// Median and range of `values` (NaN-free input), as `median [min–max]`.
pub fn median_and_range(values: &[f64]) -> Option<(f64, f64, f64)> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let mid = v.len() / 2;
    let median = if v.len() % 2 == 1 {
        v[mid]
    } else {
        f64::midpoint(v[mid - 1], v[mid])
    };
    Some((median, v[0], v[v.len() - 1]))
}

/// The closing lines of a multi-run bench: median and spread (min–max) of each figure.
pub fn describe_runs(runs: &[RunFigures]) -> String {
    let line = |name: &str, unit: &str, values: Vec<f64>| {
        median_and_range(&values).map_or(String::new(), |(m, lo, hi)| {
            format!("  {name:<22} {m:>8.2} {unit:<3} [{lo:.2}–{hi:.2}]\n")
        })
    };
    let mut s = format!("median of {} runs [min–max]:\n", runs.len());
    s.push_str(&line(
        "ingest p50",
        "ms",
        runs.iter().map(|r| r.p50_ms).collect(),
    ));
    s.push_str(&line(
        "ingest p99",
        "ms",
        runs.iter().map(|r| r.p99_ms).collect(),
    ));
    s.push_str(&line(
        "hub CPU",
        "%",
        runs.iter().map(|r| r.hub_cpu_pct).collect(),
    ));
    let db: Vec<f64> = runs.iter().filter_map(|r| r.db_cpu_pct).collect();
    if !db.is_empty() {
        s.push_str(&line("PostgreSQL CPU", "%", db));
    }
    let lost: u64 = runs.iter().map(|r| r.lost).sum();
    s.push_str(&format!("  unacknowledged (all runs) {lost}\n"));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_range_of_three_runs_and_of_an_even_count() {
        assert_eq!(
            median_and_range(&[215.0, 32.0, 962.0]),
            Some((215.0, 32.0, 962.0))
        );
        assert_eq!(
            median_and_range(&[4.0, 1.0, 2.0, 3.0]),
            Some((2.5, 1.0, 4.0))
        );
        assert_eq!(median_and_range(&[f64::NAN]), None);
    }

    #[test]
    fn the_postgres_port_is_read_from_the_url_with_5432_by_default() {
        assert_eq!(
            postgres_port("postgres://postgres@127.0.0.1:5433/postgres"),
            Some(5433)
        );
        assert_eq!(
            postgres_port("postgres://u:p:w@localhost/db?sslmode=disable"),
            Some(5432)
        );
        assert_eq!(postgres_port("postgresql://[::1]:6000/x"), Some(6000));
    }

    #[test]
    fn this_process_cpu_time_and_parent_are_read_from_proc() {
        assert!(cpu_s(std::process::id(), true).is_some_and(|s| s >= 0.0));
        assert_eq!(
            parent_of(std::process::id()),
            Some(std::os::unix::process::parent_id())
        );
        assert_eq!(cpu_s(u32::MAX, false), None);
    }
}
