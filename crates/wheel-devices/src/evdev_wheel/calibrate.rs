//! Driving the guided wheel measurement (`telerehab wheel calibrate`) on a kernel FF wheel:
//! the person turns the wheel lock to lock while the raw axis is sampled; then, only after
//! they confirm their hands are off, two gentle pushes (at most
//! [`CALIBRATION_MAX_TORQUE_NM`](haptic_wheel::calibrate::CALIBRATION_MAX_TORQUE_NM), ramped through a
//! [`TorqueLimiter`]) show which way the motor turns it, and the update durations give the
//! usable rate. The analysis is [`haptic_wheel::calibrate`].

use super::{EvdevWheel, FfDevice};
use haptic_wheel::calibrate::{
    CalibrationError, TurnResult, analyze_push, analyze_turn, gentle_torque_nm, measured_profile,
    usable_update_rate_hz,
};
use haptic_wheel::profile::DeviceProfile;
use haptic_wheel::safety::TorqueLimiter;
use haptic_wheel::wheel::{Wheel, WheelError};

/// How the procedure talks to the person at the wheel.
pub trait Guide {
    /// Tell them something (an instruction or a result).
    fn say(&mut self, text: &str);
    /// Ask a yes/no question; `true` for yes.
    fn confirm(&mut self, question: &str) -> bool;
}

/// Why the measurement stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CalibrateError {
    /// The wheel misbehaved or went away.
    #[error(transparent)]
    Wheel(#[from] WheelError),
    /// A measurement did not give a usable answer.
    #[error(transparent)]
    Measurement(#[from] CalibrationError),
    /// The person did not confirm hands off: no torque was applied.
    #[error("hands off was not confirmed, so no torque was applied; nothing was written")]
    NotConfirmed,
}

/// What the measurement found.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationReport {
    /// The profile to write.
    pub profile: DeviceProfile,
    /// The turn lock to lock.
    pub turn: TurnResult,
    /// The axis range the driver declares (min, max).
    pub declared: (i32, i32),
    /// Raw displacement under the positive and the negative push.
    pub push_deltas: (i32, i32),
    /// The largest torque commanded, N·m.
    pub peak_commanded_nm: f64,
}

/// Sampling period of the procedure, ns.
const SAMPLE_NS: u64 = 2_000_000;
/// How long each push holds, ns.
const PUSH_NS: u64 = 600_000_000;

impl<D: FfDevice> EvdevWheel<D> {
    /// The kernel's raw state of the steering axis.
    pub fn raw_axis(&mut self) -> Result<super::AxisState, WheelError> {
        match self.dev.axis(self.axis) {
            Ok(a) => Ok(a),
            Err(_) => Err(self.lose()),
        }
    }

    /// Run the guided measurement: `turn_s` seconds to turn lock to lock, then (after the
    /// hands-off confirmation) the gentle pushes. `rated_torque_nm` (maker's sheet) goes into
    /// the profile when given. Torque is zero on every way out.
    pub fn calibrate(
        &mut self,
        guide: &mut dyn Guide,
        turn_s: f64,
        rated_torque_nm: Option<f64>,
    ) -> Result<CalibrationReport, CalibrateError> {
        let result = self.calibrate_inner(guide, turn_s, rated_torque_nm);
        let _ = self.command_torque(0.0);
        result
    }

    fn sample_for(
        &mut self,
        ns: u64,
        torque: Option<(&mut TorqueLimiter, f64)>,
    ) -> Result<(Vec<i32>, Vec<u64>, f64), WheelError> {
        let mut raw = Vec::with_capacity((ns / SAMPLE_NS) as usize + 1);
        let mut update_ns = Vec::new();
        let mut peak = 0.0f64;
        let start = self.clock.now_ns();
        let mut torque = torque;
        let mut k = 0u64;
        while self.clock.now_ns().saturating_sub(start) < ns {
            if let Some((lim, target)) = torque.as_mut() {
                let cmd = lim.apply(*target, SAMPLE_NS as f64 * 1e-9).torque_nm;
                peak = peak.max(cmd.abs());
                let t0 = self.clock.now_ns();
                self.command_torque(cmd)?;
                update_ns.push(self.clock.now_ns().saturating_sub(t0));
            }
            raw.push(self.raw_axis()?.value);
            k += 1;
            self.clock
                .sleep_until_ns(start + k * SAMPLE_NS, std::time::Duration::ZERO);
        }
        Ok((raw, update_ns, peak))
    }

    fn calibrate_inner(
        &mut self,
        guide: &mut dyn Guide,
        turn_s: f64,
        rated_torque_nm: Option<f64>,
    ) -> Result<CalibrationReport, CalibrateError> {
        let axis = self.raw_axis()?;
        let declared = (axis.minimum, axis.maximum);
        guide.say(&format!(
            "Step 1 of 2: turn the wheel slowly all the way to the LEFT lock, then all the way to \
             the RIGHT lock, then back to the centre. You have {turn_s:.0} s. No force is applied."
        ));
        let (raw, _, _) = self.sample_for((turn_s * 1e9) as u64, None)?;
        let turn = analyze_turn(&raw, declared)?;
        let gentle = gentle_torque_nm(self.max_torque_nm());
        if !guide.confirm(&format!(
            "Step 2 of 2: the wheel will push gently (at most {gentle:.2} N·m) left and right. \
             Take your hands off the rim and keep clear. Are your hands off?"
        )) {
            return Err(CalibrateError::NotConfirmed);
        }
        // Ramp at 1 N·m/s: a push builds up over a few hundred ms, never a jolt.
        let mut lim = TorqueLimiter::new(gentle, 1.0);
        let mut deltas = [0i32; 2];
        let mut updates = Vec::new();
        let mut peak = 0.0f64;
        for (i, target) in [gentle, -gentle].into_iter().enumerate() {
            let before = self.raw_axis()?.value;
            let (raw, up, p) = self.sample_for(PUSH_NS, Some((&mut lim, target)))?;
            let (_, up0, p0) = self.sample_for(PUSH_NS / 2, Some((&mut lim, 0.0)))?;
            deltas[i] = raw.last().copied().unwrap_or(before) - before;
            updates.extend(up);
            updates.extend(up0);
            peak = peak.max(p).max(p0);
        }
        self.command_torque(0.0)?;
        let torque_sign = analyze_push(deltas[0], deltas[1], turn.angle_sign, turn.step_units)?;
        // The backend's own sign was applied to the pushes: the device's is their product.
        let torque_sign = torque_sign * self.profile.torque_sign;
        let rate = usable_update_rate_hz(&updates, self.profile.driver.max_update_rate_hz());
        let profile = measured_profile(
            &self.profile,
            declared,
            &turn,
            torque_sign,
            rate,
            rated_torque_nm,
        );
        guide.say(&format!(
            "Measured: {:.0}° lock to lock, angle sign {:+}, torque sign {:+}, encoder step {} \
             units ({:.4}°), torque updates up to {:.0} Hz.",
            2.0 * profile.half_range_rad.to_degrees(),
            profile.angle_sign,
            profile.torque_sign,
            turn.step_units,
            (f64::from(turn.step_units) * profile.ka_rad_per_unit).to_degrees(),
            profile.max_update_rate_hz
        ));
        Ok(CalibrationReport {
            profile,
            turn,
            declared,
            push_deltas: (deltas[0], deltas[1]),
            peak_commanded_nm: peak,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evdev_wheel::fake::{FakeFfDevice, FakeHandle};
    use clock::Clock;
    use haptic_wheel::wheel_config::WheelConfig;

    /// A person who turns the wheel when asked (a scripted sweep) and lets go when asked.
    struct Person {
        fake: FakeHandle,
        hands_off: bool,
        said: Vec<String>,
    }

    impl Guide for Person {
        fn say(&mut self, text: &str) {
            self.said.push(text.to_string());
        }
        fn confirm(&mut self, question: &str) -> bool {
            self.said.push(question.to_string());
            if self.hands_off {
                self.fake.set_script(None);
                self.fake.set_value(32_768);
                self.fake.set_compliance(20_000.0);
            }
            self.hands_off
        }
    }

    /// A fake wheel with a person at it who turns it when asked and lets go (`hands_off`) or
    /// not when asked.
    fn wheel(
        usb_id: (u16, u16),
        motor_nm: f64,
        hands_off: bool,
    ) -> (EvdevWheel<FakeFfDevice>, FakeHandle, Person) {
        let (clock, _mock) = Clock::mock();
        let dev = FakeFfDevice::wheel("fake", usb_id, motor_nm, clock.clone());
        let fake = dev.handle();
        // Left lock first (raw goes down to 8 192), then right (57 343), then centre: a wheel
        // set to half of its declared range, left lowering the value.
        fake.set_script(Some(Box::new(|t_ns: u64| {
            let t = t_ns as f64 * 1e-9;
            let x = if t < 2.0 {
                32_768.0 - 24_576.0 * t / 2.0
            } else if t < 6.0 {
                8_192.0 + 49_151.0 * (t - 2.0) / 4.0
            } else {
                57_343.0 - 24_575.0 * ((t - 6.0) / 2.0).min(1.0)
            };
            x.round() as i32
        })));
        let w = EvdevWheel::with_device(dev, "fake", WheelConfig::default(), clock).unwrap();
        let person = Person {
            fake: fake.clone(),
            hands_off,
            said: Vec::new(),
        };
        (w, fake, person)
    }

    #[test]
    fn the_procedure_measures_range_signs_and_rate_with_a_gentle_torque_only_after_hands_off() {
        let (mut w, fake, mut person) = wheel((0x045e, 0x0034), 1.87, true);
        let r = w.calibrate(&mut person, 8.0, None).unwrap();
        // The thesis SideWinder's profile spans ±2.25 rad over the declared range; the wheel
        // turned over three quarters of it.
        let declared_half = DeviceProfile::thesis_sidewinder().half_range_rad;
        assert!(
            (r.profile.half_range_rad - 0.75 * declared_half).abs() < 1e-3,
            "{r:?}"
        );
        assert_eq!(r.profile.angle_sign, -1.0);
        // The fake gives way towards lower values under a positive level: with angle sign −1
        // that is a left turn, so a positive device force turns the wheel left.
        assert_eq!(r.profile.torque_sign, 1.0);
        assert!(r.turn.step_units >= 1);
        assert_eq!(r.profile.max_update_rate_hz, 1000.0);
        assert!(r.peak_commanded_nm <= 0.1 * 1.87 + 1e-9);
        assert!(fake.peak_motor_torque_nm() <= haptic_wheel::calibrate::CALIBRATION_MAX_TORQUE_NM);
        assert_eq!(fake.motor_torque_nm(), 0.0, "zero torque at the end");
        r.profile.validate().unwrap();
    }

    #[test]
    fn no_torque_is_ever_applied_without_the_hands_off_confirmation() {
        let (mut w, fake, mut person) = wheel((0x1d50, 0x6015), 25.0, false);
        let err = w.calibrate(&mut person, 8.0, None).unwrap_err();
        assert!(matches!(err, CalibrateError::NotConfirmed), "{err}");
        assert_eq!(fake.peak_motor_torque_nm(), 0.0);
    }

    #[test]
    fn an_unknown_wheel_is_pushed_with_at_most_a_tenth_of_its_capped_torque() {
        let (mut w, fake, mut person) = wheel((0x1d50, 0x6015), 25.0, true);
        let r = w.calibrate(&mut person, 8.0, Some(25.0)).unwrap();
        assert!(
            fake.peak_motor_torque_nm() <= 0.1 + 1e-9,
            "{}",
            fake.peak_motor_torque_nm()
        );
        assert_eq!(
            r.profile.torque_source,
            haptic_wheel::TorqueSource::Clinician
        );
        assert_eq!(r.profile.max_torque_nm, 25.0);
    }
}
