//! The seam under [`EvdevWheel`](super::EvdevWheel): what the backend needs from a kernel
//! input device ([`FfDevice`]), implemented by the real device node ([`KernelDevice`]) and,
//! for tests without hardware, by [`FakeFfDevice`](super::fake::FakeFfDevice).

use std::io;
use std::path::Path;
use std::time::SystemTime;

use evdev::{AbsInfo, AbsoluteAxisCode, EventType, FFEffect, FFEffectCode, FFEffectData, KeyCode};

use crate::devices::{DeviceClass, DeviceInfo, DeviceTraits, classify};
use haptic_wheel::profile::DeviceProfile;

/// A steering axis's state as the kernel keeps it (`EVIOCGABS`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AxisState {
    /// Current raw value.
    pub value: i32,
    /// Smallest raw value the driver declares.
    pub minimum: i32,
    /// Largest raw value the driver declares.
    pub maximum: i32,
}

/// An uploaded force-feedback effect, by its index in the device's own table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EffectSlot(pub usize);

/// What [`EvdevWheel`](super::EvdevWheel) needs from a force-feedback input device. Every
/// method the haptic loop calls (`drain_events`, `axis`, `update`, `play`, `stop`) must not
/// allocate after the first call.
pub trait FfDevice {
    /// Name, axes, buttons and force-feedback effects, for classification.
    fn traits(&self) -> DeviceTraits;
    /// USB vendor and product id.
    fn usb_id(&self) -> (u16, u16);
    /// Where the device is plugged in (the kernel's `phys`, e.g.
    /// `usb-0000:00:14.0-2/input0`), if the driver says.
    fn phys(&self) -> Option<String> {
        None
    }
    /// The unit's own id (the kernel's `uniq`, often a serial number), if the driver gives one.
    fn uniq(&self) -> Option<String> {
        None
    }
    /// How many effects the device holds at once.
    fn max_ff_effects(&self) -> usize;
    /// The kernel's current state of `axis`.
    fn axis(&self, axis: AbsoluteAxisCode) -> io::Result<AxisState>;
    /// Read every pending input event without blocking; the kernel's time stamp of the
    /// newest, `None` when none was pending. An unplugged device answers an error.
    fn drain_events(&mut self) -> io::Result<Option<SystemTime>>;
    /// Upload a new effect (`EVIOCSFF` with id −1).
    fn upload(&mut self, data: FFEffectData) -> io::Result<EffectSlot>;
    /// Replace an uploaded effect's parameters in place (`EVIOCSFF` with its id).
    fn update(&mut self, slot: EffectSlot, data: FFEffectData) -> io::Result<()>;
    /// Start playing an effect once (it plays for its replay length).
    fn play(&mut self, slot: EffectSlot) -> io::Result<()>;
    /// Stop an effect.
    fn stop(&mut self, slot: EffectSlot) -> io::Result<()>;
    /// Erase an effect (`EVIOCRMFF`); best effort.
    fn erase(&mut self, slot: EffectSlot);
    /// Device-wide gain, 0..=65535.
    fn set_gain(&mut self, gain: u16) -> io::Result<()>;
    /// Device-wide autocentre strength, 0..=65535.
    fn set_autocenter(&mut self, strength: u16) -> io::Result<()>;
}

fn axis_name(a: AbsoluteAxisCode) -> &'static str {
    match a {
        AbsoluteAxisCode::ABS_X => "x",
        AbsoluteAxisCode::ABS_Y => "y",
        AbsoluteAxisCode::ABS_Z => "z",
        AbsoluteAxisCode::ABS_RX => "rx",
        AbsoluteAxisCode::ABS_RY => "ry",
        AbsoluteAxisCode::ABS_RZ => "rz",
        AbsoluteAxisCode::ABS_THROTTLE => "throttle",
        AbsoluteAxisCode::ABS_RUDDER => "rudder",
        AbsoluteAxisCode::ABS_WHEEL => "wheel",
        AbsoluteAxisCode::ABS_GAS => "gas",
        AbsoluteAxisCode::ABS_BRAKE => "brake",
        AbsoluteAxisCode::ABS_HAT0X => "hat0x",
        AbsoluteAxisCode::ABS_HAT0Y => "hat0y",
        _ => "other",
    }
}

fn ff_name(c: FFEffectCode) -> &'static str {
    match c {
        FFEffectCode::FF_CONSTANT => "constant",
        FFEffectCode::FF_PERIODIC => "periodic",
        FFEffectCode::FF_RAMP => "ramp",
        FFEffectCode::FF_SPRING => "spring",
        FFEffectCode::FF_FRICTION => "friction",
        FFEffectCode::FF_DAMPER => "damper",
        FFEffectCode::FF_INERTIA => "inertia",
        FFEffectCode::FF_RUMBLE => "rumble",
        FFEffectCode::FF_GAIN => "gain",
        FFEffectCode::FF_AUTOCENTER => "autocenter",
        _ => "other",
    }
}

/// A real `/dev/input/event*` node, opened read-write and non-blocking.
#[derive(Debug)]
pub struct KernelDevice {
    // Effects first: fields drop in order, so they are erased before the device closes.
    effects: Vec<Option<FFEffect>>,
    dev: evdev::raw_stream::RawDevice,
}

impl KernelDevice {
    /// Open `path` read-write (force feedback is written to the node) and non-blocking (the
    /// haptic loop drains events without waiting).
    pub fn open(path: &Path) -> io::Result<Self> {
        use std::os::unix::fs::OpenOptionsExt;
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(path)?;
        Ok(Self {
            effects: Vec::with_capacity(8),
            dev: evdev::raw_stream::RawDevice::from_fd(file.into())?,
        })
    }

    /// Open `path` only to describe it (read-write when allowed, else read-only, as
    /// `telerehab devices` must list a wheel it could not drive).
    pub fn open_for_listing(path: &Path) -> io::Result<Self> {
        Ok(Self {
            effects: Vec::new(),
            dev: evdev::raw_stream::RawDevice::open(path)?,
        })
    }

    fn effect(&mut self, slot: EffectSlot) -> io::Result<&mut FFEffect> {
        self.effects
            .get_mut(slot.0)
            .and_then(Option::as_mut)
            .ok_or_else(|| io::Error::from(io::ErrorKind::NotFound))
    }
}

impl FfDevice for KernelDevice {
    fn traits(&self) -> DeviceTraits {
        let mut abs_axes: Vec<&'static str> = self
            .dev
            .supported_absolute_axes()
            .map(|s| s.iter().map(axis_name).collect())
            .unwrap_or_default();
        abs_axes.retain(|a| *a != "other");
        let mut ff_effects: Vec<&'static str> = self
            .dev
            .supported_ff()
            .map(|s| s.iter().map(ff_name).collect())
            .unwrap_or_default();
        ff_effects.retain(|a| *a != "other");
        let gamepad_buttons = self
            .dev
            .supported_keys()
            .is_some_and(|k| k.contains(KeyCode::BTN_SOUTH));
        DeviceTraits {
            name: self.dev.name().unwrap_or("(unnamed)").to_string(),
            ff_effects,
            abs_axes,
            gamepad_buttons,
        }
    }

    fn usb_id(&self) -> (u16, u16) {
        let id = self.dev.input_id();
        (id.vendor(), id.product())
    }

    fn phys(&self) -> Option<String> {
        self.dev.physical_path().map(str::to_owned)
    }

    fn uniq(&self) -> Option<String> {
        self.dev.unique_name().map(str::to_owned)
    }

    fn max_ff_effects(&self) -> usize {
        self.dev.max_ff_effects()
    }

    fn axis(&self, axis: AbsoluteAxisCode) -> io::Result<AxisState> {
        let abs = self.dev.get_abs_state()?;
        let info = AbsInfo::from(abs[axis.0 as usize]);
        Ok(AxisState {
            value: info.value(),
            minimum: info.minimum(),
            maximum: info.maximum(),
        })
    }

    fn drain_events(&mut self) -> io::Result<Option<SystemTime>> {
        match self.dev.fetch_events() {
            Ok(events) => Ok(events
                .filter(|e| e.event_type() == EventType::SYNCHRONIZATION)
                .map(|e| e.timestamp())
                .last()),
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => Ok(None),
            Err(e) => Err(e),
        }
    }

    fn upload(&mut self, data: FFEffectData) -> io::Result<EffectSlot> {
        let effect = self.dev.upload_ff_effect(data)?;
        self.effects.push(Some(effect));
        Ok(EffectSlot(self.effects.len() - 1))
    }

    fn update(&mut self, slot: EffectSlot, data: FFEffectData) -> io::Result<()> {
        self.effect(slot)?.update(data)
    }

    fn play(&mut self, slot: EffectSlot) -> io::Result<()> {
        self.effect(slot)?.play(1)
    }

    fn stop(&mut self, slot: EffectSlot) -> io::Result<()> {
        self.effect(slot)?.stop()
    }

    fn erase(&mut self, slot: EffectSlot) {
        // Dropping an FFEffect erases it (EVIOCRMFF).
        if let Some(e) = self.effects.get_mut(slot.0) {
            e.take();
        }
    }

    fn set_gain(&mut self, gain: u16) -> io::Result<()> {
        self.dev.set_ff_gain(gain)
    }

    fn set_autocenter(&mut self, strength: u16) -> io::Result<()> {
        self.dev.set_ff_autocenter(strength)
    }
}

/// Open `path` and describe it; `Ok(None)` for devices the station does not use.
pub fn inspect(path: &Path) -> io::Result<Option<DeviceInfo>> {
    let dev = KernelDevice::open_for_listing(path)?;
    let traits = dev.traits();
    let Some(class) = classify(&traits) else {
        return Ok(None);
    };
    let (vendor, product) = dev.usb_id();
    let profile = (class == DeviceClass::Wheel).then(|| DeviceProfile::for_usb_id(vendor, product));
    Ok(Some(DeviceInfo {
        path: path.display().to_string(),
        class,
        traits,
        usb_id: Some((vendor, product)),
        profile,
        ceiling: None,
        expected_update_rate_hz: None,
        max_ff_effects: dev.max_ff_effects(),
    }))
}
