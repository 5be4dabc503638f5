use super::*;
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

/// Inclination RMS (deg) over the second half and the final scale estimate of the filter `cfg`
/// over `seconds` of
/// turning at 200 °/s about an axis that wanders in the sensor frame (as BROAD's fast
/// rotations turn an IMU round and round), read by a gyroscope with per-axis scale error
/// `scale`, a bias and white noise, and an ideal accelerometer.
fn turning(cfg: FusionConfig, scale: Vector3<f64>, seconds: f64) -> (f64, Vector3<f64>) {
    use rand::{Rng, SeedableRng};
    let dt = 1.0 / 200.0;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let bias = Vector3::new(0.3, -0.2, 0.25).map(f64::to_radians);
    let mut q = UnitQuaternion::identity();
    let mut f = OrientationFilter::new(cfg).unwrap();
    let (mut incl2, mut n) = (0.0, 0usize);
    for k in 0..(seconds / dt) as usize {
        let t = k as f64 * dt;
        let axis = Vector3::new(
            (0.3 * t).sin(),
            (0.23 * t).cos(),
            0.6 + 0.4 * (0.17 * t).sin(),
        );
        let w = axis.normalize() * 200f64.to_radians();
        let noise = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0) * 0.002);
        let gyr = w.component_mul(&(Vector3::repeat(1.0) + scale)) + bias + noise;
        let acc = q.inverse() * Vector3::new(0.0, 0.0, 9.81);
        let est = f.update(&gyr, Some(&acc), dt);
        q *= UnitQuaternion::from_scaled_axis(w * dt);
        if t > seconds / 2.0 {
            let up_t = q.inverse() * Vector3::z();
            let up_e = est.inverse() * Vector3::z();
            incl2 += up_t.angle(&up_e).to_degrees().powi(2);
            n += 1;
        }
    }
    ((incl2 / n as f64).sqrt(), f.gyro_scale_error())
}

#[test]
fn estimating_a_gyroscopes_scale_error_lowers_the_inclination_error_it_causes() {
    // BROAD's IMU read up to 0.8 % off at up to 1 450 °/s: here 0.8 % high, 0.5 % low and
    // 0.3 % high on the three axes, turning at 200 °/s for two minutes.
    let scale = Vector3::new(0.008, -0.005, 0.003);
    let on = FusionConfig {
        gyro_scale_estimation: true,
        ..FusionConfig::default()
    };
    let (plain, zero) = turning(FusionConfig::default(), scale, 120.0);
    let (scaled, estimate) = turning(on, scale, 120.0);
    println!(
        "inclination RMS {plain:.3}° without, {scaled:.3}° with scale estimation; estimate \
         {estimate:?} against {scale:?}"
    );
    assert_eq!(zero, Vector3::zeros());
    assert!(
        scaled < 0.8 * plain,
        "{scaled:.3}° with scale estimation against {plain:.3}° without"
    );
    for i in 0..3 {
        assert!(
            (estimate[i] - scale[i]).abs() < 0.0015,
            "axis {i}: estimated {:.4}, true {:.4}",
            estimate[i],
            scale[i]
        );
    }
}

/// Inclination RMS (deg) over the second half, the final scale estimate and the share of
/// samples the translation gate let the scale be learned from, for the filter `cfg` over
/// `seconds` of a sensor carried about: 0.1 m oscillations at 1.3 / 1.7 / 2.1 Hz along the
/// three earth axes (up to 17 m/s² of linear acceleration, as BROAD's fast translations)
/// and a wobble of up to 57 °/s per axis, read by a gyroscope with per-axis scale error `scale`, a
/// bias and white noise, and an accelerometer with white noise.
fn carried(cfg: FusionConfig, scale: Vector3<f64>, seconds: f64) -> (f64, Vector3<f64>, f64) {
    use rand::{Rng, SeedableRng};
    use std::f64::consts::TAU;
    let dt = 1.0 / 200.0;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let bias = Vector3::new(0.3, -0.2, 0.25).map(f64::to_radians);
    let mut q = UnitQuaternion::identity();
    let mut f = OrientationFilter::new(cfg).unwrap();
    let (mut incl2, mut n, mut open) = (0.0, 0usize, 0usize);
    let steps = (seconds / dt) as usize;
    for k in 0..steps {
        let t = k as f64 * dt;
        let w = Vector3::new(
            (TAU * 0.9 * t).sin(),
            (TAU * 1.1 * t).cos(),
            (TAU * 0.7 * t).sin(),
        ) * 1.0;
        let lin = Vector3::new(1.3f64, 1.7, 2.1)
            .map(|fr| -0.1 * (TAU * fr).powi(2))
            .component_mul(&Vector3::new(
                (TAU * 1.3 * t).sin(),
                (TAU * 1.7 * t).sin(),
                (TAU * 2.1 * t).sin(),
            ));
        let gyr_noise = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0) * 0.002);
        let acc_noise = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0) * 0.02);
        let gyr = w.component_mul(&(Vector3::repeat(1.0) + scale)) + bias + gyr_noise;
        let acc = q.inverse() * (Vector3::new(0.0, 0.0, 9.81) + lin) + acc_noise;
        let est = f.update(&gyr, Some(&acc), dt);
        open += f.scale_observable() as usize;
        q *= UnitQuaternion::from_scaled_axis(w * dt);
        if t > seconds / 2.0 {
            let up_t = q.inverse() * Vector3::z();
            let up_e = est.inverse() * Vector3::z();
            incl2 += up_t.angle(&up_e).to_degrees().powi(2);
            n += 1;
        }
    }
    (
        (incl2 / n as f64).sqrt(),
        f.gyro_scale_error(),
        open as f64 / steps as f64,
    )
}

#[test]
fn scale_estimation_does_not_worsen_a_carried_sensor_whose_motion_is_translation() {
    let scale = Vector3::new(0.008, -0.005, 0.003);
    let on = FusionConfig {
        gyro_scale_estimation: true,
        ..FusionConfig::default()
    };
    let ungated = FusionConfig {
        scale_translation_speed_m_s: 1e3,
        ..on
    };
    let (plain, _, _) = carried(FusionConfig::default(), scale, 120.0);
    let (gated, estimate, open) = carried(on, scale, 120.0);
    let (free, free_estimate, _) = carried(ungated, scale, 120.0);
    println!(
        "inclination RMS {plain:.4}° without, {gated:.4}° with scale estimation (gate open \
         {:.1} % of samples, estimate {estimate:?}), {free:.4}° without the gate (estimate \
         {free_estimate:?})",
        100.0 * open
    );
    // The case is one where learning the scale from translation harms: without the gate the
    // estimate moves away from the truth (the acceleration's error is fitted) and the
    // inclination error grows.
    assert!(
        free > 1.02 * plain,
        "{free:.4}° without the gate against {plain:.4}° without scale estimation"
    );
    assert!(
        gated <= 1.01 * plain,
        "{gated:.4}° with scale estimation against {plain:.4}° without"
    );
    assert!(
        open < 0.05,
        "the gate let {:.1} % of samples in",
        100.0 * open
    );
    for i in 0..3 {
        assert!(
            (estimate[i] - scale[i]).abs() <= scale[i].abs() + 1e-4,
            "axis {i}: estimated {:.5}, further from the true {:.4} than the start 0",
            estimate[i],
            scale[i]
        );
    }
}

/// The 1 kHz path's cost with scale estimation stays within the 2× of the default
/// filter's (issue 47), measured in the same run: the best of 9 alternating rounds of 4 000
/// samples of a wandering 200 °/s turn (the translation gate open: the full six-state step
/// runs) for each filter. 2026-12-08, load average 9–10: 1.63× in the debug build CI runs
/// (three runs alike), 1.38× in a release build.
#[test]
fn scale_estimation_costs_at_most_twice_the_default_filter_a_sample() {
    use std::time::Instant;
    const RATIO_LIMIT: f64 = 2.0;
    let dt = 1e-3;
    let mut q = UnitQuaternion::identity();
    let samples: Vec<(Vector3<f64>, Vector3<f64>)> = (0..4000)
        .map(|k| {
            let t = k as f64 * dt;
            let w = Vector3::new((0.3 * t).sin(), (0.23 * t).cos(), 0.6).normalize()
                * 200f64.to_radians();
            let acc = q.inverse() * Vector3::new(0.0, 0.0, 9.81);
            q *= UnitQuaternion::from_scaled_axis(w * dt);
            (w, acc)
        })
        .collect();
    let on = FusionConfig {
        gyro_scale_estimation: true,
        ..FusionConfig::default()
    };
    let (mut plain_f, mut scaled_f) = (
        OrientationFilter::new(FusionConfig::default()).unwrap(),
        OrientationFilter::new(on).unwrap(),
    );
    let (mut plain, mut scaled) = (f64::MAX, f64::MAX);
    let mut open = 0usize;
    for _ in 0..9 {
        let t = Instant::now();
        for (g, a) in &samples {
            std::hint::black_box(plain_f.update(g, Some(a), dt));
        }
        plain = plain.min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        for (g, a) in &samples {
            std::hint::black_box(scaled_f.update(g, Some(a), dt));
        }
        scaled = scaled.min(t.elapsed().as_secs_f64());
        open += scaled_f.scale_observable() as usize;
    }
    let ratio = scaled / plain;
    println!("scale estimation: {ratio:.2}× the default filter's cost a sample");
    assert!(open > 0, "the translation gate stayed shut on a pure turn");
    assert!(
        ratio <= RATIO_LIMIT,
        "scale estimation costs {ratio:.2}× the default filter a sample"
    );
}

#[test]
fn scale_estimation_off_is_the_filter_as_before_and_its_estimate_stays_zero() {
    let off = run(3, 1.0, 1.0 / 200.0, Some(1.0), FusionConfig::default());
    let explicit = run(
        3,
        1.0,
        1.0 / 200.0,
        Some(1.0),
        FusionConfig {
            gyro_scale_estimation: false,
            scale_sigma_init_percent: 2.5,
            ..FusionConfig::default()
        },
    );
    assert_eq!(off.incl_rms_deg.to_bits(), explicit.incl_rms_deg.to_bits());
    let f = OrientationFilter::new(FusionConfig::default()).unwrap();
    assert_eq!(f.gyro_scale_error(), Vector3::zeros());
}

/// The table in BENCHMARKS.md: how each error source and each part of the filter matters, for
/// our filter and for the reference VQF (the same switches with `rest_tilt_check` off, which
/// `matches_reference_vqf_on_golden_signal_to_1e_9` ties to the `vqf` package) on the same
/// records. Ours must be within 0.1° of VQF's inclination RMS and 0.3° of its total RMS in
/// every row.
#[test]
fn fusion_error_table_by_condition_is_within_reference_vqf_margins() {
    let dt = 1.0 / 200.0;
    let d = FusionConfig::default();
    let no_motion_bias = FusionConfig {
        motion_bias_estimation: false,
        ..d
    };
    let no_bias_at_all = FusionConfig {
        motion_bias_estimation: false,
        rest_bias_estimation: false,
        ..d
    };
    let mems = GyroSpec::consumer_mems();
    let one_pct = GyroSpec {
        scale_error: 0.01,
        ..mems
    };
    // (condition, seed, bias deg/s, gyro, config, rest s per 40 s); the same records as the
    // `fusion_table_data` example writes for scripts/compare_vqf.py.
    let rows = [
        ("default, random bias (seed 1)", 1, None, mems, d, 6.0),
        ("default, bias 1 deg/s (seed 2)", 2, Some(1.0), mems, d, 6.0),
        (
            "default, bias 1.5 deg/s (seed 3)",
            3,
            Some(-1.5),
            mems,
            d,
            6.0,
        ),
        (
            "no motion-bias estimation",
            2,
            Some(1.0),
            mems,
            no_motion_bias,
            6.0,
        ),
        (
            "no bias estimation at all",
            2,
            Some(1.0),
            mems,
            no_bias_at_all,
            6.0,
        ),
        ("1 % gyro scale error", 2, Some(1.0), one_pct, d, 6.0),
        ("no pauses, random bias (seed 1)", 1, None, mems, d, 0.0),
        (
            "no pauses, bias 1 deg/s (seed 2)",
            2,
            Some(1.0),
            mems,
            d,
            0.0,
        ),
        (
            "no pauses, bias 1.5 deg/s (seed 3)",
            3,
            Some(-1.5),
            mems,
            d,
            0.0,
        ),
        (
            "no pauses, no motion-bias estimation",
            2,
            Some(1.0),
            mems,
            no_motion_bias,
            0.0,
        ),
    ];
    println!(
        "| condition (5 min, 200 Hz) | incl RMS (deg) | incl max | total RMS | total end | bias err (deg/s) | VQF incl RMS | VQF total RMS |\n|---|---|---|---|---|---|---|---|"
    );
    let mut out = Vec::new();
    for (name, seed, bias, spec, cfg, rest_s) in rows {
        let e = run_spec(seed, 5.0, dt, bias, cfg, rest_s, spec);
        let reference = FusionConfig {
            rest_tilt_check: false,
            ..cfg
        };
        let v = run_spec(seed, 5.0, dt, bias, reference, rest_s, spec);
        println!(
            "| {name} | {:.3} | {:.3} | {:.3} | {:.3} | {:.4} | {:.3} | {:.3} |",
            e.incl_rms_deg,
            e.incl_max_deg,
            e.total_rms_deg,
            e.total_end_deg,
            e.bias_err_deg_s,
            v.incl_rms_deg,
            v.total_rms_deg
        );
        out.push((name, e, v));
    }
    for (name, e, v) in &out {
        assert!(
            e.incl_rms_deg <= v.incl_rms_deg + 0.1,
            "{name}: inclination RMS {} vs VQF {}",
            e.incl_rms_deg,
            v.incl_rms_deg
        );
        assert!(
            e.total_rms_deg <= v.total_rms_deg + 0.3,
            "{name}: total RMS {} vs VQF {}",
            e.total_rms_deg,
            v.total_rms_deg
        );
    }
    // Bias estimation must matter: without it the heading drifts away.
    assert!(out[1].1.total_rms_deg * 5.0 < out[4].1.total_rms_deg);
    // Without pauses, motion-bias estimation must still help the inclination.
    assert!(out[7].1.incl_rms_deg * 2.0 < out[9].1.incl_rms_deg);
}

/// Motion that never pauses: the Kalman-filter motion-bias estimate alone keeps inclination
/// under 1° RMS. Heading is another matter: only where the motion turns the sensor enough for
/// the whole bias to show in the horizontal plane (seed 2) does the total stay within a few
/// degrees; seeds 1 and 3 drift in heading by tens of degrees, as the reference VQF does on
/// the same records (`fusion_error_table_by_condition_is_within_reference_vqf_margins`).
#[test]
fn without_pauses_inclination_stays_under_1_deg_and_seed_2_total_under_8_deg() {
    for (seed, bias) in [(1, None), (2, Some(1.0)), (3, Some(-1.5))] {
        let e = run_with(seed, 5.0, 1.0 / 200.0, bias, FusionConfig::default(), 0.0);
        println!(
            "seed {seed}: inclination RMS {:.3}°, total RMS {:.3}°",
            e.incl_rms_deg, e.total_rms_deg
        );
        assert!(
            e.incl_rms_deg < 1.0,
            "seed {seed}: inclination RMS {}",
            e.incl_rms_deg
        );
        if seed == 2 {
            assert!(e.total_rms_deg < 8.0, "total RMS {}", e.total_rms_deg);
        }
    }
}

#[test]
fn gyro_only_sensor_still_estimates_bias_at_rest_and_its_sigma_shrinks() {
    let mut f = OrientationFilter::new(FusionConfig::default()).unwrap();
    let sigma0 = f.bias_sigma_rad_s().to_degrees();
    assert!((sigma0 - 0.5).abs() < 1e-12, "initial sigma {sigma0}");
    let bias = Vector3::new(0.8, -0.5, 0.3).map(f64::to_radians);
    for _ in 0..2000 {
        f.update(&bias, None, 0.01);
    }
    assert!(f.is_rest());
    let err = (f.bias_rad_s() - bias).amax().to_degrees();
    assert!(err < 0.01, "bias error {err} deg/s");
    assert!(f.bias_sigma_rad_s().to_degrees() < 0.05);
}

#[test]
fn jittery_sample_period_keeps_a_still_sensor_level_within_0_01_deg() {
    // A still, tilted sensor sampled at 100 Hz and at alternating 5/15 ms. (The first,
    // aligning correction nudges the bias, and rest pulls it back; the residue is ~1e-7 rad/s.)
    let acc = Vector3::new(0.0, 9.81 * 0.5f64.sin(), 9.81 * 0.5f64.cos());
    for jitter in [false, true] {
        let mut f = OrientationFilter::new(FusionConfig::default()).unwrap();
        for k in 0..2000 {
            let dt = match (jitter, k % 2) {
                (false, _) => 0.01,
                (true, 0) => 0.005,
                (true, _) => 0.015,
            };
            f.update(&Vector3::zeros(), Some(&acc), dt);
        }
        let up = f.orientation().inverse() * Vector3::z();
        let err_deg = up.angle(&acc).to_degrees();
        assert!(err_deg < 0.01, "jitter {jitter}: {err_deg}°");
        assert!(f.is_rest());
    }
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

/// Reference VQF 2.1 (C++ core, default parameters) on the signal of `golden_signal`, printed by
/// `scripts/vqf_golden.py`: (sample, quaternion w x y z, bias rad/s, rest).
const VQF_GOLDEN: [(usize, [f64; 4], [f64; 3], bool); 12] = [
    (
        999,
        [
            0.351861476903474,
            -0.059960267884844404,
            0.29070482772559975,
            -0.8877437527144381,
        ],
        [
            0.010621385942963541,
            -0.001136152531465488,
            0.005193950832283119,
        ],
        false,
    ),
    (
        1999,
        [
            0.941548304540904,
            0.22221571714216012,
            0.21962818590470304,
            -0.1259778759439692,
        ],
        [
            0.011176268463063108,
            -0.005158605288990705,
            0.005811286628585505,
        ],
        false,
    ),
    (
        2999,
        [
            0.9403222966559495,
            0.22620306636675738,
            0.21944800098958894,
            -0.12833053432301492,
        ],
        [
            0.01565189344275017,
            -0.012232648266854298,
            0.008687366642080167,
        ],
        true,
    ),
    (
        3999,
        [
            0.4396109812677469,
            -0.70351599575159,
            0.40116457469630684,
            -0.38842555641871584,
        ],
        [
            0.01568025526335528,
            -0.012238100831916822,
            0.008702345727176236,
        ],
        false,
    ),
    (
        4999,
        [
            -0.477467029164408,
            -0.07624825655594307,
            0.6477234411995321,
            -0.5887833074686563,
        ],
        [
            0.015675484113076475,
            -0.012247037030418004,
            0.008693217069588557,
        ],
        false,
    ),
    (
        5999,
        [
            0.14778278832353642,
            0.17452839030009035,
            0.2861036729949774,
            -0.9305078058529996,
        ],
        [
            0.015682370020621082,
            -0.012258257371060307,
            0.008676279070400035,
        ],
        false,
    ),
    (
        6999,
        [
            -0.8286576537953727,
            0.1780552040533111,
            0.009131734392468184,
            -0.5306029104168839,
        ],
        [
            0.01567509574528389,
            -0.01222800045957156,
            0.008680484500021936,
        ],
        false,
    ),
    (
        7999,
        [
            -0.7409879913453915,
            0.5873658604013662,
            0.2478190635886078,
            -0.21100676396492782,
        ],
        [
            0.015671307983615542,
            -0.012219857464148023,
            0.008716034478940822,
        ],
        false,
    ),
    (
        8999,
        [
            0.35149775638324043,
            -0.03733445588351641,
            -0.16006309769194027,
            -0.9216481272257273,
        ],
        [
            0.01565588126649269,
            -0.012272172399292154,
            0.008675515868392322,
        ],
        false,
    ),
    (
        9999,
        [
            -0.13476307540937973,
            -0.22244623615380504,
            0.3529489317316715,
            -0.8987678438377084,
        ],
        [
            0.015694943448680415,
            -0.012226748391035408,
            0.008658673562796312,
        ],
        false,
    ),
    (
        10999,
        [
            -0.3822062943759924,
            -0.8648801233997816,
            0.20671985028248865,
            -0.2513317015152213,
        ],
        [
            0.015761630740432988,
            -0.012195458274888535,
            0.008650685765301674,
        ],
        false,
    ),
    (
        11999,
        [
            0.3596062295009685,
            -0.8250146162653864,
            0.4347629282153788,
            -0.031865952083123816,
        ],
        [
            0.01574935812739891,
            -0.012224390062243549,
            0.008664367007248047,
        ],
        false,
    ),
];

/// The closed-form test signal of `scripts/vqf_golden.py`, built in the same order: 120 s at
/// 100 Hz, motion, 10 s still from t = 20 s, then 90 s of motion without a pause; gyro bias
/// (0.9, −0.7, 0.5) deg/s.
fn golden_signal() -> Vec<(Vector3<f64>, Vector3<f64>)> {
    let dt = 0.01;
    let bias = Vector3::new(
        0.9f64.to_radians(),
        (-0.7f64).to_radians(),
        0.5f64.to_radians(),
    );
    let s = 0.3f64.sin();
    let mut q = [0.3f64.cos(), s * 0.6, s * 0.8, 0.0];
    (0..12000)
        .map(|k| {
            let t = k as f64 * dt;
            let m = if (20.0..30.0).contains(&t) { 0.0 } else { 1.0 };
            let w = [
                m * (1.1 * (1.3 * t).sin() + 0.4 * (3.1 * t + 0.5).sin()),
                m * (-0.9 * (0.7 * t + 1.0).sin() + 0.3 * (2.3 * t).cos()),
                m * (0.8 * (0.9 * t).cos() + 0.5 * (1.7 * t + 2.0).sin()),
            ];
            let a_e = [
                m * 0.8 * (2.0 * t).sin(),
                m * 0.6 * (1.5 * t).cos(),
                9.81 + m * 0.5 * (1.1 * t).sin(),
            ];
            // Rotate by the inverse of q (earth → sensor), term by term as the script does.
            let [qw, x, y, z] = [q[0], -q[1], -q[2], -q[3]];
            let f = [
                (1.0 - 2.0 * y * y - 2.0 * z * z) * a_e[0]
                    + 2.0 * (x * y - qw * z) * a_e[1]
                    + 2.0 * (x * z + qw * y) * a_e[2],
                2.0 * (x * y + qw * z) * a_e[0]
                    + (1.0 - 2.0 * x * x - 2.0 * z * z) * a_e[1]
                    + 2.0 * (y * z - qw * x) * a_e[2],
                2.0 * (x * z - qw * y) * a_e[0]
                    + 2.0 * (y * z + qw * x) * a_e[1]
                    + (1.0 - 2.0 * x * x - 2.0 * y * y) * a_e[2],
            ];
            let n = 1e-3 * (37.0 * k as f64).sin();
            let gyr = Vector3::new(
                w[0] + bias.x + n,
                w[1] + bias.y - n,
                w[2] + bias.z + 0.5 * n,
            );
            let acc = Vector3::new(f[0] + 10.0 * n, f[1] - 10.0 * n, f[2] + 5.0 * n);
            let h = 0.5 * dt;
            let th = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            if th > 0.0 {
                let s = (h * th).sin() / th;
                let d = [(h * th).cos(), s * w[0], s * w[1], s * w[2]];
                let p = [
                    q[0] * d[0] - q[1] * d[1] - q[2] * d[2] - q[3] * d[3],
                    q[0] * d[1] + q[1] * d[0] + q[2] * d[3] - q[3] * d[2],
                    q[0] * d[2] - q[1] * d[3] + q[2] * d[0] + q[3] * d[1],
                    q[0] * d[3] + q[1] * d[2] - q[2] * d[1] + q[3] * d[0],
                ];
                let nq = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3]).sqrt();
                q = p.map(|c| c / nq);
            }
            (gyr, acc)
        })
        .collect()
}

#[test]
fn matches_reference_vqf_on_golden_signal_to_1e_9() {
    let data = golden_signal();
    let mut f = OrientationFilter::new(FusionConfig::reference_vqf()).unwrap();
    let mut checks = VQF_GOLDEN.iter().peekable();
    let (mut max_q, mut max_b) = (0.0f64, 0.0f64);
    for (k, (g, a)) in data.iter().enumerate() {
        let q = f.update(g, Some(a), 0.01);
        if let Some((_, q_ref, b_ref, rest)) = checks.next_if(|c| c.0 == k) {
            let q_ref = Quaternion::new(q_ref[0], q_ref[1], q_ref[2], q_ref[3]);
            // q and −q are the same rotation.
            let dq = (q.quaternion() - q_ref)
                .norm()
                .min((q.quaternion() + q_ref).norm());
            let db = (f.bias_rad_s() - Vector3::from(*b_ref)).amax();
            max_q = max_q.max(dq);
            max_b = max_b.max(db);
            assert_eq!(f.is_rest(), *rest, "rest flag at sample {k}");
        }
    }
    assert!(checks.next().is_none());
    println!("largest quaternion difference {max_q:.2e}, bias {max_b:.2e} rad/s");
    assert!(max_q < 1e-9 && max_b < 1e-9, "{max_q:e} {max_b:e}");
}
