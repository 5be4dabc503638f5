//! Safety invariants 1–3 of the whole chain, across every mode and transition, checked in
//! N·m at the motor of every built-in wheel profile and of an unknown wheel on each driver.
//!
//! One random script of operations (ticks with jittered, stalled or backwards clocks; wheel
//! readings that are real, arbitrary — NaN and infinities included —, missing, stale or from
//! the future; any external torque; pause, resume, stop; regimen changes, ceiling changes,
//! effects added and the effect gain changed, valid or not) is played against a
//! [`HapticChain`] driving each real backend on its in-memory device (the evdev backend on
//! Linux, the DirectInput backend everywhere: `crate::backend_tests`): the product's own
//! N·m → device level mapping, gain and update-rate policy, with a motor as strong as the
//! profile states. After every operation:
//!
//! - the command is finite, within the ceiling in force, and within the slew limit of the
//!   previous command (a ceiling lowered at run time holds at once: the step goes to the new
//!   ceiling, then the slew limit applies);
//! - the motor's torque is within the ceiling in force, at once after a lowered ceiling (the
//!   backend is told the ceiling every tick, as the station's loop does, and brings a held
//!   level down without waiting for its rate policy), and within one kernel level of the
//!   command whenever the backend sent it;
//! - between two updates to the command's own level the motor steps by no more than the slew
//!   limit allows over the ticks in between, plus one kernel level; a held level only moves
//!   towards zero (brought down to a lowered ceiling);
//! - after a stop, a pause or a continuous fault, command and motor are zero once the fade
//!   bound `fade_out_s + ceiling / slew` has passed on the supervisor's clock, and stay there.

use crate::backend_tests::{Backend, Motor};
use crate::strategies::{DT_NS, any_effect, any_finite_or_not, any_model};
use clock::{Clock, MockClock};
use haptic_wheel::chain::*;
use haptic_wheel::profile::{DeviceProfile, DriverFamily};
use haptic_wheel::wheel_config::WheelConfig;
use haptic_wheel::*;
use proptest::prelude::*;

/// How the clock moves before a tick.
#[derive(Clone, Copy, Debug)]
enum Gap {
    /// The nominal 1 ms.
    Nominal,
    /// Any gap up to the watchdog's limit (a late or early tick), ns.
    Jitter(u64),
    /// A stall beyond the watchdog's limit, ns.
    Stall(u64),
    /// The chain is handed a time this far before the previous tick's, ns.
    Backwards(u64),
}

/// Which wheel reading the chain gets.
#[derive(Clone, Copy, Debug)]
enum Reading {
    /// Read from the wheel (the backend's conversion of the kernel's axis).
    Wheel,
    /// An arbitrary angle stamped now, rad (NaN and infinities included).
    Angle(f64),
    /// The read failed.
    Missing,
    /// A reading this old, ns.
    Stale(u64),
    /// A reading stamped this far in the future, ns.
    Future(u64),
}

#[derive(Clone, Debug)]
enum Op {
    /// `repeat` ticks with the same gap, reading kind and external torque (N·m).
    Tick {
        gap: Gap,
        reading: Reading,
        external_nm: f64,
        repeat: u16,
    },
    Pause,
    Resume,
    /// A regimen change mid-stream; its ceiling is a fraction of the device maximum (above 1:
    /// must be refused) or NaN.
    Regimen {
        regimen: HapticRegimen,
        ceiling_fraction: Option<f64>,
    },
    /// A run-time ceiling change, as a fraction of the device maximum (above 1 or NaN: must
    /// be refused).
    Ceiling(f64),
    /// Add and play an effect (refused when invalid or the stack is full).
    Effect(Effect),
    /// The effect stack's global gain (refused outside [0, 1]).
    EffectGain(f64),
    /// Remove every effect.
    ClearEffects,
}

fn any_gap() -> impl Strategy<Value = Gap> {
    prop_oneof![
        6 => Just(Gap::Nominal),
        3 => (50_000u64..=10_000_000).prop_map(Gap::Jitter),
        1 => (10_000_001u64..80_000_000).prop_map(Gap::Stall),
        1 => (1u64..3_000_000).prop_map(Gap::Backwards),
    ]
}

fn any_reading() -> impl Strategy<Value = Reading> {
    prop_oneof![
        8 => Just(Reading::Wheel),
        2 => any_finite_or_not().prop_map(Reading::Angle),
        1 => Just(Reading::Missing),
        1 => (20_000_001u64..200_000_000).prop_map(Reading::Stale),
        1 => (1u64..5_000_000).prop_map(Reading::Future),
    ]
}

fn any_torque() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -3.0f64..3.0,
        3 => any_finite_or_not(),
        1 => prop_oneof![Just(f64::MAX), Just(-1e300), Just(40.0), Just(f64::MIN_POSITIVE)],
    ]
}

fn any_fraction() -> impl Strategy<Value = f64> {
    prop_oneof![
        16 => 0.0f64..=1.0,
        1 => 1.000_001f64..3.0,
        1 => Just(f64::NAN),
        1 => Just(-0.5),
    ]
}

fn any_regimen_model() -> impl Strategy<Value = Option<SpringDamper>> {
    prop_oneof![
        16 => any_model(),
        1 => Just(Some(SpringDamper { k_nm_per_rad: f64::NAN, ..Default::default() })),
        1 => Just(Some(SpringDamper { b_nm_s_per_rad: f64::INFINITY, ..Default::default() })),
    ]
}

fn any_effect_or_invalid() -> impl Strategy<Value = Effect> {
    prop_oneof![
        8 => any_effect(),
        1 => Just(Effect::new(EffectKind::Constant { level_nm: f64::NAN })),
        1 => (any::<f64>(), any::<f64>()).prop_map(|(g, d)| Effect {
            gain: g,
            duration_s: Some(d),
            ..Effect::new(EffectKind::Constant { level_nm: 1.0 })
        }),
    ]
}

fn any_op() -> impl Strategy<Value = Op> {
    // Healthy stretches (the loop on time, the wheel read) long enough to reach full torque,
    // and short disturbances of any kind.
    let healthy_gap = prop_oneof![
        4 => Just(Gap::Nominal),
        1 => (50_000u64..=10_000_000).prop_map(Gap::Jitter),
    ];
    let healthy_reading = prop_oneof![
        6 => Just(Reading::Wheel),
        1 => (-10.0f64..10.0).prop_map(Reading::Angle),
    ];
    prop_oneof![
        8 => (healthy_gap, healthy_reading, any_torque(), 1u16..300).prop_map(
            |(gap, reading, external_nm, repeat)| Op::Tick { gap, reading, external_nm, repeat }
        ),
        3 => (any_gap(), any_reading(), any_torque(), 1u16..20).prop_map(
            |(gap, reading, external_nm, repeat)| Op::Tick { gap, reading, external_nm, repeat }
        ),
        // A lasting outage: the wheel stops answering.
        1 => (any_torque(), 100u16..800).prop_map(|(external_nm, repeat)| Op::Tick {
            gap: Gap::Nominal,
            reading: Reading::Missing,
            external_nm,
            repeat,
        }),
        1 => Just(Op::Pause),
        1 => Just(Op::Resume),
        2 => (
            proptest::collection::vec(
                prop_oneof![12 => any_effect(), 1 => any_effect_or_invalid()],
                0..5
            ),
            any_regimen_model(),
            proptest::option::of(any_fraction()),
        )
            .prop_map(|(effects, model, ceiling_fraction)| Op::Regimen {
                regimen: HapticRegimen { effects, model, ceiling_nm: None },
                ceiling_fraction,
            }),
        1 => any_fraction().prop_map(Op::Ceiling),
        1 => any_effect_or_invalid().prop_map(Op::Effect),
        1 => prop_oneof![0.0f64..=1.0, Just(f64::NAN), Just(1.5)].prop_map(Op::EffectGain),
        1 => Just(Op::ClearEffects),
    ]
}

/// The safety settings of one case: every field inside its validated range.
fn any_safety() -> impl Strategy<Value = (Option<f64>, SafetyConfig)> {
    (
        proptest::option::of(0.0f64..=1.0),
        50.0f64..2000.0,
        0.001f64..1.0,
        0.01f64..0.5,
    )
        .prop_map(|(ceiling_fraction, slew, soft, fade)| {
            (
                ceiling_fraction,
                SafetyConfig {
                    ceiling_nm: None,
                    slew_nm_per_s: slew,
                    soft_start_s: soft,
                    fade_out_s: fade,
                    ..SafetyConfig::default()
                },
            )
        })
}

/// Every wheel the product knows how to drive: each built-in profile (opened by its USB id,
/// as the backend resolves it, or given inline when it has no id) and an unknown wheel on
/// each driver family (32 N·m assumed, capped at 1 N·m).
fn every_wheel() -> Vec<(String, (u16, u16), Option<DeviceProfile>)> {
    let mut wheels: Vec<_> = DeviceProfile::builtin()
        .into_iter()
        .map(|p| match (p.usb_vendor, p.usb_products.first()) {
            (Some(v), Some(&pid)) => (p.name.clone(), (v, pid), None),
            _ => (p.name.clone(), (0x1d50, 0x6015), Some(p)),
        })
        .collect();
    // Unknown products of known vendors get their vendor's driver; an unknown vendor is USB
    // PID; HID++ is only reachable with an inline profile.
    for (vendor, driver) in [
        (0x1d50u16, DriverFamily::HidPidff),
        (0x046d, DriverFamily::Lg4ff),
        (0x044f, DriverFamily::Tmff2),
        (0x0eb7, DriverFamily::Fanatec),
    ] {
        let id = (vendor, 0xfff0);
        assert_eq!(DeviceProfile::for_usb_id(id.0, id.1).driver, driver);
        wheels.push((format!("unknown wheel on {driver:?}"), id, None));
    }
    wheels.push((
        "unknown wheel on Hidpp".into(),
        (0x1d50, 0x6015),
        Some(DeviceProfile::unknown(DriverFamily::Hidpp)),
    ));
    wheels
}

/// What the chain and the motor did, tick after tick, and the bounds they must keep.
struct Checker {
    slew_nm_per_s: f64,
    fade_out_s: f64,
    max_tick_gap_s: f64,
    /// One kernel level at the motor, N·m.
    level_nm: f64,
    /// The motor's torque for a kernel level, N·m, signed as the command.
    motor_per_level_nm: f64,
    last_cmd_nm: f64,
    /// Lowest ceiling since the previous tick (a lowered ceiling holds at once).
    ceiling_since_tick_nm: f64,
    /// The motor's torque and the slew allowance accumulated since its last change.
    last_motor_nm: f64,
    allowance_since_motor_nm: f64,
    ceiling_since_motor_nm: f64,
    /// When the backend last sent the command's own level (or would have sent the same), ns.
    last_in_step_ns: u64,
    /// Since a stop, a pause and the start of the current run of faulted ticks.
    since_stop: Option<Fade>,
    since_pause: Option<Fade>,
    since_fault: Option<Fade>,
}

/// Time since a fade began on the supervisor's clock (the sum of min(gap, max_tick_gap)), s,
/// ticks since it passed the fade bound, and the highest torque level the fade may have to
/// come down from, N·m: the level when it began and every ceiling in force since. A ceiling
/// lowered mid-fade clamps the torque lower at once, so the bound stays the one of the level
/// the fade began at (measuring it against the new, lower ceiling blamed a fade that was
/// within its bound all along).
#[derive(Clone, Copy, Debug, Default)]
struct Fade {
    since_s: f64,
    ticks_past_bound: u32,
    from_nm: f64,
}

impl Fade {
    /// A fade beginning at `level_nm`.
    fn from(level_nm: f64) -> Self {
        Self {
            from_nm: level_nm,
            ..Self::default()
        }
    }
}

impl Checker {
    fn fade_bound_s(&self, ceiling_nm: f64) -> f64 {
        self.fade_out_s + ceiling_nm / self.slew_nm_per_s
    }
}

/// Play `ops` on one wheel; `Err` names the first broken invariant.
#[allow(clippy::too_many_arguments)]
fn play_on_wheel<B: Backend>(
    name: &str,
    usb_id: (u16, u16),
    profile: Option<DeviceProfile>,
    gain: f64,
    ceiling_fraction: Option<f64>,
    safety: SafetyConfig,
    model: Option<SpringDamper>,
    passivity: bool,
    ops: &[Op],
) -> Result<(), TestCaseError> {
    let (clock, mock): (Clock, MockClock) = Clock::mock();
    // The motor is as strong as the profile states: for an unknown wheel, the strongest
    // plausible motor the backend assumes.
    let stated = profile
        .clone()
        .unwrap_or_else(|| DeviceProfile::for_usb_id(usb_id.0, usb_id.1));
    let motor_nm = stated.max_torque_nm;
    let cfg = WheelConfig {
        profile,
        gain,
        ..WheelConfig::default()
    };
    let (wheel, fake) = B::open(name, usb_id, motor_nm, cfg, clock).unwrap();
    let device_max = wheel.max_torque_nm();
    let p = wheel.profile();
    prop_assert!(device_max <= p.usable_max_nm() + 1e-12, "{name}");
    let interval_ns = B::min_update_interval_ns(&wheel);
    let safety = SafetyConfig {
        ceiling_nm: ceiling_fraction.map(|f| f * device_max),
        ..safety
    };
    let chain_cfg = HapticChainConfig {
        safety,
        model,
        passivity: passivity.then(PassivityParams::default),
        ..HapticChainConfig::for_encoder_step(p.ka_rad_per_unit)
    };
    let c = HapticChain::new(chain_cfg, device_max).unwrap();
    let scale_nm = p.max_torque_nm * B::gain(&wheel);
    let k = Checker {
        slew_nm_per_s: safety.slew_nm_per_s,
        fade_out_s: safety.fade_out_s,
        max_tick_gap_s: safety.max_tick_gap_s,
        level_nm: scale_nm / B::FULL_SCALE,
        motor_per_level_nm: p.torque_sign * scale_nm / B::FULL_SCALE,
        last_cmd_nm: 0.0,
        ceiling_since_tick_nm: c.ceiling_nm(),
        last_motor_nm: 0.0,
        allowance_since_motor_nm: 0.0,
        ceiling_since_motor_nm: c.ceiling_nm(),
        last_in_step_ns: 0,
        since_stop: None,
        since_pause: None,
        since_fault: None,
    };
    let mut rig = Rig::<B> {
        name: name.to_string(),
        c,
        wheel,
        fake,
        mock,
        k,
        last_chain_ns: None,
        safety,
        device_max,
        interval_ns,
    };
    // Set the clock off zero so backwards steps have room.
    rig.mock.advance_ns(10_000_000);
    for op in ops {
        rig.apply(op)?;
    }
    rig.stop()
}

/// What the supervisor sees of a tick.
struct TickView {
    /// A tick gap, a clock going backwards or a stale reading.
    faulted: bool,
    /// The slew allowance of this tick, N·m.
    allowance: f64,
    /// Time the supervisor's fades advanced this tick, s.
    progress: f64,
}

/// One wheel under test with its chain and the checker.
struct Rig<B: Backend> {
    name: String,
    c: HapticChain,
    wheel: B::W,
    fake: B::M,
    mock: MockClock,
    k: Checker,
    last_chain_ns: Option<u64>,
    safety: SafetyConfig,
    device_max: f64,
    interval_ns: u64,
}

impl<B: Backend> Rig<B> {
    /// One tick: the clock moves by `gap`, the chain gets `reading` and `external_nm`, its
    /// command goes to the wheel; every invariant is checked.
    fn tick(&mut self, gap: Gap, reading: Reading, external_nm: f64) -> Result<(), TestCaseError> {
        let now_ns = self.advance(gap);
        let reading = self.reading(reading, now_ns);
        let view = self.supervisor_view(now_ns, reading);
        let tel = self.c.tick(TickInput {
            now_ns,
            reading,
            external_nm,
        });
        let cmd = tel.torque_nm;
        let ceiling = self.c.ceiling_nm();
        self.check_command(&tel, ceiling, view.allowance)?;
        self.check_fades(&tel, ceiling, &view)?;
        self.check_motor(cmd, ceiling, view.allowance)?;
        self.k.last_cmd_nm = cmd;
        self.k.ceiling_since_tick_nm = ceiling;
        Ok(())
    }

    /// Move the clock by `gap`; the chain's now, ns.
    fn advance(&mut self, gap: Gap) -> u64 {
        match gap {
            Gap::Nominal => {
                self.mock.advance_ns(DT_NS);
                self.mock.now_ns()
            }
            Gap::Jitter(g) | Gap::Stall(g) => {
                self.mock.advance_ns(g);
                self.mock.now_ns()
            }
            Gap::Backwards(b) => self
                .last_chain_ns
                .unwrap_or(self.mock.now_ns())
                .saturating_sub(b),
        }
    }

    /// The chain's reading of this tick at `now_ns`.
    fn reading(&mut self, reading: Reading, now_ns: u64) -> Option<WheelReading> {
        match reading {
            Reading::Wheel => self.wheel.read().ok(),
            Reading::Angle(a) => Some(WheelReading {
                angle_rad: a,
                t_ns: now_ns,
            }),
            Reading::Missing => None,
            Reading::Stale(age) => Some(WheelReading {
                angle_rad: 0.1,
                t_ns: now_ns.saturating_sub(age),
            }),
            Reading::Future(ahead) => Some(WheelReading {
                angle_rad: 0.1,
                t_ns: now_ns + ahead,
            }),
        }
    }

    /// The supervisor's view of a tick at `now_ns` with `reading`.
    fn supervisor_view(&mut self, now_ns: u64, reading: Option<WheelReading>) -> TickView {
        let gap_s = self
            .last_chain_ns
            .map_or(0.0, |t| now_ns.saturating_sub(t) as f64 * 1e-9);
        let backwards = self.last_chain_ns.is_some_and(|t| now_ns < t);
        let stale = reading.is_none_or(|r| {
            r.t_ns > now_ns || (now_ns - r.t_ns) as f64 * 1e-9 > self.safety.max_reading_age_s
        });
        let faulted = backwards || gap_s > self.k.max_tick_gap_s || stale;
        self.last_chain_ns = Some(now_ns);
        // The slew allowance of this tick: the supervisor's capped dt, floored at 0.1 ms.
        let slew_dt = gap_s.min(self.k.max_tick_gap_s).max(1e-4);
        let allowance = self.k.slew_nm_per_s * slew_dt;
        let progress = gap_s.min(self.k.max_tick_gap_s);
        TickView {
            faulted,
            allowance,
            progress,
        }
    }

    /// The chain's command `tel` under `ceiling` N·m, within the slew `allowance` N·m.
    fn check_command(
        &self,
        tel: &TickTelemetry,
        ceiling: f64,
        allowance: f64,
    ) -> Result<(), TestCaseError> {
        let name = &self.name;
        let cmd = tel.torque_nm;
        // The chain's command.
        prop_assert!(cmd.is_finite(), "{name}: non-finite command {cmd}");
        prop_assert!(
            cmd.abs() <= ceiling + 1e-12,
            "{name}: command {cmd} N·m above the {ceiling} N·m ceiling"
        );
        let from = self
            .k
            .last_cmd_nm
            .clamp(-self.k.ceiling_since_tick_nm, self.k.ceiling_since_tick_nm);
        prop_assert!(
            (cmd - from).abs() <= allowance + 1e-9,
            "{name}: command stepped {from} → {cmd} N·m, slew allows {allowance} N·m ({:?})",
            tel.watchdog
        );
        Ok(())
    }

    /// The fade bounds of a stop, a pause and a fault, with the command `tel` under `ceiling`.
    fn check_fades(
        &mut self,
        tel: &TickTelemetry,
        ceiling: f64,
        view: &TickView,
    ) -> Result<(), TestCaseError> {
        let name = self.name.clone();
        let (cmd, faulted, progress) = (tel.torque_nm, view.faulted, view.progress);
        // The fade bounds, on the supervisor's clock: zero from the third tick past the bound
        // (the scale reaches exactly zero on the tick after its ramp crossed it, the limiter
        // then needs its last step).
        let fault_from_nm = self.k.last_cmd_nm.abs().max(ceiling);
        self.k.since_fault = if faulted {
            Some(
                self.k
                    .since_fault
                    .unwrap_or_else(|| Fade::from(fault_from_nm)),
            )
        } else {
            None
        };
        let (fade_out_s, slew_nm_per_s) = (self.k.fade_out_s, self.k.slew_nm_per_s);
        for (what, fade) in [
            ("stop", &mut self.k.since_stop),
            ("pause", &mut self.k.since_pause),
            ("fault", &mut self.k.since_fault),
        ] {
            if let Some(f) = fade {
                f.since_s += progress;
                f.from_nm = f.from_nm.max(ceiling);
                let bound = fade_out_s + f.from_nm / slew_nm_per_s;
                if f.since_s >= bound {
                    f.ticks_past_bound += 1;
                }
                prop_assert!(
                    f.ticks_past_bound < 3 || cmd == 0.0,
                    "{name}: {cmd} N·m {} s after the {what} ({:?}), fade bound {bound} s",
                    f.since_s,
                    tel.watchdog
                );
            }
        }
        if self.k.since_stop.is_some_and(|f| f.ticks_past_bound >= 3) {
            prop_assert_eq!(tel.watchdog, WatchdogState::Stopped);
        }

        Ok(())
    }

    /// The motor, driven with `cmd` under `ceiling` as the station's loop drives it, within
    /// the slew `allowance` of this tick.
    fn check_motor(&mut self, cmd: f64, ceiling: f64, allowance: f64) -> Result<(), TestCaseError> {
        let name = self.name.clone();
        let interval_ns = self.interval_ns;
        let _ = self.wheel.set_torque_ceiling_nm(ceiling);
        let _ = self.wheel.command_torque(cmd);
        let level = B::sent_level(&self.wheel);
        let motor = f64::from(level) * self.k.motor_per_level_nm;
        let magnitude = self.fake.torque_nm();
        prop_assert!(
            (magnitude - motor.abs()).abs() <= 1e-9,
            "{name}: the fake's motor {magnitude} N·m vs level {level}"
        );
        prop_assert!(
            motor.abs() <= ceiling + 1e-9,
            "{name}: {motor} N·m at the motor over the {ceiling} N·m ceiling"
        );
        let own = B::level_for(&self.wheel, cmd);
        if level == own {
            self.k.last_in_step_ns = self.mock.now_ns();
            prop_assert!(
                (motor - cmd).abs() <= self.k.level_nm + 1e-9 && motor.abs() <= cmd.abs() + 1e-12,
                "{name}: level {level} gives {motor} N·m for a {cmd} N·m command"
            );
        } else {
            // Throttled by the driver's rate policy: never a zero, never longer than one
            // update interval.
            prop_assert!(own != 0, "{name}: a zero command was throttled");
            prop_assert!(
                self.mock.now_ns().saturating_sub(self.k.last_in_step_ns) < self.interval_ns,
                "{name}: level {level} held {} ns, interval {interval_ns} ns",
                self.mock.now_ns() - self.k.last_in_step_ns
            );
        }
        self.k.allowance_since_motor_nm += allowance;
        if level != own {
            // Held by the rate policy, or a held level brought down to a lowered ceiling: until
            // the backend sends the command's own level, the motor only moves towards zero.
            let last = self.k.last_motor_nm;
            prop_assert!(
                motor.abs() <= last.abs() + 1e-12 && motor * last >= 0.0,
                "{name}: a held level moved the motor {last} → {motor} N·m"
            );
        } else if motor != self.k.last_motor_nm {
            let from = self.k.last_motor_nm.clamp(
                -self.k.ceiling_since_motor_nm,
                self.k.ceiling_since_motor_nm,
            );
            prop_assert!(
                (motor - from).abs()
                    <= self.k.allowance_since_motor_nm + 2.0 * self.k.level_nm + 1e-9,
                "{name}: motor stepped {from} → {motor} N·m, slew allows {} N·m",
                self.k.allowance_since_motor_nm
            );
            self.k.allowance_since_motor_nm = 0.0;
            self.k.ceiling_since_motor_nm = ceiling;
        }
        self.k.last_motor_nm = motor;
        Ok(())
    }

    /// A ceiling change to `after` N·m.
    fn note_ceiling(&mut self, after: f64) {
        let k = &mut self.k;
        k.ceiling_since_tick_nm = k.ceiling_since_tick_nm.min(after);
        k.ceiling_since_motor_nm = k.ceiling_since_motor_nm.min(after);
    }

    /// Apply one operation of the script.
    fn apply(&mut self, op: &Op) -> Result<(), TestCaseError> {
        let name = self.name.clone();
        match op {
            Op::Tick {
                gap,
                reading,
                external_nm,
                repeat,
            } => {
                for _ in 0..*repeat {
                    self.tick(*gap, *reading, *external_nm)?;
                }
            }
            Op::Pause => {
                self.c.set_paused(true);
                let from_nm = self.k.last_cmd_nm.abs().max(self.c.ceiling_nm());
                self.k.since_pause.get_or_insert(Fade::from(from_nm));
            }
            Op::Resume => {
                self.c.set_paused(false);
                self.k.since_pause = None;
            }
            Op::Regimen {
                regimen,
                ceiling_fraction,
            } => {
                let regimen = HapticRegimen {
                    ceiling_nm: ceiling_fraction.map(|f| f * self.device_max),
                    ..regimen.clone()
                };
                let before = self.c.ceiling_nm();
                let valid = regimen.validate(self.device_max).is_ok();
                let applied = self.c.apply_regimen(&regimen);
                prop_assert_eq!(applied.is_ok(), valid, "{}: {:?}", name, applied);
                match applied {
                    Ok(()) => {
                        if let Some(want) = regimen.ceiling_nm {
                            prop_assert_eq!(self.c.ceiling_nm(), want);
                        }
                    }
                    Err(e) => {
                        prop_assert_eq!(
                            self.c.ceiling_nm(),
                            before,
                            "{}: refused but changed",
                            name
                        );
                        let msg = e.to_string();
                        prop_assert!(msg.contains('='), "{name}: the error names no field: {msg}");
                    }
                }
                self.note_ceiling(self.c.ceiling_nm());
            }
            Op::Ceiling(f) => {
                let before = self.c.ceiling_nm();
                let want = f * self.device_max;
                let r = self.c.set_ceiling_nm(want);
                let valid = want.is_finite() && (0.0..=self.device_max).contains(&want);
                prop_assert_eq!(
                    r.is_ok(),
                    valid,
                    "{}: ceiling {} refused or not",
                    name,
                    want
                );
                if let Err(e) = r {
                    prop_assert!(e.to_string().contains("ceiling_nm"), "{name}: {e}");
                    prop_assert_eq!(self.c.ceiling_nm(), before);
                }
                self.note_ceiling(self.c.ceiling_nm());
            }
            Op::Effect(e) => match self.c.effects_mut().add(*e) {
                Ok(id) => self.c.effects_mut().play(id).unwrap(),
                Err(err) => prop_assert!(
                    e.validate().is_err() || err.to_string().contains("full"),
                    "{name}: a valid effect refused: {err}"
                ),
            },
            Op::EffectGain(g) => {
                let valid = g.is_finite() && (0.0..=1.0).contains(g);
                prop_assert_eq!(self.c.effects_mut().set_gain(*g).is_ok(), valid);
            }
            Op::ClearEffects => self.c.effects_mut().clear(),
        }
        Ok(())
    }

    /// Stop, and check the fade to zero at the motor.
    fn stop(&mut self) -> Result<(), TestCaseError> {
        let name = self.name.clone();
        // Whatever happened, a stop ends at zero torque within the fade bound, on healthy ticks
        // and on faulted ones alike.
        self.c.request_stop();
        self.k.since_stop = Some(Fade::from(
            self.k.last_cmd_nm.abs().max(self.c.ceiling_nm()),
        ));
        let bound_ticks = (self.k.fade_bound_s(self.c.ceiling_nm()) / 1e-3).ceil() as usize + 5;
        for i in 0..bound_ticks {
            let reading = if i % 7 == 3 {
                Reading::Missing
            } else {
                Reading::Wheel
            };
            self.tick(Gap::Nominal, reading, 1e300)?;
        }
        prop_assert_eq!(
            B::sent_level(&self.wheel),
            0,
            "{}: the motor still pushes",
            name
        );
        prop_assert_eq!(self.fake.torque_nm(), 0.0);
        Ok(())
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// DESIGN.md safety invariants 1–3 in N·m at the motor, on every wheel, for any script of
    /// modes and transitions (see the module's documentation).
    #[test]
    fn every_mode_keeps_ceiling_slew_and_fade_at_the_motor_of_every_wheel(
        ops in proptest::collection::vec(any_op(), 1..40),
        gain in 0.05f64..=1.0,
        (ceiling_fraction, safety) in any_safety(),
        model in any_model(),
        passivity in any::<bool>(),
    ) {
        for (name, usb_id, profile) in every_wheel() {
            #[cfg(all(target_os = "linux", feature = "evdev"))]
            play_on_wheel::<crate::backend_tests::evdev_rig::Evdev>(
                &name, usb_id, profile.clone(), gain, ceiling_fraction, safety, model, passivity,
                &ops,
            )?;
            play_on_wheel::<crate::backend_tests::dinput_rig::Dinput>(
                &name, usb_id, profile, gain, ceiling_fraction, safety, model, passivity, &ops,
            )?;
        }
    }
}

#[test]
fn every_built_in_profile_and_each_unknown_driver_is_covered() {
    let wheels = every_wheel();
    assert_eq!(wheels.len(), DeviceProfile::builtin().len() + 5);
    // The unknown ones are opened as unknown (assumed 32 N·m, capped at 1 N·m).
    for (name, id, profile) in wheels.iter().filter(|w| w.0.starts_with("unknown")) {
        let p = profile
            .clone()
            .unwrap_or_else(|| DeviceProfile::for_usb_id(id.0, id.1));
        assert_eq!(p.usable_max_nm(), 1.0, "{name}");
        assert_eq!(p.max_torque_nm, 32.0, "{name}");
    }
}
