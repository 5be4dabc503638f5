//! Per-tick cost of the whole simulated plant (wheel, patient, car, road, score, safety
//! chain): what the 1 kHz haptic thread computes each period.

use criterion::{Criterion, criterion_group, criterion_main};
use session::config::StationConfig;
use session::{course, plant::Plant};
use std::hint::black_box;

fn bench_tick(c: &mut Criterion) {
    let cfg = StationConfig::default();
    let mut plant = Plant::simulated(
        &cfg,
        course::build(&cfg, None).expect("the default course builds"),
    )
    .expect("the default configuration builds");
    c.bench_function("sim_plant_tick", |b| b.iter(|| black_box(plant.tick())));
}

criterion_group!(benches, bench_tick);
criterion_main!(benches);
