use super::*;
use crate::bias::RestConfig;
use crate::sensor::{AccSpec, GyroSpec, SensorModel};
use crate::sim::motion::RandomMotion;

struct Errors {
    incl_rms_deg: f64,
    incl_max_deg: f64,
    total_rms_deg: f64,
    total_end_deg: f64,
    bias_err_deg_s: f64,
}

/// Inclination: angle between true and estimated sensor-frame "up". Total: after removing the
/// constant heading offset measured over seconds 5–10.
fn run(seed: u64, minutes: f64, dt: f64, bias_deg_s: Option<f64>, cfg: FusionConfig) -> Errors {
    run_with(seed, minutes, dt, bias_deg_s, cfg, 6.0)
}

fn run_with(
    seed: u64,
    minutes: f64,
    dt: f64,
    bias_deg_s: Option<f64>,
    cfg: FusionConfig,
    rest_s: f64,
) -> Errors {
    run_spec(
        seed,
        minutes,
        dt,
        bias_deg_s,
        cfg,
        rest_s,
        GyroSpec::consumer_mems(),
    )
}

fn run_spec(
    seed: u64,
    minutes: f64,
    dt: f64,
    bias_deg_s: Option<f64>,
    cfg: FusionConfig,
    rest_s: f64,
    spec: GyroSpec,
) -> Errors {
    let mut motion = RandomMotion::new(seed, 120.0, 0.15, 40.0, rest_s);
    let mut sensor = SensorModel::new(spec, Some(AccSpec::consumer_mems()), seed + 100).unwrap();
    if let Some(b) = bias_deg_s {
        sensor.set_gyro_bias_rad_s(Vector3::new(b, -0.8 * b, 0.6 * b).map(f64::to_radians));
    }
    let mut f = OrientationFilter::new(cfg).unwrap();
    let n = (minutes * 60.0 / dt) as usize;
    let (mut incl2, mut incl_max, mut tot2, mut cnt) = (0.0, 0.0f64, 0.0, 0usize);
    let mut offset: Option<UnitQuaternion<f64>> = None;
    let mut end = 0.0;
    let mut now = motion.next(dt);
    for k in 0..n {
        let r = sensor.measure(&now.rate_rad_s, &now.specific_force_m_s2, dt);
        let q = f.update(&r.rate_rad_s, r.acc_m_s2.as_ref(), dt);
        // The filter's output after sample k is the orientation at t_{k+1}.
        let truth = motion.next(dt);
        now = truth;
        let t = k as f64 * dt;
        if t >= 10.0 && offset.is_none() {
            // Heading offset between the filter's earth frame and the truth's (rotation about z).
            let d = truth.orientation * q.inverse();
            let (_, _, yaw) = d.euler_angles();
            offset = Some(UnitQuaternion::from_euler_angles(0.0, 0.0, yaw));
        }
        if let Some(off) = offset {
            let up_t = truth.orientation.inverse() * Vector3::z();
            let up_e = q.inverse() * Vector3::z();
            let incl = up_t.angle(&up_e).to_degrees();
            let tot = so3::angle_between(&truth.orientation, &(off * q)).to_degrees();
            incl2 += incl * incl;
            incl_max = incl_max.max(incl);
            tot2 += tot * tot;
            cnt += 1;
            end = tot;
        }
    }
    let bias_err = (f.bias_rad_s() - sensor.gyro_bias_rad_s())
        .norm()
        .to_degrees();
    Errors {
        incl_rms_deg: (incl2 / cnt as f64).sqrt(),
        incl_max_deg: incl_max,
        total_rms_deg: (tot2 / cnt as f64).sqrt(),
        total_end_deg: end,
        bias_err_deg_s: bias_err,
    }
}

#[test]
fn arm_like_motion_with_mems_noise_and_bias_keeps_inclination_under_1_deg_and_total_under_3_deg() {
    println!(
        "| seed | bias (deg/s) | incl RMS | incl max | total RMS | total end | bias err (deg/s) |\n|---|---|---|---|---|---|---|"
    );
    for (seed, bias) in [(1, None), (2, Some(1.0)), (3, Some(-1.5))] {
        let e = run(seed, 5.0, 1.0 / 200.0, bias, FusionConfig::default());
        println!(
            "| {seed} | {bias:?} | {:.3} | {:.3} | {:.3} | {:.3} | {:.4} |",
            e.incl_rms_deg, e.incl_max_deg, e.total_rms_deg, e.total_end_deg, e.bias_err_deg_s
        );
        assert!(e.incl_rms_deg < 1.0, "inclination RMS {}", e.incl_rms_deg);
        assert!(e.total_rms_deg < 3.0, "total RMS {}", e.total_rms_deg);
        assert!(e.bias_err_deg_s < 0.1, "bias error {}", e.bias_err_deg_s);
    }
}

/// The table in BENCHMARKS.md: how each error source and each part of the filter matters.
#[test]
fn fusion_error_table_by_condition() {
    let dt = 1.0 / 200.0;
    let d = FusionConfig::default();
    let no_motion_bias = FusionConfig {
        motion_bias_tau_s: 0.0,
        ..d
    };
    let no_bias_at_all = FusionConfig {
        motion_bias_tau_s: 0.0,
        rest: RestConfig {
            rate_threshold_deg_s: 0.01,
            ..d.rest
        },
        ..d
    };
    let one_pct = GyroSpec {
        scale_error: 0.01,
        ..GyroSpec::consumer_mems()
    };
    let rows: [(&str, Errors); 6] = [
        (
            "default, pauses, bias 1°/s",
            run_spec(2, 5.0, dt, Some(1.0), d, 6.0, GyroSpec::consumer_mems()),
        ),
        (
            "no motion-bias estimation",
            run_spec(
                2,
                5.0,
                dt,
                Some(1.0),
                no_motion_bias,
                6.0,
                GyroSpec::consumer_mems(),
            ),
        ),
        (
            "no bias estimation at all",
            run_spec(
                2,
                5.0,
                dt,
                Some(1.0),
                no_bias_at_all,
                6.0,
                GyroSpec::consumer_mems(),
            ),
        ),
        (
            "1 % gyro scale error",
            run_spec(2, 5.0, dt, Some(1.0), d, 6.0, one_pct),
        ),
        (
            "no pauses (motion bias only)",
            run_spec(2, 5.0, dt, Some(1.0), d, 0.0, GyroSpec::consumer_mems()),
        ),
        (
            "no pauses, no motion bias",
            run_spec(
                2,
                5.0,
                dt,
                Some(1.0),
                no_motion_bias,
                0.0,
                GyroSpec::consumer_mems(),
            ),
        ),
    ];
    println!(
        "| condition (5 min, 200 Hz) | incl RMS (deg) | incl max | total RMS | total end | bias err (deg/s) |\n|---|---|---|---|---|---|"
    );
    for (name, e) in &rows {
        println!(
            "| {name} | {:.3} | {:.3} | {:.3} | {:.3} | {:.4} |",
            e.incl_rms_deg, e.incl_max_deg, e.total_rms_deg, e.total_end_deg, e.bias_err_deg_s
        );
    }
    // Bias estimation must matter: without it the heading drifts away.
    assert!(rows[0].1.total_rms_deg * 5.0 < rows[2].1.total_rms_deg);
    // Without pauses, motion-bias estimation must still help the inclination.
    assert!(rows[4].1.incl_rms_deg < rows[5].1.incl_rms_deg);
}

#[test]
fn first_sample_aligns_inclination_and_nan_is_ignored() {
    let mut f = OrientationFilter::new(FusionConfig::default()).unwrap();
    // Sensor lying on its side: gravity reaction along +x of the sensor.
    let q = f.update(&Vector3::zeros(), Some(&Vector3::new(9.81, 0.0, 0.0)), 0.01);
    assert!(((q * Vector3::x()) - Vector3::z()).norm() < 1e-9);
    let q2 = f.update(
        &Vector3::new(f64::NAN, 0.0, 0.0),
        Some(&Vector3::new(9.81, 0.0, 0.0)),
        0.01,
    );
    assert_eq!(q, q2);
}

#[test]
fn fuse_checks_lengths_and_config() {
    let g = vec![Vector3::zeros(); 3];
    let a = vec![Vector3::z() * 9.81; 2];
    assert!(fuse(&g, &a, 0.01, FusionConfig::default()).is_err());
    let c = FusionConfig {
        tau_acc_s: -1.0,
        ..FusionConfig::default()
    };
    assert!(c.validate().unwrap_err().to_string().contains("tau_acc_s"));
}
