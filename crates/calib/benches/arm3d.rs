//! Speed of the spatial arm calibration: the online update (per sample, the 1 kHz station
//! thread's cost), the online estimate, and the batch fit of a 60 s recording at 100 Hz
//! (6 000 samples) per heading model. Data: `gyro_imu`'s arm model over a wheel sweep with
//! 1° white direction noise (seed 7).
//!
//! `cargo bench -p calib --bench arm3d -- --warm-up-time 1 --measurement-time 3`

use calib::arm3d::{
    ArmLoopOptions, ArmLoopSamples, HeadingModel, OnlineArm3d, OnlineArm3dOptions, calibrate_arm_3d,
};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use gyro_imu::arm;
use gyro_imu::sim::arm::{PatientArmConfig, sine_road};
use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::hint::black_box;

type Dirs = Vec<[f64; 3]>;

fn recording(n: usize, rate_hz: f64) -> (Dirs, Dirs, Dirs) {
    let cfg = PatientArmConfig::default();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let noise = Normal::new(0.0, 1f64.to_radians() / 2f64.sqrt()).unwrap();
    let mut perturb = |v: Vector3<f64>| -> [f64; 3] {
        let e1 = v.cross(&Vector3::z()).normalize();
        let e2 = v.cross(&e1);
        (v + e1 * noise.sample(&mut rng) + e2 * noise.sample(&mut rng))
            .normalize()
            .into()
    };
    let (mut u, mut f, mut g) = (vec![], vec![], vec![]);
    for k in 0..n {
        let t = k as f64 / rate_hz;
        let (wheel, _) = sine_road(t, 0.8, 0.2, 0.25, 0.45);
        let (sw, pr) = cfg.posture(t, wheel);
        let st = arm::solve(&cfg.geometry, wheel, sw, pr).unwrap();
        u.push(perturb(st.upper.column(0).into_owned()));
        f.push(perturb(st.fore.column(0).into_owned()));
        g.push(cfg.geometry.grip(wheel).into());
    }
    (u, f, g)
}

fn online(c: &mut Criterion) {
    let (u, f, g) = recording(1000, 1000.0);
    let mut group = c.benchmark_group("arm3d_online");
    group.throughput(Throughput::Elements(u.len() as u64));
    for (name, heading_offset) in [("update_5_unknowns", false), ("update_7_unknowns", true)] {
        let opts = OnlineArm3dOptions {
            heading_offset,
            ..Default::default()
        };
        group.bench_function(format!("{name}_x1000"), |b| {
            let mut est = OnlineArm3d::new(opts).unwrap();
            b.iter(|| {
                for k in 0..u.len() {
                    est.update(black_box(u[k]), black_box(f[k]), black_box(g[k]))
                        .unwrap();
                }
            })
        });
    }
    group.finish();
    let mut est = OnlineArm3d::new(OnlineArm3dOptions::default()).unwrap();
    for k in 0..u.len() {
        est.update(u[k], f[k], g[k]).unwrap();
    }
    c.bench_function("arm3d_online/estimate_7_unknowns", |b| {
        b.iter(|| black_box(&est).estimate().unwrap())
    });
}

fn batch(c: &mut Criterion) {
    let (u, f, g) = recording(6000, 100.0);
    let t: Vec<f64> = (0..u.len()).map(|k| k as f64 / 100.0).collect();
    let s = ArmLoopSamples {
        time_s: Some(&t),
        ..ArmLoopSamples::new(&u, &f, &g)
    };
    let mut group = c.benchmark_group("arm3d_batch_6000_samples");
    for heading in [
        HeadingModel::Exact,
        HeadingModel::Offset,
        HeadingModel::OffsetAndDrift,
    ] {
        let opts = ArmLoopOptions {
            heading,
            ..Default::default()
        };
        group.bench_function(heading.name(), |b| {
            b.iter(|| calibrate_arm_3d(black_box(&s), &opts).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, online, batch);
criterion_main!(benches);
