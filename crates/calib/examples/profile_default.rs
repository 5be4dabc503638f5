//! Time of the default calibration calls on the held-out-style cases of the Python benchmark
//! (`pyext/bench/bench_vs_scipy.py`), for profiling (`perf record` on it) and before/after
//! checks; prints the median time of many calls and the errors against the truth.
//!
//! - `planar`: `calibrate` with the default options (`auto`: noise profile, robust corrected
//!   global start, robust LM with gyro-bias terms), wheel ±60° at 0.2 Hz, 100 Hz, 0.5° of white
//!   noise on φ3 and φ4, no timestamps (as the Python benchmark calls it).
//! - `arm3d`: `calibrate_arm_3d` with the default options (`offset_and_drift`, errors in
//!   variables), `gyro_imu`'s default patient on the two-sine road, 1° of white direction noise
//!   and a heading error of +3° / −2° drifting by +2 / −1.5 °/min.
//!
//! `cargo run --release -p calib --example profile_default [planar|arm3d] [samples] [calls]`

use calib::fourbar::testdata;
use calib::{
    ArmLoopOptions, ArmLoopSamples, FourbarOptions, FourbarSamples, calibrate, calibrate_arm_3d,
};
use gyro_imu::arm;
use gyro_imu::sim::arm::{PatientArmConfig, sine_road};
use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::time::Instant;

/// Median and minimum (µs) of `calls` calls of `f`, and its last result. (The clock is read
/// here, in the timing example, never in the library.)
#[allow(clippy::disallowed_methods)]
fn timed<T>(calls: usize, mut f: impl FnMut() -> T) -> (f64, f64, T) {
    let mut times_us = Vec::with_capacity(calls);
    let mut last = None;
    for _ in 0..calls {
        let t0 = Instant::now();
        last = Some(f());
        times_us.push(t0.elapsed().as_secs_f64() * 1e6);
    }
    times_us.sort_by(f64::total_cmp);
    (
        times_us[calls / 2],
        times_us[0],
        last.expect("at least one call"),
    )
}

fn planar(n: usize, calls: usize) {
    let mut rec = testdata::recording(n, 60.0);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let noise = Normal::new(0.0, 0.5f64.to_radians()).expect("σ > 0");
    for v in rec.phi3.iter_mut().chain(rec.phi4.iter_mut()) {
        *v += noise.sample(&mut rng);
    }
    let s = FourbarSamples::new(&rec.phi2, &rec.phi3, &rec.phi4);
    let options = FourbarOptions::default();
    let (median, min, c) = timed(calls, || {
        calibrate(std::hint::black_box(&s), testdata::L2, &options).expect("calibrates")
    });
    let t = &rec.truth;
    println!(
        "planar, {n} samples, {calls} calls: median {median:.1} µs (min {min:.1}); iterations {}; \
         l1 {:+.3} % l3 {:+.3} % l4 {:+.3} %; outliers {:.3}",
        c.iterations,
        100.0 * (c.params.l1_m / t.l1_m - 1.0),
        100.0 * (c.params.l3_m / t.l3_m - 1.0),
        100.0 * (c.params.l4_m / t.l4_m - 1.0),
        c.outlier_fraction
    );
}

fn arm3d(n: usize, calls: usize) {
    let cfg = PatientArmConfig::default();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let noise = Normal::new(0.0, 1f64.to_radians() / 2f64.sqrt()).expect("σ > 0");
    let (offset, rate) = (
        [3f64.to_radians(), -2f64.to_radians()],
        [2f64.to_radians() / 60.0, -1.5f64.to_radians() / 60.0],
    );
    let (mut u, mut f, mut g, mut time_s) = (vec![], vec![], vec![], vec![]);
    for k in 0..n {
        let t = k as f64 / 100.0;
        let (wheel, _) = sine_road(t, 0.8, 0.2, 0.25, 0.45);
        let (swivel, pronation) = cfg.posture(t, wheel);
        let st = arm::solve(&cfg.geometry, wheel, swivel, pronation).expect("reachable");
        for (seg, (dirs, axis)) in [(&mut u, st.upper.column(0)), (&mut f, st.fore.column(0))]
            .into_iter()
            .enumerate()
        {
            let v = Vector3::from(axis.into_owned());
            let e1 = v.cross(&Vector3::z()).normalize();
            let e2 = v.cross(&e1);
            let w = (v + e1 * noise.sample(&mut rng) + e2 * noise.sample(&mut rng)).normalize();
            let (s, c) = (offset[seg] + rate[seg] * t).sin_cos();
            dirs.push([c * w.x - s * w.y, s * w.x + c * w.y, w.z]);
        }
        g.push(cfg.geometry.grip(wheel).into());
        time_s.push(t);
    }
    let s = ArmLoopSamples {
        time_s: Some(&time_s),
        ..ArmLoopSamples::new(&u, &f, &g)
    };
    let options = ArmLoopOptions::default();
    let (median, min, c) = timed(calls, || {
        calibrate_arm_3d(std::hint::black_box(&s), &options).expect("calibrates")
    });
    let geo = &cfg.geometry;
    println!(
        "arm3d, {n} samples, {calls} calls: median {median:.1} µs (min {min:.1}); passes {}; \
         upper arm {:+.2} mm, forearm {:+.2} mm",
        c.iterations,
        1e3 * (c.params.upper_arm_m - geo.upper_arm_m),
        1e3 * (c.params.forearm_m - geo.forearm_m),
    );
}

fn main() {
    let mut args = std::env::args().skip(1);
    let which = args.next().unwrap_or_else(|| "planar".into());
    let n: usize = args.next().map_or(6000, |a| a.parse().expect("samples"));
    let calls: usize = args
        .next()
        .map_or(300, |a| a.parse().expect("calls"))
        .max(1);
    match which.as_str() {
        "planar" => planar(n, calls),
        "arm3d" => arm3d(n, calls),
        other => panic!("unknown case {other:?}: planar or arm3d"),
    }
}
