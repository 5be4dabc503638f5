//! Accuracy of the spatial arm calibration (`calib::arm3d`) under direction noise and IMU
//! heading drift: the table in BENCHMARKS.md.
//!
//! `cargo run --release -p calib --example arm3d_noise_study`
//!
//! Truth: `gyro_imu`'s default patient (shoulder (−0.42, −0.17, 0.25) m, upper arm 0.30 m,
//! forearm 0.33 m, 0.14 m rim tilted 20°) turning the wheel by a two-sine road (about ±60°),
//! elbow swivel following the wheel plus a slow free oscillation. 60 s per recording, 10 seeds
//! per row; figures are the mean |error| over the seeds.

use calib::arm3d::{
    ArmLoopOptions, ArmLoopSamples, HeadingModel, OnlineArm3d, OnlineArm3dOptions, calibrate_arm_3d,
};
use gyro_imu::arm;
use gyro_imu::fusion::{FusionConfig, OrientationFilter};
use gyro_imu::sim::arm::{PatientArmConfig, SimArm, sine_road};
use nalgebra::{UnitQuaternion, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

type Dirs = Vec<[f64; 3]>;

struct Rec {
    u: Dirs,
    f: Dirs,
    g: Dirs,
    t: Vec<f64>,
}

/// How the measured directions differ from the truth.
#[derive(Clone, Copy)]
enum Noise {
    /// White, RMS angle (deg).
    White(f64),
    /// Gauss–Markov (first order, time constant 1 s), RMS angle (deg).
    Colored(f64),
    /// Heading drift (deg/min) of upper and forearm, plus white noise (deg).
    Drift(f64, f64, f64),
    /// The real pipeline: simulated consumer MEMS IMUs (gyro + accelerometer, 1 kHz) through
    /// the orientation filter (`gyro_imu::fusion`), mounting known; decimated to 100 Hz.
    Imu,
}

fn truth_rec(seconds: f64, rate_hz: f64) -> Rec {
    let cfg = PatientArmConfig::default();
    let n = (seconds * rate_hz) as usize;
    let mut r = Rec {
        u: vec![],
        f: vec![],
        g: vec![],
        t: vec![],
    };
    for k in 0..n {
        let t = k as f64 / rate_hz;
        let (wheel, _) = sine_road(t, 0.8, 0.2, 0.25, 0.45);
        let (sw, pr) = cfg.posture(t, wheel);
        let st = arm::solve(&cfg.geometry, wheel, sw, pr).unwrap();
        r.u.push(st.upper.column(0).into_owned().into());
        r.f.push(st.fore.column(0).into_owned().into());
        r.g.push(cfg.geometry.grip(wheel).into());
        r.t.push(t);
    }
    r
}

fn tangent_basis(v: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let e1 = v.cross(&Vector3::z()).normalize();
    (e1, v.cross(&e1))
}

fn recording(noise: Noise, seed: u64) -> Rec {
    if let Noise::Imu = noise {
        return imu_rec(seed);
    }
    let mut r = truth_rec(60.0, 100.0);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let std = Normal::new(0.0, 1.0).unwrap();
    let (white, colored, drift) = match noise {
        Noise::White(d) => (d, 0.0, [0.0; 2]),
        Noise::Colored(d) => (0.0, d, [0.0; 2]),
        Noise::Drift(a, b, w) => (w, 0.0, [a, b]),
        Noise::Imu => unreachable!(),
    };
    let a = (-0.01f64 / 1.0).exp();
    for (seg, dirs) in [&mut r.u, &mut r.f].into_iter().enumerate() {
        let mut state = [
            std.sample(&mut rng) * colored.to_radians() / 2f64.sqrt(),
            std.sample(&mut rng) * colored.to_radians() / 2f64.sqrt(),
        ];
        for (d, t) in dirs.iter_mut().zip(&r.t) {
            let v = Vector3::from(*d);
            let (e1, e2) = tangent_basis(&v);
            let s = white.to_radians() / 2f64.sqrt();
            let q = colored.to_radians() / 2f64.sqrt() * (1.0 - a * a).sqrt();
            for x in state.iter_mut() {
                *x = a * *x + q * std.sample(&mut rng);
            }
            let w = (v
                + e1 * (s * std.sample(&mut rng) + state[0])
                + e2 * (s * std.sample(&mut rng) + state[1]))
                .normalize();
            let psi = (drift[seg] / 60.0).to_radians() * t;
            let (sn, c) = psi.sin_cos();
            *d = [c * w.x - sn * w.y, sn * w.x + c * w.y, w.z];
        }
    }
    r
}

fn imu_rec(seed: u64) -> Rec {
    let cfg = PatientArmConfig::default();
    let id = UnitQuaternion::identity();
    let mut sim = SimArm::consumer_mems(cfg, id, id, seed).unwrap();
    let mut fu = OrientationFilter::new(FusionConfig::default()).unwrap();
    let mut ff = OrientationFilter::new(FusionConfig::default()).unwrap();
    let dt = 0.001;
    let mut r = Rec {
        u: vec![],
        f: vec![],
        g: vec![],
        t: vec![],
    };
    for k in 0..60_000 {
        let t = k as f64 * dt;
        let (wheel, rate) = sine_road(t, 0.8, 0.2, 0.25, 0.45);
        let truth = sim.step((t * 1e9) as u64, wheel, rate, dt).unwrap();
        if k == 0 {
            fu.set_orientation(truth.upper_sensor);
            ff.set_orientation(truth.fore_sensor);
        }
        let (su, sf) = sim.latest().unwrap();
        let qu = fu.update(&su.rate_rad_s, su.acc_m_s2.as_ref(), dt);
        let qf = ff.update(&sf.rate_rad_s, sf.acc_m_s2.as_ref(), dt);
        if k % 10 == 0 {
            // segment = sensor · mount⁻¹ (identity here); the long axis is x
            r.u.push((qu * Vector3::x()).into());
            r.f.push((qf * Vector3::x()).into());
            r.g.push(cfg.geometry.grip(wheel).into());
            r.t.push(t);
        }
    }
    r
}

#[derive(Default)]
struct Row {
    upper_mm: f64,
    fore_mm: f64,
    shoulder_mm: f64,
    se_upper_mm: f64,
    n: usize,
    fails: usize,
}

const METHODS: [&str; 5] = [
    "exact, no EiV",
    "exact",
    "offset",
    "offset_and_drift",
    "online",
];

fn fit(r: &Rec, method: &str) -> Result<calib::Arm3dCalibration, calib::CalibError> {
    if method == "online" {
        let mut est = OnlineArm3d::new(OnlineArm3dOptions {
            forgetting: 1.0,
            ..Default::default()
        })?;
        for k in 0..r.u.len() {
            est.update(r.u[k], r.f[k], r.g[k])?;
        }
        return est.estimate();
    }
    let (heading, errors_in_variables) = match method {
        "exact, no EiV" => (HeadingModel::Exact, false),
        "exact" => (HeadingModel::Exact, true),
        "offset" => (HeadingModel::Offset, true),
        _ => (HeadingModel::OffsetAndDrift, true),
    };
    let s = ArmLoopSamples {
        time_s: Some(&r.t),
        ..ArmLoopSamples::new(&r.u, &r.f, &r.g)
    };
    calibrate_arm_3d(
        &s,
        &ArmLoopOptions {
            heading,
            errors_in_variables,
            ..Default::default()
        },
    )
}

/// Mean |error| per method over 10 seeds.
fn run(noise: Noise) -> Vec<Row> {
    let geo = PatientArmConfig::default().geometry;
    let mut rows: Vec<Row> = METHODS.iter().map(|_| Row::default()).collect();
    for seed in 0..10 {
        let r = recording(noise, 1000 + seed);
        for (row, m) in rows.iter_mut().zip(METHODS) {
            match fit(&r, m) {
                Ok(c) => {
                    row.upper_mm += (c.params.upper_arm_m - geo.upper_arm_m).abs() * 1e3;
                    row.fore_mm += (c.params.forearm_m - geo.forearm_m).abs() * 1e3;
                    row.shoulder_mm +=
                        (Vector3::from(c.params.shoulder_m) - geo.shoulder()).norm() * 1e3;
                    row.se_upper_mm += c.std_errors.upper_arm_m * 1e3;
                    row.n += 1;
                }
                Err(_) => row.fails += 1,
            }
        }
    }
    for row in &mut rows {
        let n = row.n.max(1) as f64;
        row.upper_mm /= n;
        row.fore_mm /= n;
        row.shoulder_mm /= n;
        row.se_upper_mm /= n;
    }
    rows
}

fn main() {
    let scenarios = [
        ("none", Noise::White(0.0)),
        ("white 1°", Noise::White(1.0)),
        ("white 2°", Noise::White(2.0)),
        ("coloured 1.5° (τ = 1 s)", Noise::Colored(1.5)),
        ("drift +2 / −1.5 °/min", Noise::Drift(2.0, -1.5, 0.0)),
        (
            "drift +2 / −1.5 °/min + white 1.5°",
            Noise::Drift(2.0, -1.5, 1.5),
        ),
        ("simulated IMUs + orientation filter", Noise::Imu),
    ];
    println!(
        "| direction error | fit | upper arm |err| mm | forearm |err| mm | shoulder |err| mm | reported σ upper mm | failures |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (name, noise) in scenarios {
        for (m, r) in METHODS.iter().zip(run(noise)) {
            println!(
                "| {name} | {m} | {:.2} | {:.2} | {:.2} | {:.2} | {}/10 |",
                r.upper_mm, r.fore_mm, r.shoulder_mm, r.se_upper_mm, r.fails
            );
        }
    }
}
