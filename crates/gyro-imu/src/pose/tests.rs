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

/// [`ArmPoseEstimator::update`] as it was written before the fit shared its solves (issue 47):
/// one plain [`arm::solve`] for every trial and one more for the pose fitted. The reference the
/// shared solves must match bit for bit: recorded joint angles replay from the raw inputs.
fn update_by_plain_solves(
    est: &mut ArmPoseEstimator,
    wheel_rad: f64,
    upper: &ImuSample,
    fore: &ImuSample,
    dt_s: f64,
) -> Result<ArmPose, ImuError> {
    if !wheel_rad.is_finite() {
        return Err(ImuError::InvalidInput(format!("wheel angle {wheel_rad}")));
    }
    if !est.started {
        let s = arm::solve(&est.geo, wheel_rad, est.params.x, 0.0)?;
        est.upper
            .set_orientation(arm::to_quat(&s.upper) * est.mount.upper);
        est.fore
            .set_orientation(arm::to_quat(&s.fore) * est.mount.fore);
        est.started = true;
    }
    let qu = est
        .upper
        .update(&upper.rate_rad_s, upper.acc_m_s2.as_ref(), dt_s);
    let qf = est
        .fore
        .update(&fore.rate_rad_s, fore.acc_m_s2.as_ref(), dt_s);
    let up_u = est.mount.upper * (qu.inverse() * Vector3::z());
    let up_f = est.mount.fore * (qf.inverse() * Vector3::z());
    let geo = est.geo;
    let residual = |p: &Vector2<f64>| -> Result<[f64; 6], ImuError> {
        let s = arm::solve(&geo, wheel_rad, p.x, p.y)?;
        let pu = s.upper.transpose() * Vector3::z();
        let pf = s.fore.transpose() * Vector3::z();
        Ok([
            pu.x - up_u.x,
            pu.y - up_u.y,
            pu.z - up_u.z,
            pf.x - up_f.x,
            pf.y - up_f.y,
            pf.z - up_f.z,
        ])
    };
    let mut p = est.params;
    let mut r0 = residual(&p)?;
    for _ in 0..3 {
        let h = 1e-6;
        let r_a = residual(&(p + Vector2::new(h, 0.0)))?;
        let r_b = residual(&(p + Vector2::new(0.0, h)))?;
        let (mut jtj, mut jtr) = (Matrix2::zeros(), Vector2::zeros());
        for i in 0..6 {
            let j = Vector2::new((r_a[i] - r0[i]) / h, (r_b[i] - r0[i]) / h);
            jtj += j * j.transpose();
            jtr += j * r0[i];
        }
        jtj += Matrix2::identity() * 1e-4;
        let Some(step) = jtj.try_inverse().map(|m| m * jtr) else {
            break;
        };
        let step = step.map(|x| x.clamp(-0.3, 0.3));
        let cand = p - step;
        match residual(&cand) {
            Ok(rc) if norm2(&rc) <= norm2(&r0) => {
                p = cand;
                r0 = rc;
            }
            _ => break,
        }
        if step.norm() < 1e-9 {
            break;
        }
    }
    est.params = p;
    let state = arm::solve(&est.geo, wheel_rad, p.x, p.y)?;
    let angles = arm::joint_angles(&state.upper, &state.fore);
    est.rom.update(&angles);
    Ok(ArmPose {
        angles,
        swivel_rad: p.x,
        state,
        fit_residual_rad: (norm2(&r0) / 2.0).sqrt(),
    })
}

/// Every float of a pose, as bits (NaN compares equal to the same NaN).
fn pose_bits(p: &ArmPose) -> Vec<u64> {
    let mut v: Vec<f64> = p.angles.to_array().to_vec();
    v.extend([p.swivel_rad, p.fit_residual_rad]);
    v.extend(p.state.upper.iter());
    v.extend(p.state.fore.iter());
    v.extend(p.state.elbow_m.iter());
    v.extend(p.state.grip_m.iter());
    v.into_iter().map(f64::to_bits).collect()
}

/// The fit solves the chain once per wheel angle and shares the elbow and the twist between
/// its trials; its poses, errors and ranges of motion are those of a plain solve per trial,
/// bit for bit, over a noisy simulated session with sensors mounted askew, an initial swivel
/// of −0 (where a step in pronation alone changes the swivel's bits), NaN rates, NaN wheel
/// angles and a reacquisition.
#[test]
fn the_fit_is_bit_for_bit_the_fit_by_plain_solves() {
    let cfg = PatientArmConfig::default();
    let mu = so3::exp_quat(&Vector3::new(0.4, -1.0, 2.0));
    let mf = so3::exp_quat(&Vector3::new(-2.0, 0.3, 0.5));
    for initial_swivel in [None, Some(-0.0), Some(0.35)] {
        let mut arm = SimArm::consumer_mems(cfg, mu, mf, 5).unwrap();
        let mounting = Mounting {
            upper: mu.inverse(),
            fore: mf.inverse(),
        };
        let mut shared =
            ArmPoseEstimator::new(cfg.geometry, mounting, FusionConfig::default()).unwrap();
        if let Some(s) = initial_swivel {
            shared.set_initial_swivel(s);
        }
        let mut plain = shared.clone();
        let dt = 0.001;
        let mut checked = 0;
        for k in 0..20_000 {
            let t = k as f64 * dt;
            let (w, wd) = sine_road(t, 0.8, 0.2, 0.25, 0.45);
            arm.step((t * 1e9) as u64, w, wd, dt).unwrap();
            let (mut u, f) = arm.latest().unwrap();
            if k % 997 == 0 {
                u.rate_rad_s.x = f64::NAN;
            }
            // Now and then a wheel angle that is no angle (an error, both ways).
            let wheel = if k % 1999 == 1000 { f64::NAN } else { w };
            if k == 12_000 {
                shared.reacquire();
                plain.reacquire();
            }
            match (
                shared.update(wheel, &u, &f, dt),
                update_by_plain_solves(&mut plain, wheel, &u, &f, dt),
            ) {
                (Ok(a), Ok(b)) => {
                    assert_eq!(pose_bits(&a), pose_bits(&b), "tick {k}");
                    checked += 1;
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "tick {k}"),
                (a, b) => panic!("tick {k}: {a:?} against {b:?}"),
            }
        }
        assert!(checked > 19_000, "{checked}");
        assert_eq!(
            shared.range_of_motion(),
            plain.range_of_motion(),
            "ranges of motion"
        );
        assert_eq!(shared.params, plain.params);
    }
}

/// The shared solves (issue 47) are kept from sliding back, as a ratio to the plain-solve fit
/// ([`update_by_plain_solves`], the same answers bit for bit) measured in the same run: the
/// best of 9 alternating rounds of 2 000 updates each, two estimators fed the same samples.
/// 2026-12-08, loaded machine: 0.62–0.64 in the debug build CI runs, 0.59–0.60 in release; the
/// bound leaves room for noise (BENCHMARKS.md, "`--speed max` of a recorded 10-minute session").
#[test]
fn an_update_with_shared_solves_costs_well_under_one_with_plain_solves() {
    use std::time::Instant;
    const RATIO_LIMIT: f64 = 0.8;
    let cfg = PatientArmConfig::default();
    let mut arm = SimArm::consumer_mems(
        cfg,
        UnitQuaternion::identity(),
        UnitQuaternion::identity(),
        5,
    )
    .unwrap();
    let dt = 0.001;
    let samples: Vec<(f64, ImuSample, ImuSample)> = (0..2000)
        .map(|k| {
            let t = k as f64 * dt;
            let (w, wd) = sine_road(t, 0.8, 0.2, 0.25, 0.45);
            arm.step((t * 1e9) as u64, w, wd, dt).unwrap();
            let (u, f) = arm.latest().unwrap();
            (w, u, f)
        })
        .collect();
    let mounting = Mounting {
        upper: UnitQuaternion::identity(),
        fore: UnitQuaternion::identity(),
    };
    let mut shared =
        ArmPoseEstimator::new(cfg.geometry, mounting, FusionConfig::default()).unwrap();
    shared.set_initial_swivel(cfg.swivel_mean_rad);
    let mut plain = shared.clone();
    let (mut best_shared, mut best_plain) = (f64::MAX, f64::MAX);
    for _ in 0..9 {
        let t = Instant::now();
        for (w, u, f) in &samples {
            std::hint::black_box(shared.update(*w, u, f, dt).unwrap());
        }
        best_shared = best_shared.min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        for (w, u, f) in &samples {
            std::hint::black_box(update_by_plain_solves(&mut plain, *w, u, f, dt).unwrap());
        }
        best_plain = best_plain.min(t.elapsed().as_secs_f64());
    }
    let ratio = best_shared / best_plain;
    println!("pose update with shared solves: {ratio:.2} of one with plain solves");
    assert!(
        ratio < RATIO_LIMIT,
        "an update with shared solves costs {ratio:.2} of one with plain solves"
    );
}
