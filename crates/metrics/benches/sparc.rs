//! Benchmark: SPARC and LDLJ of a 60 s, 100 Hz speed profile (6000 samples; FFT of 131 072
//! points), deterministic input (a train of minimum-jerk submovements, no RNG).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use metrics::{SparcParams, ldlj_speed, sparc};

fn signal() -> Vec<f64> {
    (0..6000)
        .map(|i| {
            // One 1.5 s minimum-jerk submovement every 2 s.
            let t = (f64::from(i) * 0.01) % 2.0 / 1.5;
            if t < 1.0 {
                30.0 * t.powi(2) * (1.0 - t).powi(2)
            } else {
                0.0
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let v = signal();
    c.bench_function("sparc_60s_100hz", |b| {
        b.iter(|| sparc(black_box(&v), 100.0, SparcParams::default()).unwrap())
    });
    c.bench_function("ldlj_60s_100hz", |b| {
        b.iter(|| ldlj_speed(black_box(&v), 100.0).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
