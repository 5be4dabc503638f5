//! Per-tick cost of `Assist::step` for every mode (the 1 kHz haptic loop's budget is 1 ms).
//!
//! `cargo bench -p assist --bench step -- --warm-up-time 1 --measurement-time 3`

use assist::{
    AanParams, Assist, AssistMode, AssistSpec, ForceParams, HybridParams, Limits, Measurement,
    ModelSpec, MotionParams, ResistParams,
};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

fn bench_step(c: &mut Criterion) {
    let limits = Limits {
        ceiling_nm: 1.87,
        slew_nm_per_s: 50.0,
    };
    let modes = [
        ("none", AssistMode::None {}),
        ("resist", AssistMode::Resist(ResistParams::default())),
        ("motion", AssistMode::Motion(MotionParams::default())),
        ("force", AssistMode::Force(ForceParams::default())),
        ("hybrid", AssistMode::Hybrid(HybridParams::default())),
        (
            "assist_as_needed",
            AssistMode::AssistAsNeeded(AanParams::default()),
        ),
    ];
    let mut group = c.benchmark_group("assist_step");
    for (name, mode) in modes {
        let spec = AssistSpec {
            model: ModelSpec::default(),
            mode,
        };
        let mut assist = Assist::new(&spec).expect("default spec is valid");
        let mut i = 0u64;
        group.bench_function(name, |b| {
            b.iter(|| {
                // A moving dial reference and a wheel lagging it, deterministic.
                let t = i as f64 * 0.001;
                i += 1;
                let reference = 0.7 * (1.57 * t).sin();
                let m = Measurement {
                    angle_rad: 0.6 * (1.57 * t - 0.2).sin(),
                    vel_rad_s: 0.94 * (1.57 * t - 0.2).cos(),
                };
                black_box(assist.step(black_box(m), black_box(reference), limits, 0.001))
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_step);
criterion_main!(benches);
