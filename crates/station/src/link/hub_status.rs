//! Is the paired hub reachable, will it serve this station, and how far apart are the two
//! clocks? One short conversation (`telerehab doctor --hub`, the first-run window): `Hello` for
//! the session [`probe_session_id`], then at once `Bye`; the hub answers `Bye` with its clock
//! (`hub_unix_ms`, PROTOCOL.md) or `Error` `update_required` when this station is too old (or
//! it too old for the station).

use std::time::Duration;

use netlink::{
    Bye, CheckNews, ClientTls, Frame, FrameDecoder, Hello, PROTOCOL_VERSION, encode_to_vec,
};
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};

use crate::home::{Home, Pairing};

/// The exercise named in the check's `Hello` (a hub of this version then stores nothing); its
/// session id is [`probe_session_id`].
pub const PROBE_EXERCISE: &str = netlink::frame::CHECK_EXERCISE;

/// The session id of a station's checks: `doctor-check-` and a hash of the station id (session
/// ids are unique across a hub's stations), the same at every check, so that a hub older than
/// [`netlink::frame::CHECK_EXERCISE`] keeps one empty session per station for them.
pub fn probe_session_id(station_id: &str) -> String {
    // FNV-1a, 64 bits: stable across releases and platforms.
    let hash = station_id.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{PROBE_EXERCISE}-{hash:016x}")
}

/// What the hub said.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum HubStatus {
    /// It serves this station.
    Reachable {
        /// The hub's clock minus this station's, ms (midpoint of the exchange); `None` from
        /// a hub older than the `hub_unix_ms` field.
        clock_offset_ms: Option<i64>,
    },
    /// It refuses this station's link protocol: the message to show, in plain words, naming
    /// the update.
    UpdateRequired(String),
    /// No conversation: why (no route, TLS refused, no answer in time, …).
    Unreachable(String),
}

/// The patient's words for a hub's `update_required` answer: a hub of this version already
/// says "update required: …" in plain words; an older hub's message is wrapped so that it
/// names the update.
pub fn update_required_message(hub_message: &str) -> String {
    if hub_message.starts_with("update required") {
        hub_message.to_owned()
    } else {
        format!("update required: {hub_message} — install the newest telerehab package")
    }
}

/// Asks the paired hub (TLS with the station's certificate), waiting `timeout` at most, and
/// keeps in `home` the patient's news it answers with (a hub of protocol version 4): the
/// clinic's pain settings, the therapist's unseen messages and the current regimen.
/// Blocking: runs its own one-thread runtime (call it off any async runtime).
pub fn check_hub(home: &Home, pairing: &Pairing, timeout: Duration) -> HubStatus {
    let runtime = match tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
    {
        Ok(r) => r,
        Err(e) => return HubStatus::Unreachable(format!("cannot start the network runtime: {e}")),
    };
    let tls = home.client_tls(pairing);
    let mut news = CheckNews::default();
    let status = runtime.block_on(probe_keeping(
        &pairing.hub,
        Some(&tls),
        (&pairing.station_id, &pairing.patient_id),
        timeout,
        &mut news,
    ));
    keep_news(home, news);
    status
}

/// Keeps in `home` what a check brought: the pain settings, the messages not kept yet, and
/// a regimen that passes the station's safety bounds and differs from the kept one (a
/// refused one leaves the kept one in force, logged).
pub fn keep_news(home: &Home, news: CheckNews) {
    super::keep_care(Some(home), news.care);
    if !news.messages.is_empty() {
        let mut inbox = crate::messages::Inbox::load(&home.messages_path());
        if inbox.keep_received(news.messages) {
            tracing::info!("the hub's check brought a message");
        }
    }
    if let Some(r) = news.regimen {
        let kept = std::fs::read_to_string(home.regimen_path()).ok();
        if kept.as_deref() == Some(r.toml.as_str()) && home.regimen_prescriber() == r.prescribed_by
        {
            return;
        }
        let outcome = super::keep_regimen_from_hub(home, &r);
        tracing::info!(regimen = %r.id, "the hub's check brought a regimen: {outcome}");
    }
}

/// How long the check waits after its `Hello` for the hub's answer before it says `Bye`
/// itself: a hub of this version answers at once (after the patient's news); one older than
/// the check rule answers only the station's `Bye`.
pub const CARE_WAIT: Duration = Duration::from_millis(500);

/// The conversation with the hub at `address` (`host:port`), over TLS unless `tls` is `None`
/// (plaintext: loopback only, for tests), as `(station_id, patient_id)`.
pub async fn probe(
    address: &str,
    tls: Option<&ClientTls>,
    ids: (&str, &str),
    timeout: Duration,
) -> HubStatus {
    probe_keeping(address, tls, ids, timeout, &mut CheckNews::default()).await
}

/// [`probe`], gathering in `news` the patient's news the hub sends before its answer.
pub async fn probe_keeping(
    address: &str,
    tls: Option<&ClientTls>,
    (station_id, patient_id): (&str, &str),
    timeout: Duration,
    news: &mut CheckNews,
) -> HubStatus {
    let hello = Hello {
        protocol_version: PROTOCOL_VERSION,
        min_protocol_version: Some(netlink::frame::MIN_PROTOCOL_VERSION),
        wheel: None,
        station_id: station_id.to_owned(),
        patient_id: patient_id.to_owned(),
        session_id: probe_session_id(station_id),
        exercise: PROBE_EXERCISE.to_owned(),
        started_unix_ms: netlink::frame::unix_ms_now(),
        software_version: format!("telerehab {}", env!("CARGO_PKG_VERSION")),
    };
    let talk = async {
        let tcp = tokio::net::TcpStream::connect(address)
            .await
            .map_err(|e| format!("cannot connect: {e}"))?;
        match tls {
            None => Ok::<_, String>(converse(tcp, &hello, news).await),
            Some(tls) => {
                let (connector, name) = tls.connector().map_err(|e| e.to_string())?;
                let stream = connector
                    .connect(name, tcp)
                    .await
                    .map_err(|e| format!("TLS handshake failed: {e}"))?;
                Ok(converse(stream, &hello, news).await)
            }
        }
    };
    match tokio::time::timeout(timeout, talk).await {
        Err(_) => HubStatus::Unreachable(format!(
            "{address}: no answer within {} s",
            timeout.as_secs_f64()
        )),
        Ok(Err(e)) => HubStatus::Unreachable(format!("{address}: {e}")),
        Ok(Ok(status)) => status,
    }
}

/// Hello; the patient's news (gathered in `news`) until the hub's answer, or [`CARE_WAIT`];
/// then, if the hub has not answered, Bye and its answer.
async fn converse<S: AsyncRead + AsyncWrite + Unpin>(
    mut stream: S,
    hello: &Hello,
    news: &mut CheckNews,
) -> HubStatus {
    let bye = Frame::Bye(Bye {
        session_id: hello.session_id.clone(),
        reason: "station check".into(),
        final_seq: None,
        measures: Default::default(),
        hub_unix_ms: None,
        checkin: None,
        difficulty: None,
        exercises: Vec::new(),
    });
    let bytes = match encode_to_vec(&Frame::Hello(hello.clone())) {
        Ok(b) => b,
        Err(e) => return HubStatus::Unreachable(format!("cannot encode Hello: {e}")),
    };
    if let Err(e) = stream.write_all(&bytes).await {
        return HubStatus::Unreachable(format!("cannot send: {e}"));
    }
    let mut decoder = FrameDecoder::new();
    let mut buf = vec![0u8; 16 * 1024];
    // A hub of this version sends the news right after the Hello, then its Bye (an older
    // hub the Bye alone; one that refuses the Hello says so at once).
    let mut early = None;
    let _ = tokio::time::timeout(CARE_WAIT, async {
        loop {
            match decoder.next_frame() {
                Ok(Some(f @ (Frame::Care(_) | Frame::Message(_) | Frame::Regimen(_)))) => {
                    gather(news, f);
                    continue;
                }
                // A refusal or an end: the answer, read below.
                Ok(Some(f @ (Frame::Error(_) | Frame::Bye(_)))) => {
                    early = Some(f);
                    return;
                }
                Ok(Some(_)) => continue,
                Ok(None) => {}
                Err(_) => return,
            }
            match stream.read(&mut buf).await {
                Ok(0) | Err(_) => return,
                Ok(n) => decoder.extend(&buf[..n]),
            }
        }
    })
    .await;
    let sent_unix_ms = netlink::frame::unix_ms_now();
    if early.is_none()
        && let Err(e) = stream
            .write_all(&encode_to_vec(&bye).unwrap_or_default())
            .await
    {
        return HubStatus::Unreachable(format!("cannot send: {e}"));
    }
    loop {
        let next = match early.take() {
            Some(f) => Ok(Some(f)),
            None => decoder.next_frame(),
        };
        match next {
            Err(e) => return HubStatus::Unreachable(format!("unreadable answer: {e}")),
            Ok(Some(Frame::Bye(b))) => {
                let received_unix_ms = netlink::frame::unix_ms_now();
                let midpoint = (sent_unix_ms as i64 + received_unix_ms as i64) / 2;
                let clock_offset_ms = b.hub_unix_ms.map(|hub| hub as i64 - midpoint);
                return HubStatus::Reachable { clock_offset_ms };
            }
            Ok(Some(Frame::Error(e))) => {
                return if e.code.as_deref() == Some(netlink::frame::UPDATE_REQUIRED) {
                    HubStatus::UpdateRequired(update_required_message(&e.message))
                } else {
                    HubStatus::Unreachable(format!("the hub refused: {}", e.message))
                };
            }
            // News after the wait (a slow hub) is kept as well; an Ack is not what the check
            // waits for.
            Ok(Some(f)) => {
                gather(news, f);
                continue;
            }
            Ok(None) => {}
        }
        match stream.read(&mut buf).await {
            Ok(0) => return HubStatus::Unreachable("the hub closed the connection".into()),
            Ok(n) => decoder.extend(&buf[..n]),
            Err(e) => return HubStatus::Unreachable(format!("connection lost: {e}")),
        }
    }
}

/// Keeps `frame` in `news` if it is news (the pain settings, a message, the regimen).
fn gather(news: &mut CheckNews, frame: Frame) {
    match frame {
        Frame::Care(c) => news.care = Some(c),
        Frame::Message(m) => news.messages.push(m),
        Frame::Regimen(r) => news.regimen = Some(r),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use netlink::{TherapistConfig, TherapistServer};

    fn ask_hub_with_min_version(min_protocol_version: u16) -> HubStatus {
        ask_hub_and_list_its_store(min_protocol_version).0
    }

    /// Files anywhere under `dir`.
    fn files_under(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
        let mut out = Vec::new();
        for entry in std::fs::read_dir(dir).unwrap().map(Result::unwrap) {
            if entry.file_type().unwrap().is_dir() {
                out.extend(files_under(&entry.path()));
            } else {
                out.push(entry.path());
            }
        }
        out
    }

    /// The check's answer, and the files the hub's store holds after it.
    fn ask_hub_and_list_its_store(
        min_protocol_version: u16,
    ) -> (HubStatus, Vec<std::path::PathBuf>) {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let tmp = tempfile::tempdir().unwrap();
        runtime.block_on(async {
            let mut config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), tmp.path(), None);
            config.min_protocol_version = min_protocol_version;
            let (server, _events) = TherapistServer::bind(config).await.unwrap();
            let addr = server.local_addr().to_string();
            let status = probe(&addr, None, ("st-1", "p-1"), Duration::from_secs(10)).await;
            server.shutdown(Duration::from_secs(5)).await;
            (status, files_under(tmp.path()))
        })
    }

    #[test]
    fn a_check_leaves_no_session_at_the_hub() {
        let (status, stored) = ask_hub_and_list_its_store(netlink::frame::MIN_PROTOCOL_VERSION);
        assert!(matches!(status, HubStatus::Reachable { .. }), "{status:?}");
        assert_eq!(stored, Vec::<std::path::PathBuf>::new());
    }

    #[test]
    fn a_hub_serving_this_station_is_reachable_with_a_small_clock_difference() {
        let status = ask_hub_with_min_version(netlink::frame::MIN_PROTOCOL_VERSION);
        let HubStatus::Reachable {
            clock_offset_ms: Some(offset),
        } = status
        else {
            panic!("{status:?}");
        };
        // Same machine, same clock: only the rounding of the midpoint and scheduling apart.
        assert!(offset.abs() < 5_000, "{offset}");
    }

    #[test]
    fn a_hub_needing_a_newer_protocol_refuses_with_update_required_in_plain_words() {
        let status = ask_hub_with_min_version(PROTOCOL_VERSION + 1);
        let HubStatus::UpdateRequired(message) = status else {
            panic!("{status:?}");
        };
        assert_eq!(
            message,
            format!(
                "update required: this station speaks link protocol {PROTOCOL_VERSION}, the hub \
                 needs ≥ {} — install the newest telerehab package",
                PROTOCOL_VERSION + 1
            )
        );
    }

    #[test]
    fn no_hub_listening_is_unreachable_with_the_address_named() {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        drop(listener);
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let status = runtime.block_on(probe(&addr, None, ("st-1", "p-1"), Duration::from_secs(5)));
        let HubStatus::Unreachable(why) = status else {
            panic!("{status:?}");
        };
        assert!(why.starts_with(&addr), "{why}");
    }

    #[test]
    fn an_older_hubs_update_message_is_worded_to_name_the_update() {
        let old = "the station speaks protocol versions 1..=1, the hub 2..=2";
        assert!(update_required_message(old).ends_with("install the newest telerehab package"));
        let new = "update required: this station speaks link protocol 1, the hub needs ≥ 2 — x";
        assert_eq!(update_required_message(new), new);
    }

    /// `telerehab run` against a hub that needs a newer protocol, as `run` does it: the
    /// session runs whole, its summaries wait in the home's queue, and the error names the
    /// update.
    #[test]
    fn a_session_refused_by_a_newer_hub_runs_queues_its_summaries_and_names_the_update() {
        use session::{self, Controls, SessionOptions};
        let tmp = tempfile::tempdir().unwrap();
        let hub_runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .unwrap();
        let mut hub_config = TherapistConfig::new(
            "127.0.0.1:0".parse().unwrap(),
            tmp.path().join("store"),
            None,
        );
        hub_config.min_protocol_version = PROTOCOL_VERSION + 1;
        let (server, _events) = hub_runtime
            .block_on(TherapistServer::bind(hub_config))
            .unwrap();
        let mut cfg = session::config::StationConfig::default();
        cfg.session.duration_s = 2.0;
        cfg.therapist.address = server.local_addr().to_string();
        cfg.validate().unwrap();
        let home = Home::at(tmp.path().join("home"));
        let clock = clock::Clock::real();
        let link = crate::link::Link::start(&cfg, &clock, Some(&home)).unwrap();
        let opts = SessionOptions {
            clock,
            ..SessionOptions::simulated(cfg)
        };
        let report = session::run(&opts, &Controls::default(), &mut &link).unwrap();
        let linked = link
            .finish(
                report.summaries,
                &Default::default(),
                None,
                &report.end_reason(),
            )
            .unwrap();
        hub_runtime.block_on(server.shutdown(Duration::from_secs(5)));
        assert!(
            report.summaries > 0 && !report.haptic.stopped_early,
            "{report:?}"
        );
        assert_eq!((linked.acked, linked.queued), (0, Some(report.summaries)));
        let error = linked.last_error.unwrap_or_default();
        assert!(
            error.starts_with(&format!(
                "update required: this station speaks link protocol {PROTOCOL_VERSION}, the hub \
                 needs ≥ {}",
                PROTOCOL_VERSION + 1
            )) && error.ends_with("install the newest telerehab package"),
            "{error}"
        );
    }

    #[test]
    fn each_station_checks_in_its_own_valid_session_id() {
        let a = probe_session_id("st-1");
        assert_eq!(a, probe_session_id("st-1"));
        assert_ne!(a, probe_session_id("st-2"));
        assert!(netlink::frame::check_id("session_id", &a).is_ok(), "{a}");
        assert!(netlink::frame::check_id("session_id", &probe_session_id(&"x".repeat(64))).is_ok());
    }
}
