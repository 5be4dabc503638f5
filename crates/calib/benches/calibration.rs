//! Speed of the calibration methods on a 20 s recording at 100 Hz (2 000 samples), and of the
//! serial-chain calibration of the thesis's two-link example.
//!
//! `cargo bench -p calib --bench calibration -- --warm-up-time 1 --measurement-time 3`

use calib::fourbar::testdata;
use calib::serial::end_pose;
use calib::{
    FourbarMethod, FourbarOptions, FourbarParams, FourbarSamples, OnlineFourbar, OnlineOptions,
    SerialOptions, calibrate, calibrate_serial_chain, se3,
};
use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Matrix3, Matrix4, Vector3, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::hint::black_box;

/// The shared ±60° recording of 2 000 samples with 0.5° of Gaussian noise on φ3 and φ4.
fn recording() -> (Vec<f64>, Vec<f64>, Vec<f64>, FourbarParams) {
    let mut rec = testdata::recording(2000, 60.0);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let noise = Normal::new(0.0, 0.5f64.to_radians()).unwrap();
    for v in rec.phi3.iter_mut().chain(rec.phi4.iter_mut()) {
        *v += noise.sample(&mut rng);
    }
    (rec.phi2, rec.phi3, rec.phi4, rec.truth)
}

fn fourbar(c: &mut Criterion) {
    let (phi2, phi3, phi4, truth) = recording();
    let s = FourbarSamples::new(&phi2, &phi3, &phi4);
    let start = FourbarParams {
        l3_m: 0.3,
        l4_m: 0.35,
        ..truth
    };
    let mut group = c.benchmark_group("fourbar_2000_samples");
    let plain = FourbarOptions {
        gyro_bias: false,
        robust: false,
        errors_in_variables: false,
        ..Default::default()
    };
    for (name, method, initial, base) in [
        (
            "global",
            FourbarMethod::Global,
            None,
            FourbarOptions::default(),
        ),
        ("auto", FourbarMethod::Auto, None, FourbarOptions::default()),
        ("thesis_gn", FourbarMethod::Thesis, Some(start), plain),
        (
            "lm",
            FourbarMethod::Lm,
            Some(start),
            FourbarOptions::default(),
        ),
        (
            "lm_plain_least_squares",
            FourbarMethod::Lm,
            Some(start),
            plain,
        ),
    ] {
        let o = FourbarOptions {
            method,
            initial,
            ..base
        };
        group.bench_function(name, |b| {
            b.iter(|| calibrate(black_box(&s), testdata::L2, &o).unwrap())
        });
    }
    group.bench_function("online_update_and_estimate", |b| {
        b.iter(|| {
            let mut est = OnlineFourbar::new(testdata::L2, OnlineOptions::default()).unwrap();
            for k in 0..phi2.len() {
                est.update(phi2[k], phi3[k], phi4[k]).unwrap();
            }
            est.estimate().unwrap()
        })
    });
    group.finish();
}

fn serial(c: &mut Criterion) {
    let rz = |q: f64| se3::exp(&Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, q));
    let tx = |l: f64| se3::from_parts(&Matrix3::identity(), &Vector3::new(l, 0.0, 0.0));
    let truth = [Matrix4::identity(), tx(0.6), tx(1.0)];
    let nominal = [Matrix4::identity(), tx(1.2991), tx(0.5)];
    let mut motions = Vec::new();
    let mut measured = Vec::new();
    for k in 0..20 {
        let qs = [rz(0.1 * k as f64 - 1.0), rz(1.0 - 0.13 * k as f64)];
        measured.push(end_pose(&truth, &qs));
        motions.extend(qs);
    }
    c.bench_function("serial_rr_table_4_2_20_poses", |b| {
        b.iter(|| {
            calibrate_serial_chain(&nominal, &motions, &measured, &SerialOptions::default())
                .unwrap()
        })
    });
}

criterion_group!(benches, fourbar, serial);
criterion_main!(benches);
