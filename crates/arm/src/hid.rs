//! The real patient's arm: two game-controller IMUs over HID (DualShock 4, DualSense,
//! Joy-Con, Pro Controller; see `telerehab devices`) strapped to the upper arm and forearm,
//! either way round. Polled without blocking on the haptic thread; allocation-free per tick.
//!
//! A controller that stops answering (unplugged, out of radio range) is looked for again by its
//! vendor, product and serial number on a helper thread, once every [`IMU_RESCAN_EVERY`]
//! (enumerating the HID bus and opening a controller, which reads its calibration, takes
//! milliseconds and more: never on the haptic thread), and handed over through a wait-free
//! ring; the dead one goes back to the helper to be closed. Once both answer again the arm
//! tracker is told the sensor came back, and tracking resumes with the mounting found before
//! (the straps did not move). A controller is taken back only when it is certainly the lost
//! one ([`refind`]): the same serial; or, for controllers without one, the only controller of
//! its model that is not the other sensor. Two identical controllers without serials, both
//! lost, cannot be told apart (which one is on the forearm?): neither is taken back, and the
//! log says why.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use super::{ArmTracker, WheelNow};
use anyhow::Context;
use gyro_imu::ImuError;
use gyro_imu::arm::ArmGeometry;
use gyro_imu::device::hid::HidImu;
use gyro_imu::device::{Imu, ImuDeviceInfo, ImuSample};
use record::ArmSample;

/// Samples one poll may return per device (a Joy-Con report carries three).
const POLL_CAPACITY: usize = 24;

/// How often a lost controller is looked for.
pub const IMU_RESCAN_EVERY: Duration = Duration::from_secs(1);

/// A controller IMU the haptic thread polls (a [`HidImu`]; any [`Imu`] in tests).
pub type BoxedImu = Box<dyn Imu + Send>;

/// One opened controller and its newest sample.
struct Source {
    imu: BoxedImu,
    buf: [ImuSample; POLL_CAPACITY],
    latest: Option<ImuSample>,
    failed: bool,
}

impl Source {
    fn new(imu: BoxedImu) -> Self {
        Self {
            imu,
            buf: [ImuSample {
                t_ns: 0,
                rate_rad_s: nalgebra::Vector3::zeros(),
                acc_m_s2: None,
            }; POLL_CAPACITY],
            latest: None,
            failed: false,
        }
    }

    /// Take what arrived since the last tick and hold it until the next arrival (zero-order
    /// hold at the device's rate). A read error (unplugged) stops this source until a device
    /// is found again; it is returned once.
    fn poll(&mut self) -> Result<(), ImuError> {
        if self.failed {
            return Ok(());
        }
        match self.imu.poll(&mut self.buf) {
            Ok(0) => Ok(()),
            Ok(n) => {
                self.latest = Some(mean_sample(&self.buf[..n]));
                Ok(())
            }
            Err(e) => {
                self.failed = true;
                Err(e)
            }
        }
    }
}

/// Where a lost controller is looked for. Called on the helper thread only.
pub trait ImuFinder: Send + 'static {
    /// The supported controllers present now.
    fn present(&mut self) -> Result<Vec<ImuDeviceInfo>, ImuError>;
    /// Open the controller `info` describes (enable its IMU, read its calibration).
    fn open(&mut self, info: &ImuDeviceInfo) -> Result<BoxedImu, ImuError>;
}

impl ImuFinder for Box<dyn ImuFinder> {
    fn present(&mut self) -> Result<Vec<ImuDeviceInfo>, ImuError> {
        (**self).present()
    }

    fn open(&mut self, info: &ImuDeviceInfo) -> Result<BoxedImu, ImuError> {
        (**self).open(info)
    }
}

/// The HID bus, through hidapi.
struct HidFinder {
    clock_ns: fn() -> u64,
}

impl ImuFinder for HidFinder {
    fn present(&mut self) -> Result<Vec<ImuDeviceInfo>, ImuError> {
        gyro_imu::device::enumerate()
    }

    fn open(&mut self, info: &ImuDeviceInfo) -> Result<BoxedImu, ImuError> {
        let (imu, warning) = HidImu::open(info, self.clock_ns)?;
        if let Some(w) = warning {
            tracing::warn!("IMU {}: using nominal scales ({w})", info.name);
        }
        Ok(Box::new(imu))
    }
}

/// Why no controller present is taken for a lost one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Miss {
    /// None of its model is present (not plugged back in yet).
    Absent,
    /// Controllers of its model are present, but none with its serial: another unit, whose
    /// mounting on the arm is not known.
    OtherUnit,
    /// Controllers without serials that cannot be told apart from the other sensor's.
    Ambiguous,
}

impl Miss {
    fn describe(&self) -> &'static str {
        match self {
            Self::Absent => "it is not plugged in",
            Self::OtherUnit => {
                "a controller of the same model with another serial number is present, but its \
                 mounting on the arm is not known: plug the lost one back in, or start a new \
                 session to run the sensor set-up again"
            }
            Self::Ambiguous => {
                "both controllers are of the same model and report no serial number, so which \
                 one is on the forearm cannot be told: start a new session to run the sensor \
                 set-up again"
            }
        }
    }
}

/// Which of `present` is the lost controller `lost`, when `other` is the other sensor
/// (`other_live`: it still answers, so the device at its path is not the lost one): a
/// controller of the lost one's vendor and product with its serial; without a serial, the
/// only one of its model, and only while the other sensor, if of the same model, answers.
pub fn refind<'a>(
    lost: &ImuDeviceInfo,
    other: &ImuDeviceInfo,
    other_live: bool,
    present: &'a [ImuDeviceInfo],
) -> Result<&'a ImuDeviceInfo, Miss> {
    let same_model =
        |d: &ImuDeviceInfo| d.vendor_id == lost.vendor_id && d.product_id == lost.product_id;
    let mut candidates = present
        .iter()
        .filter(|d| same_model(d) && !(other_live && d.path == other.path));
    match &lost.serial {
        Some(serial) => {
            let mut any = false;
            for d in candidates {
                if d.serial.as_ref() == Some(serial) {
                    return Ok(d);
                }
                any = true;
            }
            Err(if any { Miss::OtherUnit } else { Miss::Absent })
        }
        None => {
            let Some(first) = candidates.next() else {
                return Err(Miss::Absent);
            };
            let twin_lost = !other_live && other.serial.is_none() && same_model(other);
            if candidates.next().is_some() || twin_lost {
                Err(Miss::Ambiguous)
            } else {
                Ok(first)
            }
        }
    }
}

#[derive(Debug, Default)]
struct Shared {
    /// Sensor 0 or 1 stopped answering: look for it.
    wanted: [AtomicBool; 2],
    /// A device for sensor 0 or 1 is in the ring, not yet taken.
    pending: [AtomicBool; 2],
    /// The sensing is being dropped: end the helper.
    stop: AtomicBool,
}

/// The haptic thread's side of finding lost controllers again.
struct Refind {
    found: rtrb::Consumer<(usize, BoxedImu)>,
    retired: rtrb::Producer<BoxedImu>,
    shared: Arc<Shared>,
    helper: Option<JoinHandle<()>>,
}

impl Refind {
    /// Start the helper for the controllers `infos` (sensor 0 and 1), looking every `every`.
    fn start(
        infos: [ImuDeviceInfo; 2],
        finder: impl ImuFinder,
        every: Duration,
    ) -> std::io::Result<Self> {
        let (found_tx, found_rx) = rtrb::RingBuffer::new(2);
        let (retired_tx, retired_rx) = rtrb::RingBuffer::new(2);
        let shared = Arc::new(Shared::default());
        let helper = {
            let shared = shared.clone();
            std::thread::Builder::new()
                .name("imu-refind".into())
                .spawn(move || imu_helper(infos, finder, every, shared, found_tx, retired_rx))?
        };
        Ok(Self {
            found: found_rx,
            retired: retired_tx,
            shared,
            helper: Some(helper),
        })
    }

    /// Sensor `i` stopped answering (no allocation, no lock).
    fn want(&self, i: usize) {
        self.shared.wanted[i].store(true, Ordering::Release);
        if let Some(h) = &self.helper {
            h.thread().unpark();
        }
    }
}

impl Drop for Refind {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        if let Some(h) = self.helper.take() {
            h.thread().unpark();
            let _ = h.join();
        }
    }
}

/// The helper thread: while a sensor is wanted and none is waiting for it, look for it.
fn imu_helper(
    mut infos: [ImuDeviceInfo; 2],
    mut finder: impl ImuFinder,
    every: Duration,
    shared: Arc<Shared>,
    mut found: rtrb::Producer<(usize, BoxedImu)>,
    mut retired: rtrb::Consumer<BoxedImu>,
) {
    // What was told about each sensor during its absence (told once).
    let mut told: [Option<Miss>; 2] = [None, None];
    while !shared.stop.load(Ordering::Acquire) {
        // Close the dead controllers the haptic thread handed back.
        while retired.pop().is_ok() {}
        let wanted = [0, 1].map(|i| {
            shared.wanted[i].load(Ordering::Acquire) && !shared.pending[i].load(Ordering::Acquire)
        });
        for (told, wanted) in told.iter_mut().zip(&shared.wanted) {
            if !wanted.load(Ordering::Acquire) {
                *told = None;
            }
        }
        if wanted.iter().any(|&w| w) {
            match finder.present() {
                Err(e) => tracing::debug!("cannot list the controllers: {e}"),
                Ok(present) => {
                    for i in (0..2).filter(|&i| wanted[i]) {
                        let other_live = !shared.wanted[1 - i].load(Ordering::Acquire);
                        let info = match refind(&infos[i], &infos[1 - i], other_live, &present) {
                            Ok(info) => info.clone(),
                            Err(miss) => {
                                if miss != Miss::Absent && told[i].as_ref() != Some(&miss) {
                                    tracing::warn!(
                                        "arm IMU {} ({}) is still away: {}",
                                        i + 1,
                                        infos[i].name,
                                        miss.describe()
                                    );
                                }
                                told[i] = Some(miss);
                                continue;
                            }
                        };
                        match finder.open(&info) {
                            Ok(imu) => {
                                tracing::info!(
                                    path = %info.path,
                                    "arm IMU {} ({}) is back: re-opened; tracking resumes once \
                                     both answer",
                                    i + 1,
                                    info.name
                                );
                                infos[i].path = info.path;
                                shared.pending[i].store(true, Ordering::Release);
                                // Room for one per sensor and one pending at most: it fits.
                                let _ = found.push((i, imu));
                            }
                            Err(e) => {
                                tracing::debug!(path = %info.path, "cannot open the controller yet: {e}")
                            }
                        }
                    }
                }
            }
        }
        std::thread::park_timeout(every);
    }
}

/// One sample standing for several that arrived together (a Joy-Con report carries three):
/// the mean rate, so the integral over the interval is kept rather than the newest sample's
/// alone, the mean specific force, and the newest time. `samples` must not be empty.
fn mean_sample(samples: &[ImuSample]) -> ImuSample {
    let last = samples[samples.len() - 1];
    if samples.len() == 1 {
        return last;
    }
    let n = samples.len() as f64;
    let rate = samples
        .iter()
        .map(|s| s.rate_rad_s)
        .sum::<nalgebra::Vector3<f64>>()
        / n;
    let acc = samples
        .iter()
        .map(|s| s.acc_m_s2)
        .try_fold(nalgebra::Vector3::zeros(), |sum, a| a.map(|a| sum + a))
        .map(|sum| sum / n);
    ImuSample {
        t_ns: last.t_ns,
        rate_rad_s: rate,
        acc_m_s2: acc,
    }
}

/// Two controller IMUs and the tracker (which runs the guided procedure first).
pub struct HidArmSensing {
    a: Source,
    b: Source,
    tracker: ArmTracker,
    last: ArmSample,
    /// Finds a lost controller again (`None`: a lost one stays lost).
    refind: Option<Refind>,
}

impl HidArmSensing {
    /// Open the first two supported controllers found, for a patient of `geometry`; `None`
    /// (with the reason logged) when fewer than two are present. `clock_ns` is the clock the
    /// device timestamps are anchored to; `clock` times the guided procedure's solver out.
    pub fn open_first_two(
        geometry: ArmGeometry,
        swivel_rad: f64,
        clock_ns: fn() -> u64,
        clock: clock::Clock,
    ) -> anyhow::Result<Option<Self>> {
        let found = match gyro_imu::device::enumerate() {
            Ok(f) => f,
            Err(e) => {
                tracing::info!("no arm sensing: {e}");
                return Ok(None);
            }
        };
        if found.len() < 2 {
            tracing::info!(
                found = found.len(),
                "no arm sensing: it needs two controller IMUs, one on the upper arm and one on the forearm (see `telerehab devices`)"
            );
            return Ok(None);
        }
        let mut finder = HidFinder { clock_ns };
        let mut open = |i: usize| -> anyhow::Result<BoxedImu> {
            finder
                .open(&found[i])
                .with_context(|| format!("cannot open IMU {}", found[i].name))
        };
        let (a, b) = (open(0)?, open(1)?);
        tracing::info!(
            first = %found[0].name,
            second = %found[1].name,
            "arm sensing: two IMUs open; the guided procedure finds which is on the upper arm"
        );
        // Real IMUs: the solver times out on the session's (real) clock.
        let tracker = ArmTracker::guided(geometry, swivel_rad, true, clock)?;
        Ok(Some(Self::with_imus(
            a,
            b,
            tracker,
            Some((Box::new(finder), IMU_RESCAN_EVERY)),
        )))
    }

    /// Arm sensing from two opened controllers `a` and `b` and `tracker`; with `refind`, a
    /// controller that stops answering is looked for among those its finder offers, every so
    /// often (without it, or if no thread can be started, a lost one stays lost).
    pub fn with_imus(
        a: BoxedImu,
        b: BoxedImu,
        tracker: ArmTracker,
        refind: Option<(Box<dyn ImuFinder>, Duration)>,
    ) -> Self {
        let infos = [a.info().clone(), b.info().clone()];
        let mut tracker = tracker;
        tracker.set_gyro_ranges([a.gyro_range(), b.gyro_range()]);
        let refind = refind.and_then(|(finder, every)| {
            Refind::start(infos, finder, every)
                .inspect_err(|e| {
                    tracing::warn!(
                        "no thread to find a lost IMU again ({e}): a lost one stays lost"
                    )
                })
                .ok()
        });
        Self {
            a: Source::new(a),
            b: Source::new(b),
            tracker,
            last: ArmSample::default(),
            refind,
        }
    }

    /// Where the arm sensing is.
    pub fn setup_step(&self) -> super::SetupStep {
        self.tracker.step_now()
    }

    /// Poll both devices and update the pose; before both have delivered a sample the
    /// previous sample is kept, and after one stops the pose stays frozen (the tracker says
    /// why in the session report).
    pub fn step(&mut self, wheel: WheelNow) -> ArmSample {
        for (i, source) in [&mut self.a, &mut self.b].into_iter().enumerate() {
            if let Err(e) = source.poll() {
                self.tracker.lose_sensor(e);
                if let Some(r) = &self.refind {
                    r.want(i);
                }
            }
        }
        self.take_found();
        if let (Some(a), Some(b)) = (self.a.latest, self.b.latest) {
            self.last = self.tracker.update(wheel, &a, &b);
        }
        self.last
    }

    /// Take the controllers the helper found again (no allocation: they were opened on the
    /// helper, and the dead ones go back to it); once both answer, the tracker is told.
    fn take_found(&mut self) {
        let Some(r) = &mut self.refind else { return };
        while let Ok((i, imu)) = r.found.pop() {
            r.shared.pending[i].store(false, Ordering::Release);
            let source = if i == 0 { &mut self.a } else { &mut self.b };
            let dead = std::mem::replace(&mut source.imu, imu);
            // Room for both sensors' dead devices; were it full, closed here (still correct).
            let _ = r.retired.push(dead);
            source.failed = false;
            // The old device's last sample is not held over: the pose waits for the new one.
            source.latest = None;
            // A controller of another model may stand in: its own full scale from now on.
            let ranges = [self.a.imu.gyro_range(), self.b.imu.gyro_range()];
            self.tracker.set_gyro_ranges(ranges);
            r.shared.wanted[i].store(false, Ordering::Release);
            if !self.a.failed && !self.b.failed {
                self.tracker.regain_sensor();
            }
        }
    }

    /// This tick's raw inputs of the tracker, taken.
    pub fn take_seam(&mut self) -> super::ArmSeam {
        self.tracker.take_seam()
    }

    /// Why there are no (more) joint angles, if so.
    pub fn failure(&self) -> Option<&super::ArmFailure> {
        self.tracker.failure()
    }

    /// Range of motion of each estimated joint angle this session, rad.
    pub fn range_of_motion_rad(&self) -> [f64; 5] {
        self.tracker.range_of_motion_rad()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gyro_imu::device::ImuKind;
    use gyro_imu::pose::Mounting;
    use nalgebra::{UnitQuaternion, Vector3};
    use std::sync::Mutex;

    fn sample(t_ns: u64, rate_x: f64, acc_z: Option<f64>) -> ImuSample {
        ImuSample {
            t_ns,
            rate_rad_s: Vector3::new(rate_x, 0.0, 0.0),
            acc_m_s2: acc_z.map(|z| Vector3::new(0.0, 0.0, z)),
        }
    }

    #[test]
    fn samples_arriving_together_keep_their_mean_rate_and_the_newest_time() {
        let joycon_report = [
            sample(10, 1.0, Some(9.0)),
            sample(15, 2.0, Some(10.0)),
            sample(20, 6.0, Some(11.0)),
        ];
        let m = mean_sample(&joycon_report);
        assert_eq!(m.t_ns, 20);
        assert_eq!(m.rate_rad_s.x, 3.0);
        assert_eq!(m.acc_m_s2.unwrap().z, 10.0);
        let one = sample(7, 0.5, None);
        assert_eq!(mean_sample(&[one]), one);
        let gyro_only_in_one = [sample(1, 1.0, Some(9.8)), sample(2, 1.0, None)];
        assert_eq!(mean_sample(&gyro_only_in_one).acc_m_s2, None);
    }

    fn info(path: &str, serial: Option<&str>) -> ImuDeviceInfo {
        ImuDeviceInfo {
            kind: ImuKind::DualShock4,
            name: "DualShock 4 (v2)".into(),
            path: path.into(),
            vendor_id: 0x054c,
            product_id: 0x09cc,
            bluetooth: false,
            serial: serial.map(str::to_owned),
        }
    }

    #[test]
    fn a_lost_controller_is_found_again_by_its_serial_and_never_taken_for_another() {
        let lost = info("/dev/hidraw1", Some("aa:01"));
        let other = info("/dev/hidraw2", Some("aa:02"));
        // Back on another node: found by its serial, whatever the order.
        let present = [other.clone(), info("/dev/hidraw5", Some("aa:01"))];
        assert_eq!(
            refind(&lost, &other, true, &present).unwrap().path,
            "/dev/hidraw5"
        );
        // Only the other sensor and a third unit of the model: not the lost one.
        let third = [other.clone(), info("/dev/hidraw6", Some("aa:03"))];
        assert_eq!(refind(&lost, &other, true, &third), Err(Miss::OtherUnit));
        assert_eq!(
            refind(&lost, &other, true, std::slice::from_ref(&other)),
            Err(Miss::Absent)
        );
        // Another model is never it.
        let mut joycon = info("/dev/hidraw7", Some("aa:01"));
        joycon.product_id = 0x2006;
        assert_eq!(refind(&lost, &other, true, &[joycon]), Err(Miss::Absent));
    }

    #[test]
    fn without_serials_only_a_controller_that_cannot_be_the_other_sensor_is_taken() {
        let lost = info("/dev/hidraw1", None);
        let other = info("/dev/hidraw2", None);
        let back = info("/dev/hidraw5", None);
        // The other one answers at its own node: the newcomer is the lost one.
        let present = [other.clone(), back.clone()];
        assert_eq!(refind(&lost, &other, true, &present), Ok(&back));
        // Both identical ones lost: the first back could be either (upper arm or forearm?).
        assert_eq!(
            refind(&lost, &other, false, std::slice::from_ref(&back)),
            Err(Miss::Ambiguous)
        );
        // Two newcomers of the model: which one?
        let two = [other.clone(), back, info("/dev/hidraw6", None)];
        assert_eq!(refind(&lost, &other, true, &two), Err(Miss::Ambiguous));
        // The other sensor of another model, lost too: no ambiguity.
        let mut joycon = info("/dev/hidraw2", None);
        joycon.product_id = 0x2006;
        let back = info("/dev/hidraw5", None);
        let present = std::slice::from_ref(&back);
        assert_eq!(refind(&lost, &joycon, false, present), Ok(&back));
    }

    /// A controller in memory: a still sensor (gravity along z) until it is unplugged.
    struct FakeImu {
        info: ImuDeviceInfo,
        gone: Arc<AtomicBool>,
        t_ns: u64,
    }

    impl Imu for FakeImu {
        fn info(&self) -> &ImuDeviceInfo {
            &self.info
        }

        fn gyro_range(&self) -> gyro_imu::device::GyroRange {
            gyro_imu::device::sony::SonyCalibration::nominal().gyro_range()
        }

        fn poll(&mut self, out: &mut [ImuSample]) -> Result<usize, ImuError> {
            if self.gone.load(Ordering::Relaxed) {
                return Err(ImuError::Device("read: device disconnected".into()));
            }
            self.t_ns += 1_000_000;
            out[0] = sample(self.t_ns, 0.0, Some(9.81));
            Ok(1)
        }
    }

    /// Each controller opened: its path and unplug switch.
    type Opened = Arc<Mutex<Vec<(String, Arc<AtomicBool>)>>>;

    /// The controllers on the fake bus, and those opened.
    #[derive(Clone, Default)]
    struct FakeBus {
        present: Arc<Mutex<Vec<ImuDeviceInfo>>>,
        opened: Opened,
    }

    impl FakeBus {
        fn imu(&self, info: &ImuDeviceInfo) -> BoxedImu {
            let gone = Arc::new(AtomicBool::new(false));
            self.opened
                .lock()
                .unwrap()
                .push((info.path.clone(), gone.clone()));
            Box::new(FakeImu {
                info: info.clone(),
                gone,
                t_ns: 0,
            })
        }

        fn unplug(&self, path: &str) {
            self.present.lock().unwrap().retain(|d| d.path != path);
            for (p, gone) in self.opened.lock().unwrap().iter() {
                if p == path {
                    gone.store(true, Ordering::Relaxed);
                }
            }
        }

        fn opened(&self) -> Vec<String> {
            let opened = self.opened.lock().unwrap();
            opened.iter().map(|(p, _)| p.clone()).collect()
        }
    }

    impl ImuFinder for FakeBus {
        fn present(&mut self) -> Result<Vec<ImuDeviceInfo>, ImuError> {
            Ok(self.present.lock().unwrap().clone())
        }

        fn open(&mut self, info: &ImuDeviceInfo) -> Result<BoxedImu, ImuError> {
            Ok(self.imu(info))
        }
    }

    fn wheel_now(k: u64) -> WheelNow {
        WheelNow {
            t_ns: k * 1_000_000,
            angle_rad: 0.0,
            rate_rad_s: 0.0,
            dt_s: 0.001,
        }
    }

    /// Step `arm` (a tick a millisecond, in real time) until `until` says so or 5 s pass; the
    /// seams of the ticks stepped.
    fn step_until(
        arm: &mut HidArmSensing,
        k: &mut u64,
        until: impl Fn(&HidArmSensing, u64) -> bool,
    ) -> Vec<super::super::ArmSeam> {
        let start = std::time::Instant::now();
        let mut seams = Vec::new();
        while !until(arm, *k) {
            assert!(start.elapsed() < Duration::from_secs(5), "timed out");
            arm.step(wheel_now(*k));
            seams.push(arm.take_seam());
            *k += 1;
            std::thread::sleep(Duration::from_millis(1));
        }
        seams
    }

    #[test]
    fn an_unplugged_controller_plugged_back_in_is_re_opened_and_tracking_resumes() {
        use super::super::SetupStep;
        let (upper, fore) = (
            info("/dev/hidraw1", Some("aa:01")),
            info("/dev/hidraw2", Some("aa:02")),
        );
        let bus = FakeBus::default();
        bus.present
            .lock()
            .unwrap()
            .extend([upper.clone(), fore.clone()]);
        let square = Mounting {
            upper: UnitQuaternion::identity(),
            fore: UnitQuaternion::identity(),
        };
        let tracker = ArmTracker::known(ArmGeometry::default(), square, 0.35).unwrap();
        let mut arm = HidArmSensing::with_imus(
            bus.imu(&upper),
            bus.imu(&fore),
            tracker,
            Some((Box::new(bus.clone()), Duration::from_millis(20))),
        );
        let mut k = 0;
        step_until(&mut arm, &mut k, |_, k| k >= 20);
        assert_eq!(arm.setup_step(), SetupStep::Tracking);

        // Unplugged: the tracker is told once, and the pose holds.
        bus.unplug("/dev/hidraw2");
        let seams = step_until(&mut arm, &mut k, |a, _| {
            a.setup_step() == SetupStep::SensorLost
        });
        assert_eq!(seams.iter().filter(|s| s.lost).count(), 1);
        // Away a while: nothing of its model is present, nothing is opened.
        let seams = step_until(&mut arm, &mut k, |_, k| k >= 200);
        assert!(seams.iter().all(|s| !s.regained));
        assert_eq!(bus.opened().len(), 2);
        assert!(arm.failure().is_some());

        // A third controller of the model (another serial) is not taken for it.
        bus.present
            .lock()
            .unwrap()
            .push(info("/dev/hidraw7", Some("aa:07")));
        step_until(&mut arm, &mut k, |_, k| k >= 300);
        assert_eq!(arm.setup_step(), SetupStep::SensorLost);
        assert_eq!(bus.opened().len(), 2);

        // Plugged back in, on another node: re-opened off the haptic thread, and the tracker
        // is told it came back once it answers.
        bus.present
            .lock()
            .unwrap()
            .push(info("/dev/hidraw9", Some("aa:02")));
        let seams = step_until(&mut arm, &mut k, |a, _| {
            a.setup_step() == SetupStep::Tracking
        });
        assert_eq!(seams.iter().filter(|s| s.regained).count(), 1);
        assert_eq!(
            bus.opened().last().map(String::as_str),
            Some("/dev/hidraw9")
        );
        assert!(arm.failure().is_none());
        // Stepped again with both sensors' new samples.
        let seams = step_until(&mut arm, &mut k, |_, k| k >= 400);
        assert!(seams.iter().any(|s| s.stepped.is_some()));
        assert_eq!(arm.setup_step(), SetupStep::Tracking);
    }
}
