//! Benchmarks: model steps per second, rapier world steps per second (must be ≥ 100× real
//! time at 1 kHz, i.e. ≥ 100 000 steps/s) and road lookups. Deterministic inputs, no RNG.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use exercises::{
    DriverInput, ExerciseSpec, PreviewDriver, SpeedController, Vehicle, VehicleParams, World,
};

const STEPS: u64 = 1000;

fn model_steps(c: &mut Criterion) {
    let mut g = c.benchmark_group("model");
    g.throughput(Throughput::Elements(STEPS));
    for (name, params) in [
        ("step_linear_1ms", VehicleParams::thesis_linear()),
        ("step_saturating_1ms", VehicleParams::default()),
    ] {
        let ex = ExerciseSpec::from_name("sine-road")
            .unwrap()
            .build()
            .unwrap();
        let mut car = Vehicle::new(params, ex.start_state());
        g.bench_function(name, |b| {
            b.iter(|| {
                for i in 0..STEPS {
                    let steer = 0.02 * (i as f64 * 0.01).sin();
                    car.step(
                        DriverInput {
                            steer_rad: steer,
                            drive_force_n: 200.0,
                            brake_force_n: 0.0,
                        },
                        black_box(1e-3),
                    );
                }
                black_box(car.state());
            })
        });
    }
    g.finish();
}

fn world_steps(c: &mut Criterion) {
    let mut g = c.benchmark_group("world");
    g.throughput(Throughput::Elements(STEPS));
    // The rapier world alone: open-loop gentle sine steering on the sine road's track.
    {
        let ex = ExerciseSpec::from_name("sine-road")
            .unwrap()
            .build()
            .unwrap();
        let params = VehicleParams::default();
        // The free path (the product's) and rapier's whole pipeline (the reference), same steps.
        for (label, pipeline) in [
            ("step_1ms_open_loop", false),
            ("step_1ms_open_loop_rapier_pipeline", true),
        ] {
            let new = || {
                let w = World::new(params.clone(), ex.start_state(), ex.track_layout()).unwrap();
                if pipeline {
                    w.with_rapier_pipeline()
                } else {
                    w
                }
            };
            let mut world = new();
            let mut i = 0u64;
            g.bench_function(label, |b| {
                b.iter(|| {
                    for _ in 0..STEPS {
                        i += 1;
                        if i.is_multiple_of(20_000) {
                            world = new();
                        }
                        let steer = 0.01 * (i as f64 * 1e-3).sin();
                        world.step(
                            DriverInput {
                                steer_rad: steer,
                                drive_force_n: 100.0,
                                brake_force_n: 0.0,
                            },
                            1e-3,
                        );
                    }
                    black_box(world.drain_events());
                })
            });
        }
    }
    for name in ["sine-road", "slalom"] {
        let ex = ExerciseSpec::from_name(name).unwrap().build().unwrap();
        let road = ex.road.as_ref().unwrap();
        let params = VehicleParams::default();
        let driver = PreviewDriver::default();
        let mut world = World::new(params.clone(), ex.start_state(), ex.track_layout()).unwrap();
        let mut s_hint = 0.0;
        // A closed loop: the preview driver drives the rapier car along the road; the world
        // is reset to the start when it reaches the end so every iteration does the same work.
        g.bench_function(format!("driven_step_1ms_{name}"), |b| {
            b.iter(|| {
                for _ in 0..STEPS {
                    let st = world.state();
                    let here = road.project(st.x_m, st.y_m, s_hint);
                    s_hint = here.s_m;
                    if here.s_m > ex.length_m - 5.0 {
                        world = World::new(params.clone(), ex.start_state(), ex.track_layout())
                            .unwrap();
                        s_hint = 0.0;
                        continue;
                    }
                    let steer = driver.desired_steer_rad(&params, &st, &here, road.as_ref());
                    let input = SpeedController {
                        target_m_s: ex.target_speed_m_s(here.s_m),
                        gain_n_per_m_s: 3000.0,
                        max_force_n: 8000.0,
                    }
                    .input(st.ux_m_s, steer);
                    world.step(input, 1e-3);
                }
                black_box(world.drain_events());
            })
        });
    }
    g.finish();
}

fn road_lookups(c: &mut Criterion) {
    let mut g = c.benchmark_group("road");
    g.throughput(Throughput::Elements(STEPS));
    for name in ["sine-road", "clothoid-road"] {
        let ex = ExerciseSpec::from_name(name).unwrap().build().unwrap();
        let road = ex.road.unwrap();
        let len = ex.length_m;
        g.bench_function(format!("centre_{name}"), |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for i in 0..STEPS {
                    let s = (i as f64 * 0.137) % len;
                    acc += road.centre(black_box(s)).1;
                }
                black_box(acc)
            })
        });
        // A car moving forward 12 mm per tick, 0.5 m left of the centre line.
        g.bench_function(format!("project_forward_{name}"), |b| {
            b.iter(|| {
                let mut hint = 50.0;
                for i in 0..STEPS {
                    let s = 50.0 + i as f64 * 0.012;
                    let ([x, y], h, _) = road.centre(s);
                    let p = road.project(x - 0.5 * h.sin(), y + 0.5 * h.cos(), hint);
                    hint = p.s_m;
                }
                black_box(hint)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, model_steps, world_steps, road_lookups);
criterion_main!(benches);
