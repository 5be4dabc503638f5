//! Per-tick cost of the haptic chain (full effect stack + model + passivity + safety) and of
//! the estimators. Run: `cargo bench -p haptic-wheel --bench chain -- --warm-up-time 1 --measurement-time 3`.

use criterion::{Criterion, criterion_group, criterion_main};
use haptic_wheel::{
    Condition, ConditionKind, Effect, EffectKind, Envelope, HapticChain, HapticChainConfig,
    KalmanEstimator, KalmanParams, MovingAverage, PassivityParams, Periodic, SafetyConfig,
    SpringDamper, StateEstimator, TickInput, Waveform, WheelReading, effects::EFFECT_SLOTS,
};
use std::hint::black_box;

/// A chain with every slot of the effect stack playing (all four conditions, constant, ramp,
/// and the five periodic shapes, with envelopes), the eq. 3.5 model and passivity on.
fn full_chain() -> HapticChain {
    let cfg = HapticChainConfig {
        safety: SafetyConfig::default(),
        model: Some(SpringDamper {
            k_nm_per_rad: 2.0,
            b_nm_s_per_rad: 0.05,
            i_kg_m2: 0.001,
            centre_rad: 0.0,
        }),
        passivity: Some(PassivityParams::default()),
        estimator: KalmanParams::for_haptic_loop(haptic_wheel::THESIS_KA_RAD_PER_UNIT),
    };
    let mut chain = HapticChain::new(cfg, haptic_wheel::THESIS_WHEEL_MAX_TORQUE_NM).unwrap();
    let env = Some(Envelope {
        attack_level_nm: 0.1,
        attack_time_s: 0.5,
        fade_level_nm: 0.0,
        fade_time_s: 0.5,
    });
    let mut kinds: Vec<EffectKind> = [
        ConditionKind::Spring,
        ConditionKind::Damper,
        ConditionKind::Friction,
        ConditionKind::Inertia,
    ]
    .into_iter()
    .map(|k| EffectKind::Condition(Condition::symmetric(k, 0.1, 1.0)))
    .collect();
    kinds.push(EffectKind::Constant { level_nm: 0.2 });
    kinds.push(EffectKind::Ramp {
        start_nm: -0.2,
        end_nm: 0.2,
    });
    for w in [
        Waveform::Sine,
        Waveform::Square,
        Waveform::Triangle,
        Waveform::SawtoothUp,
        Waveform::SawtoothDown,
    ] {
        kinds.push(EffectKind::Periodic(Periodic {
            waveform: w,
            magnitude_nm: 0.05,
            offset_nm: 0.0,
            phase_rad: 0.3,
            period_s: 0.1,
        }));
    }
    let mut k = 0;
    while kinds.len() < EFFECT_SLOTS {
        kinds.push(kinds[k]);
        k += 1;
    }
    for kind in kinds {
        let id = chain
            .effects_mut()
            .add(Effect {
                kind,
                envelope: env,
                start_delay_s: 0.0,
                duration_s: Some(1.0e4),
                gain: 0.8,
            })
            .unwrap();
        chain.effects_mut().play(id).unwrap();
    }
    chain
}

fn bench_chain(c: &mut Criterion) {
    let mut chain = full_chain();
    let mut k: u64 = 0;
    c.bench_function(
        &format!("chain_tick_{EFFECT_SLOTS}_effects_model_passivity_safety"),
        |b| {
            b.iter(|| {
                k += 1;
                let now = k * 1_000_000;
                let angle = ((k as f64 * 1e-3).sin() / 0.002253).round() * 0.002253;
                black_box(chain.tick(black_box(TickInput {
                    now_ns: now,
                    reading: Some(WheelReading {
                        angle_rad: angle,
                        t_ns: now,
                    }),
                    external_nm: 0.1,
                })))
            })
        },
    );
}

fn bench_filters(c: &mut Criterion) {
    // Accuracy side by side (deterministic; printed once, not timed).
    for step in [haptic_wheel::THESIS_KA_RAD_PER_UNIT, 0.1] {
        match haptic_wheel::filter::compare_on_sim_wheel(step, 10.0) {
            Ok(cmp) => print!("{cmp}"),
            Err(e) => eprintln!("comparison failed: {e}"),
        }
    }
    let mut g = c.benchmark_group("filters");
    let mut ma = MovingAverage::thesis();
    let mut n = 0u64;
    g.bench_function("moving_average_m175_update", |b| {
        b.iter(|| {
            n += 1;
            black_box(ma.update(black_box((n % 1000) as f64 * 0.002253), 1e-3))
        })
    });
    let mut kf = KalmanEstimator::new(KalmanParams::for_encoder_step(
        haptic_wheel::THESIS_KA_RAD_PER_UNIT,
    ))
    .unwrap();
    g.bench_function("kalman_update", |b| {
        b.iter(|| {
            n += 1;
            black_box(kf.update(black_box((n % 1000) as f64 * 0.002253), 1e-3))
        })
    });
    g.finish();
}

criterion_group!(benches, bench_chain, bench_filters);
criterion_main!(benches);
