//! The hub's load generator (`telerehab hub bench`): N stations, each with its own clinic
//! certificate and mutual-TLS connection, send a summary every `1/rate` s; the latency of each
//! summary is the time from its write to the hub's (cumulative) Ack, which the hub sends only
//! after the summary is committed to the database. At the end every station says Bye and waits
//! for the hub's reply, so "lost" counts summaries the hub never acknowledged.

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

use crate::db::Db;
use crate::error::HubError;

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
            .map_err(HubError::Config)?;
        let der = first_certificate_der(&cert_pem).map_err(HubError::Config)?;
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
    } = plan;
    let (connector, name) = st.tls.connector().map_err(|e| e.to_string())?;
    let tcp = TcpStream::connect(addr).await.map_err(|e| e.to_string())?;
    let _ = tcp.set_nodelay(true);
    let tls = connector
        .connect(name, tcp)
        .await
        .map_err(|e| e.to_string())?;
    let (mut rd, mut wr) = tokio::io::split(tls);
    let session_id = format!("bench-{}", st.station_id);
    let hello = Frame::Hello(Hello {
        protocol_version: PROTOCOL_VERSION,
        min_protocol_version: None,
        station_id: st.station_id.clone(),
        patient_id: st.patient_id.clone(),
        session_id: session_id.clone(),
        exercise: "sine-road".into(),
        started_unix_ms: 0,
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
                    let bye = Frame::Bye(Bye { session_id: session_id.clone(), reason: "bench done".into(), final_seq: seq.checked_sub(1), measures: Default::default() });
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
            "hub CPU {:.0} % of one core, peak RSS {rss_mib:.0} MiB\n",
            100.0 * cpu_s / seconds
        ));
    }
    if let Some(e) = &report.first_error {
        s.push_str(&format!("first error: {e}\n"));
    }
    s
}
