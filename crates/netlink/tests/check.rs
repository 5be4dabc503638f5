//! A station's check (`doctor-check`, today's page) at a hub on loopback speaking the real
//! codec: at protocol version 4 the hub answers with the patient's news — the clinic's care,
//! the unseen messages, the current regimen — before its `Bye`, only for a station its store
//! admits; a version-3 station's `Hello`, as its bytes were written before version 4, still
//! decodes and gets the `Bye` alone, as it always did.

use std::sync::Arc;
use std::time::Duration;

use netlink::frame::{CHECK_EXERCISE, CHECK_NEWS_VERSION};
use netlink::{
    BoxFuture, Care, CheckNews, FileStore, Frame, FrameDecoder, Hello, HubStore, Message,
    PROTOCOL_VERSION, Peer, Refusal, Regimen, SessionStore, TherapistConfig, TherapistServer,
    encode_to_vec,
};
use tokio::io::{AsyncReadExt, AsyncWriteExt};

const GUARD: Duration = Duration::from_secs(20);

// This station speaks the version whose checks carry news.
const _: () = assert!(PROTOCOL_VERSION >= CHECK_NEWS_VERSION);

/// A store that knows one patient's news and refuses the station `st-stranger`.
struct News {
    files: FileStore,
}

fn news() -> CheckNews {
    CheckNews {
        care: Some(Care {
            pain_threshold_0_10: 6,
            clinic_phone: Some("+49 30 1234 567".into()),
            cleared_unix_ms: None,
        }),
        messages: vec![
            Message {
                id: "m-1".into(),
                text: "Good work.".into(),
                sent_unix_ms: 1_795_253_400_000,
            },
            Message {
                id: "m-2".into(),
                text: "Rest on Sunday.".into(),
                sent_unix_ms: 1_795_253_500_000,
            },
        ],
        regimen: Some(Regimen {
            id: "p-1-v2".into(),
            toml: "[[exercise]]\nkind = \"dial\"\nduration_s = 60.0\n".into(),
            prescribed_by: Some("ana@clinic.example".into()),
        }),
    }
}

impl HubStore for News {
    fn admit<'a>(&'a self, hello: &'a Hello, _: Peer<'a>) -> BoxFuture<'a, Result<(), Refusal>> {
        let refused = hello.station_id == "st-stranger";
        Box::pin(async move {
            if refused {
                Err(Refusal::new("unknown station st-stranger"))
            } else {
                Ok(())
            }
        })
    }

    fn station_check<'a>(&'a self, _: &'a Hello) -> BoxFuture<'a, CheckNews> {
        Box::pin(async { news() })
    }

    fn open_session<'a>(
        &'a self,
        hello: &'a Hello,
    ) -> BoxFuture<'a, Result<Box<dyn SessionStore>, Refusal>> {
        self.files.open_session(hello)
    }
}

fn check_hello(station_id: &str, protocol_version: u16) -> Hello {
    Hello {
        protocol_version,
        min_protocol_version: Some(1),
        wheel: None,
        station_id: station_id.into(),
        patient_id: "p-1".into(),
        session_id: "doctor-check-0123456789abcdef".into(),
        exercise: CHECK_EXERCISE.into(),
        started_unix_ms: 1_795_253_400_000,
        software_version: "telerehab-test".into(),
    }
}

/// Sends `hello_bytes` to a hub over the [`News`] store and reads its answer until the hub's
/// `Bye` or `Error` (the check sends no `Bye` of its own: a hub of this version answers at
/// once). Also what the hub's store directory holds afterwards.
fn ask(hello_bytes: Vec<u8>) -> (Vec<Frame>, usize) {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    runtime.block_on(async {
        let config = TherapistConfig::new("127.0.0.1:0".parse().unwrap(), tmp.path(), None);
        let store = News {
            files: FileStore::new(tmp.path().join("store")),
        };
        let (server, _events) = TherapistServer::bind_with_store(config, Arc::new(store))
            .await
            .unwrap();
        let mut tcp = tokio::net::TcpStream::connect(server.local_addr())
            .await
            .unwrap();
        tcp.write_all(&hello_bytes).await.unwrap();
        let mut decoder = FrameDecoder::new();
        let mut frames = Vec::new();
        let mut buf = vec![0u8; 16 * 1024];
        'read: loop {
            while let Some(f) = decoder.next_frame().unwrap() {
                let end = matches!(f, Frame::Bye(_) | Frame::Error(_));
                frames.push(f);
                if end {
                    break 'read;
                }
            }
            let n = tokio::time::timeout(GUARD, tcp.read(&mut buf))
                .await
                .expect("the hub answers the check")
                .unwrap();
            assert!(n > 0, "the hub closed before its answer: {frames:?}");
            decoder.extend(&buf[..n]);
        }
        server.shutdown(Duration::from_secs(5)).await;
        let stored = std::fs::read_dir(tmp.path().join("store")).map_or(0, |d| d.count());
        (frames, stored)
    })
}

#[test]
fn a_version_4_check_gets_care_messages_and_regimen_before_the_bye_and_nothing_is_stored() {
    let hello = Frame::Hello(check_hello("st-1", PROTOCOL_VERSION));
    let (frames, stored) = ask(encode_to_vec(&hello).unwrap());
    let expected = news().into_frames();
    assert_eq!(frames.len(), expected.len() + 1, "{frames:?}");
    assert_eq!(frames[..expected.len()], expected[..]);
    assert!(
        matches!(&frames[expected.len()], Frame::Bye(b) if b.hub_unix_ms.is_some()),
        "{frames:?}"
    );
    assert_eq!(stored, 0, "a check opens no session");
}

/// A `Hello` frame as a version-3 station wrote it, byte for byte (header version 1, kind 1).
fn version_3_hello_bytes() -> Vec<u8> {
    let body = br#"{"protocol_version":3,"station_id":"st-1","patient_id":"p-1","session_id":"doctor-check-0123456789abcdef","exercise":"doctor-check","started_unix_ms":1795253400000,"software_version":"telerehab 0.9","min_protocol_version":1}"#;
    let mut bytes = b"TRHB\x00\x01\x01\x00".to_vec();
    bytes.extend_from_slice(&u32::try_from(body.len()).unwrap().to_be_bytes());
    bytes.extend_from_slice(body);
    bytes
}

#[test]
fn a_version_3_stations_hello_still_decodes_and_its_check_gets_the_bye_alone() {
    let mut decoder = FrameDecoder::new();
    decoder.extend(&version_3_hello_bytes());
    let Some(Frame::Hello(old)) = decoder.next_frame().unwrap() else {
        panic!("a version-3 Hello decodes");
    };
    let mut written = check_hello("st-1", 3);
    written.software_version = "telerehab 0.9".into();
    assert_eq!(old, written);
    let (frames, _) = ask(version_3_hello_bytes());
    assert!(
        matches!(frames.as_slice(), [Frame::Bye(_)]),
        "a version-3 station is sent no frame it does not expect: {frames:?}"
    );
}

#[test]
fn a_check_from_a_station_the_store_refuses_gets_an_error_and_no_news() {
    let hello = Frame::Hello(check_hello("st-stranger", PROTOCOL_VERSION));
    let (frames, _) = ask(encode_to_vec(&hello).unwrap());
    assert!(
        matches!(frames.as_slice(), [Frame::Error(e)] if e.message.contains("st-stranger")),
        "{frames:?}"
    );
}
