//! A DirectInput wheel in memory, for testing [`DinputWheel`](super::DinputWheel) on any
//! system: it keeps the constant force the backend creates and plays it as DirectInput would
//! (each start plays for the effect's duration; gain scales; stop, unacquire and loss stop
//! it), turns it into the torque a motor of a given rating produces, and lets a test unplug
//! it, make it refuse updates, or set the steering axis and buttons. Not used by the product.

use std::sync::{Arc, Mutex, MutexGuard};

use clock::Clock;

use super::device::{
    DI_FFNOMINALMAX, DIERR_INPUTLOST, DIERR_NOTACQUIRED, DiDevice, DiError, DiIdentity, DiState,
};

/// How many of the first magnitudes written the fake keeps.
const FIRST_MAGNITUDES: usize = 8;
/// The default steering range DirectInput gives a joystick axis.
const RANGE: (i32, i32) = (0, 65_535);

#[derive(Debug)]
struct Effect {
    magnitude: i32,
    duration_us: u32,
    /// When it was last started, ns; `None` when stopped.
    started_ns: Option<u64>,
}

#[derive(Debug)]
struct State {
    clock: Clock,
    motor_nm: f64,
    x: i32,
    buttons: u128,
    gain: u32,
    autocenter: bool,
    acquired: bool,
    effect: Option<Effect>,
    /// Gone: every call answers `DIERR_INPUTLOST` once, then `DIERR_NOTACQUIRED`.
    unplugged: bool,
    told_lost: bool,
    /// Updates refused with this `HRESULT` (a driver refusing commands while it reads).
    refusing: Option<DiError>,
    peak_motor_nm: f64,
    updates: u64,
    first_magnitudes: [Option<i32>; FIRST_MAGNITUDES],
}

impl State {
    fn signed_motor_nm(&self) -> f64 {
        let now = self.clock.now_ns();
        let Some(e) = self
            .effect
            .as_ref()
            .filter(|_| self.acquired && !self.unplugged)
        else {
            return 0.0;
        };
        let playing = e
            .started_ns
            .is_some_and(|t| now.saturating_sub(t) < u64::from(e.duration_us) * 1_000);
        if !playing {
            return 0.0;
        }
        let full = f64::from(DI_FFNOMINALMAX);
        f64::from(e.magnitude) / full * f64::from(self.gain) / full * self.motor_nm
    }

    fn check(&mut self) -> Result<(), DiError> {
        if self.unplugged {
            self.acquired = false;
            let code = if self.told_lost {
                DIERR_NOTACQUIRED
            } else {
                DIERR_INPUTLOST
            };
            self.told_lost = true;
            return Err(DiError(code));
        }
        if !self.acquired {
            return Err(DiError(DIERR_NOTACQUIRED));
        }
        Ok(())
    }

    fn note_torque(&mut self) {
        self.peak_motor_nm = self.peak_motor_nm.max(self.signed_motor_nm().abs());
    }
}

/// The in-memory device. Take a [`FakeDiHandle`] from it before handing it to the backend.
#[derive(Debug)]
pub struct FakeDiDevice {
    /// What it is (fixed once made).
    identity: DiIdentity,
    state: Arc<Mutex<State>>,
}

/// The test's hand on a [`FakeDiDevice`] the backend owns.
#[derive(Clone, Debug)]
pub struct FakeDiHandle {
    state: Arc<Mutex<State>>,
}

fn lock(state: &Mutex<State>) -> MutexGuard<'_, State> {
    state.lock().unwrap_or_else(|p| p.into_inner())
}

impl FakeDiDevice {
    /// A wheel named `name` with USB id `usb_id`, instance `instance` (its GUID and instance
    /// name derive from it), a motor giving `motor_nm` at full magnitude and gain, a steering
    /// axis 0..=65535 at its centre, constant force, autocentre on and full gain.
    pub fn wheel(
        name: &str,
        usb_id: (u16, u16),
        instance: u8,
        motor_nm: f64,
        clock: Clock,
    ) -> Self {
        let identity = DiIdentity {
            product_name: name.into(),
            instance_name: if instance == 0 {
                name.into()
            } else {
                format!("{name} {}", u32::from(instance) + 1)
            },
            instance_guid: (u128::from(usb_id.0) << 48)
                | (u128::from(usb_id.1) << 32)
                | u128::from(instance),
            usb_id,
            axis_range: RANGE,
            constant_force: true,
        };
        Self {
            identity,
            state: Arc::new(Mutex::new(State {
                clock,
                motor_nm,
                x: 32_768,
                buttons: 0,
                gain: DI_FFNOMINALMAX as u32,
                autocenter: true,
                acquired: false,
                effect: None,
                unplugged: false,
                told_lost: false,
                refusing: None,
                peak_motor_nm: 0.0,
                updates: 0,
                first_magnitudes: [None; FIRST_MAGNITUDES],
            })),
        }
    }

    /// The same wheel without constant force (a gamepad with rumble only).
    pub fn without_constant_force(mut self) -> Self {
        self.identity.constant_force = false;
        self
    }

    /// The same wheel declaring another steering range.
    pub fn with_range(mut self, minimum: i32, maximum: i32) -> Self {
        self.identity.axis_range = (minimum, maximum);
        self
    }

    /// The test's handle.
    pub fn handle(&self) -> FakeDiHandle {
        FakeDiHandle {
            state: self.state.clone(),
        }
    }
}

impl FakeDiHandle {
    fn lock(&self) -> MutexGuard<'_, State> {
        lock(&self.state)
    }

    /// Torque the motor produces now, N·m (magnitude).
    pub fn motor_torque_nm(&self) -> f64 {
        self.lock().signed_motor_nm().abs()
    }

    /// The largest torque the motor produced at any write so far, N·m.
    pub fn peak_motor_torque_nm(&self) -> f64 {
        self.lock().peak_motor_nm
    }

    /// How many `SetParameters` the backend made.
    pub fn updates(&self) -> u64 {
        self.lock().updates
    }

    /// The first magnitudes the backend set, in order (up to 8).
    pub fn first_magnitudes(&self) -> Vec<i32> {
        self.lock()
            .first_magnitudes
            .iter()
            .flatten()
            .copied()
            .collect()
    }

    /// The device gain the backend set, 0..=10 000.
    pub fn gain(&self) -> u32 {
        self.lock().gain
    }

    /// Whether the wheel's own autocentre is on.
    pub fn autocenter(&self) -> bool {
        self.lock().autocenter
    }

    /// Whether the backend holds it acquired.
    pub fn acquired(&self) -> bool {
        self.lock().acquired
    }

    /// Whether a constant-force effect was created on it.
    pub fn has_effect(&self) -> bool {
        self.lock().effect.is_some()
    }

    /// Unplug (every call fails with `DIERR_INPUTLOST`, then `DIERR_NOTACQUIRED`) or plug back
    /// in (the same object stays unacquired: Windows makes a new device for a replugged one).
    pub fn set_unplugged(&self, unplugged: bool) {
        let mut s = self.lock();
        s.unplugged = unplugged;
        s.told_lost = false;
    }

    /// Refuse every update with `code` (or accept them again with `None`).
    pub fn set_refusing(&self, code: Option<i32>) {
        self.lock().refusing = code.map(DiError);
    }

    /// Set the raw steering value.
    pub fn set_x(&self, x: i32) {
        self.lock().x = x;
    }

    /// Set the buttons down, bit `i` for button `i`.
    pub fn set_buttons(&self, buttons: u128) {
        self.lock().buttons = buttons;
    }
}

impl DiDevice for FakeDiDevice {
    fn identity(&self) -> &DiIdentity {
        &self.identity
    }

    fn acquire(&mut self) -> Result<(), DiError> {
        let mut s = lock(&self.state);
        if s.unplugged {
            return Err(DiError(super::device::DIERR_UNPLUGGED));
        }
        s.acquired = true;
        Ok(())
    }

    fn unacquire(&mut self) {
        let mut s = lock(&self.state);
        s.acquired = false;
        if let Some(e) = s.effect.as_mut() {
            e.started_ns = None;
        }
    }

    fn set_autocenter(&mut self, on: bool) -> Result<(), DiError> {
        let mut s = lock(&self.state);
        s.check()?;
        s.autocenter = on;
        Ok(())
    }

    fn set_gain(&mut self, gain: u32) -> Result<(), DiError> {
        let mut s = lock(&self.state);
        s.check()?;
        s.gain = gain.min(DI_FFNOMINALMAX as u32);
        s.note_torque();
        Ok(())
    }

    fn create_constant_force(&mut self, duration_us: u32) -> Result<(), DiError> {
        let mut s = lock(&self.state);
        s.check()?;
        s.effect = Some(Effect {
            magnitude: 0,
            duration_us,
            started_ns: None,
        });
        Ok(())
    }

    fn set_magnitude(&mut self, magnitude: i32) -> Result<(), DiError> {
        let mut s = lock(&self.state);
        s.check()?;
        if let Some(code) = s.refusing {
            return Err(code);
        }
        let now = s.clock.now_ns();
        let Some(e) = s.effect.as_mut() else {
            return Err(DiError(super::device::E_FAIL));
        };
        e.magnitude = magnitude.clamp(-DI_FFNOMINALMAX, DI_FFNOMINALMAX);
        e.started_ns = Some(now);
        s.updates += 1;
        if let Some(slot) = s.first_magnitudes.iter_mut().find(|m| m.is_none()) {
            *slot = Some(magnitude);
        }
        s.note_torque();
        Ok(())
    }

    fn stop_effect(&mut self) -> Result<(), DiError> {
        let mut s = lock(&self.state);
        s.check()?;
        if let Some(e) = s.effect.as_mut() {
            e.started_ns = None;
        }
        Ok(())
    }

    fn state(&mut self) -> Result<DiState, DiError> {
        let mut s = lock(&self.state);
        s.check()?;
        Ok(DiState {
            x: s.x,
            buttons: s.buttons,
        })
    }
}
