//! proptest strategies over the haptic chain's inputs (finite and non-finite numbers, every
//! effect, the regimen's spring–damper), shared by this crate's chain tests and the real
//! backends' all-modes proptest in `wheel-devices`, which compiles this same file into its
//! tests (`#[path]`): built for tests only, so proptest never enters the shipped binary's
//! dependency graph (a cargo feature would put it there for `cargo metadata`, and so in the
//! package's copyright file). Hence the `haptic_wheel::` paths (this crate names itself so).

use proptest::prelude::*;

use haptic_wheel::effects::{
    Condition, ConditionKind, Effect, EffectKind, Envelope, Periodic, Waveform,
};
use haptic_wheel::model::SpringDamper;

/// The haptic loop's nominal period, ns (1 kHz).
pub const DT_NS: u64 = 1_000_000;

/// Any torque or angle a caller might pass: mostly finite within ±50, sometimes NaN, ±∞ or
/// any `f64` at all.
pub fn any_finite_or_not() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => -50.0f64..50.0,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => any::<f64>(),
    ]
}

/// Any effect of the thesis set with its envelope, delay, duration and gain.
pub fn any_effect() -> impl Strategy<Value = Effect> {
    let waveform = prop_oneof![
        Just(Waveform::Sine),
        Just(Waveform::Square),
        Just(Waveform::Triangle),
        Just(Waveform::SawtoothUp),
        Just(Waveform::SawtoothDown),
    ];
    let cond_kind = prop_oneof![
        Just(ConditionKind::Spring),
        Just(ConditionKind::Damper),
        Just(ConditionKind::Friction),
        Just(ConditionKind::Inertia),
    ];
    let kind = prop_oneof![
        (
            cond_kind,
            -1.0f64..1.0,
            -100.0f64..100.0,
            -100.0f64..100.0,
            0.0f64..20.0,
            0.0f64..20.0,
            0.0f64..0.5
        )
            .prop_map(
                |(kind, offset, pc, nc, ps, ns, deadband)| EffectKind::Condition(Condition {
                    kind,
                    offset,
                    positive_coefficient: pc,
                    negative_coefficient: nc,
                    positive_saturation_nm: ps,
                    negative_saturation_nm: ns,
                    deadband,
                })
            ),
        (-20.0f64..20.0).prop_map(|level_nm| EffectKind::Constant { level_nm }),
        (-20.0f64..20.0, -20.0f64..20.0)
            .prop_map(|(start_nm, end_nm)| EffectKind::Ramp { start_nm, end_nm }),
        (
            waveform,
            -20.0f64..20.0,
            -5.0f64..5.0,
            -7.0f64..7.0,
            0.001f64..2.0
        )
            .prop_map(|(waveform, magnitude_nm, offset_nm, phase_rad, period_s)| {
                EffectKind::Periodic(Periodic {
                    waveform,
                    magnitude_nm,
                    offset_nm,
                    phase_rad,
                    period_s,
                })
            }),
    ];
    (
        kind,
        proptest::option::of((0.0f64..20.0, 0.0f64..0.5, 0.0f64..20.0, 0.0f64..0.5)),
        0.0f64..0.2,
        0.01f64..2.0,
        0.0f64..=1.0,
    )
        .prop_map(|(kind, env, start_delay_s, duration, gain)| Effect {
            kind,
            envelope: env.map(|(al, at, fl, ft)| Envelope {
                attack_level_nm: al,
                attack_time_s: at,
                fade_level_nm: fl,
                fade_time_s: ft,
            }),
            start_delay_s,
            duration_s: Some(duration),
            gain,
        })
}

/// No model, or any spring–damper (eq. 3.5) within generous bounds.
pub fn any_model() -> impl Strategy<Value = Option<SpringDamper>> {
    proptest::option::of(
        (0.0f64..200.0, 0.0f64..10.0, 0.0f64..1.0, -3.0f64..3.0).prop_map(|(k, b, i, c)| {
            SpringDamper {
                k_nm_per_rad: k,
                b_nm_s_per_rad: b,
                i_kg_m2: i,
                centre_rad: c,
            }
        }),
    )
}
