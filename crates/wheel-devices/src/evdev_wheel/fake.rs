//! A force-feedback input device in memory, for testing [`EvdevWheel`](super::EvdevWheel)
//! without hardware: it keeps the effects the backend uploads and plays as the kernel would
//! (replay lengths expire, gain scales, stop stops), turns them into the torque a motor of a
//! given rating would produce, and lets a test unplug it, silence it or feed it readings.
//! Not used by the product: tests (here and in the station) and demos only.

use std::io;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use clock::Clock;
use evdev::{AbsoluteAxisCode, FFEffectData, FFEffectKind};

use super::device::{AxisState, EffectSlot, FfDevice};
use crate::devices::DeviceTraits;

#[derive(Clone, Debug)]
struct FakeEffect {
    data: FFEffectData,
    /// Monotonic time the effect was last started, ns; `None` when stopped.
    playing_since_ns: Option<u64>,
    erased: bool,
}

/// How many of the first constant-force levels written the fake keeps.
const FIRST_LEVELS: usize = 8;

struct FakeState {
    clock: Clock,
    traits: DeviceTraits,
    usb_id: (u16, u16),
    /// Where it is plugged in and its serial (`phys`, `uniq`).
    phys: Option<String>,
    uniq: Option<String>,
    motor_nm: f64,
    axis: AxisState,
    gain: u16,
    autocenter: u16,
    effects: Vec<FakeEffect>,
    unplugged: bool,
    /// Send an input event on every drain while the motor pushes (a wheel that moves).
    moves_under_torque: bool,
    /// Never send events (a hung device).
    silent: bool,
    /// Wall-clock time of a pending reading event, ns (set by [`FakeHandle::set_value`]).
    pending_event_unix_ns: Option<u64>,
    peak_motor_nm: f64,
    effect_writes: u64,
    /// Updates of an uploaded effect's parameters (a new constant-force level is one).
    effect_updates: u64,
    /// The first constant-force levels uploaded or updated, in order (fixed size: the fake
    /// must not allocate on the haptic thread).
    first_levels: [Option<i16>; FIRST_LEVELS],
    /// The raw value as a function of time, ns (a person turning the wheel), if scripted.
    script: Option<Box<dyn Fn(u64) -> i32 + Send>>,
    /// Raw units the rim gives way per N·m of (signed) motor torque, hands off; 0: rigid.
    compliance_units_per_nm: f64,
}

impl std::fmt::Debug for FakeScript<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() { "scripted" } else { "none" })
    }
}

struct FakeScript<'a>(&'a Option<Box<dyn Fn(u64) -> i32 + Send>>);

impl std::fmt::Debug for FakeState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FakeState")
            .field("usb_id", &self.usb_id)
            .field("motor_nm", &self.motor_nm)
            .field("axis", &self.axis)
            .field("unplugged", &self.unplugged)
            .field("script", &FakeScript(&self.script))
            .finish_non_exhaustive()
    }
}

impl FakeState {
    /// Signed torque of the constant-force effects now, N·m (positive: the kernel's "left").
    fn signed_constant_nm(&self, now_ns: u64) -> f64 {
        let gain = f64::from(self.gain) / f64::from(u16::MAX);
        self.effects
            .iter()
            .filter(|e| {
                !e.erased
                    && e.playing_since_ns.is_some_and(|t| {
                        now_ns.saturating_sub(t) < u64::from(e.data.replay.length) * 1_000_000
                    })
            })
            .map(|e| match e.data.kind {
                FFEffectKind::Constant { level, .. } => f64::from(level) / 32_767.0,
                _ => 0.0,
            })
            .sum::<f64>()
            * gain
            * self.motor_nm
    }

    fn err(&self) -> io::Result<()> {
        if self.unplugged {
            // ENODEV, what the kernel answers for a device that went away.
            Err(io::Error::from_raw_os_error(19))
        } else {
            Ok(())
        }
    }

    fn motor_nm_at(&self, now_ns: u64) -> f64 {
        let gain = f64::from(self.gain) / f64::from(u16::MAX);
        let mut total = 0.0;
        for e in &self.effects {
            let Some(since) = e.playing_since_ns else {
                continue;
            };
            let length_ns = u64::from(e.data.replay.length) * 1_000_000;
            if e.erased || (length_ns > 0 && now_ns.saturating_sub(since) >= length_ns) {
                continue;
            }
            // The worst case each effect can add: a constant its level; a condition its
            // larger saturation (what it pushes with at most).
            let frac = match e.data.kind {
                FFEffectKind::Constant { level, .. } => f64::from(level).abs() / 32_767.0,
                FFEffectKind::Spring { condition } | FFEffectKind::Friction { condition } => {
                    f64::from(
                        condition[0]
                            .right_saturation
                            .max(condition[0].left_saturation),
                    ) / f64::from(u16::MAX)
                }
                _ => 1.0,
            };
            total += frac * gain * self.motor_nm;
        }
        total
    }

    fn note_level(&mut self, data: &FFEffectData) {
        if let FFEffectKind::Constant { level, .. } = data.kind
            && let Some(slot) = self.first_levels.iter_mut().find(|l| l.is_none())
        {
            *slot = Some(level);
        }
    }

    fn note_torque(&mut self) {
        let now = self.clock.now_ns();
        let t = self.motor_nm_at(now);
        self.peak_motor_nm = self.peak_motor_nm.max(t);
    }
}

/// The in-memory device. Clone a [`FakeHandle`] from it before handing it to the backend.
#[derive(Debug)]
pub struct FakeFfDevice {
    state: Arc<Mutex<FakeState>>,
}

/// The test's hand on a [`FakeFfDevice`] the backend owns.
#[derive(Clone, Debug)]
pub struct FakeHandle {
    state: Arc<Mutex<FakeState>>,
}

impl FakeFfDevice {
    /// A wheel named `name` with USB id `usb_id`, a motor giving `motor_nm` at full level and
    /// gain, a 16-bit steering axis on `ABS_X` (0..=65535, centred), constant force, spring,
    /// friction, gain and autocentre. It sends an input event on every read while its motor
    /// pushes.
    pub fn wheel(name: &str, usb_id: (u16, u16), motor_nm: f64, clock: Clock) -> Self {
        Self {
            state: Arc::new(Mutex::new(FakeState {
                clock,
                traits: DeviceTraits {
                    name: name.into(),
                    ff_effects: vec!["constant", "spring", "friction", "gain", "autocenter"],
                    abs_axes: vec!["x"],
                    gamepad_buttons: false,
                },
                usb_id,
                phys: None,
                uniq: None,
                motor_nm,
                axis: AxisState {
                    value: 32_768,
                    minimum: 0,
                    maximum: 65_535,
                },
                gain: u16::MAX,
                autocenter: u16::MAX,
                effects: Vec::with_capacity(8),
                unplugged: false,
                moves_under_torque: true,
                silent: false,
                pending_event_unix_ns: None,
                peak_motor_nm: 0.0,
                effect_writes: 0,
                effect_updates: 0,
                first_levels: [None; FIRST_LEVELS],
                script: None,
                compliance_units_per_nm: 0.0,
            })),
        }
    }

    /// The same wheel plugged in at `phys` (a USB port), with serial `uniq`.
    pub fn at(self, phys: Option<&str>, uniq: Option<&str>) -> Self {
        {
            let mut s = self.lock();
            s.phys = phys.map(str::to_owned);
            s.uniq = uniq.map(str::to_owned);
        }
        self
    }

    /// The test's handle.
    pub fn handle(&self) -> FakeHandle {
        FakeHandle {
            state: self.state.clone(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, FakeState> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }
}

impl FakeHandle {
    fn lock(&self) -> MutexGuard<'_, FakeState> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Torque the motor produces now, N·m (magnitude, worst case of every playing effect).
    pub fn motor_torque_nm(&self) -> f64 {
        let s = self.lock();
        s.motor_nm_at(s.clock.now_ns())
    }

    /// The largest torque the motor produced at any effect write so far, N·m.
    pub fn peak_motor_torque_nm(&self) -> f64 {
        self.lock().peak_motor_nm
    }

    /// The first constant-force levels the backend uploaded or updated, in order (up to 8).
    pub fn first_constant_levels(&self) -> Vec<i16> {
        self.lock().first_levels.iter().flatten().copied().collect()
    }

    /// How many effect uploads, updates and plays the backend made.
    pub fn effect_writes(&self) -> u64 {
        self.lock().effect_writes
    }

    /// How many updates of an uploaded effect the backend made (`EVIOCSFF` on an existing id:
    /// each new torque level is one), plays and uploads not counted.
    pub fn effect_updates(&self) -> u64 {
        self.lock().effect_updates
    }

    /// Condition effects (spring, friction) uploaded, not erased, and playing now.
    pub fn playing_conditions(&self) -> usize {
        let s = self.lock();
        let now = s.clock.now_ns();
        s.effects
            .iter()
            .filter(|e| {
                !e.erased
                    && matches!(
                        e.data.kind,
                        FFEffectKind::Spring { .. } | FFEffectKind::Friction { .. }
                    )
                    && e.playing_since_ns.is_some_and(|t| {
                        now.saturating_sub(t) < u64::from(e.data.replay.length) * 1_000_000
                    })
            })
            .count()
    }

    /// Effects uploaded and not erased.
    pub fn live_effects(&self) -> usize {
        self.lock().effects.iter().filter(|e| !e.erased).count()
    }

    /// The device-wide gain the backend set, 0..=65535.
    pub fn gain(&self) -> u16 {
        self.lock().gain
    }

    /// The autocentre strength the backend set, 0..=65535.
    pub fn autocenter(&self) -> u16 {
        self.lock().autocenter
    }

    /// Unplug (every call fails with ENODEV) or plug back in.
    pub fn set_unplugged(&self, unplugged: bool) {
        self.lock().unplugged = unplugged;
    }

    /// Stop (or resume) sending input events, as a hung device would.
    pub fn set_silent(&self, silent: bool) {
        self.lock().silent = silent;
    }

    /// Whether the wheel sends an event on every read while its motor pushes.
    pub fn set_moves_under_torque(&self, moves: bool) {
        self.lock().moves_under_torque = moves;
    }

    /// Set the raw steering value (an input event is sent with the next read).
    pub fn set_value(&self, value: i32) {
        let mut s = self.lock();
        s.axis.value = value;
        s.pending_event_unix_ns = Some(s.clock.unix_ns());
    }

    /// Script the raw value as a function of the clock's time (a person turning the wheel);
    /// `None` ends the script.
    pub fn set_script(&self, script: Option<Box<dyn Fn(u64) -> i32 + Send>>) {
        self.lock().script = script;
    }

    /// How far the rim gives way under the motor's torque, hands off: the raw value is the
    /// current one minus `units_per_nm` × the signed constant torque (a left push lowers the
    /// value, as on a Logitech wheel).
    pub fn set_compliance(&self, units_per_nm: f64) {
        self.lock().compliance_units_per_nm = units_per_nm;
    }

    /// Declare another raw range for the steering axis.
    pub fn set_range(&self, minimum: i32, maximum: i32) {
        let mut s = self.lock();
        s.axis.minimum = minimum;
        s.axis.maximum = maximum;
    }
}

impl FfDevice for FakeFfDevice {
    fn traits(&self) -> DeviceTraits {
        self.lock().traits.clone()
    }

    fn usb_id(&self) -> (u16, u16) {
        self.lock().usb_id
    }

    fn phys(&self) -> Option<String> {
        self.lock().phys.clone()
    }

    fn uniq(&self) -> Option<String> {
        self.lock().uniq.clone()
    }

    fn max_ff_effects(&self) -> usize {
        16
    }

    fn axis(&self, _axis: AbsoluteAxisCode) -> io::Result<AxisState> {
        let s = self.lock();
        s.err()?;
        let now = s.clock.now_ns();
        let mut axis = s.axis;
        if let Some(script) = &s.script {
            axis.value = script(now);
        }
        let give = s.compliance_units_per_nm * s.signed_constant_nm(now);
        axis.value = (f64::from(axis.value) - give).round() as i32;
        Ok(axis)
    }

    fn drain_events(&mut self) -> io::Result<Option<SystemTime>> {
        let mut s = self.lock();
        s.err()?;
        let now = s.clock.now_ns();
        let moving = s.moves_under_torque && s.motor_nm_at(now) > 0.0;
        let pending = s.pending_event_unix_ns.take();
        if s.silent {
            return Ok(None);
        }
        // The newest event: one now if the motor moves the rim, else the pending reading's.
        let at = if moving {
            Some(s.clock.unix_ns())
        } else {
            pending
        };
        Ok(at.map(|ns| UNIX_EPOCH + Duration::from_nanos(ns)))
    }

    fn upload(&mut self, data: FFEffectData) -> io::Result<EffectSlot> {
        let mut s = self.lock();
        s.err()?;
        s.note_level(&data);
        s.effects.push(FakeEffect {
            data,
            playing_since_ns: None,
            erased: false,
        });
        s.effect_writes += 1;
        Ok(EffectSlot(s.effects.len() - 1))
    }

    fn update(&mut self, slot: EffectSlot, data: FFEffectData) -> io::Result<()> {
        let mut s = self.lock();
        s.err()?;
        let e = s.effects.get_mut(slot.0).filter(|e| !e.erased);
        let e = e.ok_or_else(|| io::Error::from(io::ErrorKind::NotFound))?;
        e.data = data;
        s.note_level(&data);
        s.effect_writes += 1;
        s.effect_updates += 1;
        s.note_torque();
        Ok(())
    }

    fn play(&mut self, slot: EffectSlot) -> io::Result<()> {
        let mut s = self.lock();
        s.err()?;
        let now = s.clock.now_ns();
        let e = s.effects.get_mut(slot.0).filter(|e| !e.erased);
        let e = e.ok_or_else(|| io::Error::from(io::ErrorKind::NotFound))?;
        e.playing_since_ns = Some(now);
        s.effect_writes += 1;
        s.note_torque();
        Ok(())
    }

    fn stop(&mut self, slot: EffectSlot) -> io::Result<()> {
        let mut s = self.lock();
        s.err()?;
        if let Some(e) = s.effects.get_mut(slot.0) {
            e.playing_since_ns = None;
        }
        Ok(())
    }

    fn erase(&mut self, slot: EffectSlot) {
        let mut s = self.lock();
        if let Some(e) = s.effects.get_mut(slot.0) {
            e.erased = true;
            e.playing_since_ns = None;
        }
    }

    fn set_gain(&mut self, gain: u16) -> io::Result<()> {
        let mut s = self.lock();
        s.err()?;
        s.gain = gain;
        s.note_torque();
        Ok(())
    }

    fn set_autocenter(&mut self, strength: u16) -> io::Result<()> {
        let mut s = self.lock();
        s.err()?;
        s.autocenter = strength;
        Ok(())
    }
}
