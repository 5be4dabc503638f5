//! What an operator watches (`GET /metrics`, docs/OPERATING.md): the hub's one registry of
//! Prometheus metrics and the calls that move them.
//!
//! One [`Telemetry`] per running hub, shared (`Arc`) by the station link's store, the console's
//! API and the pain mailer; each part calls a named method where the thing happens
//! (`telemetry.summary_stored(latency_s)`), never a metric by its name. Every label value is
//! one of a closed set written in this crate or in `netlink` (a reason, an outcome, a route
//! group): no pseudonym, station or session id, address or free text is ever a label, so the
//! number of series is bounded whatever stations and browsers send.
//!
//! Named `telemetry`, not `metrics`: `metrics` is the workspace's crate of movement measures,
//! which this crate depends on.

use std::sync::atomic::AtomicU64;

use prometheus_client::encoding::prometheus_text;
use prometheus_client::metrics::counter::Counter;
use prometheus_client::metrics::family::Family;
use prometheus_client::metrics::gauge::Gauge;
use prometheus_client::metrics::histogram::Histogram;
use prometheus_client::registry::{Metric, Registry, Unit};

use hub_store::db::Db;

/// The `Content-Type` of `GET /metrics` (Prometheus text format 0.0.4).
pub const CONTENT_TYPE: &str = prometheus_text::CONTENT_TYPE;

/// Every metric's name starts with this (then `_`).
pub const PREFIX: &str = "telerehab_hub";

/// Buckets of the summaries' acknowledgement latency, s: 1 ms to ~4 s (the station resends
/// after its acknowledgement timeout; the bench's target is p99 < 50 ms).
const ACK_BUCKETS_S: [f64; 13] = [
    0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0,
];

/// Buckets of the console's request durations and the pool's acquire wait, s.
const REQUEST_BUCKETS_S: [f64; 11] = [
    0.001, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 10.0,
];

/// One label: (name, value), both from the code.
type Label = [(&'static str, &'static str); 1];
/// Two labels.
type Labels2 = [(&'static str, &'static str); 2];
type HistogramFamily<S> = Family<S, Histogram, fn() -> Histogram>;

fn request_histogram() -> Histogram {
    Histogram::new(REQUEST_BUCKETS_S)
}

/// Why a station's connection was refused admission (after its TLS handshake and `Hello`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum AdmissionRefusal {
    /// It presented no client certificate (it must pair first).
    NoCertificate,
    /// Its station id is not one the hub paired.
    UnknownStation,
    /// The clinic revoked it.
    Revoked,
    /// Its certificate is not the one issued to that station id.
    CertificateMismatch,
    /// It spoke for another patient than its own.
    WrongPatient,
    /// The database could not answer the check.
    Database,
}

impl AdmissionRefusal {
    /// The `reason` label.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::NoCertificate => "no_certificate",
            Self::UnknownStation => "unknown_station",
            Self::Revoked => "revoked",
            Self::CertificateMismatch => "certificate_mismatch",
            Self::WrongPatient => "wrong_patient",
            Self::Database => "database",
        }
    }
}

/// How a replay request ended, for `replays_total{outcome}`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReplayOutcome {
    /// Its stream began.
    Started,
    /// Refused before any work: not uploaded, too large, too costly, busy.
    Refused,
    /// The file could not be read or decoded.
    Failed,
}

impl ReplayOutcome {
    const fn as_str(self) -> &'static str {
        match self {
            Self::Started => "started",
            Self::Refused => "refused",
            Self::Failed => "failed",
        }
    }
}

/// The hub's metrics and the registry that encodes them.
#[derive(Debug)]
pub struct Telemetry {
    registry: Registry,
    station_connections: Gauge,
    station_connections_unauthenticated: Gauge,
    station_admitted: Counter,
    station_refused: Family<Label, Counter>,
    summaries_ingested: Counter,
    summaries_duplicate: Counter,
    summary_ack: Histogram,
    db_pool_connections: Gauge,
    db_pool_idle: Gauge,
    db_pool_max: Gauge,
    db_pool_acquire: Histogram,
    upload_bytes: Counter,
    uploads_completed: Counter,
    uploads_failed: Counter,
    uploads_refused: Counter,
    replays: Family<Label, Counter>,
    pain_mails: Family<Label, Counter>,
    http_requests: Family<Labels2, Counter>,
    http_request_duration: HistogramFamily<Label>,
    process_start_time: Gauge<f64, AtomicU64>,
}

impl Default for Telemetry {
    fn default() -> Self {
        Self::new()
    }
}

impl Telemetry {
    /// A new registry with every metric at zero, `build_info` naming this version and the
    /// process start time read from the system clock now.
    pub fn new() -> Self {
        let mut r = Registry::with_prefix(PREFIX);
        let mut t = Self {
            station_connections: plain(
                &mut r,
                "station_connections",
                "Stations connected now (admitted, one a station)",
            ),
            station_connections_unauthenticated: plain(
                &mut r,
                "station_connections_unauthenticated",
                "Station-port connections not admitted yet (TLS handshake, Hello, pairing)",
            ),
            station_admitted: plain(
                &mut r,
                "station_admitted",
                "Station connections admitted after their Hello",
            ),
            station_refused: plain(
                &mut r,
                "station_refused",
                "Station connections refused or ended by the hub, by reason (admission, limits, protocol, connection caps)",
            ),
            summaries_ingested: plain(
                &mut r,
                "summaries_ingested",
                "Summaries stored (new, not duplicates)",
            ),
            summaries_duplicate: plain(
                &mut r,
                "summaries_duplicate",
                "Summaries received again after they were stored (a station resending)",
            ),
            summary_ack: with_unit(
                &mut r,
                "ack_latency",
                "From a summary reaching the store to its commit, after which it is acknowledged",
                Unit::Seconds,
                Histogram::new(ACK_BUCKETS_S),
            ),
            db_pool_connections: plain(
                &mut r,
                "db_pool_connections",
                "Database connections open in the pool",
            ),
            db_pool_idle: plain(
                &mut r,
                "db_pool_idle_connections",
                "Database connections open and idle",
            ),
            db_pool_max: plain(
                &mut r,
                "db_pool_max_connections",
                "Most database connections the pool opens",
            ),
            db_pool_acquire: with_unit(
                &mut r,
                "db_pool_acquire",
                "Wait for a database connection, sampled once a second",
                Unit::Seconds,
                request_histogram(),
            ),
            upload_bytes: with_unit(
                &mut r,
                "upload",
                "Bytes of recordings uploaded completely and verified",
                Unit::Bytes,
                Counter::default(),
            ),
            uploads_completed: plain(
                &mut r,
                "uploads_completed",
                "Recordings uploaded completely and verified",
            ),
            uploads_failed: plain(
                &mut r,
                "uploads_failed",
                "Recordings uploaded whole that could not be stored (the station uploads again)",
            ),
            uploads_refused: plain(
                &mut r,
                "uploads_refused",
                "Uploads refused by the hub's limits",
            ),
            replays: plain(
                &mut r,
                "replays",
                "Replay requests of the console by outcome (started, refused, failed)",
            ),
            pain_mails: plain(
                &mut r,
                "pain_mails",
                "Pain-alert mails by outcome (sent, failed)",
            ),
            http_requests: plain(
                &mut r,
                "http_requests",
                "Console and operator HTTP requests answered, by route group and status class",
            ),
            http_request_duration: with_unit(
                &mut r,
                "http_request_duration",
                "Time to answer a console or operator request (to its first byte), by route group",
                Unit::Seconds,
                Family::new_with_constructor(request_histogram),
            ),
            process_start_time: with_unit(
                &mut r,
                "process_start_time",
                "When the hub started, since the Unix epoch",
                Unit::Seconds,
                started_now(),
            ),
            registry: Registry::default(),
        };
        register_build_info(&mut r);
        t.registry = r;
        t
    }

    /// The stations connected now and the connections not admitted yet.
    pub fn set_station_connections(&self, admitted: usize, unauthenticated: usize) {
        self.station_connections.set(gauge(admitted));
        self.station_connections_unauthenticated
            .set(gauge(unauthenticated));
    }

    /// A station's connection was admitted.
    pub fn station_admitted(&self) {
        self.station_admitted.inc();
    }

    /// A station's connection was refused admission.
    pub fn admission_refused(&self, why: AdmissionRefusal) {
        self.station_refused(why.as_str());
    }

    /// A station was refused or its connection ended for `reason`: one of netlink's closed set
    /// of limit kinds (`summary_rate`, `upload_pace`, …), the hub's (`sessions_per_day`) or
    /// the link's (`protocol_error`, `connection_cap`). Refusals of an upload also count in
    /// `uploads_refused`.
    pub fn station_refused(&self, reason: &'static str) {
        self.station_refused_by(reason, 1);
    }

    /// `count` refusals for `reason` at once (the link's summary of refusals before
    /// admission).
    pub fn station_refused_by(&self, reason: &'static str, count: u64) {
        self.station_refused
            .get_or_create(&[("reason", reason)])
            .inc_by(count);
        if reason.starts_with("upload") {
            self.uploads_refused.inc_by(count);
        }
    }

    /// A summary was stored (`duplicate`: it already was), `latency_s` after it reached the
    /// store.
    pub fn summary_stored(&self, duplicate: bool, latency_s: f64) {
        if duplicate {
            self.summaries_duplicate.inc();
        } else {
            self.summaries_ingested.inc();
        }
        self.summary_ack.observe(latency_s);
    }

    /// A connection of the database pool was acquired after waiting `wait_s`.
    pub fn pool_acquired(&self, wait_s: f64) {
        self.db_pool_acquire.observe(wait_s);
    }

    /// A recording of `size_bytes` was uploaded whole and stored.
    pub fn upload_completed(&self, size_bytes: u64) {
        self.uploads_completed.inc();
        self.upload_bytes.inc_by(size_bytes);
    }

    /// A recording uploaded whole could not be stored.
    pub fn upload_failed(&self) {
        self.uploads_failed.inc();
    }

    /// A replay request ended as `outcome`.
    pub fn replay(&self, outcome: ReplayOutcome) {
        self.replays
            .get_or_create(&[("outcome", outcome.as_str())])
            .inc();
    }

    /// A pain-alert mail was sent (`sent`) or failed.
    pub fn pain_mail(&self, sent: bool) {
        let outcome = if sent { "sent" } else { "failed" };
        self.pain_mails.get_or_create(&[("outcome", outcome)]).inc();
    }

    /// A request of route group `group` was answered with `status` after `duration_s`.
    pub fn http_request(&self, group: &'static str, status: u16, duration_s: f64) {
        self.http_requests
            .get_or_create(&[("route", group), ("status", status_class(status))])
            .inc();
        self.http_request_duration
            .get_or_create(&[("route", group)])
            .observe(duration_s);
    }

    /// The process start time, s since the Unix epoch.
    pub fn process_start_time_s(&self) -> f64 {
        self.process_start_time.get()
    }

    /// Every metric in the Prometheus text format, the pool's gauges read from `db` now.
    pub fn encode(&self, db: Option<&Db>) -> String {
        if let Some(db) = db {
            let pool = db.pool();
            self.db_pool_connections.set(i64::from(pool.size()));
            self.db_pool_idle.set(gauge(pool.num_idle()));
            self.db_pool_max
                .set(i64::from(pool.options().get_max_connections()));
        }
        let mut text = String::with_capacity(8 * 1024);
        // Writing into a String cannot fail.
        let _ = prometheus_text::encode(&mut text, &self.registry);
        text
    }
}

/// How often [`sample_pool`] measures the wait for a database connection.
pub const POOL_SAMPLE_EVERY: std::time::Duration = std::time::Duration::from_secs(1);

/// Measures, every [`POOL_SAMPLE_EVERY`], how long a connection of `db`'s pool takes to get
/// (returned at once): the wait the hub's queries meet, without timing each of them. A pool
/// that gives none within a second, or cannot connect, is counted as a 10 s wait (the last
/// bucket), so the slow fraction's alert fires. Runs until aborted.
pub async fn sample_pool(db: Db, telemetry: std::sync::Arc<Telemetry>) {
    let mut every = tokio::time::interval(POOL_SAMPLE_EVERY);
    every.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        every.tick().await;
        let started = std::time::Instant::now();
        let acquired = tokio::time::timeout(POOL_SAMPLE_EVERY, db.pool().acquire()).await;
        match acquired {
            Ok(Ok(connection)) => {
                telemetry.pool_acquired(started.elapsed().as_secs_f64());
                drop(connection);
            }
            // A pool that is closed or cannot connect waits as long as it is allowed to.
            _ => telemetry.pool_acquired(started.elapsed().as_secs_f64().max(10.0)),
        }
    }
}

/// A gauge holding the system clock's time now, s since the Unix epoch.
fn started_now() -> Gauge<f64, AtomicU64> {
    let gauge = Gauge::default();
    let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH);
    gauge.set(now.map_or(0.0, |d| d.as_secs_f64()));
    gauge
}

/// `build_info{version="…"} 1`.
fn register_build_info(registry: &mut Registry) {
    let info: Family<Label, Gauge> = plain(registry, "build_info", "The hub's version (value 1)");
    info.get_or_create(&[("version", env!("CARGO_PKG_VERSION"))])
        .set(1);
}

/// A new metric of its kind's default, registered in `registry` as `name` with `help`.
fn plain<M: Metric + Clone + Default>(registry: &mut Registry, name: &str, help: &str) -> M {
    let metric = M::default();
    registry.register(name, help, metric.clone());
    metric
}

/// `metric`, registered in `registry` as `name` in `unit` with `help`.
fn with_unit<M: Metric + Clone>(
    registry: &mut Registry,
    name: &str,
    help: &str,
    unit: Unit,
    metric: M,
) -> M {
    registry.register_with_unit(name, help, unit, metric.clone());
    metric
}

fn gauge(n: usize) -> i64 {
    i64::try_from(n).unwrap_or(i64::MAX)
}

/// `2xx` … `5xx` (`other` outside 100–599).
fn status_class(status: u16) -> &'static str {
    match status / 100 {
        1 => "1xx",
        2 => "2xx",
        3 => "3xx",
        4 => "4xx",
        5 => "5xx",
        _ => "other",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The value of the sample `name` (with its labels as written), if present.
    fn sample(text: &str, name: &str) -> Option<f64> {
        text.lines()
            .find_map(|l| l.strip_prefix(name)?.strip_prefix(' ')?.parse().ok())
    }

    #[test]
    fn each_call_moves_its_own_metric_and_labels_stay_in_the_closed_set() {
        let t = Telemetry::new();
        t.station_admitted();
        t.admission_refused(AdmissionRefusal::Revoked);
        t.station_refused("upload_pace");
        t.station_refused_by("connection_cap", 5);
        t.summary_stored(false, 0.003);
        t.summary_stored(true, 0.001);
        t.upload_completed(1_000);
        t.pain_mail(false);
        t.replay(ReplayOutcome::Refused);
        t.http_request("patients", 404, 0.01);
        let text = t.encode(None);
        let p = "telerehab_hub_";
        assert_eq!(
            sample(&text, &format!("{p}station_admitted_total")),
            Some(1.0)
        );
        for (reason, n) in [
            ("revoked", 1.0),
            ("upload_pace", 1.0),
            ("connection_cap", 5.0),
        ] {
            let name = format!("{p}station_refused_total{{reason=\"{reason}\"}}");
            assert_eq!(sample(&text, &name), Some(n), "{name} in\n{text}");
        }
        assert_eq!(
            sample(&text, &format!("{p}uploads_refused_total")),
            Some(1.0)
        );
        assert_eq!(
            sample(&text, &format!("{p}summaries_ingested_total")),
            Some(1.0)
        );
        assert_eq!(
            sample(&text, &format!("{p}summaries_duplicate_total")),
            Some(1.0)
        );
        assert_eq!(
            sample(&text, &format!("{p}ack_latency_seconds_count")),
            Some(2.0)
        );
        assert_eq!(
            sample(
                &text,
                &format!("{p}ack_latency_seconds_bucket{{le=\"0.002\"}}")
            ),
            Some(1.0)
        );
        assert_eq!(
            sample(&text, &format!("{p}upload_bytes_total")),
            Some(1000.0)
        );
        let name = format!("{p}http_requests_total{{route=\"patients\",status=\"4xx\"}}");
        assert_eq!(sample(&text, &name), Some(1.0), "{text}");
        let name = format!("{p}pain_mails_total{{outcome=\"failed\"}}");
        assert_eq!(sample(&text, &name), Some(1.0));
        let build = format!("{p}build_info{{version=\"{}\"}}", env!("CARGO_PKG_VERSION"));
        assert_eq!(sample(&text, &build), Some(1.0));
        assert!(t.process_start_time_s() > 1.7e9);
    }

    #[test]
    fn status_classes_are_the_hundreds() {
        assert_eq!(status_class(200), "2xx");
        assert_eq!(status_class(503), "5xx");
        assert_eq!(status_class(99), "other");
    }
}
