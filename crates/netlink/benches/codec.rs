//! Encode/decode throughput of the wire format (summary frames, the hot path: 10 Hz per
//! station, many stations per hub).

use std::collections::BTreeMap;
use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use netlink::{Frame, FrameDecoder, Summary, decode, encode};

fn summary(seq: u64, extra: usize) -> Summary {
    Summary {
        session_id: "2026-11-21T09-30-00Z".into(),
        seq,
        t_s: seq as f64 * 0.1,
        exercise: "sine-road".into(),
        speed_m_s: 12.5 + (seq % 7) as f64 * 0.01,
        lateral_m: -0.253_771,
        rms_lateral_m: 0.310_224,
        max_lateral_m: 0.912_5,
        pct_in_lane: 97.512_3,
        max_abs_torque_nm: 1.234_5,
        loop_p99_us: 45.25,
        ticks: seq * 100,
        dropped_records: 0,
        extra: (0..extra)
            .map(|k| (format!("metric_{k:02}"), k as f64 * 0.123_456_789))
            .collect::<BTreeMap<_, _>>(),
    }
}

fn bench_codec(c: &mut Criterion) {
    assert_eq!(netlink::codec::HEADER_VERSION, 1);
    let mut group = c.benchmark_group("summary_frame");
    for extra in [0usize, 16] {
        let frame = Frame::Summary(summary(123_456, extra));
        let mut bytes = Vec::new();
        encode(&frame, &mut bytes).unwrap();
        group.throughput(Throughput::Elements(1));
        group.bench_with_input(BenchmarkId::new("encode", extra), &frame, |b, f| {
            let mut out = Vec::with_capacity(1024);
            b.iter(|| {
                out.clear();
                encode(black_box(f), &mut out).unwrap();
                black_box(out.len())
            })
        });
        group.bench_with_input(BenchmarkId::new("decode", extra), &bytes, |b, bytes| {
            b.iter(|| decode(black_box(bytes)).unwrap().unwrap().1)
        });
        println!(
            "summary frame with {extra} extra metrics: {} bytes",
            bytes.len()
        );
    }
    group.finish();

    // A stream of 1 000 frames fed in 1 400-byte chunks (a typical TCP segment).
    let mut stream = Vec::new();
    for seq in 0..1_000 {
        encode(&Frame::Summary(summary(seq, 4)), &mut stream).unwrap();
    }
    let mut group = c.benchmark_group("decoder_stream");
    group.throughput(Throughput::Bytes(stream.len() as u64));
    group.bench_function("1000_summaries_in_1400_byte_chunks", |b| {
        b.iter(|| {
            let mut dec = FrameDecoder::new();
            let mut n = 0;
            for chunk in stream.chunks(1_400) {
                dec.extend(chunk);
                while dec.next_frame().unwrap().is_some() {
                    n += 1;
                }
            }
            assert_eq!(n, 1_000);
            n
        })
    });
    group.finish();
}

criterion_group!(benches, bench_codec);
criterion_main!(benches);
