//! Safety invariants of the runtime [`Assist`] for every mode: for any bounded (or
//! non-finite) input the torque is finite, inside the ceiling and the slew limit, and a
//! non-finite input sends it towards zero.

use assist::{
    AanParams, Assist, AssistMode, AssistSpec, ForceParams, HybridParams, Limits, Measurement,
    ModelSpec, MotionParams, ResistParams,
};
use proptest::prelude::*;

fn modes() -> impl Strategy<Value = AssistMode> {
    prop_oneof![
        Just(AssistMode::None {}),
        (0.0..20.0f64, 0.0..2.0f64, 0.0..0.1f64).prop_map(|(k, b, m)| AssistMode::Resist(
            ResistParams {
                spring_nm_per_rad: k,
                damper_nm_s_per_rad: b,
                inertia_kg_m2: m,
                center_rad: 0.1,
            }
        )),
        (0.01..1.0f64, -60.0..-1.0f64).prop_map(|(a, p)| AssistMode::Motion(MotionParams {
            authority: a,
            poles_rad_s: [p, 2.0 * p, 3.0 * p],
            ..Default::default()
        })),
        (0.0..1.0f64, -2.0..2.0f64).prop_map(|(f, b)| AssistMode::Force(ForceParams {
            fraction: f,
            bias_nm: b,
            ..Default::default()
        })),
        (0.0..3.0f64).prop_map(|c| AssistMode::Hybrid(HybridParams {
            contact_nm: c,
            ..Default::default()
        })),
        (0.0..0.99f64, 0.0..50.0f64).prop_map(|(f, g)| AssistMode::AssistAsNeeded(AanParams {
            forgetting: f,
            gain_nm_per_rad: g,
            ..Default::default()
        })),
    ]
}

fn value(range: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        20 => -range..range,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
    ]
}

#[derive(Debug, Clone)]
struct Tick {
    angle: f64,
    vel: f64,
    reference: f64,
    ceiling: f64,
    slew: f64,
    dt: f64,
}

fn ticks() -> impl Strategy<Value = Vec<Tick>> {
    proptest::collection::vec(
        (
            value(10.0),
            value(200.0),
            value(10.0),
            prop_oneof![10 => 0.0..5.0f64, 1 => Just(f64::NAN)],
            prop_oneof![10 => 0.0..500.0f64, 1 => Just(-1.0)],
            prop_oneof![10 => Just(0.001), 3 => 1e-5..0.05f64, 1 => Just(0.0)],
        )
            .prop_map(|(angle, vel, reference, ceiling, slew, dt)| Tick {
                angle,
                vel,
                reference,
                ceiling,
                slew,
                dt,
            }),
        1..300,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]
    #[test]
    fn torque_is_finite_within_ceiling_and_slew_for_any_input(mode in modes(), ticks in ticks()) {
        let spec = AssistSpec { model: ModelSpec::default(), mode };
        let mut assist = Assist::new(&spec).unwrap();
        let mut prev = 0.0f64;
        for t in &ticks {
            let limits = Limits { ceiling_nm: t.ceiling, slew_nm_per_s: t.slew };
            let out = assist.step(
                Measurement { angle_rad: t.angle, vel_rad_s: t.vel },
                t.reference,
                limits,
                t.dt,
            );
            prop_assert!(out.torque_nm.is_finite());
            prop_assert!(out.reference_rad.is_finite() && out.error_rad.is_finite());
            prop_assert!((0.0..=1.0).contains(&out.assistance_level));
            let clean = limits.sanitised();
            prop_assert!(out.torque_nm.abs() <= clean.ceiling_nm, "{} > {}", out.torque_nm, clean.ceiling_nm);
            let inputs_ok = t.angle.is_finite() && t.vel.is_finite() && t.reference.is_finite()
                && t.dt > 0.0 && limits.is_sane();
            if t.dt.is_finite() && t.dt > 0.0 {
                // Slew holds unless the ceiling itself forced the torque down.
                let step = clean.slew_nm_per_s * t.dt + 1e-12;
                prop_assert!(
                    (out.torque_nm - prev).abs() <= step || out.torque_nm.abs() == clean.ceiling_nm
                        || out.torque_nm == 0.0 && !limits.is_sane(),
                    "jump {} -> {}", prev, out.torque_nm
                );
            }
            if !inputs_ok {
                prop_assert!(out.torque_nm.abs() <= prev.abs());
            }
            prev = out.torque_nm;
        }
    }
}

#[test]
fn nan_measurement_ramps_torque_to_zero_along_the_slew_limit_and_recovers() {
    let spec = AssistSpec {
        model: ModelSpec::default(),
        mode: AssistMode::Motion(MotionParams::default()),
    };
    let mut assist = Assist::new(&spec).unwrap();
    let limits = Limits {
        ceiling_nm: 1.87,
        slew_nm_per_s: 50.0,
    };
    let good = Measurement {
        angle_rad: 0.0,
        vel_rad_s: 0.0,
    };
    let mut tau = 0.0;
    for _ in 0..300 {
        tau = assist.step(good, 1.0, limits, 0.001).torque_nm;
    }
    assert!(
        tau > 1.0,
        "held wheel, far reference: torque should be large, got {tau}"
    );
    let bad = Measurement {
        angle_rad: f64::NAN,
        vel_rad_s: 0.0,
    };
    let mut prev = tau;
    let mut ticks_to_zero = 0;
    while prev != 0.0 {
        let out = assist.step(bad, 1.0, limits, 0.001);
        assert!(out.torque_nm.abs() < prev.abs() && prev - out.torque_nm <= 0.05 + 1e-12);
        prev = out.torque_nm;
        ticks_to_zero += 1;
        assert!(ticks_to_zero <= 40);
    }
    let st = assist.status();
    assert!(st.infeasible);
    assert_eq!(st.reason, Some(assist::Infeasibility::NonFiniteInput));
    // Back to good data: resumes from zero torque, within the slew limit.
    let out = assist.step(good, 1.0, limits, 0.001);
    assert!(out.torque_nm.abs() <= 0.05 + 1e-12);
}
