//! A wheel unplugged and plugged back in comes back (issue 17).
//!
//! When the wheel is opened the backend remembers what it is ([`WheelIdentity`]: its USB id,
//! force-feedback effects, axes and steering range, and where it sits: the `phys` path of its
//! port and its `uniq` serial, when the driver gives them). Once the device has gone away
//! (ENODEV), a helper thread looks for it every [`RESCAN_EVERY`] — scanning `/dev/input` and
//! opening nodes costs milliseconds, which the 1 kHz haptic thread cannot spend — and hands an
//! opened device of the same model over through a wait-free ring. The haptic thread takes it
//! on its next read, re-initialises it as at open (gain from the configuration, autocentre
//! off, the constant effect uploaded at zero, the firmware conditions uploaded again but
//! stopped) and hands the dead device back to the helper, which closes it: the haptic thread
//! neither blocks, allocates nor frees for it.
//!
//! - **The same model only.** A device with another USB id, other force-feedback effects or
//!   another steering range is never taken for the session's wheel: its profile, hence its
//!   torque and angle scales, may differ (a units hazard). The helper says so in the log, once
//!   per device and absence.
//! - **The same unit, then the same port, is preferred**: among several wheels of the model,
//!   the one with the lost wheel's `uniq`, else the one on its `phys` port, else any.
//! - **Torque starts at zero.** The re-opened device's constant effect is uploaded at level 0,
//!   and the backend sends zero until it is commanded zero once: the safety chain's supervisor
//!   saw the gap as stale readings and soft-starts from zero, and this holds even without it.
//!   Firmware conditions play again only when the haptic loop says the supervisor runs.

use std::io;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use evdev::AbsoluteAxisCode;

use super::device::{FfDevice, KernelDevice};
use super::{EvdevWheel, find_wheels, io_err};
use crate::devices::{DeviceClass, DeviceTraits, classify};
use haptic_wheel::wheel::WheelError;

/// How often the helper looks for a lost wheel.
pub const RESCAN_EVERY: Duration = haptic_wheel::wheel::REJOIN_RESCAN_EVERY;

/// The steering axis the backend reads on a device with `traits`.
pub(super) fn steering_axis(traits: &DeviceTraits) -> AbsoluteAxisCode {
    if traits.abs_axes.contains(&"wheel") {
        AbsoluteAxisCode::ABS_WHEEL
    } else {
        AbsoluteAxisCode::ABS_X
    }
}

/// What makes a device the session's wheel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WheelIdentity {
    /// The device's name, as the driver reports it.
    pub name: String,
    /// USB vendor and product id: the model, hence the profile.
    pub usb_id: (u16, u16),
    /// The force-feedback effects the driver offers.
    pub ff_effects: Vec<&'static str>,
    /// The absolute axes present.
    pub abs_axes: Vec<&'static str>,
    /// The steering axis's declared raw range (minimum, maximum): the angle scale.
    pub axis_range: (i32, i32),
    /// Where it is plugged in (the kernel's `phys`), if known.
    pub phys: Option<String>,
    /// The unit's own id (the kernel's `uniq`), if the driver gives one.
    pub uniq: Option<String>,
    /// It classifies as a force-feedback wheel.
    pub is_wheel: bool,
}

impl WheelIdentity {
    /// The identity of `dev` (an error when its steering axis cannot be read).
    pub fn of<D: FfDevice>(dev: &D) -> io::Result<Self> {
        let traits = dev.traits();
        let axis = dev.axis(steering_axis(&traits))?;
        let known = |s: Option<String>| s.filter(|s| !s.is_empty());
        Ok(Self {
            is_wheel: classify(&traits) == Some(DeviceClass::Wheel),
            usb_id: dev.usb_id(),
            axis_range: (axis.minimum, axis.maximum),
            phys: known(dev.phys()),
            uniq: known(dev.uniq()),
            name: traits.name,
            ff_effects: traits.ff_effects,
            abs_axes: traits.abs_axes,
        })
    }

    /// Whether `found` can stand for this wheel, and how closely it matches.
    pub fn likeness(&self, found: &WheelIdentity) -> Result<Likeness, Refusal> {
        let same_set = |a: &[&str], b: &[&str]| {
            a.len() == b.len() && a.iter().all(|x| b.contains(x)) && b.iter().all(|x| a.contains(x))
        };
        if !found.is_wheel {
            return Err(Refusal::NotAWheel);
        }
        if found.usb_id != self.usb_id {
            return Err(Refusal::OtherModel);
        }
        if !same_set(&found.ff_effects, &self.ff_effects)
            || !same_set(&found.abs_axes, &self.abs_axes)
        {
            return Err(Refusal::OtherCapabilities);
        }
        if found.axis_range != self.axis_range {
            return Err(Refusal::OtherRange);
        }
        let same = |a: &Option<String>, b: &Option<String>| a.is_some() && a == b;
        Ok(if same(&found.uniq, &self.uniq) {
            Likeness::SameUnit
        } else if same(&found.phys, &self.phys) {
            Likeness::SamePort
        } else {
            Likeness::SameModel
        })
    }

    /// The model in words: name and USB id.
    fn model(&self) -> String {
        format!(
            "'{}' (USB {:04x}:{:04x})",
            self.name, self.usb_id.0, self.usb_id.1
        )
    }
}

/// How closely a device found matches the lost wheel; the larger, the better.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Likeness {
    /// The same model, elsewhere.
    SameModel,
    /// The same model on the same port (`phys`).
    SamePort,
    /// The same unit (`uniq`).
    SameUnit,
}

impl Likeness {
    fn describe(self) -> &'static str {
        match self {
            Self::SameModel => "the same model, on another port",
            Self::SamePort => "the same model, on the same port",
            Self::SameUnit => "the same unit",
        }
    }
}

/// Why a device found is not taken for the lost wheel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Refusal {
    /// Not a force-feedback wheel at all.
    NotAWheel,
    /// Another model (USB id): another profile, another torque scale.
    OtherModel,
    /// The same USB id with other force-feedback effects or axes (another driver or firmware).
    OtherCapabilities,
    /// The same model declaring another steering range (another angle scale).
    OtherRange,
}

impl Refusal {
    /// Why, in words, for the log.
    pub fn describe(self) -> &'static str {
        match self {
            Self::NotAWheel => "it is not a force-feedback wheel",
            Self::OtherModel => {
                "it is another model, whose torque scale may differ (a units hazard); plug the \
                 session's own wheel back in, or end the session and start a new one on this wheel"
            }
            Self::OtherCapabilities => {
                "its driver offers other force-feedback effects or axes (another driver or \
                 firmware), so its torque scale is not known to be the same"
            }
            Self::OtherRange => {
                "it declares another steering range, so its angle scale would differ"
            }
        }
    }
}

/// Where a lost wheel is looked for: every device that may be it, opened, each with its
/// node's name (e.g. `/dev/input/event7`). Called on the helper thread only.
pub trait WheelFinder<D>: Send + 'static {
    /// The devices present now that may be the wheel.
    fn candidates(&mut self) -> Vec<(String, D)>;
}

impl<D, F> WheelFinder<D> for F
where
    F: FnMut() -> Vec<(String, D)> + Send + 'static,
{
    fn candidates(&mut self) -> Vec<(String, D)> {
        self()
    }
}

/// The kernel's force-feedback wheels: every `/dev/input` node that classifies as one, opened
/// read-write (a node udev has not yet given its permissions is tried again at the next scan).
#[derive(Clone, Copy, Debug, Default)]
pub struct KernelFinder;

impl WheelFinder<KernelDevice> for KernelFinder {
    fn candidates(&mut self) -> Vec<(String, KernelDevice)> {
        find_wheels()
            .into_iter()
            .filter_map(|path| match KernelDevice::open(&path) {
                Ok(dev) => Some((path.display().to_string(), dev)),
                Err(e) => {
                    tracing::debug!(node = %path.display(), "cannot open a wheel yet: {e}");
                    None
                }
            })
            .collect()
    }
}

/// A device the helper found and opened, for the haptic thread.
pub(super) struct Found<D> {
    dev: D,
    /// The backend's name for it: the driver's name and the node.
    name: String,
}

/// A dead device and its old name, handed back to the helper to be dropped there.
struct Retired<D> {
    _dev: D,
    _name: String,
}

#[derive(Debug, Default)]
struct Shared {
    /// The wheel is lost: look for it.
    wanted: AtomicBool,
    /// The backend is being dropped: end the helper.
    stop: AtomicBool,
}

/// The haptic thread's side of re-opening: the rings to and from the helper, and the helper.
pub(super) struct Rejoin<D> {
    found: rtrb::Consumer<Found<D>>,
    retired: rtrb::Producer<Retired<D>>,
    shared: Arc<Shared>,
    helper: Option<JoinHandle<()>>,
}

impl<D> std::fmt::Debug for Rejoin<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Rejoin")
            .field("wanted", &self.shared.wanted.load(Ordering::Relaxed))
            .finish_non_exhaustive()
    }
}

impl<D> Drop for Rejoin<D> {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        if let Some(h) = self.helper.take() {
            h.thread().unpark();
            // A panic on the helper cannot be helped here; the wheel is being dropped.
            let _ = h.join();
        }
    }
}

/// The helper thread: while the wheel is wanted and none is waiting to be taken, look for it.
fn helper<D: FfDevice>(
    identity: WheelIdentity,
    mut finder: impl WheelFinder<D>,
    every: Duration,
    shared: Arc<Shared>,
    mut found: rtrb::Producer<Found<D>>,
    mut retired: rtrb::Consumer<Retired<D>>,
) {
    // Devices refused during this absence, told once each: (model, port, node).
    let mut told: Vec<((u16, u16), Option<String>, String)> = Vec::new();
    while !shared.stop.load(Ordering::Acquire) {
        // Close the dead devices the haptic thread handed back.
        while retired.pop().is_ok() {}
        if !shared.wanted.load(Ordering::Acquire) {
            told.clear();
        } else if !found.is_full()
            && let Some(f) = look(&identity, &mut finder, &mut told)
        {
            // Room was checked: the push cannot fail.
            let _ = found.push(f);
        }
        std::thread::park_timeout(every);
    }
}

/// One look for the lost wheel: the best match among the candidates, the others dropped;
/// refusals logged (once per device: `told`).
fn look<D: FfDevice>(
    lost: &WheelIdentity,
    finder: &mut impl WheelFinder<D>,
    told: &mut Vec<((u16, u16), Option<String>, String)>,
) -> Option<Found<D>> {
    let mut best: Option<(Likeness, String, D, WheelIdentity)> = None;
    for (node, dev) in finder.candidates() {
        let id = match WheelIdentity::of(&dev) {
            Ok(id) => id,
            Err(e) => {
                tracing::debug!(%node, "cannot read a candidate wheel's steering axis: {e}");
                continue;
            }
        };
        match lost.likeness(&id) {
            Ok(l) if best.as_ref().is_none_or(|b| l > b.0) => best = Some((l, node, dev, id)),
            Ok(_) => {}
            Err(Refusal::NotAWheel) => {}
            Err(why) => {
                let key = (id.usb_id, id.phys.clone(), node.clone());
                if !told.contains(&key) {
                    tracing::warn!(
                        %node,
                        "{} was plugged in while the session's wheel {} is away: not accepted \
                         as that wheel, because {}",
                        id.model(),
                        lost.model(),
                        why.describe()
                    );
                    told.push(key);
                }
            }
        }
    }
    let (likeness, node, dev, id) = best?;
    tracing::info!(
        %node,
        "the wheel {} is back ({}): re-opened, torque from zero",
        id.model(),
        likeness.describe()
    );
    Some(Found {
        dev,
        name: format!("{} ({node})", id.name),
    })
}

impl<D: FfDevice> EvdevWheel<D> {
    /// Look for this wheel again whenever it goes away (unplugged), among the devices `finder`
    /// offers, every `every`, on a helper thread (see the module docs); a device found is
    /// taken on the next [`read`](haptic_wheel::Wheel::read), which then answers again. Without this
    /// a lost wheel stays lost.
    pub fn reopen_with(
        mut self,
        finder: impl WheelFinder<D>,
        every: Duration,
    ) -> Result<Self, WheelError>
    where
        D: Send + 'static,
    {
        let identity = WheelIdentity::of(&self.dev).map_err(|e| io_err(&self.name, e))?;
        let (found_tx, found_rx) = rtrb::RingBuffer::new(1);
        // Room for every device the haptic thread can hand back before the helper runs again.
        let (retired_tx, retired_rx) = rtrb::RingBuffer::new(2);
        let shared = Arc::new(Shared::default());
        shared.wanted.store(self.lost, Ordering::Release);
        let helper = {
            let shared = shared.clone();
            std::thread::Builder::new()
                .name("wheel-rejoin".into())
                .spawn(move || helper(identity, finder, every, shared, found_tx, retired_rx))
                .map_err(|e| io_err(&self.name, e))?
        };
        self.rejoin = Some(Rejoin {
            found: found_rx,
            retired: retired_tx,
            shared,
            helper: Some(helper),
        });
        Ok(self)
    }

    /// The wheel is looked for again when it goes away ([`EvdevWheel::reopen_with`]).
    pub fn reopens(&self) -> bool {
        self.rejoin.is_some()
    }

    /// The device went away: ask the helper to look for it (no allocation, no lock).
    pub(super) fn want_rejoin(&self) {
        if let Some(r) = &self.rejoin {
            r.shared.wanted.store(true, Ordering::Release);
            if let Some(h) = &r.helper {
                h.thread().unpark();
            }
        }
    }

    /// While lost: take the device the helper found, if any, and re-initialise it. `true` when
    /// the wheel is back. Allocation-free: the found device and its name were made on the
    /// helper, and the dead ones go back to it.
    pub(super) fn try_rejoin(&mut self) -> bool {
        let Some(r) = self.rejoin.as_mut() else {
            return false;
        };
        let Ok(found) = r.found.pop() else {
            return false;
        };
        let dead = Retired {
            _dev: std::mem::replace(&mut self.dev, found.dev),
            _name: std::mem::replace(&mut self.name, found.name),
        };
        // The ring has room for two and the helper empties it each scan; were it full, the
        // dead device would be closed here (freeing, once), which is still correct.
        let _ = r.retired.push(dead);
        if self.reinit().is_err() {
            // Gone again already: the helper keeps looking, and the next one found replaces
            // this one.
            return false;
        }
        if let Some(r) = &self.rejoin {
            r.shared.wanted.store(false, Ordering::Release);
        }
        self.lost = false;
        true
    }

    /// Set a re-opened device up as at open: gain, autocentre off, the constant effect at
    /// zero, the firmware conditions uploaded but stopped; torque held at zero until zero is
    /// commanded once.
    fn reinit(&mut self) -> io::Result<()> {
        self.constant = self.controls.arm(&mut self.dev, &self.config)?;
        self.conditions.clear();
        for i in 0..self.condition_data.len() {
            let slot = self.dev.upload(self.condition_data[i])?;
            self.conditions.push(slot);
        }
        self.conditions_active = false;
        self.level = 0;
        self.last_update_ns = None;
        self.last_play_ns = None;
        self.torque_since_ns = None;
        self.last_event_ns = self.clock.now_ns();
        self.zero_first = true;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::fake::{FakeFfDevice, FakeHandle};
    use super::*;
    use clock::{Clock, MockClock};
    use haptic_wheel::effects::{Condition, ConditionKind};
    use haptic_wheel::wheel::{Wheel, WheelFault};
    use haptic_wheel::wheel_config::WheelConfig;
    use std::sync::Mutex;
    use std::time::Instant;

    const MS: u64 = 1_000_000;
    /// The thesis SideWinder's id (a built-in profile, 1.87 N·m, hid-pidff at 1 kHz).
    const SIDEWINDER_ID: (u16, u16) = (0x045e, 0x0034);
    /// A Logitech G29's id: another model, another profile.
    const G29_ID: (u16, u16) = (0x046d, 0xc24f);
    const PORT: &str = "usb-0000:00:14.0-2/input0";

    /// The devices a test has plugged in, each taken by the first scan that sees it.
    type Bus = Arc<Mutex<Vec<(String, FakeFfDevice)>>>;

    fn plug(bus: &Bus, node: &str, dev: FakeFfDevice) -> FakeHandle {
        let handle = dev.handle();
        bus.lock().unwrap().push((node.into(), dev));
        handle
    }

    /// A SideWinder at `PORT` opened with `config`, looked for again on `bus` every 5 ms.
    fn rejoining_wheel(
        config: WheelConfig,
    ) -> (EvdevWheel<FakeFfDevice>, FakeHandle, MockClock, Bus, Clock) {
        let (clock, mock) = Clock::mock();
        let dev = FakeFfDevice::wheel("SideWinder", SIDEWINDER_ID, 1.87, clock.clone())
            .at(Some(PORT), None);
        let handle = dev.handle();
        let bus: Bus = Arc::default();
        let finder = {
            let bus = bus.clone();
            move || std::mem::take(&mut *bus.lock().unwrap())
        };
        let wheel = EvdevWheel::with_device(dev, "/dev/input/event5", config, clock.clone())
            .unwrap()
            .reopen_with(finder, Duration::from_millis(5))
            .unwrap();
        assert!(wheel.reopens());
        (wheel, handle, mock, bus, clock)
    }

    /// Read `w` once a millisecond (of the mock clock and of real time, the helper's) until it
    /// answers, or 5 s of real time; every torque command meanwhile fails as unplugged.
    fn read_until_back(w: &mut EvdevWheel<FakeFfDevice>, mock: &MockClock) -> bool {
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(5) {
            mock.advance_ns(MS);
            if w.read().is_ok() {
                return true;
            }
            assert_eq!(
                w.command_torque(1.0).unwrap_err().fault(),
                Some(WheelFault::Unplugged)
            );
            std::thread::sleep(Duration::from_millis(1));
        }
        false
    }

    fn spring() -> Condition {
        Condition::symmetric(ConditionKind::Spring, 0.5, 0.5)
    }

    #[test]
    fn an_unplugged_wheel_plugged_back_in_is_re_opened_and_driven_from_zero_torque() {
        let config = WheelConfig {
            gain: 0.8,
            effect_length_ms: 50,
            ..Default::default()
        };
        let (mut w, old, mock, bus, clock) = rejoining_wheel(config.clone());
        w.upload_condition(&spring(), 0.5).unwrap();
        w.set_firmware_effects_active(true);
        for _ in 0..10 {
            mock.advance_ns(MS);
            w.read().unwrap();
            w.command_torque(1.0).unwrap();
        }
        assert!(old.motor_torque_nm() > 0.9);

        // Unplugged: it says so on every call and the motor stops within one effect length.
        old.set_unplugged(true);
        mock.advance_ns(MS);
        assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
        // Nothing to find: lost on every read (the helper scans meanwhile).
        for _ in 0..20 {
            mock.advance_ns(MS);
            assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
            std::thread::sleep(Duration::from_millis(1));
        }
        mock.advance_ns(50 * MS);
        assert_eq!(
            old.motor_torque_nm(),
            0.0,
            "the old device's motor while away"
        );

        // Plugged back in, a new device node on the same port: re-opened on the next read.
        let new = FakeFfDevice::wheel("SideWinder", SIDEWINDER_ID, 1.87, clock.clone())
            .at(Some(PORT), None);
        let new = plug(&bus, "/dev/input/event9", new);
        assert_eq!(new.motor_torque_nm(), 0.0);
        assert!(read_until_back(&mut w, &mock), "the wheel came back");
        assert!(w.capabilities().name.contains("/dev/input/event9"));
        // Set up as at open: the configured gain, autocentre off, the constant effect at zero,
        // the spring uploaded again but stopped; no torque.
        assert_eq!(new.gain(), config.gain_level());
        assert_eq!(new.autocenter(), 0);
        assert_eq!(new.first_constant_levels(), [0]);
        assert_eq!(new.live_effects(), 2, "the constant effect and the spring");
        assert_eq!(new.playing_conditions(), 0);
        assert_eq!(new.motor_torque_nm(), 0.0);

        // The first torque after re-open is zero whatever is asked, until zero is asked.
        mock.advance_ns(MS);
        w.command_torque(1.0).unwrap();
        assert_eq!(w.sent_level(), 0);
        assert_eq!(new.motor_torque_nm(), 0.0);
        mock.advance_ns(MS);
        w.command_torque(0.0).unwrap();
        mock.advance_ns(MS);
        w.command_torque(1.0).unwrap();
        assert_eq!(new.first_constant_levels()[..3], [0, 0, 0]);
        assert!(w.sent_level() > 0);
        assert!(
            (new.motor_torque_nm() - 1.0).abs() < 1e-3,
            "{}",
            new.motor_torque_nm()
        );
        // The firmware spring plays again when the supervisor runs.
        w.set_firmware_effects_active(true);
        assert_eq!(new.playing_conditions(), 1);
        assert!(w.read().is_ok());
    }

    #[test]
    fn another_wheel_model_plugged_in_is_not_taken_for_the_wheel() {
        let (mut w, old, mock, bus, clock) = rejoining_wheel(WheelConfig::default());
        old.set_unplugged(true);
        mock.advance_ns(MS);
        assert!(w.read().is_err());
        // A G29 on the very same port: another profile, another torque scale.
        let g29 = FakeFfDevice::wheel("G29", G29_ID, 2.2, clock.clone()).at(Some(PORT), None);
        let g29 = plug(&bus, "/dev/input/event9", g29);
        let start = Instant::now();
        while !bus.lock().unwrap().is_empty() {
            assert!(start.elapsed() < Duration::from_secs(5), "never looked at");
            std::thread::sleep(Duration::from_millis(1));
        }
        // Several scans later it is still not taken, and was never driven.
        std::thread::sleep(Duration::from_millis(50));
        for _ in 0..10 {
            mock.advance_ns(MS);
            assert_eq!(w.read().unwrap_err().fault(), Some(WheelFault::Unplugged));
        }
        assert_eq!(g29.live_effects(), 0);
        assert_eq!(g29.effect_writes(), 0);
        assert_eq!(g29.gain(), u16::MAX, "its gain untouched");
        // The session's own model is.
        let same = FakeFfDevice::wheel("SideWinder", SIDEWINDER_ID, 1.87, clock.clone());
        let same = plug(&bus, "/dev/input/event10", same);
        assert!(read_until_back(&mut w, &mock));
        assert_eq!(same.live_effects(), 1);
    }

    #[test]
    fn a_wheel_is_known_by_its_model_range_and_effects_and_its_unit_or_port_is_preferred() {
        let (clock, _) = Clock::mock();
        let wheel = |usb_id, phys: Option<&str>, uniq: Option<&str>| {
            FakeFfDevice::wheel("SideWinder", usb_id, 1.87, clock.clone()).at(phys, uniq)
        };
        let id = |d: &FakeFfDevice| WheelIdentity::of(d).unwrap();
        let lost = id(&wheel(SIDEWINDER_ID, Some(PORT), Some("SN1")));
        assert_eq!(lost.likeness(&lost), Ok(Likeness::SameUnit));
        let other_port = id(&wheel(SIDEWINDER_ID, Some("usb-3"), None));
        assert_eq!(lost.likeness(&other_port), Ok(Likeness::SameModel));
        let same_port = id(&wheel(SIDEWINDER_ID, Some(PORT), Some("SN2")));
        assert_eq!(lost.likeness(&same_port), Ok(Likeness::SamePort));
        let g29 = id(&wheel(G29_ID, Some(PORT), Some("SN1")));
        assert_eq!(lost.likeness(&g29), Err(Refusal::OtherModel));
        assert!(Refusal::OtherModel.describe().contains("units hazard"));
        let narrow = wheel(SIDEWINDER_ID, Some(PORT), Some("SN1"));
        narrow.handle().set_range(0, 1023);
        assert_eq!(lost.likeness(&id(&narrow)), Err(Refusal::OtherRange));

        // Among several: the same unit first, then the same port, then any of the model.
        let mut finder = {
            let clock = clock.clone();
            move || {
                let w = |phys: &str, uniq: Option<&str>| {
                    FakeFfDevice::wheel("SideWinder", SIDEWINDER_ID, 1.87, clock.clone())
                        .at(Some(phys), uniq)
                };
                vec![
                    ("/dev/input/event1".to_string(), w("usb-3", None)),
                    ("/dev/input/event2".to_string(), w(PORT, None)),
                    ("/dev/input/event3".to_string(), w("usb-4", Some("SN1"))),
                    ("/dev/input/event4".to_string(), w("usb-5", Some("SN2"))),
                ]
            }
        };
        let found = look(&lost, &mut finder, &mut Vec::new()).unwrap();
        assert_eq!(found.name, "SideWinder (/dev/input/event3)");
        let anonymous = WheelIdentity {
            uniq: None,
            ..lost.clone()
        };
        let found = look(&anonymous, &mut finder, &mut Vec::new()).unwrap();
        assert_eq!(found.name, "SideWinder (/dev/input/event2)");
        let elsewhere = WheelIdentity {
            uniq: None,
            phys: Some("usb-9".into()),
            ..lost
        };
        let found = look(&elsewhere, &mut finder, &mut Vec::new()).unwrap();
        assert_eq!(found.name, "SideWinder (/dev/input/event1)");
    }
}

#[cfg(test)]
mod log_tests {
    use super::super::fake::FakeFfDevice;
    use super::*;
    use clock::Clock;
    use std::fmt::Write as _;
    use std::sync::Mutex;
    use tracing::field::{Field, Visit};
    use tracing::span;

    /// Every event logged on this thread, as "LEVEL field=value ...".
    #[derive(Clone, Default)]
    struct Capture(Arc<Mutex<Vec<String>>>);

    struct Fields(String);

    impl Visit for Fields {
        fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
            let _ = write!(self.0, "{}={value:?} ", field.name());
        }
    }

    impl tracing::Subscriber for Capture {
        fn enabled(&self, _: &tracing::Metadata<'_>) -> bool {
            true
        }
        fn new_span(&self, _: &span::Attributes<'_>) -> span::Id {
            span::Id::from_u64(1)
        }
        fn record(&self, _: &span::Id, _: &span::Record<'_>) {}
        fn record_follows_from(&self, _: &span::Id, _: &span::Id) {}
        fn event(&self, event: &tracing::Event<'_>) {
            let mut f = Fields(format!("{} ", event.metadata().level()));
            event.record(&mut f);
            self.0.lock().unwrap().push(f.0);
        }
        fn enter(&self, _: &span::Id) {}
        fn exit(&self, _: &span::Id) {}
    }

    #[test]
    fn another_model_is_refused_in_a_log_line_once_and_the_wheel_back_is_told() {
        let (clock, _) = Clock::mock();
        let sidewinder = |clock: &Clock| {
            FakeFfDevice::wheel("SideWinder", (0x045e, 0x0034), 1.87, clock.clone())
        };
        let lost = WheelIdentity::of(&sidewinder(&clock)).unwrap();
        let g29 = {
            let clock = clock.clone();
            move || {
                let g29 = FakeFfDevice::wheel("G29", (0x046d, 0xc24f), 2.2, clock.clone());
                vec![("/dev/input/event9".to_string(), g29)]
            }
        };
        let capture = Capture::default();
        let logs = capture.0.clone();
        tracing::subscriber::with_default(capture, || {
            let mut told = Vec::new();
            let mut finder = g29;
            assert!(look(&lost, &mut finder, &mut told).is_none());
            assert!(look(&lost, &mut finder, &mut told).is_none());
            let mut same = move || vec![("/dev/input/event10".to_string(), sidewinder(&clock))];
            assert!(look(&lost, &mut same, &mut told).is_some());
        });
        let logs = logs.lock().unwrap();
        assert_eq!(logs.len(), 2, "{logs:#?}");
        assert!(
            logs[0].starts_with("WARN")
                && logs[0].contains("'G29' (USB 046d:c24f)")
                && logs[0].contains("not accepted")
                && logs[0].contains("units hazard"),
            "{}",
            logs[0]
        );
        assert!(
            logs[1].starts_with("INFO") && logs[1].contains("is back"),
            "{}",
            logs[1]
        );
    }
}
