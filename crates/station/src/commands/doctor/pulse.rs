//! `telerehab doctor --pulse`: a gentle test pulse, left then right, through the same haptic
//! chain (limiter, soft start, watchdog, the patient's ceiling) as every session's torque, and
//! whether the encoder saw the wheel move.

use haptic_wheel::{
    DeviceProfile, HapticChain, HapticChainConfig, SafetyConfig, TickInput, Wheel, WheelError,
    ZeroTorqueOnDrop,
};

/// The pulse's torque as a share of the wheel's usable maximum (its rated torque, or the low
/// cap of an unknown wheel).
pub const PULSE_FRACTION: f64 = 0.10;
/// How long each direction is pushed, s.
pub const PULSE_EACH_S: f64 = 0.3;
/// Torque-free time after the pulse, s (the chain fades to zero).
const REST_S: f64 = 0.2;
/// The haptic chain's tick during the pulse, s.
pub const TICK_S: f64 = 0.002;
/// Least turn each way counted as "the wheel moved", rad (half a degree).
pub const MOVED_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// What the pulse asks of the wheel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PulsePlan {
    /// The torque asked each way, N·m (before the chain, which may only lower it).
    pub torque_nm: f64,
    /// Zero torque first while the chain's soft start runs, s.
    pub settle_s: f64,
    /// Each direction, s.
    pub each_s: f64,
}

impl PulsePlan {
    /// The pulse for a wheel of `profile` under the patient's ceiling `ceiling_nm`: a tenth of
    /// the usable maximum, never above the ceiling.
    pub fn for_wheel(profile: &DeviceProfile, ceiling_nm: f64, safety: &SafetyConfig) -> Self {
        Self {
            torque_nm: (PULSE_FRACTION * profile.usable_max_nm())
                .min(ceiling_nm)
                .max(0.0),
            settle_s: safety.soft_start_s + 0.1,
            each_s: PULSE_EACH_S,
        }
    }

    /// The torque asked `t_s` after the start, N·m: nothing, left (negative), right, nothing.
    pub fn torque_at(&self, t_s: f64) -> f64 {
        let pulse_s = t_s - self.settle_s;
        if (0.0..self.each_s).contains(&pulse_s) {
            -self.torque_nm
        } else if (self.each_s..2.0 * self.each_s).contains(&pulse_s) {
            self.torque_nm
        } else {
            0.0
        }
    }

    /// The whole pulse, s.
    pub fn duration_s(&self) -> f64 {
        self.settle_s + 2.0 * self.each_s + REST_S
    }
}

/// What the encoder saw. Each push's turn is counted beyond where the wheel would have coasted
/// at its speed when the push began (a free wheel still turning left when the right push
/// starts is slowed by it before it turns right).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PulseOutcome {
    /// Turn the left push caused, rad.
    pub left_rad: f64,
    /// Turn the right push caused, rad.
    pub right_rad: f64,
    /// Largest torque sent to the motor, N·m.
    pub peak_nm: f64,
}

impl PulseOutcome {
    /// Moved at least [`MOVED_RAD`] each way, the two ways opposite.
    pub fn moved(&self) -> bool {
        self.left_rad.abs() >= MOVED_RAD
            && self.right_rad.abs() >= MOVED_RAD
            && self.left_rad.signum() != self.right_rad.signum()
    }
}

/// Runs `plan` on `wheel` through a haptic chain with `safety`; `wait_tick` waits one
/// [`TICK_S`] (sleeps, or steps a simulated wheel) and returns now on the wheel's clock, ns.
/// The wheel is sent zero torque when this returns, however it returns.
pub fn run_pulse<W: Wheel>(
    wheel: &mut W,
    plan: &PulsePlan,
    safety: SafetyConfig,
    mut wait_tick: impl FnMut(&mut W) -> u64,
) -> Result<PulseOutcome, WheelError> {
    let device_max_nm = wheel.max_torque_nm();
    let step_rad = wheel.capabilities().angle_resolution_rad;
    let mut chain = HapticChain::new(
        HapticChainConfig {
            safety,
            ..HapticChainConfig::for_encoder_step(step_rad)
        },
        device_max_nm,
    )?;
    let mut guard = ZeroTorqueOnDrop::new(&mut *wheel);
    let marks_s = [
        plan.settle_s,
        plan.settle_s + plan.each_s,
        plan.settle_s + 2.0 * plan.each_s,
    ];
    // (angle, rad; velocity, rad/s) when each push starts and when the last ends.
    let mut marks: [Option<(f64, f64)>; 3] = [None; 3];
    let mut peak_nm: f64 = 0.0;
    let mut last = (0.0, 0.0);
    let mut start_ns = None;
    loop {
        let now_ns = wait_tick(guard.wheel());
        let t_s = (now_ns - *start_ns.get_or_insert(now_ns)) as f64 * 1e-9;
        if t_s > plan.duration_s() {
            break;
        }
        let reading = guard.wheel().read().ok();
        let tel = chain.tick(TickInput {
            now_ns,
            reading,
            external_nm: plan.torque_at(t_s),
        });
        last = (tel.angle_rad, tel.vel_rad_s);
        for (mark, at) in marks.iter_mut().zip(marks_s) {
            if mark.is_none() && t_s >= at {
                *mark = Some(last);
            }
        }
        peak_nm = peak_nm.max(tel.torque_nm.abs());
        guard.wheel().set_torque_ceiling_nm(chain.ceiling_nm())?;
        guard.wheel().command_torque(tel.torque_nm)?;
    }
    let [a, b, c] = marks.map(|m| m.unwrap_or(last));
    let caused = |(from_rad, from_rad_s): (f64, f64), (to_rad, _): (f64, f64)| {
        to_rad - from_rad - from_rad_s * plan.each_s
    };
    Ok(PulseOutcome {
        left_rad: caused(a, b),
        right_rad: caused(b, c),
        peak_nm,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use haptic_wheel::{DriverFamily, SimWheel, SimWheelParams};

    /// Every built-in wheel and an unknown one (assumed rating, capped).
    fn every_profile() -> Vec<DeviceProfile> {
        let mut all = DeviceProfile::builtin();
        all.push(DeviceProfile::unknown(DriverFamily::HidPidff));
        all
    }

    /// The pulse on a simulated wheel as strong as `profile`'s usable maximum; the outcome and
    /// the largest torque the simulated motor applied, N·m.
    fn pulse_on_sim(profile: &DeviceProfile, ceiling_nm: f64) -> (PulsePlan, PulseOutcome, f64) {
        let safety = SafetyConfig {
            ceiling_nm: Some(ceiling_nm),
            ..SafetyConfig::default()
        };
        let plan = PulsePlan::for_wheel(profile, ceiling_nm, &safety);
        let mut sim = SimWheel::new(SimWheelParams {
            max_torque_nm: profile.usable_max_nm(),
            torque_step_nm: profile.usable_max_nm() / 32_767.0,
            ..SimWheelParams::default()
        });
        let mut motor_peak_nm: f64 = 0.0;
        let outcome = run_pulse(&mut sim, &plan, safety, |w| {
            w.advance(TICK_S, 0.0);
            motor_peak_nm = motor_peak_nm.max(w.motor_torque_nm().abs());
            w.time_ns()
        })
        .unwrap();
        (plan, outcome, motor_peak_nm)
    }

    #[test]
    fn the_pulse_stays_within_a_tenth_of_every_wheels_torque_and_the_patients_ceiling() {
        for p in every_profile() {
            let usable_nm = p.usable_max_nm();
            for ceiling_nm in [usable_nm, 0.05] {
                let (plan, outcome, motor_nm) = pulse_on_sim(&p, ceiling_nm);
                let limit_nm = (PULSE_FRACTION * usable_nm).min(ceiling_nm);
                assert!(plan.torque_nm <= limit_nm + 1e-12, "{}: {plan:?}", p.name);
                assert!(
                    // The motor quantises to its torque step, as a real one does.
                    outcome.peak_nm <= limit_nm + 1e-9
                        && motor_nm <= limit_nm + usable_nm / 32_767.0,
                    "{}: sent {} N·m, motor {motor_nm} N·m, limit {limit_nm} N·m",
                    p.name,
                    outcome.peak_nm
                );
                assert!(plan.torque_at(plan.settle_s + 0.1) < 0.0);
                assert!(plan.torque_at(plan.settle_s + plan.each_s + 0.1) > 0.0);
                assert_eq!(plan.torque_at(0.0), 0.0);
                assert_eq!(plan.torque_at(plan.duration_s()), 0.0);
            }
        }
    }

    #[test]
    fn the_pulse_turns_a_free_simulated_wheel_left_then_right_and_passes() {
        let g29 = DeviceProfile::logitech_g29();
        let (_, outcome, _) = pulse_on_sim(&g29, g29.usable_max_nm());
        assert!(outcome.moved(), "{outcome:?}");
        assert!(
            outcome.left_rad < 0.0 && outcome.right_rad > 0.0,
            "{outcome:?}"
        );
    }

    #[test]
    fn a_wheel_held_against_the_pulse_fails_it() {
        let g29 = DeviceProfile::logitech_g29();
        let safety = SafetyConfig::default();
        let plan = PulsePlan::for_wheel(&g29, g29.usable_max_nm(), &safety);
        let mut sim = SimWheel::new(SimWheelParams {
            max_torque_nm: g29.usable_max_nm(),
            ..SimWheelParams::default()
        });
        // A hand (or a jammed wheel) cancelling the motor's torque.
        let outcome = run_pulse(&mut sim, &plan, safety, |w| {
            let motor_nm = w.motor_torque_nm();
            w.advance(TICK_S, -motor_nm);
            w.time_ns()
        })
        .unwrap();
        assert!(!outcome.moved(), "{outcome:?}");
        assert!(outcome.peak_nm > 0.0, "{outcome:?}");
    }

    #[test]
    fn a_wheel_that_does_not_turn_fails_the_pulse() {
        let still = PulseOutcome {
            left_rad: 0.001,
            right_rad: -0.001,
            peak_nm: 0.2,
        };
        assert!(!still.moved());
    }
}
