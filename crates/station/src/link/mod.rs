//! The station side of the therapist link: a small tokio runtime owning the netlink
//! store-and-forward task. The recorder thread hands it summaries without ever waiting; with a
//! home directory each summary is first appended to the on-disk [`queue`].

pub mod hub_status;
pub mod queue;
pub mod uploads;
pub mod wheel;

use crate::home::Home;
use anyhow::Context;
use clock::Clock;
use netlink::{
    ClientTls, Hello, Identity, PROTOCOL_VERSION, StationLink, StationLinkConfig, Summary,
    SummarySender,
};
use queue::QueueFile;
use report::terminal::LinkReport;
use session::config::StationConfig;
use session::faults::HubSwitch;
use session::{LiveSummary, SessionObserver};
use std::collections::BTreeMap;
use std::sync::Mutex;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// How long the end of a session waits for the therapist to acknowledge what is pending.
const FINISH_TIMEOUT: Duration = Duration::from_secs(3);

/// The therapist link of one session (absent when no therapist is configured).
pub struct Link {
    inner: Option<Inner>,
}

struct Inner {
    runtime: tokio::runtime::Runtime,
    sender: SummarySender,
    link: StationLink,
    session_id: String,
    exercise: String,
    address: String,
    /// The session's on-disk queue (with a home directory).
    queue: Option<Mutex<QueueFile>>,
    /// Where a regimen the hub prescribes is kept for the next session.
    home: Option<Home>,
    /// The session's Hello and TLS, for the recording's upload.
    hello: Hello,
    tls: Option<ClientTls>,
    /// The relay an injected hub-down cuts, told the session time of each summary.
    hub_switch: Option<HubSwitch>,
    /// From the Hello's `started_unix_ms` to the session's time 0, ns: the link starts (and
    /// waits for the prescription) before the exercise does, and a summary's `t_s` counts
    /// from the Hello's start, as the hub reads it.
    t0_after_hello_ns: u64,
    /// The therapist's messages kept in the home, the one the start card shows, and the
    /// "seen" said on this link (confirmed when the hub answers its `Bye`).
    messages: Mutex<Messages>,
}

/// The link's part in the therapist's messages.
#[derive(Default)]
struct Messages {
    inbox: Option<crate::messages::Inbox>,
    showing: Option<String>,
    said: Vec<netlink::MessageSeen>,
}

impl Inner {
    /// Keeps the messages the link received since the last look (saved if any was new).
    fn keep_new_messages(&mut self) {
        let m = self
            .messages
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let Some(inbox) = m.inbox.as_mut() else {
            return;
        };
        let mut new = false;
        while let Some(message) = self.link.try_recv_message() {
            new |= inbox.add(message);
        }
        if new {
            m.save();
        }
    }
}

/// Keeps in `home` the clinic's pain settings the hub sent, if it sent any.
pub(crate) fn keep_care(home: Option<&Home>, care: Option<netlink::Care>) {
    let (Some(home), Some(care)) = (home, care) else {
        return;
    };
    let settings = crate::checkin::care::CareSettings::from(&care);
    match settings.save(&home.care_path()) {
        Ok(()) => tracing::info!(
            threshold = settings.pain_threshold_0_10,
            "the clinic's pain settings kept"
        ),
        Err(e) => tracing::warn!("the clinic's pain settings are not kept: {e:#}"),
    }
}

impl Messages {
    fn save(&self) {
        if let Some(Err(e)) = self.inbox.as_ref().map(crate::messages::Inbox::save) {
            tracing::warn!("the therapist's messages are not kept: {e:#}");
        }
    }
}

/// How long [`Link::await_prescription`] waits for the hub's push once connected.
pub const PUSH_GRACE: Duration = Duration::from_secs(1);

/// A session identifier from the start time to the millisecond, the seed and 32 random bits:
/// `2026-11-21T09-30-00.123Z-s7-9f86d081`, unique even for two stations started at once.
pub fn session_id(start: SystemTime, seed: u64, random: u32) -> String {
    let stamp = humantime::format_rfc3339_millis(start)
        .to_string()
        .replace(':', "-");
    format!("{stamp}-s{seed}-{random:08x}")
}

/// The first frame of the link: who this station, patient and session are, started now on
/// `clock`, and the patient's wheel when known.
fn hello(cfg: &StationConfig, clock: &Clock, wheel: Option<netlink::WheelInfo>) -> Hello {
    let start_unix_ns = clock.unix_ns();
    Hello {
        protocol_version: PROTOCOL_VERSION,
        min_protocol_version: None,
        station_id: cfg.session.station_id.clone(),
        patient_id: cfg.session.patient_id.clone(),
        session_id: session_id(
            UNIX_EPOCH + Duration::from_nanos(start_unix_ns),
            cfg.session.seed,
            rand::random(),
        ),
        exercise: cfg.session.exercise.clone(),
        started_unix_ms: start_unix_ns / 1_000_000,
        software_version: concat!("telerehab ", env!("CARGO_PKG_VERSION")).into(),
        wheel,
    }
}

impl Link {
    /// Start the link if the configuration names a therapist. Plaintext is refused to
    /// anything but loopback; `therapist.ca_pem` enables TLS. The session's start time (its
    /// identifier at the hub) is read on `clock`.
    ///
    /// With `home`, every summary is queued on disk first, and sessions an earlier run left
    /// undelivered are sent in the background.
    pub fn start(cfg: &StationConfig, clock: &Clock, home: Option<&Home>) -> anyhow::Result<Self> {
        Self::start_with_wheel(cfg, clock, home, None)
    }

    /// [`Link::start`], telling the hub the patient's `wheel` in every `Hello` (see
    /// [`wheel::for_hub`]).
    pub fn start_with_wheel(
        cfg: &StationConfig,
        clock: &Clock,
        home: Option<&Home>,
        wheel: Option<netlink::WheelInfo>,
    ) -> anyhow::Result<Self> {
        let t = &cfg.therapist;
        if t.address.is_empty() {
            return Ok(Self { inner: None });
        }
        // Resolved by the link on each connection attempt: a hub name that does not resolve
        // (home internet down) never blocks or ends the exercise.
        let addr = t.address.as_str();
        let host = t
            .address
            .rsplit_once(':')
            .map(|(h, _)| h)
            .unwrap_or(&t.address);
        let tls = t.ca_pem.as_ref().map(|ca| ClientTls {
            ca_pem_path: ca.clone(),
            server_name: t
                .server_name
                .clone()
                .unwrap_or_else(|| host.trim_matches(['[', ']']).to_string()),
            identity: t
                .cert_pem
                .clone()
                .zip(t.key_pem.clone())
                .map(|(cert, key)| Identity {
                    cert_pem_path: cert,
                    key_pem_path: key,
                }),
        });
        let hello = hello(cfg, clock, wheel);
        let session_id = hello.session_id.clone();
        let mut config = StationLinkConfig::new(addr, tls.clone(), hello.clone());
        config.validate().context("therapist link")?;
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .thread_name("netlink")
            .enable_all()
            .build()
            .context("cannot start the network runtime")?;
        // An injected hub-down (a simulated session's fault) puts a relay between the link and
        // its hub, checked above as the hub itself.
        let hub_switch = HubSwitch::start(runtime.handle(), addr, &cfg.faults)
            .context("the relay of the injected hub-down")?;
        if let Some(switch) = &hub_switch {
            config.addr = switch.address().into();
        }
        let queue = match home {
            Some(home) => {
                let dir = home.queue_dir();
                // Listed before this session's own queue file exists.
                let earlier = queue::pending(&dir)?;
                spawn_delivery(&runtime, earlier, &dir, addr, tls.clone());
                Some(Mutex::new(QueueFile::create(&dir, &config.hello)?))
            }
            None => None,
        };
        let (sender, link) =
            StationLink::spawn(runtime.handle(), config).context("therapist link")?;
        let mut messages = Messages {
            inbox: home.map(|h| crate::messages::Inbox::load(&h.messages_path())),
            ..Messages::default()
        };
        // Shown before but not confirmed by a hub: said again on this link.
        for seen in messages
            .inbox
            .as_ref()
            .map(|i| i.unconfirmed())
            .unwrap_or_default()
        {
            link.report_seen(seen.clone());
            messages.said.push(seen);
        }
        tracing::info!(therapist = %t.address, tls = t.ca_pem.is_some(), session = %session_id, "therapist link started");
        Ok(Self {
            inner: Some(Inner {
                runtime,
                sender,
                link,
                session_id,
                exercise: cfg.session.exercise.clone(),
                address: t.address.clone(),
                queue,
                home: home.cloned(),
                hello,
                tls,
                hub_switch,
                t0_after_hello_ns: 0,
                messages: Mutex::new(messages),
            }),
        })
    }

    /// Waits, before the session starts, for the regimen the hub pushes when the link
    /// connects (it sends the patient's current one right after the `Hello`): the newest one
    /// received, or `None` once the link has been connected for [`PUSH_GRACE`] without one,
    /// or after `within` (the hub unreachable). Without a link, `None` at once. Not validated
    /// here: the caller validates it as any prescription.
    pub fn await_prescription(&mut self, within: Duration) -> Option<netlink::Regimen> {
        let inner = self.inner.as_mut()?;
        let start = std::time::Instant::now();
        let mut connected_at = None;
        let mut newest = None;
        while start.elapsed() < within {
            while let Some(r) = inner.link.try_recv_regimen() {
                newest = Some(r);
            }
            if newest.is_some() {
                // A moment for a second push (the hub saving a newer one just now).
                std::thread::sleep(Duration::from_millis(20));
                while let Some(r) = inner.link.try_recv_regimen() {
                    newest = Some(r);
                }
                return newest;
            }
            if inner.link.stats().connected {
                let at = *connected_at.get_or_insert_with(std::time::Instant::now);
                if at.elapsed() >= PUSH_GRACE {
                    return None;
                }
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        None
    }

    /// The therapist's message for this session's start card: the newest not yet shown of
    /// those the hub has sent (now, or before and kept in the home, so it shows when the hub
    /// is unreachable too). `None` without a link or a message.
    pub fn message_for_start(&mut self) -> Option<String> {
        let inner = self.inner.as_mut()?;
        inner.keep_new_messages();
        let m = inner
            .messages
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let (id, text) = m
            .inbox
            .as_ref()?
            .to_show()
            .map(|k| (k.id.clone(), k.text.clone()))?;
        tracing::info!(message = %id, "the start card shows the therapist's message");
        m.showing = Some(id);
        Some(text)
    }

    /// The start card's message was drawn on the screen at `at_unix_ms`: kept as seen in the
    /// home and said to the hub (now if connected, and on every later link until a hub
    /// confirms it).
    pub fn message_shown(&self, at_unix_ms: u64) {
        let Some(inner) = &self.inner else { return };
        let mut m = inner
            .messages
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let Some(id) = m.showing.take() else { return };
        let Some(seen) = m.inbox.as_mut().and_then(|i| i.mark_seen(&id, at_unix_ms)) else {
            return;
        };
        m.save();
        tracing::info!(message = %id, at_unix_ms, "the therapist's message was shown");
        inner.link.report_seen(seen.clone());
        m.said.push(seen);
    }

    /// The exercise the summaries name (after a prescription received at the start changed
    /// the session's).
    pub fn set_exercise(&mut self, exercise: &str) {
        if let Some(inner) = &mut self.inner {
            inner.exercise = exercise.to_owned();
        }
    }

    /// The session's time 0 is now on `clock`: its summaries' times count from the Hello's
    /// start, so a summary at session time t is stamped t plus the wait since the Hello (the
    /// console's end-to-end delay and charts stay true).
    pub fn session_starts_now(&mut self, clock: &Clock) {
        if let Some(inner) = &mut self.inner {
            let hello_ns = inner.hello.started_unix_ms.saturating_mul(1_000_000);
            inner.t0_after_hello_ns = clock.unix_ns().saturating_sub(hello_ns);
        }
    }

    /// Hand one summary to the link. Never waits: a full queue is counted in the link's
    /// `dropped` figure and reported at the end.
    pub fn send(&self, s: &LiveSummary) {
        let Some(inner) = &self.inner else { return };
        keep_care(inner.home.as_ref(), inner.link.take_care());
        let r = &s.record;
        if let Some(switch) = &inner.hub_switch {
            switch.at(r.t_ns);
        }
        let summary = Summary {
            session_id: inner.session_id.clone(),
            seq: s.seq,
            t_s: r.t_ns.saturating_add(inner.t0_after_hello_ns) as f64 * 1e-9,
            exercise: inner.exercise.clone(),
            speed_m_s: r.vehicle.map_or(0.0, |v| v.ux_m_s),
            lateral_m: r.vehicle.map_or(0.0, |v| v.lateral_m),
            rms_lateral_m: r.score.rms_lateral_m,
            max_lateral_m: r.score.max_lateral_m,
            pct_in_lane: r.score.pct_in_lane,
            max_abs_torque_nm: s.max_abs_torque_nm,
            loop_p99_us: s.loop_p99_us,
            ticks: r.tick + 1,
            dropped_records: r.timing.dropped_records,
            extra: s.extra.clone(),
        };
        if let Some(q) = &inner.queue {
            q.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .push(&summary);
        }
        // Counted by the link (LinkStats::dropped/rejected) and reported at the end; logged
        // here because a rejected summary is a bug worth seeing at once.
        if let Err(e) = inner.sender.send(summary) {
            tracing::warn!(seq = s.seq, "summary not queued for the therapist: {e}");
        }
    }

    /// The patient's end-screen answers, for the session's `Bye` (with a home, queued first
    /// like the measures, so they reach the hub however the link fares).
    pub fn set_checkin(&mut self, checkin: &netlink::CheckIn) {
        let Some(inner) = self.inner.as_mut() else {
            return;
        };
        if let Some(q) = &inner.queue {
            q.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .set_checkin(checkin);
        }
        inner.link.set_checkin(checkin.clone());
    }

    /// The difficulty the session ran at and why, for the session's `Bye` (with a home,
    /// queued first like the check-in).
    pub fn set_difficulty(&mut self, difficulty: &netlink::DifficultyChange) {
        let Some(inner) = self.inner.as_mut() else {
            return;
        };
        if let Some(q) = &inner.queue {
            q.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .set_difficulty(difficulty);
        }
        inner.link.set_difficulty(difficulty.clone());
    }

    /// Each exercise's own results, for the session's `Bye` (with a home, queued first like
    /// the measures); the standard assessment's parts tagged with `assessment`, the one the
    /// session ran first.
    pub fn set_exercises(
        &mut self,
        exercises: &[record::ExerciseResult],
        assessment: Option<netlink::AssessmentTag>,
    ) {
        let Some(inner) = self.inner.as_mut() else {
            return;
        };
        let exercises: Vec<netlink::ExerciseResult> = exercises
            .iter()
            .map(|e| netlink::ExerciseResult {
                assessment: assessment
                    .filter(|_| exercises::assessment::is_assessment_name(&e.kind)),
                ..exercise_for_the_hub(e)
            })
            .collect();
        if let Some(q) = &inner.queue {
            q.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .set_exercises(&exercises);
        }
        inner.link.set_exercises(exercises);
    }

    /// End the link: send Bye, wait a short while for the last acknowledgements, and report
    /// honestly what was not delivered.
    ///
    /// Why the session ended (`end_reason`, see `SessionReport::end_reason`) and its movement
    /// `measures` (name → value) go in the Bye; with a home they are queued first, so they reach the hub with the summaries however the session ends.
    /// With a home, `recording` (the session's MCAP file, if one was written) is queued for
    /// upload and sent for up to [`UPLOAD_WITHIN`]; the rest resumes later.
    pub fn finish(
        self,
        produced: u64,
        measures: &BTreeMap<String, f64>,
        recording: Option<&std::path::Path>,
        end_reason: &str,
    ) -> Option<LinkReport> {
        let mut inner = self.inner?;
        let mut regimens = inner.link.take_regimens();
        // Messages that arrived too late for this session's start card (or in a session
        // without a window) are kept for the next one.
        inner.keep_new_messages();
        // And those arriving while the link finishes (after its Bye), read once it has.
        let mut late_messages = inner.link.take_messages();
        let measures = within_bye_limit(measures);
        if let Some(q) = &inner.queue {
            let mut q = q.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
            q.set_measures(&measures);
            q.set_end_reason(end_reason);
        }
        keep_care(inner.home.as_ref(), inner.link.take_care());
        let stats = inner.runtime.block_on(inner.link.finish_with_measures(
            end_reason,
            measures,
            FINISH_TIMEOUT,
        ));
        let (upload, pushed) = match (&inner.home, recording) {
            (Some(home), Some(path)) => {
                let (said, pushed) = upload_now(
                    &inner.runtime,
                    (&inner.address, inner.tls.as_ref(), &inner.hello),
                    home,
                    path,
                );
                (Some(said), pushed)
            }
            _ => (None, netlink::upload::Pushed::default()),
        };
        keep_care(inner.home.as_ref(), pushed.care.clone());
        inner.runtime.shutdown_timeout(Duration::from_millis(200));
        // A regimen pushed on the upload's connection is newer than the live link's.
        let regimen = keep_prescribed_regimen(&mut regimens, pushed.regimen, inner.home.as_ref());
        let messages = inner
            .messages
            .into_inner()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(mut inbox) = messages.inbox {
            // Messages pushed late or on the upload's connection are kept as the live link's:
            // unseen, for the next start card.
            let mut late = Vec::new();
            while let Ok(m) = late_messages.try_recv() {
                late.push(m);
            }
            inbox.keep_received(late.into_iter().chain(pushed.messages));
            if stats.bye_acknowledged {
                // The hub handled every frame before its Bye, the "seen" among them.
                inbox.confirm(&messages.said);
                if let Err(e) = inbox.save() {
                    tracing::warn!("the therapist's messages are not kept: {e:#}");
                }
            }
        }
        let mut queued = None;
        if let Some(q) = inner.queue {
            let q = q
                .into_inner()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if let Some(e) = &q.error {
                tracing::warn!("the on-disk summary queue stopped: {e}");
            }
            if stats.pending == 0 && stats.bye_acknowledged && q.error.is_none() {
                q.delivered();
            } else {
                queued = Some(produced.saturating_sub(stats.acked));
            }
        }
        Some(LinkReport {
            address: inner.address,
            produced,
            sent: stats.sent,
            acked: stats.acked,
            undelivered: produced.saturating_sub(stats.acked),
            queued,
            regimen,
            upload,
            // A hub that cannot serve this station's protocol says so once and for all: that
            // is what the patient (and their technician) must read.
            last_error: stats
                .update_required
                .map(|m| hub_status::update_required_message(&m))
                .or(stats.last_error),
        })
    }
}

/// How long the end of a session spends uploading its recording before leaving the rest for
/// the next run or `telerehab sync`.
pub const UPLOAD_WITHIN: Duration = Duration::from_secs(20);

/// Queues the session's recording and uploads what can be in [`UPLOAD_WITHIN`]: what
/// happened in words, and what the hub pushed on the way.
fn upload_now(
    runtime: &tokio::runtime::Runtime,
    (address, tls, hello): (&str, Option<&ClientTls>, &Hello),
    home: &Home,
    path: &std::path::Path,
) -> (String, netlink::upload::Pushed) {
    let dir = home.uploads_dir();
    if let Err(e) = uploads::enqueue(&dir, hello, path) {
        return (format!("not queued: {e:#}"), Default::default());
    }
    let report = runtime.block_on(uploads::upload_all(
        &dir,
        address,
        tls,
        uploads::UPLOAD_BYTES_PER_S,
        UPLOAD_WITHIN,
    ));
    (report.describe(), report.pushed)
}

/// The measures the clinic reads first (the caseload's trends, the console's progress and the
/// report's front), kept first when a session names more than a `Bye` may carry.
const FIRST_MEASURES: [&str; 26] = [
    "pct_in_lane",
    "rms_lateral_m",
    "dial_rms_error_deg",
    "wheel_rom_deg",
    "shoulder_elevation_rom_deg",
    "elbow_flexion_rom_deg",
    "sparc_median",
    "assist_level_mean",
    "active_s",
    "session_s",
    "patient_work_pct",
    "max_abs_torque_nm",
    "cone_hits",
    "movements",
    "speed_metric_median",
    "speed_peaks_median",
    "movement_time_s_median",
    "reaction_time_s_median",
    "anticipation_pct",
    "initial_direction_error_deg_mean",
    "path_length_ratio_median",
    "movements_per_min",
    "reversals_per_min",
    "ldlj_median",
    "discrete_movements",
    "active_pct",
];

/// At most [`netlink::frame::MAX_EXTRA_ENTRIES`] of a session's measures, as a `Bye` may carry
/// (a hub refuses more): the clinic's first measures ([`FIRST_MEASURES`]), then the others in
/// name order; what is left out is logged by name (the recording keeps every measure).
fn within_bye_limit(measures: &BTreeMap<String, f64>) -> BTreeMap<String, f64> {
    let max = netlink::frame::MAX_EXTRA_ENTRIES;
    if measures.len() <= max {
        return measures.clone();
    }
    let first = FIRST_MEASURES
        .iter()
        .filter_map(|k| measures.get_key_value(*k));
    let rest = measures
        .iter()
        .filter(|(k, _)| !FIRST_MEASURES.contains(&k.as_str()));
    let kept: BTreeMap<String, f64> = first
        .chain(rest)
        .take(max)
        .map(|(k, v)| (k.clone(), *v))
        .collect();
    let left: Vec<&str> = measures
        .keys()
        .filter(|k| !kept.contains_key(*k))
        .map(String::as_str)
        .collect();
    tracing::warn!(
        "the session named {} measures, a Bye carries {max}: left out of the hub's copy (the recording keeps them): {}",
        measures.len(),
        left.join(", ")
    );
    kept
}

/// The newest regimen the hub sent during the session (`newer`: one it sent after, on the
/// recording's upload), validated against the station's safety
/// bounds and kept in the home for the next session (never applied mid-session). What
/// happened, for the report.
fn keep_prescribed_regimen(
    regimens: &mut tokio::sync::mpsc::Receiver<netlink::Regimen>,
    newer: Option<netlink::Regimen>,
    home: Option<&Home>,
) -> Option<String> {
    let mut newest = None;
    while let Ok(r) = regimens.try_recv() {
        newest = Some(r);
    }
    let r = newer.or(newest)?;
    let Some(home) = home else {
        return Some(format!(
            "{} received; no home directory to keep it in",
            r.id
        ));
    };
    Some(keep_regimen_from_hub(home, &r))
}

/// Validates `r` against the station's safety bounds and keeps it in `home` for the next
/// sessions (a refused one leaves the kept one in force). What happened, in words for the
/// report and the log.
pub(crate) fn keep_regimen_from_hub(home: &Home, r: &netlink::Regimen) -> String {
    if let Err(e) = regimen::Regimen::from_toml(&r.toml, &r.id) {
        tracing::warn!("regimen {} from the hub refused: {e}", r.id);
        return format!("{} refused: {e}", r.id);
    }
    match home.keep_regimen(r) {
        Ok(()) => format!("{} kept for the next session", r.id),
        Err(e) => format!("{} not kept: {e:#}", r.id),
    }
}

/// Delivers, in the background on the link's runtime, the sessions an earlier run left in the
/// queue (it ends with the runtime; what is not delivered stays for the next run or `sync`).
fn spawn_delivery(
    runtime: &tokio::runtime::Runtime,
    earlier: Vec<queue::Queued>,
    dir: &std::path::Path,
    address: &str,
    tls: Option<ClientTls>,
) {
    if earlier.is_empty() {
        return;
    }
    let (dir, address) = (dir.to_owned(), address.to_owned());
    runtime.spawn(async move {
        let timeout = Duration::from_secs(30);
        match queue::deliver_sessions(earlier, &dir, &address, tls, timeout).await {
            Ok(r) if r.sessions > 0 => tracing::info!(
                sessions = r.sessions,
                delivered = r.delivered,
                remaining = r.remaining,
                "queued sessions from earlier runs"
            ),
            Ok(_) => {}
            Err(e) => tracing::warn!("queued sessions not delivered: {e:#}"),
        }
    });
}

/// The link watches a session for its summaries.
impl SessionObserver for &Link {
    fn on_summary(&mut self, summary: &LiveSummary) {
        self.send(summary);
    }
}

/// An exercise's results as the `Bye` carries them.
pub fn exercise_for_the_hub(e: &record::ExerciseResult) -> netlink::ExerciseResult {
    netlink::ExerciseResult {
        index: e.index,
        kind: e.kind.clone(),
        name: e.name.clone(),
        prescribed_s: e.prescribed_s,
        active_s: e.active_s,
        scores: e.scores.clone(),
        assessment: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_session_naming_more_measures_than_a_bye_carries_keeps_the_clinics_first() {
        let mut measures: BTreeMap<String, f64> = (0..80)
            .map(|i| (format!("aaa_extra_{i:02}"), f64::from(i)))
            .collect();
        measures.insert("pct_in_lane".into(), 97.0);
        measures.insert("sparc_median".into(), -1.8);
        measures.insert("reaction_time_s_median".into(), 0.4);
        let kept = within_bye_limit(&measures);
        assert_eq!(kept.len(), netlink::frame::MAX_EXTRA_ENTRIES);
        assert_eq!(kept["pct_in_lane"], 97.0);
        assert_eq!(kept["sparc_median"], -1.8);
        assert_eq!(kept["reaction_time_s_median"], 0.4);
        assert!(kept.contains_key("aaa_extra_00") && !kept.contains_key("aaa_extra_79"));
        // A Bye with them is one the hub accepts.
        let bye = netlink::Bye {
            session_id: "s".into(),
            reason: "complete".into(),
            final_seq: None,
            measures: kept,
            hub_unix_ms: None,
            checkin: None,
            difficulty: None,
            exercises: Vec::new(),
        };
        assert!(netlink::Frame::Bye(bye).validate().is_ok());
        // Within the limit, every measure goes.
        measures.retain(|k, _| !k.starts_with("aaa_extra_"));
        assert_eq!(within_bye_limit(&measures), measures);
    }

    #[test]
    fn session_id_is_a_valid_wire_identifier() {
        let id = session_id(
            UNIX_EPOCH + Duration::from_millis(1_795_000_000_123),
            7,
            0x9f86_d081,
        );
        assert_eq!(id, "2026-11-18T11-06-40.123Z-s7-9f86d081");
        netlink::frame::check_id("session_id", &id).unwrap();
    }

    #[test]
    fn the_hello_is_stamped_on_the_sessions_clock() {
        let (clock, mock) = Clock::mock();
        mock.advance(Duration::from_millis(90_500));
        let mut cfg = StationConfig::default();
        cfg.session.seed = 3;
        let hello = hello(&cfg, &clock, None);
        assert!(
            hello.session_id.starts_with("2026-01-01T00-01-30.500Z-s3-"),
            "{}",
            hello.session_id
        );
        assert_ne!(
            hello.session_id,
            super::hello(&cfg, &clock, None).session_id,
            "random part"
        );
        assert_eq!(
            hello.started_unix_ms,
            clock::MOCK_UNIX_START_NS / 1_000_000 + 90_500
        );
    }
}
