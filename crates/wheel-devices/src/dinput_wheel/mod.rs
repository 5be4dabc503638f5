//! The real wheel on Windows: DirectInput 8 force feedback, behind the [`DiDevice`] seam so
//! that every rule below is tested on any system without hardware ([`fake::FakeDiDevice`]).
//! The implementation on the `windows` crate (`com`) is built on Windows only.
//!
//! - **Torque in N·m at the motor**, as on Linux: DirectInput's constant-force magnitude
//!   (±[`DI_FFNOMINALMAX`] = ±10 000, the thesis's effect units, eq. 3.3) is a share of the
//!   motor's full torque, scaled again by the device gain (`DIPROP_FFGAIN`, 0…10 000). The
//!   magnitude for a torque τ is `trunc(τ / (max_torque_nm · gain) · 10 000)`
//!   ([`motor_fraction`]), truncated towards zero so the
//!   motor never gives more than τ, with τ first clamped to the profile's usable maximum. The
//!   per-model [`DeviceProfile`]s are the evdev backend's, found by the USB id DirectInput
//!   reports; an unknown wheel gets the same conservative profile ([`DeviceProfile::unknown`]).
//! - **Torque out.** One constant-force effect (`DIEFF_CARTESIAN`, the X axis), its magnitude
//!   set with `SetParameters(DIEP_TYPESPECIFICPARAMS | DIEP_START)`: the latest value wins and
//!   every update starts the effect again for `effect_length_ms`, so if this process hangs the
//!   motor stops within one length. Updates follow the same rate policy as on Linux (the
//!   profile's driver family; zero never throttled; a held magnitude over a lowered ceiling
//!   comes down at once, [`Wheel::set_torque_ceiling_nm`]) and are counted
//!   ([`Wheel::motor_updates`]). A non-finite torque or ceiling is refused with zero sent.
//! - **Readings.** `Poll` then `GetDeviceState` (`DIJOYSTATE2`): the X axis is the steering
//!   angle (scaled from the range the device declares, `DIPROP_RANGE`), the buttons are kept
//!   ([`DinputWheel::buttons`]). DirectInput's state has no event times: a reading is stamped
//!   when it was read, and a hung device shows as failing calls rather than as silence
//!   ([`WheelFault::Silent`] is the evdev backend's alone). A value outside the declared range
//!   is [`WheelFault::OutOfRange`].
//! - **Device loss.** `DIERR_INPUTLOST`, `DIERR_NOTACQUIRED` and `DIERR_UNPLUGGED` are
//!   [`WheelFault::Unplugged`], the error the evdev backend gives for ENODEV; every call fails
//!   fast from then on. Any other failed update is a refused command
//!   ([`WheelError::write_refused`]) the safety chain counts.
//! - **Unplugged and plugged back in** ([`DinputWheel::reopen_with`]): the same model (USB id
//!   and steering range) is looked for every [`REJOIN_RESCAN_EVERY`], the same unit (instance
//!   GUID), then the same instance name, preferred; another model is refused. It is set up as
//!   at open and driven from zero. Unlike evdev's helper thread, the look happens on the
//!   haptic thread while the wheel is away (DirectInput devices are made and used on one
//!   thread here): a tick every 250 ms then takes as long as enumerating, which only happens
//!   while the session is already stopped for the missing wheel.
//! - On open: acquired exclusively in the background, autocentre off (it would fight the
//!   haptic models), gain from the configuration, one constant force at zero. On drop:
//!   magnitude zero, effect stopped, gain back to full, autocentre on if the configuration's
//!   exit value asks for any (DirectInput's autocentre is on or off), unacquired.

pub mod device;
pub mod fake;

#[cfg(windows)]
#[allow(unsafe_code)]
pub mod com;

use clock::Clock;

pub use device::{
    DI_FFNOMINALMAX, DiDevice, DiError, DiFinder, DiIdentity, DiState, Likeness, Refusal,
};

use haptic_wheel::profile::DeviceProfile;
pub use haptic_wheel::wheel::REJOIN_RESCAN_EVERY;
use haptic_wheel::wheel::{
    MotorUpdates, Wheel, WheelCapabilities, WheelError, WheelFault, WheelReading,
};
use haptic_wheel::wheel_config::{WheelConfig, motor_fraction};

/// Full scale of a DirectInput magnitude or gain, as a float.
pub const MAGNITUDE_FULL_SCALE: f64 = DI_FFNOMINALMAX as f64;

/// The DirectInput magnitude (±10 000) that makes a motor of `motor_nm` at device gain `gain`
/// give at most `torque_nm` (thesis eq. 3.3), with the profile's `torque_sign`, after
/// clamping to ±`usable_nm`; truncated towards zero.
pub fn magnitude_for(torque_nm: f64, usable_nm: f64, motor_nm: f64, gain: f64, sign: f64) -> i32 {
    (motor_fraction(torque_nm, usable_nm, motor_nm, gain, sign) * MAGNITUDE_FULL_SCALE).trunc()
        as i32
}

/// The DirectInput gain (0..=10 000) for a gain fraction, rounded; the fraction the device
/// then really runs at is this over 10 000.
pub fn gain_units(gain: f64) -> u32 {
    (gain.clamp(0.0, 1.0) * MAGNITUDE_FULL_SCALE).round() as u32
}

/// Set `dev` up as the backend drives it, at open and when the wheel is found again: acquired,
/// autocentre off, the gain, one constant force at zero.
fn arm<D: DiDevice>(dev: &mut D, gain: u32, effect_length_ms: u16) -> Result<(), DiError> {
    dev.acquire()?;
    dev.set_autocenter(false)?;
    dev.set_gain(gain)?;
    dev.create_constant_force(u32::from(effect_length_ms) * 1_000)
}

/// The backend's name for a device.
fn name_of(id: &DiIdentity) -> String {
    format!("{} (DirectInput: {})", id.product_name, id.instance_name)
}

/// A force-feedback wheel driven through DirectInput 8 (any [`DiDevice`]).
pub struct DinputWheel<D: DiDevice> {
    dev: D,
    clock: Clock,
    name: String,
    profile: DeviceProfile,
    /// The configuration, its gain the one the device really runs at.
    config: WheelConfig,
    centre: f64,
    ka_rad_per_unit: f64,
    usable_nm: f64,
    magnitude: i32,
    buttons: u128,
    min_interval_ns: u64,
    last_update_ns: Option<u64>,
    /// The device went away; every call fails fast until it is found again.
    lost: bool,
    /// A re-opened device: the torque stays zero until zero is commanded once.
    zero_first: bool,
    /// Finds the wheel again when it goes away, and how often it looks, ns.
    finder: Option<(Box<dyn DiFinder<D>>, u64)>,
    /// When the next look for a lost wheel is due, ns on the backend's clock.
    next_look_ns: u64,
    updates: MotorUpdates,
}

impl<D: DiDevice> std::fmt::Debug for DinputWheel<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DinputWheel")
            .field("name", &self.name)
            .field("magnitude", &self.magnitude)
            .field("lost", &self.lost)
            .finish_non_exhaustive()
    }
}

impl<D: DiDevice> DinputWheel<D> {
    /// Drive `dev` with `config`; the profile is the configured one, else the built-in one
    /// for its USB id, else an unknown wheel's.
    pub fn with_device(mut dev: D, config: WheelConfig, clock: Clock) -> Result<Self, WheelError> {
        config.validate()?;
        let id = dev.identity().clone();
        let name = name_of(&id);
        if !id.constant_force {
            return Err(WheelError::Unsupported {
                device: name,
                reason: "DirectInput offers no constant force on it".into(),
            });
        }
        let profile = config.resolve_profile(id.usb_id.0, id.usb_id.1);
        profile.validate()?;
        let (min, max) = id.axis_range;
        let span = f64::from(max) - f64::from(min);
        if span <= 0.0 {
            return Err(WheelError::Unsupported {
                device: name,
                reason: format!("steering axis has an empty range {span}"),
            });
        }
        let gain = gain_units(config.gain);
        arm(&mut dev, gain, config.effect_length_ms).map_err(|e| WheelError::Io {
            device: name.clone(),
            source: std::io::Error::other(e),
        })?;
        let gain = f64::from(gain) / MAGNITUDE_FULL_SCALE;
        let rate = config.update_rate_for(profile.driver, profile.max_update_rate_hz);
        Ok(Self {
            dev,
            name,
            usable_nm: profile.usable_max_nm().min(profile.max_torque_nm * gain),
            // Scale from the device's own axis range (Ka of thesis eq. 3.2 for this wheel).
            ka_rad_per_unit: 2.0 * profile.half_range_rad / span,
            centre: 0.5 * (f64::from(max) + f64::from(min)),
            profile,
            magnitude: 0,
            buttons: 0,
            min_interval_ns: (1e9 / rate).round() as u64,
            last_update_ns: None,
            lost: false,
            zero_first: false,
            finder: None,
            next_look_ns: 0,
            updates: MotorUpdates::default(),
            config: WheelConfig { gain, ..config },
            clock,
        })
    }

    /// Look for the wheel with `finder` every `every` once it has gone away, and take the
    /// same model back (see the module's doc).
    pub fn reopen_with(mut self, finder: impl DiFinder<D>, every: std::time::Duration) -> Self {
        self.finder = Some((Box::new(finder), every.as_nanos() as u64));
        self
    }

    /// The last magnitude sent, ±10 000.
    pub fn sent_magnitude(&self) -> i32 {
        self.magnitude
    }

    /// The minimum time between torque updates this wheel's rate policy allows, ns.
    pub fn min_update_interval_ns(&self) -> u64 {
        self.min_interval_ns
    }

    /// The device-wide gain in force, fraction of full.
    pub fn gain(&self) -> f64 {
        self.config.gain
    }

    /// The buttons of the last reading, bit `i` for button `i`.
    pub fn buttons(&self) -> u128 {
        self.buttons
    }

    /// The device under the backend (tests inspect a fake through it).
    pub fn device(&self) -> &D {
        &self.dev
    }

    fn lose(&mut self) -> WheelError {
        if !self.lost {
            self.lost = true;
            self.updates.interrupted();
            self.next_look_ns = self.clock.now_ns();
        }
        WheelError::Fault(WheelFault::Unplugged)
    }

    /// What a failed call on a running wheel is: a lost device, or a refused command.
    fn failed(&mut self, e: DiError) -> WheelError {
        if e.is_device_loss() {
            self.lose()
        } else {
            WheelError::write_refused()
        }
    }

    /// The magnitude for `torque_nm` N·m with the torque sign `sign` (±1); a lost wheel is
    /// refused, and so is a non-finite torque, with zero sent.
    fn magnitude_within(&mut self, torque_nm: f64, sign: f64) -> Result<i32, WheelError> {
        if self.lost {
            return Err(WheelError::Fault(WheelFault::Unplugged));
        }
        if !torque_nm.is_finite() {
            self.send(0, self.clock.now_ns())?;
            return Err(WheelError::NonFiniteTorque(torque_nm));
        }
        let p = &self.profile;
        Ok(magnitude_for(
            torque_nm,
            self.usable_nm,
            p.max_torque_nm,
            self.config.gain,
            sign,
        ))
    }

    fn send(&mut self, magnitude: i32, now_ns: u64) -> Result<(), WheelError> {
        if let Err(e) = self.dev.set_magnitude(magnitude) {
            return Err(self.failed(e));
        }
        self.updates.written(now_ns);
        self.magnitude = magnitude;
        self.last_update_ns = Some(now_ns);
        Ok(())
    }

    /// While lost: look for the wheel if a look is due, and take the best match. Whether the
    /// wheel is back.
    fn try_rejoin(&mut self) -> bool {
        let now = self.clock.now_ns();
        let Some((finder, every_ns)) = self.finder.as_mut() else {
            return false;
        };
        if now < self.next_look_ns {
            return false;
        }
        self.next_look_ns = now.saturating_add(*every_ns);
        let lost = self.dev.identity();
        let mut best: Option<(Likeness, D)> = None;
        for dev in finder.candidates() {
            match lost.likeness(dev.identity()) {
                Ok(l) if best.as_ref().is_none_or(|b| l > b.0) => best = Some((l, dev)),
                Ok(_) => {}
                Err(why) => tracing::debug!(
                    "{} is not taken for the lost wheel: {why:?}",
                    name_of(dev.identity())
                ),
            }
        }
        let Some((_, mut dev)) = best else {
            return false;
        };
        let gain = gain_units(self.config.gain);
        if arm(&mut dev, gain, self.config.effect_length_ms).is_err() {
            return false;
        }
        self.name = name_of(dev.identity());
        self.dev = dev;
        self.lost = false;
        self.zero_first = true;
        self.magnitude = 0;
        self.last_update_ns = None;
        true
    }
}

impl<D: DiDevice> Wheel for DinputWheel<D> {
    fn read(&mut self) -> Result<WheelReading, WheelError> {
        if self.lost && !self.try_rejoin() {
            return Err(WheelError::Fault(WheelFault::Unplugged));
        }
        let now = self.clock.now_ns();
        let state = match self.dev.state() {
            Ok(s) => s,
            Err(e) => return Err(self.failed(e)),
        };
        let (min, max) = self.dev.identity().axis_range;
        if state.x < min || state.x > max {
            return Err(WheelError::Fault(WheelFault::OutOfRange));
        }
        self.buttons = state.buttons;
        Ok(WheelReading {
            angle_rad: self.profile.angle_sign
                * self.ka_rad_per_unit
                * (f64::from(state.x) - self.centre),
            t_ns: now,
        })
    }

    fn command_torque(&mut self, torque_nm: f64) -> Result<(), WheelError> {
        let mut magnitude = self.magnitude_within(torque_nm, self.profile.torque_sign)?;
        let now = self.clock.now_ns();
        // A re-opened device gets zero until zero is asked for: never a step on re-open.
        if self.zero_first {
            self.zero_first = magnitude != 0;
            magnitude = 0;
        }
        let stopping = magnitude == 0 && self.magnitude != 0;
        if haptic_wheel::wheel_config::update_due(
            self.last_update_ns,
            now,
            self.min_interval_ns,
            stopping,
        ) {
            self.send(magnitude, now)
        } else {
            Ok(())
        }
    }

    fn set_torque_ceiling_nm(&mut self, ceiling_nm: f64) -> Result<(), WheelError> {
        let bound = self.magnitude_within(ceiling_nm.abs(), 1.0)?;
        if self.magnitude.abs() > bound.abs() {
            // Down at once, the policy's schedule kept (as on evdev).
            let scheduled = self.last_update_ns;
            let sent = self.send(self.magnitude.signum() * bound.abs(), self.clock.now_ns());
            self.last_update_ns = scheduled;
            sent
        } else {
            Ok(())
        }
    }

    fn max_torque_nm(&self) -> f64 {
        self.usable_nm
    }

    fn profile(&self) -> DeviceProfile {
        self.profile.clone()
    }

    fn capabilities(&self) -> WheelCapabilities {
        WheelCapabilities {
            name: self.name.clone(),
            max_torque_nm: self.usable_nm,
            half_range_rad: self.profile.half_range_rad,
            angle_resolution_rad: self.ka_rad_per_unit,
            max_update_rate_hz: 1e9 / self.min_interval_ns as f64,
            firmware_conditions: false,
        }
    }

    fn motor_updates(&self) -> Option<MotorUpdates> {
        Some(self.updates)
    }
}

impl<D: DiDevice> Drop for DinputWheel<D> {
    fn drop(&mut self) {
        // Best effort: the device may already be gone, and a gone device applies no torque.
        let _ = self.dev.set_magnitude(0);
        let _ = self.dev.stop_effect();
        let _ = self.dev.set_gain(DI_FFNOMINALMAX as u32);
        let _ = self
            .dev
            .set_autocenter(self.config.autocenter_on_exit > 0.0);
        self.dev.unacquire();
    }
}

#[cfg(test)]
mod tests;
