//! Throughput of gyro integration, orientation fusion, the arm-pose estimator and the guided
//! mounting calibration.
//!
//! `cargo bench -p gyro-imu --bench integration -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use gyro_imu::arm::ArmGeometry;
use gyro_imu::fusion::{FusionConfig, OrientationFilter};
use gyro_imu::integrate::{self, Method, QuatIntegrator};
use gyro_imu::pose::{ArmPoseEstimator, Mounting};
use gyro_imu::sensor::{AccSpec, GyroSpec, SensorModel};
use gyro_imu::sim::arm::{PatientArmConfig, SimArm, sine_road};
use gyro_imu::sim::motion::RandomMotion;
use nalgebra::{UnitQuaternion, Vector3};

const N: usize = 100_000;

fn rates() -> Vec<Vector3<f64>> {
    let mut m = RandomMotion::new(7, 150.0, 0.1, 30.0, 0.0);
    (0..N).map(|_| m.next(1.0 / 286.0).rate_rad_s).collect()
}

fn bench_integration(c: &mut Criterion) {
    let r = rates();
    let mut g = c.benchmark_group("integrate");
    g.throughput(Throughput::Elements(N as u64));
    for m in Method::ALL {
        g.bench_function(m.name(), |b| {
            b.iter(|| integrate::integrate_final(black_box(&r), 1.0 / 286.0, m))
        });
    }
    g.bench_function("streaming_quat", |b| {
        b.iter(|| {
            let mut s = QuatIntegrator::default();
            for w in black_box(&r) {
                s.step(w, 1.0 / 286.0);
            }
            s.orientation()
        })
    });
    g.finish();
}

fn bench_fusion(c: &mut Criterion) {
    let mut m = RandomMotion::new(3, 120.0, 0.15, 40.0, 6.0);
    let mut s =
        SensorModel::new(GyroSpec::consumer_mems(), Some(AccSpec::consumer_mems()), 1).unwrap();
    let data: Vec<_> = (0..N)
        .map(|_| {
            let t = m.next(0.005);
            let r = s.measure(&t.rate_rad_s, &t.specific_force_m_s2, 0.005);
            (r.rate_rad_s, r.acc_m_s2.unwrap())
        })
        .collect();
    let mut g = c.benchmark_group("fusion");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("orientation_filter", |b| {
        b.iter(|| {
            let mut f = OrientationFilter::new(FusionConfig::default()).unwrap();
            for (w, a) in black_box(&data) {
                f.update(w, Some(a), 0.005);
            }
            f.orientation()
        })
    });
    g.finish();

    // One arm-pose estimator tick (two filters + chain fit), the haptic thread's cost.
    let cfg = PatientArmConfig::default();
    let id = UnitQuaternion::identity();
    let mut arm = SimArm::consumer_mems(cfg, id, id, 5).unwrap();
    let ticks: Vec<_> = (0..2000)
        .map(|k| {
            let t = k as f64 * 0.001;
            let (w, wd) = sine_road(t, 0.8, 0.2, 0.25, 0.45);
            arm.step((t * 1e9) as u64, w, wd, 0.001).unwrap();
            let (u, f) = arm.latest().unwrap();
            (w, u, f)
        })
        .collect();
    let mut g = c.benchmark_group("arm_pose");
    g.throughput(Throughput::Elements(ticks.len() as u64));
    g.bench_function("estimator_update", |b| {
        b.iter(|| {
            let mut e = ArmPoseEstimator::new(
                ArmGeometry::default(),
                Mounting {
                    upper: id,
                    fore: id,
                },
                FusionConfig::default(),
            )
            .unwrap();
            let mut last = 0.0;
            for (w, u, f) in black_box(&ticks) {
                last = e.update(*w, u, f, 0.001).unwrap().angles.elbow_flexion_rad;
            }
            last
        })
    });
    g.finish();
}

/// The guided mounting calibration as the station runs it at 1 kHz: 5 s still, 20 s turning
/// the wheel (default patient: swivel follows the wheel and wanders). `add` is the per-tick
/// cost on the haptic thread, `finish` the one-off solve at the end of the procedure.
fn bench_mounting(c: &mut Criterion) {
    use gyro_imu::device::ImuSample;
    use gyro_imu::mounting::MountingCalibrator;
    let cfg = PatientArmConfig::default();
    let id = UnitQuaternion::identity();
    let mut arm = SimArm::consumer_mems(cfg, id, id, 9).unwrap();
    let dt = 0.001;
    let (n_still, n_sweep) = (5_000, 20_000);
    let samples: Vec<(f64, f64, ImuSample, ImuSample)> = (0..n_still + n_sweep)
        .map(|k| {
            let t = k as f64 * dt;
            let (w, wd) = if k < n_still {
                (0.0, 0.0)
            } else {
                sine_road(t - 5.0, 1.0, 0.25, 0.0, 0.1)
            };
            arm.step((t * 1e9) as u64, w, wd, dt).unwrap();
            let (u, f) = arm.latest().unwrap();
            (w, wd, u, f)
        })
        .collect();
    let fill = || {
        let mut cal = MountingCalibrator::new(cfg.geometry, cfg.swivel_mean_rad).unwrap();
        cal.reserve_motion(n_sweep);
        for (k, (w, wd, u, f)) in samples.iter().enumerate() {
            if k < n_still {
                cal.add_still(*w, u, f).unwrap();
            } else {
                cal.add_motion(*w, *wd, u, f).unwrap();
            }
        }
        cal
    };
    let mut g = c.benchmark_group("mounting");
    g.throughput(Throughput::Elements(samples.len() as u64));
    g.bench_function("add_25k_samples", |b| b.iter(|| black_box(fill())));
    g.finish();
    let cal = fill();
    let mut g = c.benchmark_group("mounting");
    g.sample_size(10);
    g.bench_function("finish_20k_sweep", |b| {
        b.iter(|| black_box(cal.finish().unwrap()))
    });
    g.finish();
}

criterion_group!(benches, bench_integration, bench_fusion, bench_mounting);
criterion_main!(benches);
