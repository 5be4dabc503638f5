//! The chain end to end on the simulated wheel: the clamp holds for any effect/model
//! combination (proptest), passivity stabilises a stiff spring on a delayed wheel, stop and
//! watchdog reach zero torque.

use super::*;
use crate::effects::{Effect, EffectKind, Periodic, Waveform};
use crate::sim::{SimWheel, SimWheelParams};
use crate::strategies::{DT_NS, any_effect, any_finite_or_not, any_model};
use crate::wheel::Wheel;
use proptest::prelude::*;

fn chain(model: Option<SpringDamper>, passivity: Option<PassivityParams>) -> HapticChain {
    let cfg = HapticChainConfig {
        safety: SafetyConfig {
            soft_start_s: 0.05,
            ..Default::default()
        },
        model,
        passivity,
        estimator: KalmanParams::for_haptic_loop(crate::THESIS_KA_RAD_PER_UNIT),
    };
    HapticChain::new(cfg, crate::THESIS_WHEEL_MAX_TORQUE_NM).unwrap()
}

/// Closed loop: chain ↔ simulated wheel at 1 kHz for `ticks`, hand torque from `hand`.
/// Returns every tick's telemetry and the wheel's true angles.
fn run_closed_loop(
    chain: &mut HapticChain,
    wheel: &mut SimWheel,
    ticks: usize,
    hand: impl Fn(usize, &SimWheel) -> f64,
) -> (Vec<TickTelemetry>, Vec<f64>) {
    let mut tel = Vec::with_capacity(ticks);
    let mut angles = Vec::with_capacity(ticks);
    for k in 0..ticks {
        let reading = wheel.read().ok();
        let t = chain.tick(TickInput {
            now_ns: wheel.time_ns(),
            reading,
            external_nm: 0.0,
        });
        wheel.command_torque(t.torque_nm).unwrap();
        let h = hand(k, wheel);
        wheel.advance(DT_NS as f64 * 1e-9, h);
        tel.push(t);
        angles.push(wheel.true_angle_rad());
    }
    (tel, angles)
}

fn peak_abs(xs: &[f64]) -> f64 {
    xs.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// A stiff virtual spring (K = 25 N·m/rad, like an end stop reaching full torque in ~4°) on a
/// wheel with 4 ms of USB delay and 1 ms of jitter, released from 0.05 rad with no hand on it.
fn stiff_spring_case(passivity: Option<PassivityParams>) -> (Vec<TickTelemetry>, Vec<f64>) {
    let mut wheel = SimWheel::new(SimWheelParams {
        usb_delay_s: 0.004,
        usb_jitter_s: 0.001,
        ..Default::default()
    });
    wheel.set_state(0.05, 0.0);
    let model = SpringDamper {
        k_nm_per_rad: 25.0,
        b_nm_s_per_rad: 0.0,
        i_kg_m2: 0.0,
        centre_rad: 0.0,
    };
    let mut c = chain(Some(model), passivity);
    run_closed_loop(&mut c, &mut wheel, 4000, |_, _| 0.0)
}

#[test]
fn stiff_spring_on_a_delayed_wheel_oscillates_without_passivity_and_settles_with_it() {
    let (tel_off, ang_off) = stiff_spring_case(None);
    let pc = PassivityParams {
        port_delay_ticks: 4,
        ..Default::default()
    };
    let (tel_on, ang_on) = stiff_spring_case(Some(pc));
    let last_s = 3000..4000;
    let amp_off = peak_abs(&ang_off[last_s.clone()]);
    let amp_on = peak_abs(&ang_on[last_s.clone()]);
    let torque_off = peak_abs(
        &tel_off[last_s.clone()]
            .iter()
            .map(|t| t.torque_nm)
            .collect::<Vec<_>>(),
    );
    println!(
        "last second: without passivity peak angle {amp_off:.4} rad, peak torque {torque_off:.3} N·m; \
         with passivity peak angle {amp_on:.5} rad, min observed energy {:.4} J",
        tel_on
            .iter()
            .map(|t| t.passivity_energy_j)
            .fold(f64::INFINITY, f64::min)
    );
    // Without the controller the oscillation does not decay: a limit cycle at least as large
    // as the release (growing energy until the torque ceiling caps it).
    assert!(amp_off >= 0.05, "no sustained oscillation: {amp_off}");
    // With it, the wheel comes to rest within a few encoder steps of the centre.
    assert!(amp_on < 0.01, "not stabilised: {amp_on}");
    assert!(
        tel_on
            .iter()
            .any(|t| t.passivity_damping_nm_s_per_rad > 0.0)
    );
}

#[test]
fn soft_spring_is_left_alone_by_the_passivity_controller() {
    // K = 0.83 N·m/rad (1.87 N·m at 129°) is passive at any rate (FIELD-NOTES).
    let mut wheel = SimWheel::new(SimWheelParams::default());
    wheel.set_state(0.8, 0.0);
    let model = SpringDamper {
        k_nm_per_rad: 0.83,
        b_nm_s_per_rad: 0.05,
        i_kg_m2: 0.0,
        centre_rad: 0.0,
    };
    let mut c = chain(Some(model), Some(PassivityParams::default()));
    let (tel, ang) = run_closed_loop(&mut c, &mut wheel, 4000, |_, _| 0.0);
    let damped_ticks = tel
        .iter()
        .filter(|t| t.passivity_damping_nm_s_per_rad > 0.0)
        .count();
    assert!(
        damped_ticks < 40,
        "controller active on {damped_ticks} ticks"
    );
    assert!(
        ang[3999].abs() < 0.05,
        "spring returns the wheel to centre: {}",
        ang[3999]
    );
}

#[test]
fn stats_accumulate_clipping_time_passivity_and_faults() {
    let mut wheel = SimWheel::new(SimWheelParams::default());
    let mut c = chain(None, None);
    c.set_ceiling_nm(0.5).unwrap();
    let id = c
        .effects_mut()
        .add(Effect::new(EffectKind::Constant { level_nm: 1.0 }))
        .unwrap();
    c.effects_mut().play(id).unwrap();
    let (tel, _) = run_closed_loop(&mut c, &mut wheel, 1000, |_, _| 0.0);
    let mut stats = HapticStats::default();
    for (k, t) in tel.iter().enumerate() {
        stats.record(t, if k == 10 { 3_000_000 } else { 50_000 }, 20_000, 500_000);
    }
    assert_eq!(stats.ticks, 1000);
    assert_eq!(stats.late_ticks, 1);
    assert_eq!(stats.max_lateness_ns, 3_000_000);
    // Soft start reaches the 0.5 N·m ceiling after 25 ms; clipped from then on.
    assert!(
        (stats.clipped_s - 0.975).abs() < 0.01,
        "{}",
        stats.clipped_s
    );
    assert!(stats.max_abs_torque_nm <= 0.5);
    assert_eq!(stats.fault_ticks, 0);
    assert!((stats.clipped_fraction(1.0) - stats.clipped_s).abs() < 1e-12);
}

#[test]
fn regimen_applies_all_or_nothing_and_round_trips_through_toml() {
    let text = r#"
ceiling_nm = 1.2

[model]
k_nm_per_rad = 0.8
b_nm_s_per_rad = 0.05
i_kg_m2 = 0.0
centre_rad = 0.0

[[effects]]
kind = { constant = { level_nm = 0.4 } }

[[effects]]
start_delay_s = 0.5
duration_s = 2.0
gain = 0.5
kind = { periodic = { waveform = "sine", magnitude_nm = 0.3, offset_nm = 0.0, phase_rad = 0.0, period_s = 0.5 } }
envelope = { attack_level_nm = 0.0, attack_time_s = 0.2, fade_level_nm = 0.0, fade_time_s = 0.2 }
"#;
    let regimen: HapticRegimen = toml::from_str(text).unwrap();
    assert_eq!(regimen.effects.len(), 2);
    let back: HapticRegimen = toml::from_str(&toml::to_string(&regimen).unwrap()).unwrap();
    assert_eq!(back, regimen);

    let mut c = chain(None, None);
    c.apply_regimen(&regimen).unwrap();
    assert_eq!(c.ceiling_nm(), 1.2);
    let tel = c.tick(TickInput {
        now_ns: 0,
        reading: Some(WheelReading {
            angle_rad: 0.0,
            t_ns: 0,
        }),
        external_nm: 0.0,
    });
    assert!((tel.effects_nm - 0.4).abs() < 1e-12, "{}", tel.effects_nm);

    // A bad effect (negative period) or a ceiling above the device is refused, naming it,
    // and nothing changes.
    let mut bad = regimen.clone();
    bad.effects.push(Effect::new(EffectKind::Periodic(Periodic {
        waveform: Waveform::Square,
        magnitude_nm: 0.1,
        offset_nm: 0.0,
        phase_rad: 0.0,
        period_s: -1.0,
    })));
    bad.ceiling_nm = Some(0.3);
    let msg = c.apply_regimen(&bad).unwrap_err().to_string();
    assert!(
        msg.contains("effects[2]") && msg.contains("period_s"),
        "{msg}"
    );
    assert_eq!(c.ceiling_nm(), 1.2);
    let too_strong = HapticRegimen {
        ceiling_nm: Some(3.0),
        ..HapticRegimen::default()
    };
    assert!(
        c.apply_regimen(&too_strong)
            .unwrap_err()
            .to_string()
            .contains("ceiling_nm")
    );
    assert!(toml::from_str::<HapticRegimen>("surprise = 1").is_err());
}

#[test]
fn stop_request_fades_to_zero_and_stays_there() {
    let mut wheel = SimWheel::new(SimWheelParams::default());
    let mut c = chain(None, None);
    let id = c
        .effects_mut()
        .add(Effect::new(EffectKind::Constant { level_nm: 1.0 }))
        .unwrap();
    c.effects_mut().play(id).unwrap();
    let (tel, _) = run_closed_loop(&mut c, &mut wheel, 500, |_, _| 0.0);
    assert!((tel[499].torque_nm - 1.0).abs() < 1e-9);
    c.request_stop();
    let (tel, _) = run_closed_loop(&mut c, &mut wheel, 500, |_, _| 0.0);
    assert_eq!(tel[499].torque_nm, 0.0);
    assert_eq!(tel[499].watchdog, WatchdogState::Stopped);
}

#[test]
fn failed_reads_fade_the_torque_out() {
    let mut c = chain(None, None);
    let id = c
        .effects_mut()
        .add(Effect::new(EffectKind::Constant { level_nm: -1.5 }))
        .unwrap();
    c.effects_mut().play(id).unwrap();
    let mut last = None;
    for k in 0..600u64 {
        let now = k * DT_NS;
        let reading = (k < 200).then_some(WheelReading {
            angle_rad: 0.0,
            t_ns: now,
        });
        last = Some(c.tick(TickInput {
            now_ns: now,
            reading,
            external_nm: 0.0,
        }));
    }
    let last = last.unwrap();
    assert_eq!(last.torque_nm, 0.0);
    assert_eq!(last.fault(), Some(Fault::StaleReading));
}

#[test]
fn chain_config_round_trips_through_toml_and_rejects_unknown_fields() {
    let cfg = HapticChainConfig::for_encoder_step(0.002253);
    let text = toml::to_string(&cfg).unwrap();
    let back: HapticChainConfig = toml::from_str(&text).unwrap();
    assert_eq!(cfg, back);
    let bad = format!("{text}\nsurprise = 1\n");
    assert!(toml::from_str::<HapticChainConfig>(&bad).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Safety invariants 1–2: whatever effects, model, readings and external torque arrive,
    /// the torque sent is finite, within the patient's ceiling and within the slew limit.
    #[test]
    fn clamp_and_slew_hold_for_any_effect_and_model_combination(
        effects in proptest::collection::vec(any_effect(), 0..8),
        model in any_model(),
        passivity in any::<bool>(),
        ceiling in 0.0f64..1.87,
        angles in proptest::collection::vec(any_finite_or_not(), 50..300),
        externals in proptest::collection::vec(any_finite_or_not(), 1..20),
    ) {
        let cfg = HapticChainConfig {
            safety: SafetyConfig { ceiling_nm: Some(ceiling), soft_start_s: 0.01, ..Default::default() },
            model,
            passivity: passivity.then(PassivityParams::default),
            estimator: KalmanParams::for_haptic_loop(crate::THESIS_KA_RAD_PER_UNIT),
        };
        let slew = cfg.safety.slew_nm_per_s;
        let mut c = HapticChain::new(cfg, crate::THESIS_WHEEL_MAX_TORQUE_NM).unwrap();
        for e in effects {
            let id = c.effects_mut().add(e).unwrap();
            c.effects_mut().play(id).unwrap();
        }
        let mut last = 0.0f64;
        for (k, a) in angles.iter().enumerate() {
            let now = k as u64 * DT_NS;
            let t = c.tick(TickInput {
                now_ns: now,
                reading: Some(WheelReading { angle_rad: *a, t_ns: now }),
                external_nm: externals[k % externals.len()],
            });
            prop_assert!(t.torque_nm.is_finite());
            prop_assert!(t.torque_nm.abs() <= ceiling + 1e-12, "{} > {}", t.torque_nm, ceiling);
            prop_assert!((t.torque_nm - last).abs() <= slew * 1e-3 + 1e-12);
            last = t.torque_nm;
        }
    }
}
