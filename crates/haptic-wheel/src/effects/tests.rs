//! Each effect type against its definition: shape, envelope, timing, clamp.

use super::toolbox::{ToolboxEffect, ToolboxKind, to_effect};
use super::*;
use crate::DeviceProfile;
use approx::assert_abs_diff_eq;

fn at_angle(angle_rad: f64) -> WheelState {
    WheelState {
        angle_rad,
        ..Default::default()
    }
}

fn at_vel(vel_rad_s: f64) -> WheelState {
    WheelState {
        vel_rad_s,
        ..Default::default()
    }
}

fn cond(kind: ConditionKind) -> Condition {
    Condition {
        kind,
        offset: 0.1,
        positive_coefficient: 2.0,
        negative_coefficient: 0.5,
        positive_saturation_nm: 1.0,
        negative_saturation_nm: 0.2,
        deadband: 0.05,
    }
}

#[test]
fn spring_restores_towards_offset_with_per_side_coefficient_deadband_and_saturation() {
    let c = cond(ConditionKind::Spring);
    // Inside the deadband around the offset: no force.
    assert_eq!(c.torque_nm(&at_angle(0.1)), 0.0);
    assert_eq!(c.torque_nm(&at_angle(0.149)), 0.0);
    assert_eq!(c.torque_nm(&at_angle(0.051)), 0.0);
    // Positive side: −2·(θ − 0.15).
    assert_abs_diff_eq!(c.torque_nm(&at_angle(0.35)), -0.4, epsilon = 1e-12);
    // Negative side: −0.5·(θ − 0.05).
    assert_abs_diff_eq!(c.torque_nm(&at_angle(-0.15)), 0.1, epsilon = 1e-12);
    // Saturation per side.
    assert_abs_diff_eq!(c.torque_nm(&at_angle(3.0)), -1.0, epsilon = 1e-12);
    assert_abs_diff_eq!(c.torque_nm(&at_angle(-3.0)), 0.2, epsilon = 1e-12);
}

#[test]
fn damper_opposes_velocity_linearly_and_saturates() {
    let c = cond(ConditionKind::Damper);
    let at_offset = WheelState {
        angle_rad: 5.0,
        vel_rad_s: 0.1,
        acc_rad_s2: 50.0,
    };
    assert_eq!(
        c.torque_nm(&at_offset),
        0.0,
        "damper ignores angle and acceleration"
    );
    assert_abs_diff_eq!(c.torque_nm(&at_vel(0.45)), -0.6, epsilon = 1e-12);
    assert_abs_diff_eq!(c.torque_nm(&at_vel(-0.15)), 0.1, epsilon = 1e-12);
    assert_abs_diff_eq!(c.torque_nm(&at_vel(100.0)), -1.0, epsilon = 1e-12);
}

#[test]
fn friction_has_constant_magnitude_opposing_motion_beyond_the_smoothing_zone() {
    let c = Condition::symmetric(ConditionKind::Friction, 0.3, 1.0);
    assert_eq!(c.torque_nm(&at_vel(0.0)), 0.0);
    assert_abs_diff_eq!(c.torque_nm(&at_vel(0.5)), -0.3, epsilon = 1e-12);
    assert_abs_diff_eq!(c.torque_nm(&at_vel(50.0)), -0.3, epsilon = 1e-12);
    assert_abs_diff_eq!(c.torque_nm(&at_vel(-2.0)), 0.3, epsilon = 1e-12);
    // Linear within the smoothing zone: half way → half force.
    let half = FRICTION_SMOOTHING_RAD_S / 2.0;
    assert_abs_diff_eq!(c.torque_nm(&at_vel(half)), -0.15, epsilon = 1e-12);
    // Saturation caps a coefficient above it.
    let c = Condition::symmetric(ConditionKind::Friction, 3.0, 0.4);
    assert_abs_diff_eq!(c.torque_nm(&at_vel(1.0)), -0.4, epsilon = 1e-12);
}

#[test]
fn inertia_opposes_acceleration() {
    let c = Condition::symmetric(ConditionKind::Inertia, 0.01, 1.0);
    let s = WheelState {
        angle_rad: 1.0,
        vel_rad_s: 1.0,
        acc_rad_s2: 20.0,
    };
    assert_abs_diff_eq!(c.torque_nm(&s), -0.2, epsilon = 1e-12);
    let s = WheelState {
        acc_rad_s2: -500.0,
        ..s
    };
    assert_abs_diff_eq!(c.torque_nm(&s), 1.0, epsilon = 1e-12);
}

fn enveloped(kind: EffectKind) -> Effect {
    Effect {
        kind,
        envelope: Some(Envelope {
            attack_level_nm: 0.2,
            attack_time_s: 0.1,
            fade_level_nm: 0.0,
            fade_time_s: 0.2,
        }),
        start_delay_s: 0.05,
        duration_s: Some(1.0),
        gain: 1.0,
    }
}

#[test]
fn constant_force_follows_its_envelope_delay_and_duration() {
    let e = enveloped(EffectKind::Constant { level_nm: -1.0 });
    let s = WheelState::default();
    assert_eq!(e.torque_nm(0.04, &s), 0.0, "before the start delay");
    assert_abs_diff_eq!(e.torque_nm(0.05, &s), -0.2, epsilon = 1e-12); // attack level
    assert_abs_diff_eq!(e.torque_nm(0.10, &s), -0.6, epsilon = 1e-12); // half way up
    assert_abs_diff_eq!(e.torque_nm(0.50, &s), -1.0, epsilon = 1e-12); // sustain
    assert_abs_diff_eq!(e.torque_nm(0.95, &s), -0.5, epsilon = 1e-12); // half way down
    assert_abs_diff_eq!(e.torque_nm(1.0499, &s), -0.0005, epsilon = 1e-9);
    assert_eq!(e.torque_nm(1.05, &s), 0.0, "after the duration");
    assert!(e.finished(1.05) && !e.finished(1.0));
}

#[test]
fn ramp_moves_linearly_from_start_to_end_over_its_duration() {
    let e = Effect {
        duration_s: Some(2.0),
        ..Effect::new(EffectKind::Ramp {
            start_nm: -1.0,
            end_nm: 1.0,
        })
    };
    let s = WheelState::default();
    assert_abs_diff_eq!(e.torque_nm(0.0, &s), -1.0, epsilon = 1e-12);
    assert_abs_diff_eq!(e.torque_nm(0.5, &s), -0.5, epsilon = 1e-12);
    assert_abs_diff_eq!(e.torque_nm(1.5, &s), 0.5, epsilon = 1e-12);
    assert_eq!(e.torque_nm(2.0, &s), 0.0);
    // A ramp needs a finite duration.
    assert!(
        Effect::new(EffectKind::Ramp {
            start_nm: 0.0,
            end_nm: 1.0
        })
        .validate()
        .is_err()
    );
}

#[test]
fn ramp_envelope_scales_its_magnitude() {
    let e = enveloped(EffectKind::Ramp {
        start_nm: 1.0,
        end_nm: 1.0,
    });
    let s = WheelState::default();
    assert_abs_diff_eq!(e.torque_nm(0.05, &s), 0.2, epsilon = 1e-12);
    assert_abs_diff_eq!(e.torque_nm(0.95, &s), 0.5, epsilon = 1e-12);
}

fn periodic(waveform: Waveform) -> Effect {
    Effect::new(EffectKind::Periodic(Periodic {
        waveform,
        magnitude_nm: 0.8,
        offset_nm: 0.1,
        phase_rad: 0.0,
        period_s: 0.2,
    }))
}

/// Values at cycle fractions 0, ⅛, ¼, ⅜, ½, ⅝, ¾, ⅞ (just inside, for the square's edges).
fn samples(e: &Effect) -> Vec<f64> {
    (0..8)
        .map(|k| e.torque_nm(0.2 * (k as f64 / 8.0) + 1e-9, &WheelState::default()))
        .collect()
}

#[test]
fn periodic_waveforms_match_their_definitions() {
    let m = 0.8;
    let o = 0.1;
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    let cases: [(Waveform, [f64; 8]); 5] = [
        (Waveform::Sine, [0.0, s2, 1.0, s2, 0.0, -s2, -1.0, -s2]),
        (
            Waveform::Square,
            [1.0, 1.0, 1.0, 1.0, -1.0, -1.0, -1.0, -1.0],
        ),
        (
            Waveform::Triangle,
            [0.0, 0.5, 1.0, 0.5, 0.0, -0.5, -1.0, -0.5],
        ),
        (
            Waveform::SawtoothUp,
            [-1.0, -0.75, -0.5, -0.25, 0.0, 0.25, 0.5, 0.75],
        ),
        (
            Waveform::SawtoothDown,
            [1.0, 0.75, 0.5, 0.25, 0.0, -0.25, -0.5, -0.75],
        ),
    ];
    for (w, unit) in cases {
        let got = samples(&periodic(w));
        for (k, (g, u)) in got.iter().zip(unit).enumerate() {
            assert_abs_diff_eq!(*g, o + m * u, epsilon = 1e-6);
            let _ = k;
        }
    }
}

#[test]
fn periodic_phase_shifts_the_wave_and_envelope_scales_only_the_magnitude() {
    let mut e = periodic(Waveform::Sine);
    if let EffectKind::Periodic(p) = &mut e.kind {
        p.phase_rad = std::f64::consts::FRAC_PI_2;
    }
    // A quarter-cycle phase turns the sine into a cosine.
    assert_abs_diff_eq!(
        e.torque_nm(0.0, &WheelState::default()),
        0.9,
        epsilon = 1e-12
    );
    e.envelope = Some(Envelope {
        attack_level_nm: 0.0,
        attack_time_s: 0.1,
        fade_level_nm: 0.0,
        fade_time_s: 0.0,
    });
    // At t = 0 the magnitude is the attack level 0: only the offset remains.
    assert_abs_diff_eq!(
        e.torque_nm(0.0, &WheelState::default()),
        0.1,
        epsilon = 1e-12
    );
    // At t = 0.025 (a quarter of the attack) the magnitude is 0.2, and the wave is at
    // cycle fraction 0.125 + 0.25: sin(0.75π) = 1/√2.
    let expected = 0.1 + 0.2 * std::f64::consts::FRAC_1_SQRT_2;
    assert_abs_diff_eq!(
        e.torque_nm(0.025, &WheelState::default()),
        expected,
        epsilon = 1e-9
    );
}

#[test]
fn stack_sums_then_clamps_once() {
    let mut stack = EffectStack::new(1.0);
    let a = stack
        .add(Effect::new(EffectKind::Constant { level_nm: 0.8 }))
        .unwrap();
    let b = stack
        .add(Effect::new(EffectKind::Constant { level_nm: 0.7 }))
        .unwrap();
    let c = stack
        .add(Effect::new(EffectKind::Constant { level_nm: -0.9 }))
        .unwrap();
    let s = WheelState::default();
    stack.play(a).unwrap();
    stack.play(b).unwrap();
    let out = stack.render(0, &s);
    assert_eq!((out.torque_nm, out.clipped, out.active), (1.0, true, 2));
    // Clamping after the sum: 0.8 + 0.7 − 0.9 = 0.6 (clamping each first would not change
    // this case, but clamping a partial sum of a and b would give 0.1).
    stack.play(c).unwrap();
    let out = stack.render(1_000_000, &s);
    assert_abs_diff_eq!(out.torque_nm, 0.6, epsilon = 1e-12);
    assert!(!out.clipped);
    stack.set_gain(0.5).unwrap();
    assert_abs_diff_eq!(stack.render(2_000_000, &s).torque_nm, 0.3, epsilon = 1e-12);
    assert!(stack.set_gain(1.5).is_err());
}

#[test]
fn stack_stops_finished_effects_and_rejects_stale_ids() {
    let mut stack = EffectStack::new(2.0);
    let e = stack
        .add(Effect {
            duration_s: Some(0.01),
            ..Effect::new(EffectKind::Constant { level_nm: 1.0 })
        })
        .unwrap();
    stack.play(e).unwrap();
    let s = WheelState::default();
    assert_eq!(stack.render(5_000_000, &s).torque_nm, 1.0);
    assert_eq!(stack.render(14_000_000, &s).torque_nm, 1.0);
    assert_eq!(stack.render(15_000_000, &s).torque_nm, 0.0);
    assert!(!stack.is_playing(e));
    stack.remove(e).unwrap();
    assert_eq!(stack.play(e), Err(EffectError::NoSuchEffect(e)));
    let e2 = stack
        .add(Effect::new(EffectKind::Constant { level_nm: 1.0 }))
        .unwrap();
    assert_ne!(e, e2, "a reused slot gets a new generation");
}

#[test]
fn stack_refuses_invalid_effects_and_overflow() {
    let mut stack = EffectStack::new(2.0);
    let bad = Effect::new(EffectKind::Constant { level_nm: f64::NAN });
    let err = stack.add(bad).unwrap_err();
    assert!(err.to_string().contains("level_nm"), "{err}");
    for _ in 0..EFFECT_SLOTS {
        stack
            .add(Effect::new(EffectKind::Constant { level_nm: 0.1 }))
            .unwrap();
    }
    assert_eq!(
        stack.add(Effect::new(EffectKind::Constant { level_nm: 0.1 })),
        Err(EffectError::StackFull)
    );
}

#[test]
fn toolbox_units_convert_with_the_thesis_scales() {
    let p = DeviceProfile::thesis_sidewinder();
    // eff2 = effect('inf', [], 'constant', [10000], [1 1]) → full torque, 1.873 N·m.
    let e = to_effect(
        &ToolboxEffect {
            duration_us: None,
            envelope: None,
            kind: ToolboxKind::Constant(10_000.0),
        },
        &p,
    )
    .unwrap();
    assert_abs_diff_eq!(
        e.torque_nm(0.0, &WheelState::default()),
        1.873,
        epsilon = 1e-12
    );
    // eff3 = effect('inf', [], 'spring', [0 5000 5000 5000 5000 0]): half coefficient gives
    // half of full force at full deflection, saturating at half force.
    let e = to_effect(
        &ToolboxEffect {
            duration_us: None,
            envelope: None,
            kind: ToolboxKind::Condition(
                ConditionKind::Spring,
                [0.0, 5000.0, 5000.0, 5000.0, 5000.0, 0.0],
            ),
        },
        &p,
    )
    .unwrap();
    let full = at_angle(p.half_range_rad);
    assert_abs_diff_eq!(e.torque_nm(0.0, &full), -1.873 / 2.0, epsilon = 1e-9);
    // eff4 = effect('inf', [], 'square', [10000 0 0 100000]): 0.1 s period.
    let e = to_effect(
        &ToolboxEffect {
            duration_us: Some(1_000_000.0),
            envelope: Some([0.0, 100_000.0, 0.0, 0.0]),
            kind: ToolboxKind::Periodic(Waveform::Square, [10_000.0, 0.0, 9000.0, 100_000.0]),
        },
        &p,
    )
    .unwrap();
    let EffectKind::Periodic(per) = e.kind else {
        panic!("periodic expected")
    };
    assert_abs_diff_eq!(per.period_s, 0.1, epsilon = 1e-15);
    assert_abs_diff_eq!(per.phase_rad, std::f64::consts::FRAC_PI_2, epsilon = 1e-12);
    assert_eq!(e.duration_s, Some(1.0));
    assert_abs_diff_eq!(e.envelope.unwrap().attack_time_s, 0.1, epsilon = 1e-15);
}

proptest::proptest! {
    /// Whatever effects play, the stack's output is finite and within its limit.
    #[test]
    fn stack_output_stays_within_its_limit(
        levels in proptest::collection::vec(-100.0f64..100.0, 1..EFFECT_SLOTS),
        coefs in proptest::collection::vec(-1.0e3f64..1.0e3, 1..4),
        angle in -10.0f64..10.0,
        vel in -100.0f64..100.0,
        t_ms in 0u64..5000,
    ) {
        let mut stack = EffectStack::new(1.87);
        for l in &levels {
            let id = stack.add(Effect::new(EffectKind::Constant { level_nm: *l })).unwrap();
            stack.play(id).unwrap();
        }
        for (c, kind) in coefs.iter().zip([ConditionKind::Spring, ConditionKind::Damper, ConditionKind::Friction]) {
            if let Ok(id) = stack.add(Effect::new(EffectKind::Condition(Condition::symmetric(kind, *c, 50.0)))) {
                stack.play(id).unwrap();
            }
        }
        let s = WheelState { angle_rad: angle, vel_rad_s: vel, acc_rad_s2: 0.0 };
        let out = stack.render(t_ms * 1_000_000, &s);
        proptest::prop_assert!(out.torque_nm.is_finite() && out.torque_nm.abs() <= 1.87);
    }
}
