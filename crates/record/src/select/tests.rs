//! Selections read through the summary hold exactly what the whole read holds in the window,
//! decompress only the chunks holding it, and read the same front to back without a summary.

use super::*;
use crate::columns::{ChannelData, Values, read_columns};
use crate::tests::tick;
use crate::{MetricsSample, RecordWriter, ScoreSample, SessionMetadata, TickRecord};
use mcap::records::op;
use std::collections::BTreeMap;
use std::io::Cursor;

/// The log time of session time 0 in these recordings, ns (a wall-clock time, as the station's).
const START_UNIX_NS: u64 = 1_796_608_036_319_384_172;

/// `seconds` of a session at 1 kHz, its first tick at `first_ns` of session time: the car on
/// the road over its second third only (a channel that stops), a score every 100 ticks, the
/// recorder's flush every second (a chunk a second), the measures at the end.
fn session(seconds: u64, first_ns: u64) -> Vec<u8> {
    let meta = SessionMetadata {
        seed: 3,
        loop_rate_hz: 1000.0,
        ..Default::default()
    };
    let mut w = RecordWriter::new(Cursor::new(Vec::new()), START_UNIX_NS, &meta).unwrap();
    let n = seconds * 1000;
    let mut last = TickRecord::default();
    for k in 0..n {
        let mut rec = tick(k);
        rec.t_ns = first_ns + k * 1_000_000;
        rec.wheel.angle_rad = (k as f64 * 1e-3).sin();
        if !(n / 3..2 * n / 3).contains(&k) {
            rec.vehicle = None;
        }
        rec.score = ScoreSample {
            cone_hits: (k / 100) as u32,
            ..rec.score
        };
        w.write_tick(&rec, k % 100 == 0).unwrap();
        if k % 1000 == 999 {
            w.flush().unwrap();
        }
        last = rec;
    }
    w.write_metrics(&last, &MetricsSample::default()).unwrap();
    w.finish().unwrap().into_inner()
}

/// The bytes with the footer saying there is no summary (as a file of a writer that wrote
/// none): read front to back.
fn without_summary(bytes: &[u8]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let footer = out.len() - 37;
    assert_eq!(out[footer], op::FOOTER);
    out[footer + 9..footer + 17].fill(0);
    out
}

fn select(topics: &[&str], start_s: Option<f64>, end_s: Option<f64>) -> Selection {
    Selection {
        topics: Some(topics.iter().map(|t| t.to_string()).collect()),
        start_s,
        end_s,
    }
}

fn read(bytes: &[u8], selection: &Selection) -> Selected {
    read_selected(Cursor::new(bytes), StreamLimits::default(), selection).unwrap()
}

/// The rows of `values` (`elements` a row) that `keep` marks.
fn rows(values: &Values, keep: &[bool], elements: usize) -> Values {
    fn pick<T: Clone>(v: &[T], keep: &[bool], e: usize) -> Vec<T> {
        v.iter()
            .enumerate()
            .filter(|(i, _)| keep[i / e])
            .map(|(_, x)| x.clone())
            .collect()
    }
    let e = elements.max(1);
    match values {
        Values::F64(v) => Values::F64(pick(v, keep, e)),
        Values::U64(v) => Values::U64(pick(v, keep, e)),
        Values::Bool(v) => Values::Bool(pick(v, keep, e)),
        Values::Text { codes, labels } => Values::Text {
            codes: pick(codes, keep, e),
            labels: labels.clone(),
        },
    }
}

/// A column's values as they compare: floats by their bits (a NaN equal to itself), labels
/// coded again in order of first appearance (which a window changes).
fn labelled(values: &Values) -> Values {
    match values {
        Values::F64(v) => Values::U64(v.iter().map(|x| x.to_bits()).collect()),
        Values::Text { codes, labels } => {
            let mut seen = Vec::new();
            let mut out = Vec::new();
            for &c in codes {
                let label = &labels[c as usize];
                let at = seen.iter().position(|l| l == label).unwrap_or_else(|| {
                    seen.push(label.clone());
                    seen.len() - 1
                });
                out.push(at as u32);
            }
            Values::Text {
                codes: out,
                labels: seen,
            }
        }
        other => other.clone(),
    }
}

/// A channel as it compares: each column's name, elements, description and values (label
/// codes renumbered as [`labelled`] does), or the JSON messages.
#[derive(PartialEq)]
enum Seen {
    Columns(Vec<(String, usize, String, Values)>),
    Json(Vec<u8>, Vec<Vec<u8>>),
}

/// Only the first difference is worth printing (the whole columns are too long to).
impl std::fmt::Debug for Seen {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Seen::Columns(cols) => write!(f, "{} columns", cols.len()),
            Seen::Json(_, messages) => write!(f, "{} JSON messages", messages.len()),
        }
    }
}

/// Asserts `have` is `want`, naming the first column and value that differ.
#[track_caller]
fn assert_seen(have: &Seen, want: &Seen, what: &str) {
    if let (Seen::Columns(a), Seen::Columns(b)) = (have, want) {
        for (x, y) in a.iter().zip(b) {
            if x != y {
                let (n, m) = (format!("{:?}", x.3), format!("{:?}", y.3));
                let at = n
                    .bytes()
                    .zip(m.bytes())
                    .position(|(p, q)| p != q)
                    .unwrap_or(0);
                let from = at.saturating_sub(80);
                panic!(
                    "{what}: column {} differs (lengths of debug text {} and {}): have …{}… want …{}…",
                    x.0,
                    n.len(),
                    m.len(),
                    &n[from..(at + 80).min(n.len())],
                    &m[from..(at + 80).min(m.len())]
                );
            }
        }
    }
    assert_eq!(have, want, "{what}");
}

/// `data` as it compares, its rows cut to those `keep` marks (`None`: all).
fn seen(data: &ChannelData, keep: Option<&dyn Fn(f64) -> bool>) -> Seen {
    match data {
        ChannelData::Columns(cols) => {
            let t_s = match &cols.iter().find(|c| c.name == "t_s").unwrap().values {
                Values::F64(t) => t.clone(),
                other => panic!("{other:?}"),
            };
            let rows_kept: Vec<bool> = t_s.iter().map(|&t| keep.is_none_or(|k| k(t))).collect();
            Seen::Columns(
                cols.iter()
                    .map(|c| {
                        let values = labelled(&rows(&c.values, &rows_kept, c.elements));
                        (c.name.clone(), c.elements, c.description.clone(), values)
                    })
                    .collect(),
            )
        }
        ChannelData::Json { schema, messages } => Seen::Json(
            schema.clone(),
            messages
                .iter()
                .filter(|m| {
                    let v: serde_json::Value = serde_json::from_slice(m).unwrap();
                    keep.is_none_or(|k| k(v["t_s"].as_f64().unwrap()))
                })
                .cloned()
                .collect(),
        ),
    }
}

/// The whole read's channel `topic` cut to `[start_s, end_s)` by its `t_s`, as an analyst
/// would slice it.
fn sliced(whole: &RecordingColumns, topic: &str, start_s: f64, end_s: f64) -> Seen {
    let keep = move |t: f64| start_s <= t && t < end_s;
    seen(whole.channel(topic).unwrap(), Some(&keep))
}

fn topics(r: &RecordingColumns) -> Vec<&str> {
    r.channels.iter().map(|(t, _)| t.as_str()).collect()
}

#[test]
fn a_window_of_chosen_channels_holds_exactly_what_the_whole_read_holds_in_it() {
    let bytes = session(30, 0);
    let whole = read_columns(Cursor::new(&bytes), StreamLimits::default()).unwrap();
    let chosen = [
        "/wheel", "/vehicle", "/score", "/raw/imu", "/arm", "/metrics",
    ];
    let order: Vec<&str> = topics(&whole)
        .into_iter()
        .filter(|t| chosen.contains(t))
        .collect();
    assert_eq!(order.len(), chosen.len());
    // Off the millisecond grid and on it; across the car's stop at 20 s; the start; the end
    // (the measures); an empty window.
    for (start_s, end_s) in [
        (7.2345, 9.87654),
        (5.0, 6.0),
        (18.5, 21.25),
        (-3.0, 0.5),
        (29.5, 100.0),
        (12.0, 12.0),
    ] {
        let got = read(&bytes, &select(&chosen, Some(start_s), Some(end_s)));
        assert_eq!(got.route, Route::Indexed);
        assert_eq!(got.columns.metadata, whole.metadata);
        assert_eq!(topics(&got.columns), order);
        for topic in chosen {
            let want = sliced(&whole, topic, start_s, end_s);
            let have = seen(got.columns.channel(topic).unwrap(), None);
            assert_seen(&have, &want, &format!("{topic} over [{start_s}, {end_s})"));
        }
    }
}

/// Whether two reads hold the same: metadata, channels in order, each channel's values.
fn assert_same(a: &RecordingColumns, b: &RecordingColumns) {
    assert_eq!(a.metadata, b.metadata);
    assert_eq!(topics(a), topics(b));
    for ((topic, x), (_, y)) in a.channels.iter().zip(&b.channels) {
        assert_seen(&seen(x, None), &seen(y, None), topic);
    }
}

#[test]
fn without_a_summary_a_selection_reads_the_same_front_to_back() {
    let bytes = session(12, 0);
    let bare = without_summary(&bytes);
    for selection in [
        select(&["/wheel", "/score"], Some(3.3), Some(7.0)),
        select(&["/timing"], None, None),
        Selection {
            topics: None,
            start_s: Some(9.5),
            end_s: None,
        },
    ] {
        let indexed = read(&bytes, &selection);
        let linear = read(&bare, &selection);
        assert_eq!(indexed.route, Route::Indexed);
        assert_eq!(linear.route, Route::Linear);
        assert_eq!(linear.chunks_read, linear.chunks_in_file);
        assert_same(&indexed.columns, &linear.columns);
    }
}

#[test]
fn a_recording_whose_first_tick_is_not_at_zero_is_read_with_the_offset_its_messages_show() {
    // The earliest stamp is taken as session time 0 first; the first message decoded shows
    // the offset is 7 s less, and the selection is read again with it.
    let bytes = session(12, 7_000_000_007);
    let whole = read_columns(Cursor::new(&bytes), StreamLimits::default()).unwrap();
    let got = read(
        &bytes,
        &select(&["/wheel", "/score"], Some(10.25), Some(12.5)),
    );
    assert_eq!(got.route, Route::Indexed);
    for topic in ["/wheel", "/score"] {
        let want = sliced(&whole, topic, 10.25, 12.5);
        assert_seen(
            &seen(got.columns.channel(topic).unwrap(), None),
            &want,
            topic,
        );
    }
    match got.columns.channel("/wheel") {
        Some(ChannelData::Columns(cols)) => match &cols[0].values {
            Values::U64(ticks) => assert_eq!(ticks.len(), 2250),
            other => panic!("{other:?}"),
        },
        other => panic!("{other:?}"),
    }
}

/// The log times of `topic`'s messages, chunk by chunk in file order (chunks without any
/// included), read by mcap's own reader from the chunks themselves (not from the indexes).
fn stamps_by_chunk(bytes: &[u8], topic: &str) -> Vec<Vec<u64>> {
    let mut ids = BTreeMap::new();
    let mut out = Vec::new();
    for record in mcap::read::LinearReader::new(bytes).unwrap() {
        let mcap::records::Record::Chunk { header, data } = record.unwrap() else {
            continue;
        };
        let mut stamps = Vec::new();
        for inner in mcap::read::ChunkReader::new(header, &data).unwrap() {
            match inner.unwrap() {
                mcap::records::Record::Channel(c) => {
                    ids.insert(c.id, c.topic);
                }
                mcap::records::Record::Message { header, .. }
                    if ids.get(&header.channel_id).is_some_and(|t| t == topic) =>
                {
                    stamps.push(header.log_time);
                }
                _ => {}
            }
        }
        out.push(stamps);
    }
    out
}

#[test]
fn a_window_decompresses_only_the_chunks_holding_its_messages() {
    let bytes = session(30, 0);
    let (start_s, end_s) = (10.5, 12.5);
    let got = read(&bytes, &select(&["/wheel"], Some(start_s), Some(end_s)));
    // The chunks needed: those holding a /wheel block stamped in the window, and the one of
    // the last block stamped before it, whose samples may reach into it.
    let by_chunk = stamps_by_chunk(&bytes, "/wheel");
    let (t0, t1) = (
        START_UNIX_NS + (start_s * 1e9) as u64,
        START_UNIX_NS + (end_s * 1e9) as u64,
    );
    let before = by_chunk
        .iter()
        .flatten()
        .filter(|&&t| t <= t0)
        .max()
        .copied();
    let from = before.unwrap_or(t0);
    let needed = by_chunk
        .iter()
        .filter(|stamps| stamps.iter().any(|t| (from..t1).contains(t)))
        .count();
    // A chunk a second: 10 to 12 s.
    assert_eq!(needed, 3);
    assert_eq!(got.chunks_read, needed as u64);
    assert_eq!(got.chunks_in_file, by_chunk.len() as u64);
    assert!(got.chunks_in_file > 30, "{}", got.chunks_in_file);
    // The measures, written once at the very end: one chunk, whatever the window.
    let end = read(&bytes, &select(&["/metrics"], None, None));
    assert_eq!(end.chunks_read, 1);
}

#[test]
fn a_channel_the_recording_lacks_or_a_window_ending_before_it_starts_is_refused_by_name() {
    let bytes = session(3, 0);
    for file in [bytes.clone(), without_summary(&bytes)] {
        for (asked, missing) in [
            (vec!["/wheel", "/nope"], "/nope"),
            (vec!["/arm/scene"], "/arm/scene"),
        ] {
            let e = read_selected(
                Cursor::new(&file),
                StreamLimits::default(),
                &select(&asked, None, None),
            )
            .unwrap_err();
            match &e {
                ReadError::NoSuchChannel { topic, present } => {
                    assert_eq!(topic, missing);
                    assert!(present.contains(&"/wheel".to_string()), "{present:?}");
                    assert!(!present.contains(&"/arm/scene".to_string()), "{present:?}");
                }
                other => panic!("{other}"),
            }
            assert!(e.to_string().contains(missing), "{e}");
        }
    }
    for (selection, says) in [
        (
            select(&["/wheel"], Some(5.0), Some(2.0)),
            "start_s 5 s is after end_s 2 s",
        ),
        (select(&["/wheel"], Some(f64::NAN), None), "start_s is NaN"),
        (select(&[], None, None), "no channel named"),
    ] {
        let e =
            read_selected(Cursor::new(&bytes), StreamLimits::default(), &selection).unwrap_err();
        assert!(matches!(e, ReadError::BadSelection(_)), "{e}");
        assert!(e.to_string().contains(says), "{e}");
    }
}

#[test]
fn a_recording_cut_short_is_refused_as_the_whole_read_refuses_it() {
    let bytes = session(3, 0);
    let cut = &bytes[..bytes.len() / 2];
    let whole = read_columns(Cursor::new(cut), StreamLimits::default()).unwrap_err();
    let part = read_selected(
        Cursor::new(cut),
        StreamLimits::default(),
        &select(&["/wheel"], Some(1.0), None),
    )
    .unwrap_err();
    assert_eq!(part.to_string(), whole.to_string());
}

#[test]
fn the_info_from_the_summary_is_what_a_walk_over_the_whole_file_finds() {
    let bytes = session(12, 0);
    let limits = StreamLimits::default();
    let indexed = recording_info(Cursor::new(&bytes), limits).unwrap();
    let walked = recording_info(Cursor::new(without_summary(&bytes)), limits).unwrap();
    assert!(indexed.indexed && !walked.indexed);
    assert_eq!(indexed.channels, walked.channels);
    assert_eq!(indexed.metadata, walked.metadata);
    assert_eq!(indexed.chunks, walked.chunks);
    let channel = |topic: &str| indexed.channels.iter().find(|c| c.topic == topic).unwrap();
    let s = |t_ns: u64| Some(t_ns as f64 * 1e-9);
    // 12 000 ticks in blocks of 100; the car on the road from 4 s to 8 s.
    let wheel = channel("/wheel");
    assert_eq!(
        (wheel.messages, wheel.first_s, wheel.last_s),
        (120, s(0), s(11_900_000_000))
    );
    assert!(
        wheel.readable && wheel.schema == "telerehab.WheelBlock",
        "{wheel:?}"
    );
    let vehicle = channel("/vehicle");
    assert_eq!(
        (vehicle.messages, vehicle.first_s, vehicle.last_s),
        (40, s(4_000_000_000), s(7_900_000_000))
    );
    let score = channel("/score");
    assert_eq!((score.messages, score.encoding.as_str()), (120, "json"));
    assert!(!channel("/arm/scene").readable);
    assert_eq!(indexed.metadata["seed"], "3");
}

/// The shortest of three wall times of `f`, s.
fn best_of_three(mut f: impl FnMut()) -> f64 {
    (0..3)
        .map(|_| {
            let t = std::time::Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// How many times faster one channel over ten seconds of two minutes reads than the whole
/// file, at least (25–55× measured in a debug build on a loaded 2-core machine; BENCHMARKS.md,
/// issue 47).
const MIN_SPEED_UP: f64 = 8.0;

#[test]
fn one_channel_over_ten_seconds_of_two_minutes_reads_many_times_faster_than_the_whole_file() {
    // Two reads compared in one run (a ratio, never an absolute time): the window needs 10
    // of the file's 122 chunks (one a second, the first with the schemas and channels, the
    // last with the measures) and one of its seven block channels.
    let bytes = session(120, 0);
    let whole_s = best_of_three(|| {
        read_columns(Cursor::new(&bytes), StreamLimits::default()).unwrap();
    });
    let mut part = None;
    let part_s = best_of_three(|| {
        part = Some(read(&bytes, &select(&["/wheel"], Some(60.0), Some(70.0))));
    });
    let part = part.unwrap();
    assert_eq!((part.chunks_read, part.chunks_in_file), (10, 122));
    let speed_up = whole_s / part_s;
    eprintln!("whole {whole_s:.3} s, one channel over 10 s {part_s:.4} s: {speed_up:.1}x");
    assert!(speed_up >= MIN_SPEED_UP, "only {speed_up:.1}x faster");
}
