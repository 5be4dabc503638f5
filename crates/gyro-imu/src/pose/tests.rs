use super::*;
use crate::arm::ArmGeometry;
use crate::mounting::MountingCalibrator;
use crate::sensor::{AccSpec, GyroSpec};
use crate::sim::arm::{PatientArmConfig, SimArm, sine_road};
use crate::so3;

/// Envelope (and its rate) that is 0 for 5 s of every 40 s and 1 elsewhere, with 1 s
/// smoothstep ramps.
fn straights(t: f64) -> (f64, f64) {
    let ph = t % 40.0;
    let ramp = |x: f64| (x * x * (3.0 - 2.0 * x), 6.0 * x * (1.0 - x));
    if ph < 5.0 {
        (0.0, 0.0)
    } else if ph < 6.0 {
        ramp(ph - 5.0)
    } else if ph > 39.0 {
        let (v, d) = ramp(40.0 - ph);
        (v, -d)
    } else {
        (1.0, 0.0)
    }
}

/// RMS errors (deg) of the five joint angles and the session's ROM error, for a simulated
/// session: guided mounting calibration, then `minutes` of sine-road steering.
fn session(
    seed: u64,
    minutes: f64,
    dt: f64,
    gyro: GyroSpec,
    acc: Option<AccSpec>,
) -> ([f64; 5], [f64; 5]) {
    let mu = so3::exp_quat(&Vector3::new(0.5 + seed as f64, -2.0, 1.0));
    let mf = so3::exp_quat(&Vector3::new(-1.5, 0.7 * seed as f64, 2.5));
    let session_cfg = PatientArmConfig::default();
    let cal_cfg = PatientArmConfig {
        swivel_amp_rad: 0.0,
        swivel_per_wheel: 0.0,
        ..session_cfg
    };
    let mut arm = SimArm::new(cal_cfg, gyro, acc, mu, mf, seed).unwrap();
    // Guided mounting calibration: 5 s still, 20 s of ±57° turning.
    let mut cal = MountingCalibrator::new(cal_cfg.geometry, cal_cfg.swivel_mean_rad).unwrap();
    let (n_still, n_move) = ((5.0 / dt) as usize, (20.0 / dt) as usize);
    for k in 0..n_still + n_move {
        let (w, wd) = if k < n_still {
            (0.0, 0.0)
        } else {
            sine_road((k - n_still) as f64 * dt, 1.0, 0.25, 0.0, 0.1)
        };
        arm.step((k as f64 * dt * 1e9) as u64, w, wd, dt).unwrap();
        let (u, f) = arm.latest().unwrap();
        if k < n_still {
            cal.add_still(w, &u, &f).unwrap()
        } else {
            cal.add_motion(w, wd, &u, &f).unwrap()
        }
    }
    let mounting = cal.finish().unwrap().mounting;
    // The session: the patient's swivel now wanders and follows the wheel.
    let mut arm = SimArm::new(session_cfg, gyro, acc, mu, mf, seed + 1000).unwrap();
    let mut est =
        ArmPoseEstimator::new(session_cfg.geometry, mounting, FusionConfig::default()).unwrap();
    let n = (minutes * 60.0 / dt) as usize;
    let mut sq = [0.0; 5];
    let mut truth_rom = RangeOfMotion::default();
    let mut count = 0;
    for k in 0..n {
        let t = k as f64 * dt;
        // Sine road: 46° at 0.2 Hz plus 14° at 0.45 Hz, with a 5 s straight (rest) every
        // 40 s, entered and left smoothly.
        let (e, ed) = straights(t);
        let (r, rd) = sine_road(t, 0.8, 0.2, 0.25, 0.45);
        let (w, wd) = (e * r, ed * r + e * rd);
        let truth = arm.step((t * 1e9) as u64, w, wd, dt).unwrap();
        let (u, f) = arm.latest().unwrap();
        let pose = est.update(w, &u, &f, dt).unwrap();
        if t < 10.0 {
            continue; // settling (first LPF time constants)
        }
        truth_rom.update(&truth.angles);
        let (a, b) = (pose.angles.to_array(), truth.angles.to_array());
        for i in 0..5 {
            let d = (a[i] - b[i] + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            sq[i] += d * d;
        }
        count += 1;
    }
    let rms = sq.map(|s| (s / count as f64).sqrt().to_degrees());
    let est_rng = est.range_of_motion().range_rad();
    let true_rng = truth_rom.range_rad();
    let rom_err = std::array::from_fn(|i| (est_rng[i] - true_rng[i]).to_degrees());
    (rms, rom_err)
}

#[test]
fn ten_minute_simulated_session_joint_angles_within_2_deg_rms() {
    let (rms, rom) = session(
        1,
        10.0,
        1.0 / 200.0,
        GyroSpec::consumer_mems(),
        Some(AccSpec::consumer_mems()),
    );
    println!("| angle | RMS error (deg) | ROM error (deg) |\n|---|---|---|");
    for i in 0..5 {
        println!(
            "| {} | {:.3} | {:.3} |",
            JointAngles::NAMES[i],
            rms[i],
            rom[i]
        );
    }
    for (i, e) in rms.iter().enumerate().take(4) {
        assert!(*e < 2.0, "{} RMS {e}°", JointAngles::NAMES[i]);
    }
    assert!(rms[4] < 3.0, "pronation RMS {}°", rms[4]);
}

#[test]
fn estimator_rejects_nan_wheel_and_unreachable_geometry() {
    let m = Mounting {
        upper: UnitQuaternion::identity(),
        fore: UnitQuaternion::identity(),
    };
    let mut est =
        ArmPoseEstimator::new(ArmGeometry::default(), m, FusionConfig::default()).unwrap();
    let s = ImuSample {
        t_ns: 0,
        rate_rad_s: Vector3::zeros(),
        acc_m_s2: Some(Vector3::z() * 9.81),
    };
    assert!(est.update(f64::NAN, &s, &s, 0.005).is_err());
    let far = ArmGeometry {
        shoulder_m: [-1.5, 0.0, 0.0],
        ..Default::default()
    };
    assert!(ArmPoseEstimator::new(far, m, FusionConfig::default()).is_err());
}

/// With ideal sensors the only errors left are the model's and the filters': near zero.
#[test]
fn ideal_sensors_give_joint_angles_within_0_1_deg() {
    let ideal_acc = AccSpec {
        resolution_m_s2: 0.0,
        bias_std_m_s2: 0.0,
        noise_density_m_s2_sqrt_hz: 0.0,
        saturation_m_s2: 100.0,
    };
    let (rms, _) = session(1, 2.0, 1.0 / 200.0, GyroSpec::ideal(), Some(ideal_acc));
    assert!(rms.iter().all(|e| *e < 0.1), "{rms:?}");
}
