//! A hub served in the test's runtime and a paired station speaking the real link codec to it
//! over loopback TLS: what the tests of the station link share.

use std::net::SocketAddr;
use std::path::Path;
use std::time::{Duration, Instant};

use base64::Engine;
use hub::Role;
use hub::bench::BenchStation;
use hub::clinic::{Bound, Clinic, ServeOptions};
use netlink::{Bye, Frame, FrameDecoder, Hello, Summary};
use tokio::io::{AsyncReadExt, AsyncWriteExt, ReadHalf};
use tokio::net::TcpStream;
use tokio_rustls::client::TlsStream;

/// Longest any step of these tests waits.
pub const GUARD: Duration = Duration::from_secs(20);

/// A station's TLS connection to the hub.
pub type Tls = TlsStream<TcpStream>;

fn now_ms() -> i64 {
    hub::web::system_now_ms()
}

/// A clinic under `dir` (SQLite) with one paired station.
pub async fn clinic_with_station(dir: &Path) -> (Clinic, BenchStation) {
    clinic_with_station_on(dir, None).await
}

/// A clinic under `dir` on `database` (`None`: SQLite) with one paired station.
pub async fn clinic_with_station_on(dir: &Path, database: Option<&str>) -> (Clinic, BenchStation) {
    let clinic = Clinic::at(dir.join("clinic"));
    clinic
        .init(
            "root@clinic.example",
            &["localhost".to_owned()],
            database,
            now_ms(),
        )
        .await
        .unwrap();
    let db = clinic.open_db(None).await.unwrap();
    db.add_therapist(
        "ada@clinic.example",
        "correct horse battery staple",
        Role::Therapist,
        now_ms(),
    )
    .await
    .unwrap();
    let station = hub::bench::provision(
        &db,
        &clinic.ca().unwrap(),
        "localhost",
        1,
        &dir.join("stations"),
        now_ms(),
    )
    .await
    .unwrap()
    .remove(0);
    db.close().await;
    (clinic, station)
}

/// `hub serve` of `clinic` with `options`, in this runtime, once it listens.
pub async fn start_hub_with(clinic: &Clinic, options: ServeOptions) -> RunningHub {
    let db = clinic.open_db(None).await.unwrap();
    let clinic = clinic.clone();
    let (bound_tx, bound_rx) = tokio::sync::oneshot::channel();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let task = tokio::spawn(async move {
        hub::clinic::serve(
            &clinic,
            db,
            options,
            move |b| {
                let _ = bound_tx.send(b);
            },
            |_| {},
            async move {
                let _ = stopped.await;
            },
        )
        .await
    });
    let bound = tokio::time::timeout(GUARD, bound_rx)
        .await
        .expect("hub listening")
        .expect("hub started");
    RunningHub { bound, stop, task }
}

/// A hub served by [`start_hub_with`].
pub struct RunningHub {
    pub bound: Bound,
    pub stop: tokio::sync::oneshot::Sender<()>,
    pub task: tokio::task::JoinHandle<Result<(), hub::HubError>>,
}

impl RunningHub {
    /// Asks it to stop and waits (at most [`GUARD`]).
    pub async fn stop(self) {
        let _ = self.stop.send(());
        let _ = tokio::time::timeout(GUARD, self.task).await;
    }
}

/// A `Bye` ending `session_id` after `final_seq`.
pub fn bye(session_id: &str, final_seq: Option<u64>) -> Bye {
    Bye {
        session_id: session_id.to_owned(),
        reason: "done".into(),
        final_seq,
        measures: Default::default(),
        hub_unix_ms: None,
        checkin: None,
        difficulty: None,
        exercises: Vec::new(),
    }
}

/// Summary `seq` of `session_id` at `t_s` (s of session time).
pub fn summary_at(session_id: &str, seq: u64, t_s: f64) -> Frame {
    let mut s = Summary::example(session_id, seq);
    s.t_s = t_s;
    Frame::Summary(s)
}

/// The `Hello` of `st` opening `session_id`, started at `started_unix_ms`.
pub fn hello(st: &BenchStation, session_id: &str, started_unix_ms: u64) -> Frame {
    Frame::Hello(Hello {
        started_unix_ms,
        ..super::hello(&st.station_id, &st.patient_id, session_id)
    })
}

pub async fn connect(addr: SocketAddr, st: &BenchStation) -> Tls {
    let (connector, name) = st.tls.connector().unwrap();
    let tcp = TcpStream::connect(addr).await.unwrap();
    connector.connect(name, tcp).await.unwrap()
}

pub fn bytes(frames: &[Frame]) -> Vec<u8> {
    frames
        .iter()
        .flat_map(|f| netlink::encode_to_vec(f).unwrap())
        .collect()
}

/// Frames from the hub until it closes the connection (or `GUARD`).
pub async fn frames_until_closed(rd: &mut ReadHalf<Tls>) -> Vec<Frame> {
    frames_until(rd, GUARD).await
}

/// Frames from the hub until it closes the connection or `limit` has passed.
pub async fn frames_until(rd: &mut ReadHalf<Tls>, limit: Duration) -> Vec<Frame> {
    let mut decoder = FrameDecoder::new();
    let mut buf = vec![0u8; 16 * 1024];
    let mut out = Vec::new();
    let _ = tokio::time::timeout(limit, async {
        loop {
            match rd.read(&mut buf).await {
                Ok(0) | Err(_) => break,
                Ok(n) => {
                    decoder.extend(&buf[..n]);
                    while let Ok(Some(f)) = decoder.next_frame() {
                        out.push(f);
                    }
                }
            }
        }
    })
    .await;
    out
}

/// Sends `frames` on a new connection and returns what the hub answered until it closed.
pub async fn exchange(addr: SocketAddr, st: &BenchStation, frames: &[Frame]) -> Vec<Frame> {
    let (mut rd, mut wr) = tokio::io::split(connect(addr, st).await);
    wr.write_all(&bytes(frames)).await.unwrap();
    let got = frames_until_closed(&mut rd).await;
    drop(wr);
    got
}

/// One connection uploading a `size`-byte recording of its own session (started `days_ago`):
/// the bytes the hub acknowledged before `until`.
pub async fn upload(
    addr: SocketAddr,
    st: BenchStation,
    session_id: String,
    started: u64,
    size: usize,
    until: Instant,
) -> u64 {
    let data = vec![7u8; size];
    let sha = hub::db::sha256_hex(&data);
    let (mut rd, mut wr) = tokio::io::split(connect(addr, &st).await);
    let start = Frame::UploadStart(netlink::frame::UploadStart {
        session_id: session_id.clone(),
        size_bytes: size as u64,
        sha256: sha,
    });
    wr.write_all(&bytes(&[hello(&st, &session_id, started), start]))
        .await
        .unwrap();
    let mut decoder = FrameDecoder::new();
    let mut buf = vec![0u8; 16 * 1024];
    let mut acked = 0u64;
    loop {
        let left = until.saturating_duration_since(Instant::now());
        let n = match tokio::time::timeout(left, rd.read(&mut buf)).await {
            Ok(Ok(n)) if n > 0 => n,
            _ => return acked,
        };
        decoder.extend(&buf[..n]);
        while let Ok(Some(f)) = decoder.next_frame() {
            let Frame::UploadAt(at) = f else {
                continue;
            };
            acked = at.offset;
            if at.complete || Instant::now() >= until {
                return acked;
            }
            let from = usize::try_from(at.offset).unwrap();
            let to = (from + netlink::frame::MAX_CHUNK_BYTES).min(size);
            let chunk = Frame::UploadChunk(netlink::frame::UploadChunk {
                session_id: session_id.clone(),
                offset: at.offset,
                data: base64::engine::general_purpose::STANDARD.encode(&data[from..to]),
            });
            if wr.write_all(&bytes(&[chunk])).await.is_err() {
                return acked;
            }
        }
    }
}
