//! What the hub may send a station at any time after the `Hello` — the therapist's `Message`s,
//! a `Regimen`, `Ack`s, an `Error` or a `Bye` — injected by a scripted hub (a real TCP listener
//! on loopback speaking the real codec) at arbitrary points of a recording's upload and of a
//! live session (after the Hello, between summaries, after the station's Bye): the upload
//! still completes with the bytes verified, the live link delivers every summary and ends in
//! order, and every message and the newest regimen reach the station. A property test over
//! interleavings with a fixed seed (a few seconds).
//!
//! The upload's window: chunks go ahead of the hub's answers, never more than
//! [`netlink::upload::UPLOAD_WINDOW_CHUNKS`], and an answer the station did not expect (the hub
//! holding less than it thought) makes it send again from there.
//!
//! Every wait is bounded by [`GUARD`] as a liveness guard; nothing asserts on speed.

use std::collections::BTreeSet;
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use base64::Engine;
use netlink::upload::{Pushed, UploadError, upload_recording_keeping};
use netlink::{
    Ack, Backoff, Bye, ErrorFrame, Frame, FrameDecoder, Hello, Message, PROTOCOL_VERSION, Regimen,
    StationLink, StationLinkConfig, Summary, encode_to_vec,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};

const GUARD: Duration = Duration::from_secs(20);

/// A frame the hub sends on its own, as the script says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Push {
    /// The therapist's message `m-N` (the same N twice is the same message sent again).
    Message(u8),
    /// Regimen `r-N`.
    Regimen(u8),
    /// A cumulative Ack of what is stored (as the hub sends after every summary and on
    /// connecting).
    Ack,
    /// A refusal: the connection ends (the station tries again).
    Error,
    /// The hub ends the connection (as at its shutdown).
    Bye,
}

impl Push {
    fn ends_connection(self) -> bool {
        matches!(self, Push::Error | Push::Bye)
    }
}

fn push() -> impl Strategy<Value = Push> {
    prop_oneof![
        4 => (0u8..6).prop_map(Push::Message),
        2 => (0u8..3).prop_map(Push::Regimen),
        2 => Just(Push::Ack),
        1 => Just(Push::Error),
        1 => Just(Push::Bye),
    ]
}

/// Pushes, each sent when the hub is at its `step` (the count of frames it has answered, over
/// every connection): sent in order, those of a step before the hub's own answer at that step.
fn script(steps: u16) -> impl Strategy<Value = Vec<(u16, Push)>> {
    prop::collection::vec((0..steps, push()), 0..14).prop_map(|mut v| {
        v.sort_by_key(|(at, _)| *at);
        v
    })
}

fn hello(session: &str) -> Hello {
    Hello {
        protocol_version: PROTOCOL_VERSION,
        station_id: "st-push".into(),
        patient_id: "p-push".into(),
        session_id: session.into(),
        exercise: "sine-road".into(),
        started_unix_ms: 1_795_253_400_000,
        software_version: "telerehab-test".into(),
        min_protocol_version: None,
        wheel: None,
    }
}

/// One accepted connection, read and written with the link's codec.
struct Conn {
    stream: TcpStream,
    decoder: FrameDecoder,
}

impl Conn {
    async fn accept(listener: &TcpListener) -> Conn {
        let (stream, _) = tokio::time::timeout(GUARD, listener.accept())
            .await
            .expect("the station connects")
            .unwrap();
        Conn {
            stream,
            decoder: FrameDecoder::new(),
        }
    }

    /// The next frame, `None` once the station closed.
    async fn read(&mut self) -> Option<Frame> {
        let mut buf = [0u8; 16 * 1024];
        loop {
            if let Some(f) = self
                .decoder
                .next_frame()
                .expect("the station speaks the codec")
            {
                return Some(f);
            }
            let n = tokio::time::timeout(GUARD, self.stream.read(&mut buf))
                .await
                .expect("the station says something or closes")
                .unwrap_or(0);
            if n == 0 {
                return None;
            }
            self.decoder.extend(&buf[..n]);
        }
    }

    async fn write(&mut self, frame: &Frame) {
        // A station gone after its answer is no failure of the hub's.
        let _ = self.stream.write_all(&encode_to_vec(frame).unwrap()).await;
    }

    /// Ends the connection in order: no more from the hub, and the station's last frames read
    /// (so nothing it had not read is cut off by a reset).
    async fn close(mut self) {
        let _ = self.stream.shutdown().await;
        while self.read().await.is_some() {}
    }
}

/// What the scripted hub did, for the assertions.
#[derive(Debug, Default)]
struct Sent {
    /// Ids of the messages sent, in order (with repeats).
    messages: Vec<String>,
    /// The last regimen sent.
    regimen: Option<String>,
    /// Connections ended by the script.
    ended: usize,
}

/// The script's remaining pushes and the hub's step.
struct Script {
    pushes: std::collections::VecDeque<(u16, Push)>,
    step: u16,
    sent: Arc<Mutex<Sent>>,
}

impl Script {
    fn new(pushes: Vec<(u16, Push)>) -> Self {
        Script {
            pushes: pushes.into(),
            step: 0,
            sent: Arc::default(),
        }
    }

    /// Sends the pushes due at the current step (an Ack of `acked` when there is one); true if
    /// one of them ended the connection (the rest wait for the next connection, same step).
    async fn send_due(&mut self, conn: &mut Conn, session: &str, acked: Option<u64>) -> bool {
        while self.pushes.front().is_some_and(|(at, _)| *at <= self.step) {
            let (_, p) = self.pushes.pop_front().unwrap();
            let frame = match p {
                Push::Message(n) => {
                    let id = format!("m-{n}");
                    self.sent.lock().unwrap().messages.push(id.clone());
                    Frame::Message(Message {
                        text: format!("Well done this week ({id}) - keep going!"),
                        id,
                        sent_unix_ms: 1_795_253_000_000 + u64::from(n),
                    })
                }
                Push::Regimen(n) => {
                    let id = format!("r-{n}");
                    self.sent.lock().unwrap().regimen = Some(id.clone());
                    Frame::Regimen(Regimen {
                        id,
                        toml: "[session]\nduration_s = 60\n".into(),
                        prescribed_by: Some("ana@clinic.example".into()),
                    })
                }
                Push::Ack => match acked {
                    Some(seq) => Frame::Ack(Ack {
                        session_id: session.into(),
                        seq,
                    }),
                    None => continue,
                },
                Push::Error => Frame::Error(ErrorFrame {
                    message: "scripted refusal".into(),
                    code: None,
                }),
                Push::Bye => Frame::Bye(hub_bye(session, acked)),
            };
            conn.write(&frame).await;
            if p.ends_connection() {
                self.sent.lock().unwrap().ended += 1;
                return true;
            }
        }
        false
    }
}

fn hub_bye(session: &str, final_seq: Option<u64>) -> Bye {
    Bye {
        session_id: session.into(),
        reason: "scripted".into(),
        final_seq,
        measures: Default::default(),
        hub_unix_ms: Some(1_795_253_400_000),
        checkin: None,
        difficulty: None,
        exercises: Vec::new(),
    }
}

fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap()
}

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(20_261_206),
        failure_persistence: None,
        ..Config::default()
    }
}

// ---- Uploads -------------------------------------------------------------------------------

/// 100 000 deterministic bytes: four chunks.
fn recording(dir: &Path) -> (std::path::PathBuf, Vec<u8>) {
    recording_of(dir, 100_000)
}

/// `len` deterministic bytes.
fn recording_of(dir: &Path, len: usize) -> (std::path::PathBuf, Vec<u8>) {
    let mut x: u64 = 0x2545_F491_4F6C_DD1D;
    let bytes: Vec<u8> = (0..len)
        .map(|_| {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (x >> 56) as u8
        })
        .collect();
    let path = dir.join("session.mcap");
    std::fs::write(&path, &bytes).unwrap();
    (path, bytes)
}

/// The scripted hub's side of one upload connection: the Hello and UploadStart, then an
/// `UploadAt` for each chunk (resuming from what it `held`), the script's pushes before each.
/// True once it answered `complete`.
async fn serve_upload(
    listener: &TcpListener,
    script: &mut Script,
    held: &mut Vec<u8>,
    whole: &[u8],
) -> bool {
    let mut conn = Conn::accept(listener).await;
    let Some(Frame::Hello(h)) = conn.read().await else {
        panic!("Hello first");
    };
    let session = h.session_id;
    let Some(Frame::UploadStart(start)) = conn.read().await else {
        panic!("UploadStart after the Hello");
    };
    assert_eq!(start.size_bytes, whole.len() as u64);
    loop {
        if script.send_due(&mut conn, &session, Some(0)).await {
            conn.close().await;
            return false;
        }
        let complete = held.as_slice() == whole;
        conn.write(&Frame::UploadAt(netlink::frame::UploadAt {
            session_id: session.clone(),
            offset: held.len() as u64,
            complete,
        }))
        .await;
        script.step += 1;
        if complete {
            conn.close().await;
            return true;
        }
        match conn.read().await {
            Some(Frame::UploadChunk(c)) => {
                assert_eq!(c.offset, held.len() as u64, "a chunk where the hub said");
                held.extend(
                    base64::engine::general_purpose::STANDARD
                        .decode(c.data)
                        .unwrap(),
                );
            }
            Some(other) => panic!("unexpected {} from an uploading station", other.kind()),
            None => return false,
        }
    }
}

/// Uploads under `pushes`, retrying after each connection the script ends: the outcome of
/// every attempt, what the station kept and what the hub holds and sent.
async fn upload_under(pushes: Vec<(u16, Push)>) -> (Vec<String>, Pushed, Vec<u8>, Vec<u8>, Sent) {
    let tmp = tempfile::tempdir().unwrap();
    let (path, whole) = recording(tmp.path());
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    let enders = pushes.iter().filter(|(_, p)| p.ends_connection()).count();
    let mut script = Script::new(pushes);
    let mut held = Vec::new();
    let mut pushed = Pushed::default();
    let mut errors = Vec::new();
    for _ in 0..=enders {
        let station =
            upload_recording_keeping(&addr, None, hello("s-up"), &path, 50_000_000, &mut pushed);
        let (done, _) = tokio::join!(
            station,
            serve_upload(&listener, &mut script, &mut held, &whole)
        );
        match done {
            Ok(u) => {
                assert_eq!(u.size_bytes, whole.len() as u64);
                errors.push("complete".into());
                break;
            }
            Err(e @ (UploadError::Refused(_) | UploadError::Ended(_))) => {
                errors.push(e.to_string());
            }
            Err(e) => panic!("the upload broke on a frame the hub may send: {e}"),
        }
    }
    let sent = std::mem::take(&mut *script.sent.lock().unwrap());
    (errors, pushed, held, whole, sent)
}

/// The ids of `sent` once each, in order: what the station keeps.
fn once_each(sent: &[String]) -> Vec<String> {
    let mut seen = BTreeSet::new();
    sent.iter()
        .filter(|id| seen.insert(id.as_str()))
        .cloned()
        .collect()
}

proptest! {
    #![proptest_config(config(64))]

    /// Every frame the hub may push, anywhere in an upload (before its first answer, between
    /// chunks, before `complete`): messages and the newest regimen are kept, an Ack is taken,
    /// an Error or Bye ends only that attempt, and the recording arrives whole.
    #[test]
    fn an_upload_takes_every_frame_the_hub_pushes_and_keeps_the_messages(
        pushes in script(7)
    ) {
        let (outcomes, pushed, held, whole, sent) = runtime().block_on(upload_under(pushes));
        prop_assert_eq!(outcomes.last().map(String::as_str), Some("complete"), "{:?}", outcomes);
        prop_assert_eq!(outcomes.len(), sent.ended + 1, "{:?}", outcomes);
        prop_assert!(held == whole, "the hub holds the station's bytes");
        let kept: Vec<String> = pushed.messages.iter().map(|m| m.id.clone()).collect();
        prop_assert_eq!(kept, once_each(&sent.messages));
        prop_assert_eq!(pushed.regimen.map(|r| r.id), sent.regimen);
    }
}

// ---- The live link ------------------------------------------------------------------------

/// Summaries of the live session.
const SUMMARIES: u64 = 20;

/// The largest n with 0..=n all stored.
fn stored_prefix(stored: &BTreeSet<u64>) -> Option<u64> {
    let mut last = None;
    for (i, s) in stored.iter().enumerate() {
        if *s != i as u64 {
            break;
        }
        last = Some(*s);
    }
    last
}

/// The scripted hub of a live session: stores and acknowledges summaries over as many
/// connections as the script ends, pushing its frames after the Hello, between summaries and
/// after the station's Bye, until it has answered the station's Bye.
async fn serve_live(listener: TcpListener, mut script: Script, stored: Arc<Mutex<BTreeSet<u64>>>) {
    loop {
        let mut conn = Conn::accept(&listener).await;
        let Some(Frame::Hello(h)) = conn.read().await else {
            panic!("Hello first");
        };
        let session = h.session_id;
        let acked = || stored_prefix(&stored.lock().unwrap());
        if let Some(seq) = acked() {
            conn.write(&Frame::Ack(Ack {
                session_id: session.clone(),
                seq,
            }))
            .await;
        }
        let mut ended = false;
        let mut answered_bye = false;
        loop {
            if script.send_due(&mut conn, &session, acked()).await {
                ended = true;
                break;
            }
            script.step += 1;
            match conn.read().await {
                Some(Frame::Summary(s)) => {
                    stored.lock().unwrap().insert(s.seq);
                    if let Some(seq) = acked() {
                        conn.write(&Frame::Ack(Ack {
                            session_id: session.clone(),
                            seq,
                        }))
                        .await;
                    }
                }
                Some(Frame::MessageSeen(_)) => {}
                Some(Frame::Bye(_)) => {
                    // The Bye phase: what is due now goes before the answer.
                    if script.send_due(&mut conn, &session, acked()).await {
                        ended = true;
                        break;
                    }
                    conn.write(&Frame::Bye(hub_bye(&session, acked()))).await;
                    answered_bye = true;
                    break;
                }
                Some(other) => panic!("the station sent {other:?}"),
                None => break,
            }
        }
        conn.close().await;
        if answered_bye && !ended {
            return;
        }
    }
}

struct LiveOutcome {
    stats: netlink::LinkStats,
    messages: Vec<String>,
    regimen: Option<String>,
    stored: BTreeSet<u64>,
    sent: Sent,
}

async fn live_under(pushes: Vec<(u16, Push)>) -> LiveOutcome {
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let script = Script::new(pushes);
    let sent = script.sent.clone();
    let stored = Arc::new(Mutex::new(BTreeSet::new()));
    let hub = tokio::spawn(serve_live(listener, script, stored.clone()));
    let mut config = StationLinkConfig::new(addr, None, hello("s-live"));
    config.reconnect = Backoff {
        initial_ms: 5,
        max_ms: 40,
    };
    let (sender, mut link) =
        StationLink::spawn(&tokio::runtime::Handle::current(), config).unwrap();
    let mut messages_rx = link.take_messages();
    let mut regimens_rx = link.take_regimens();
    for seq in 0..SUMMARIES {
        sender.send(Summary::example("s-live", seq)).unwrap();
        if seq % 5 == 4 {
            // Some summaries after the hub's first pushes.
            tokio::time::sleep(Duration::from_millis(1)).await;
        }
    }
    let stats = link.finish(GUARD).await;
    hub.abort();
    let mut messages = Vec::new();
    while let Ok(m) = messages_rx.try_recv() {
        messages.push(m.id);
    }
    let mut regimen = None;
    while let Ok(r) = regimens_rx.try_recv() {
        regimen = Some(r.id);
    }
    let stored = stored.lock().unwrap().clone();
    let sent = std::mem::take(&mut *sent.lock().unwrap());
    LiveOutcome {
        stats,
        messages,
        regimen,
        stored,
        sent,
    }
}

proptest! {
    #![proptest_config(config(32))]

    /// Every frame the hub may push, anywhere in a live session (right after the Hello,
    /// between summaries, after the station's Bye): every summary is stored and the session
    /// ends in order (reconnecting after an Error or an early Bye), and every message and
    /// regimen sent reaches the station.
    #[test]
    fn the_live_link_takes_every_frame_the_hub_pushes_at_any_point(
        pushes in script(SUMMARIES as u16 + 4)
    ) {
        let out = runtime().block_on(live_under(pushes));
        prop_assert_eq!(&out.stored, &(0..SUMMARIES).collect::<BTreeSet<_>>(), "{:?}", out.stats);
        prop_assert_eq!(out.stats.pending, 0, "{:?}", out.stats);
        prop_assert!(out.stats.bye_acknowledged, "{:?}", out.stats);
        prop_assert_eq!(&out.messages, &out.sent.messages, "{:?}", out.stats);
        prop_assert_eq!(&out.regimen, &out.sent.regimen);
    }
}

// ---- The hub's side -------------------------------------------------------------------------

/// The hub routes the therapist's pushes to a station's live connection, not to one that has
/// begun an upload (whose purpose it learns at `UploadStart`, after the `Hello`): a message
/// then waits for the station's next connection.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_hub_stops_pushing_messages_to_a_connection_once_it_uploads() {
    let store = tempfile::tempdir().unwrap();
    let config = netlink::TherapistConfig::new("127.0.0.1:0".parse().unwrap(), store.path(), None);
    let (hub, _events) = netlink::TherapistServer::bind(config).await.unwrap();
    let stream = TcpStream::connect(hub.local_addr()).await.unwrap();
    let mut conn = Conn {
        stream,
        decoder: FrameDecoder::new(),
    };
    conn.write(&Frame::Hello(hello("s-route"))).await;
    for _ in 0..(GUARD.as_millis() / 10) {
        if hub.connected_stations() == ["st-push"] {
            break;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let message = |id: &str| Message {
        id: id.into(),
        text: "Well done this week - keep going!".into(),
        sent_unix_ms: 1_795_253_000_000,
    };
    // Before the upload begins, the connection is the station's route.
    assert_eq!(
        hub.send_message("st-push", message("m-before")).ok(),
        Some(true)
    );
    conn.write(&Frame::UploadStart(netlink::frame::UploadStart {
        session_id: "s-route".into(),
        size_bytes: 10,
        sha256: "00".repeat(32),
    }))
    .await;
    let mut pushed = Vec::new();
    loop {
        match conn.read().await {
            Some(Frame::Message(m)) => pushed.push(m.id),
            Some(Frame::UploadAt(at)) => {
                assert_eq!((at.offset, at.complete), (0, false));
                break;
            }
            other => panic!("expected the upload's answer, got {other:?}"),
        }
    }
    assert_eq!(pushed, ["m-before"]);
    let after = hub.send_message("st-push", message("m-after"));
    assert!(
        matches!(after, Err(netlink::NetlinkError::NotConnected(_))),
        "{after:?}"
    );
    assert!(hub.connected_stations().is_empty());
    drop(conn);
    hub.shutdown(Duration::from_secs(2)).await;
}

// ---- The upload's window -------------------------------------------------------------------

/// A chunk's bytes.
fn chunk_bytes(c: &netlink::frame::UploadChunk) -> Vec<u8> {
    base64::engine::general_purpose::STANDARD
        .decode(&c.data)
        .unwrap()
}

fn upload_at(session: &str, offset: usize, complete: bool) -> Frame {
    Frame::UploadAt(netlink::frame::UploadAt {
        session_id: session.into(),
        offset: offset as u64,
        complete,
    })
}

/// The Hello and UploadStart of an upload connection; answers the start with offset 0.
async fn start_upload(conn: &mut Conn, size: usize) -> String {
    let Some(Frame::Hello(h)) = conn.read().await else {
        panic!("Hello first");
    };
    let Some(Frame::UploadStart(start)) = conn.read().await else {
        panic!("UploadStart after the Hello");
    };
    assert_eq!(start.size_bytes, size as u64);
    conn.write(&upload_at(&h.session_id, 0, false)).await;
    h.session_id
}

/// Reads chunks and answers each as a hub does (written only at the offset held, the answer the
/// offset held after it) until the file is whole; `lose` names a chunk (by arrival, from 0)
/// whose bytes the hub loses once, answering as if it never came.
async fn serve_chunks(
    conn: &mut Conn,
    session: &str,
    whole: &[u8],
    lose: Option<usize>,
) -> Vec<u8> {
    let mut held = Vec::new();
    let mut arrived = 0;
    loop {
        let Some(Frame::UploadChunk(c)) = conn.read().await else {
            panic!("a chunk until the file is whole");
        };
        if c.offset == held.len() as u64 && lose != Some(arrived) {
            held.extend(chunk_bytes(&c));
        }
        arrived += 1;
        let complete = held.as_slice() == whole;
        conn.write(&upload_at(session, held.len(), complete)).await;
        if complete {
            return held;
        }
    }
}

/// A recording of `chunks` whole chunks in `dir`, and the scripted hub's listener and address.
async fn window_case(
    dir: &Path,
    chunks: usize,
) -> (std::path::PathBuf, Vec<u8>, TcpListener, String) {
    let (path, whole) = recording_of(dir, chunks * netlink::frame::MAX_CHUNK_BYTES);
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    (path, whole, listener, addr)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_upload_sends_its_window_of_chunks_before_any_answer_and_no_more() {
    let tmp = tempfile::tempdir().unwrap();
    let window = netlink::upload::UPLOAD_WINDOW_CHUNKS;
    // Twice the window and a bit.
    let (path, whole, listener, addr) = window_case(tmp.path(), 2 * window + 1).await;
    let hub = async {
        let mut conn = Conn::accept(&listener).await;
        let session = start_upload(&mut conn, whole.len()).await;
        // No answer yet: the station sends its whole window, each chunk where the last ended…
        let mut held = Vec::new();
        for _ in 0..window {
            let Some(Frame::UploadChunk(c)) = conn.read().await else {
                panic!("a chunk of the window");
            };
            assert_eq!(c.offset, held.len() as u64, "chunks in order, back to back");
            held.extend(chunk_bytes(&c));
        }
        // …and then waits for an answer.
        let more = tokio::time::timeout(Duration::from_millis(500), conn.read()).await;
        assert!(more.is_err(), "a chunk past the window before any answer");
        // Answered, it goes on to the end.
        for i in 1..=window {
            conn.write(&upload_at(
                &session,
                i * netlink::frame::MAX_CHUNK_BYTES,
                false,
            ))
            .await;
        }
        loop {
            let Some(Frame::UploadChunk(c)) = conn.read().await else {
                panic!("the rest of the file");
            };
            assert_eq!(c.offset, held.len() as u64);
            held.extend(chunk_bytes(&c));
            let complete = held == whole;
            conn.write(&upload_at(&session, held.len(), complete)).await;
            if complete {
                break;
            }
        }
        conn.close().await;
        held
    };
    let mut pushed = Pushed::default();
    let station =
        upload_recording_keeping(&addr, None, hello("s-up"), &path, 500_000_000, &mut pushed);
    let (done, held) = tokio::join!(station, hub);
    let done = done.unwrap();
    assert_eq!(held, whole);
    assert_eq!(done.sent_bytes, whole.len() as u64, "each byte sent once");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_hub_holding_less_than_the_station_thought_gets_the_rest_again_from_where_it_says() {
    let tmp = tempfile::tempdir().unwrap();
    let window = netlink::upload::UPLOAD_WINDOW_CHUNKS;
    let (path, whole, listener, addr) = window_case(tmp.path(), 2 * window + 3).await;
    let hub = async {
        let mut conn = Conn::accept(&listener).await;
        let session = start_upload(&mut conn, whole.len()).await;
        // The third chunk is lost: the hub's answers say offset 2 chunks until it comes again.
        let held = serve_chunks(&mut conn, &session, &whole, Some(2)).await;
        conn.close().await;
        held
    };
    let mut pushed = Pushed::default();
    let station =
        upload_recording_keeping(&addr, None, hello("s-up"), &path, 500_000_000, &mut pushed);
    let (done, held) = tokio::join!(station, hub);
    let done = done.unwrap();
    assert_eq!(held, whole, "the file whole, in order");
    // What was in flight after the lost chunk was sent again.
    assert!(done.sent_bytes > whole.len() as u64, "{}", done.sent_bytes);
    assert!(
        done.sent_bytes <= (whole.len() + window * netlink::frame::MAX_CHUNK_BYTES) as u64,
        "at most a window again: {}",
        done.sent_bytes
    );
}
