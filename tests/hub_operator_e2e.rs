//! A clinic's hub as its operator runs it (issue 45): `hub serve --log-format json
//! --metrics-listen …` writes every log line as one JSON object (time, level, target, message
//! and fields) through a paired station's session and a SIGTERM, and its `/metrics` counts the
//! session's summaries.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::Stdio;
use std::time::Duration;

use telerehab_tests::clinic::{Hub, clinic, ok, produced, run_session};

/// `GET path` from `addr` over plain HTTP: the status line and the body.
fn get(addr: &str, path: &str) -> (String, String) {
    let mut tcp = TcpStream::connect(addr).unwrap();
    tcp.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    write!(
        tcp,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut response = String::new();
    tcp.read_to_string(&mut response).unwrap();
    let (head, body) = response.split_once("\r\n\r\n").unwrap();
    (head.lines().next().unwrap().to_owned(), body.to_owned())
}

/// The value of the sample `name` in the text format, if present.
fn sample(text: &str, name: &str) -> Option<f64> {
    text.lines()
        .find_map(|l| l.strip_prefix(name)?.strip_prefix(' ')?.parse().ok())
}

#[test]
fn every_log_line_of_a_hub_with_json_logs_is_one_json_object_and_metrics_count_the_session() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let log_path = tmp.path().join("hub.log");
    let log = std::fs::File::create(&log_path).unwrap();
    let more = [
        "--log-format",
        "json",
        "--log",
        "info",
        "--metrics-listen",
        "127.0.0.1:0",
    ];
    let mut hub = Hub::serve_logging_to(&data, "127.0.0.1:0", &more, Stdio::from(log));
    let metrics = hub.metrics.clone().expect("the operator's address");
    let home = tmp.path().join("station");
    ok(
        &["pair", "--hub", &hub.stations, "--code", &code],
        Some(&home),
    );
    let n = produced(&run_session(&home, "2"));
    assert!(n > 0);

    let (status, text) = get(&metrics, "/metrics");
    assert!(status.contains(" 200 "), "{status}");
    let ingested = sample(&text, "telerehab_hub_summaries_ingested_total");
    assert_eq!(ingested, Some(n as f64), "{text}");
    let (status, body) = get(&metrics, "/readyz");
    assert!(status.contains(" 200 "), "{status}: {body}");
    assert!(
        hub.signal_and_wait("TERM", Duration::from_secs(10))
            .is_some(),
        "the hub did not stop"
    );

    let log = std::fs::read_to_string(&log_path).unwrap();
    let lines: Vec<&str> = log.lines().collect();
    assert!(lines.len() >= 5, "too few log lines:\n{log}");
    for line in &lines {
        let event: serde_json::Value =
            serde_json::from_str(line).unwrap_or_else(|e| panic!("not JSON ({e}): {line:?}"));
        for key in ["timestamp", "level", "target"] {
            assert!(event[key].is_string(), "no {key} in {line}");
        }
        assert!(
            event["message"].is_string() || event.as_object().unwrap().len() > 3,
            "neither message nor fields in {line}"
        );
    }
    // Fields stand beside the message, as a collector indexes them.
    assert!(
        lines.iter().any(|l| l.contains(r#""address":"127.0.0.1:"#)),
        "no event with its fields:\n{log}"
    );
}
