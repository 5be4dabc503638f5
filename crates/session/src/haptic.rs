//! The haptic thread: one tick per period at absolute deadlines, records out through a
//! wait-free ring buffer, torque faded to zero on every way out. Time comes from the session's
//! [`Clock`] (a mock clock in tests: deadlines are met at once and the figures are exact).

use crate::breaks::BreakClock;
use crate::controls::Controls;
use crate::plant::Plant;
use clock::Clock;
use record::{TickRecord, TimingSample};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

/// How the loop paces itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pacing {
    /// One tick per period on the wall clock, at absolute deadlines (no drift).
    RealTime,
    /// As fast as the machine allows; waits for the recorder instead of dropping records.
    Max,
}

/// What the haptic thread reports when it ends.
#[derive(Clone, Debug, Default)]
pub struct HapticOutcome {
    /// Ticks run, including the fade-out.
    pub ticks: u64,
    /// Records the recorder ring had no room for (real-time pacing only).
    pub dropped_records: u64,
    /// Whether the session was stopped early (signal or stop request) rather than by its
    /// duration or the end of its course.
    pub stopped_early: bool,
    /// Whether the operating system granted real-time scheduling.
    pub realtime_priority: bool,
    /// Wall time the loop ran, s.
    pub wall_s: f64,
    /// Range of motion of each estimated joint angle over the session, rad (order of
    /// `gyro_imu::arm::JointAngles::NAMES`); `None` without arm sensing.
    pub range_of_motion_rad: Option<[f64; 5]>,
    /// Why arm sensing stopped or never started, in words: filled by the thread that ran the
    /// loop once [`run`] has returned, so that the loop never formats it.
    pub arm_failure: Option<String>,
    /// The wheel fault that ended the session, if one did.
    pub wheel_fault: Option<haptic_wheel::WheelFault>,
    /// Times the wheel was unplugged and came back within the replug grace.
    pub wheel_replugs: u32,
    /// Force commands the wheel refused (while it answered reads).
    pub write_failures: u64,
    /// Deadlines skipped after a stall (the loop never bursts through missed ticks).
    pub skipped_deadlines: u64,
    /// The torque ceiling that held on the wheel, N·m and as a share of its motor.
    pub ceiling: Option<haptic_wheel::CeilingReport>,
    /// The wheel's rate policy: the most torque updates a second its driver takes, Hz.
    pub motor_update_policy_hz: Option<f64>,
    /// Rests taken (prescribed or asked for).
    pub rests: u32,
    /// Time spent resting, s (not exercise time).
    pub rest_s: f64,
    /// The session ended because a pause lasted longer than `[session] pause_limit_s`.
    pub paused_too_long: bool,
    /// The session ended because an arm sensor stayed unplugged longer than the replug grace.
    pub arm_sensor_unplugged: bool,
    /// The session ended because the patient's window could not be kept up.
    pub window_lost: bool,
    /// Each exercise's own scores, of the exercises started (in course order).
    pub exercise_scores: Vec<measures::ExerciseScores>,
}

/// The loop's deadline arithmetic, without a clock: the tick of slot `k` is due at
/// `start_ns + k·period_ns` (absolute deadlines: no drift), and after a stall the slots
/// already past are skipped rather than run in a burst.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Slots {
    start_ns: u64,
    period_ns: u64,
    /// The slot of the next tick; it runs ahead of the tick count after a stall.
    next: u64,
    /// Slots skipped after stalls so far.
    skipped: u64,
}

impl Slots {
    /// Slot 0 due at `start_ns`, one slot every `period_ns` (> 0).
    fn new(start_ns: u64, period_ns: u64) -> Self {
        Self {
            start_ns,
            period_ns: period_ns.max(1),
            next: 0,
            skipped: 0,
        }
    }

    /// When the next tick is due, ns on the loop's clock.
    fn deadline_ns(&self) -> u64 {
        self.start_ns + self.period_ns * self.next
    }

    /// The tick of the current slot finished at `done_ns`: move to the next slot or, with
    /// `skip_past` (real-time pacing) after a stall, to the latest slot already past (it runs
    /// at once), counting the older ones skipped (the supervisor has seen the gap). A tick
    /// merely late for the next slot is ordinary jitter and skips nothing.
    fn advance(&mut self, done_ns: u64, skip_past: bool) {
        self.next += 1;
        if skip_past {
            let latest_past = done_ns.saturating_sub(self.start_ns) / self.period_ns;
            if latest_past > self.next {
                self.skipped += latest_past - self.next;
                self.next = latest_past;
            }
        }
    }
}

/// Busy-wait before each deadline when the haptic thread has a core of its own. Not the
/// whole period: a SCHED_FIFO thread that never sleeps is throttled by the kernel's real-time
/// bandwidth limit (`sched_rt_runtime_us`, 50 ms of every second by default), measured at
/// 168 ms lateness p99 with a 1.1 ms spin against 16 µs with this one (`telerehab bench
/// window`).
const SPIN_ON_OWN_CORE: Duration = Duration::from_micros(300);

/// The busy-wait before each deadline set by [`set_spin_on_own_core`] (`u64::MAX`: none set,
/// [`SPIN_ON_OWN_CORE`]), ns.
static SPIN_ON_OWN_CORE_SET_NS: AtomicU64 = AtomicU64::new(u64::MAX);

/// Busy-wait `spin` instead of the 300 µs default before each deadline in the sessions
/// started after this in the process (`telerehab bench loop --spin-us` measures what the spin
/// buys and costs).
pub fn set_spin_on_own_core(spin: Duration) {
    let ns = u64::try_from(spin.as_nanos()).unwrap_or(u64::MAX - 1);
    SPIN_ON_OWN_CORE_SET_NS.store(ns.min(u64::MAX - 1), Ordering::Relaxed);
}

/// The busy-wait before each deadline of a haptic thread on a core of its own.
pub fn spin_on_own_core() -> Duration {
    match SPIN_ON_OWN_CORE_SET_NS.load(Ordering::Relaxed) {
        u64::MAX => SPIN_ON_OWN_CORE,
        ns => Duration::from_nanos(ns),
    }
}

/// Keep the haptic thread on the last core and everything else off it: the patient's window
/// (with a software renderer it saturates every core it may use), the recorder and the network
/// share every other core.
pub mod cores {
    use std::sync::OnceLock;

    /// Every core of the machine, read once before any thread narrows its affinity (a pinned
    /// thread only sees its own cores, and its children inherit that).
    fn all() -> &'static [usize] {
        static ALL: OnceLock<Vec<usize>> = OnceLock::new();
        ALL.get_or_init(|| {
            core_affinity::get_core_ids()
                .unwrap_or_default()
                .iter()
                .map(|c| c.id)
                .collect()
        })
    }

    /// The haptic thread's core among `cores`: the last, when there are at least two.
    pub fn haptic_core_of(cores: &[usize]) -> Option<usize> {
        match cores {
            [_, .., last] => Some(*last),
            _ => None,
        }
    }

    /// The cores every other thread may use: all of `cores` but the haptic one; empty (no
    /// pinning) on a machine with one core, where there is nothing to keep apart.
    pub fn others_of(cores: &[usize]) -> Vec<usize> {
        match haptic_core_of(cores) {
            Some(haptic) => cores.iter().copied().filter(|&c| c != haptic).collect(),
            None => Vec::new(),
        }
    }

    /// The core the haptic thread is pinned to (the last one), when there are at least two.
    pub fn haptic_core() -> Option<usize> {
        haptic_core_of(all())
    }

    /// Pin the calling thread to the last core; true when done (needs at least two cores).
    pub fn pin_haptic_thread() -> bool {
        haptic_core().is_some_and(|id| core_affinity::set_for_current(core_affinity::CoreId { id }))
    }

    /// Let the calling thread (and the threads it starts later, such as the renderer's and
    /// the window process) run on every core but the haptic one; true when done. On 4–8-core
    /// PCs the software renderer and the recorder then spread over 3–7 cores instead of
    /// fighting over one.
    pub fn keep_off_the_haptic_core() -> bool {
        let others = others_of(all());
        !others.is_empty() && set_affinity(&others)
    }

    #[cfg(target_os = "linux")]
    fn set_affinity(cores: &[usize]) -> bool {
        let mut set = rustix::thread::CpuSet::new();
        for &core in cores {
            set.set(core);
        }
        rustix::thread::sched_setaffinity(None, &set).is_ok()
    }

    #[cfg(not(target_os = "linux"))]
    fn set_affinity(cores: &[usize]) -> bool {
        // One core of the others: the portable call takes one (a set is Linux's).
        cores
            .first()
            .is_some_and(|&id| core_affinity::set_for_current(core_affinity::CoreId { id }))
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        #[test]
        fn every_other_thread_may_use_every_core_but_the_haptic_one_on_1_2_4_and_8_cores() {
            assert_eq!(haptic_core_of(&[0]), None);
            assert_eq!(others_of(&[0]), Vec::<usize>::new());
            assert_eq!(haptic_core_of(&[0, 1]), Some(1));
            assert_eq!(others_of(&[0, 1]), vec![0]);
            assert_eq!(others_of(&[0, 1, 2, 3]), vec![0, 1, 2]);
            let eight: Vec<usize> = (0..8).collect();
            assert_eq!(haptic_core_of(&eight), Some(7));
            assert_eq!(others_of(&eight), (0..7).collect::<Vec<_>>());
            // Cores as the system numbers them (a machine with cores offline).
            assert_eq!(others_of(&[0, 2, 5]), vec![0, 2]);
        }

        #[cfg(target_os = "linux")]
        #[test]
        fn a_thread_kept_off_the_haptic_core_may_run_on_all_the_others() {
            let cores = all().to_vec();
            let seen = std::thread::spawn(move || {
                let kept = keep_off_the_haptic_core();
                let set = rustix::thread::sched_getaffinity(None).expect("affinity");
                let allowed: Vec<usize> =
                    cores.iter().copied().filter(|&c| set.is_set(c)).collect();
                (kept, allowed)
            })
            .join()
            .expect("thread");
            let (kept, allowed) = seen;
            assert_eq!(kept, all().len() >= 2);
            if kept {
                assert_eq!(allowed, others_of(all()));
            }
        }
    }
}

/// Try to get real-time (SCHED_FIFO) scheduling for the calling thread; true when granted.
/// Without it the loop still runs, with more jitter; the caller logs which one it got.
pub fn request_realtime_priority() -> bool {
    #[cfg(target_os = "linux")]
    {
        use thread_priority::{
            RealtimeThreadSchedulePolicy, ThreadPriority, ThreadPriorityValue,
            ThreadSchedulePolicy, set_thread_priority_and_policy, thread_native_id,
        };
        let Ok(value) = ThreadPriorityValue::try_from(80u8) else {
            return false;
        };
        set_thread_priority_and_policy(
            thread_native_id(),
            ThreadPriority::Crossplatform(value),
            ThreadSchedulePolicy::Realtime(RealtimeThreadSchedulePolicy::Fifo),
        )
        .is_ok()
    }
    #[cfg(not(target_os = "linux"))]
    {
        false
    }
}

/// The patient window's niceness: below the session's threads (nice 0) yet with a share a
/// software rasteriser can draw with when normal-priority work fills every core. At nice 19
/// (weight 15 against 1024) beside one busy process per core the window got ~0.5 % of a core,
/// could not pull a frame within the supervisor's 5 s, and was restarted again and again (the
/// exercise pausing each time); nice 10 (weight 110) gives it ~7 times that share.
pub const WINDOW_NICE: i32 = 10;

/// Put the calling thread, and the threads it starts later (a software rasteriser's workers),
/// at [`WINDOW_NICE`]: the recorder and the network come first, yet unlike the idle class
/// (SCHED_IDLE) or nice 19 it keeps enough of the CPU under any load that a busy machine slows
/// the patient's window down rather than starving it into looking hung to its supervisor.
/// True when granted.
pub fn request_background_priority() -> bool {
    #[cfg(target_os = "linux")]
    {
        // Linux keeps the nice value per thread: `setpriority` on this thread's id.
        let tid = rustix::thread::gettid();
        rustix::process::setpriority_process(Some(tid), WINDOW_NICE).is_ok()
    }
    #[cfg(not(target_os = "linux"))]
    {
        false
    }
}

/// Longest the supervisor may take to fade the torque out after a stop, s; past it the loop
/// commands zero at once.
const MAX_FADE_S: f64 = 2.0;

/// Run the loop until `total_ticks` have run or `stop` is set, then let the safety supervisor
/// fade the torque out and command zero. Every record goes to `out` (dropped and counted if
/// the ring is full in real time). Deadlines, lateness and periods are read on `clock`; a mock
/// clock asks for no real-time priority (nothing waits on it).
pub fn run(
    plant: &mut Plant,
    out: &mut rtrb::Producer<TickRecord>,
    total_ticks: u64,
    pacing: Pacing,
    isolate_core: bool,
    controls: &Controls,
    clock: &Clock,
) -> HapticOutcome {
    let real_time = pacing == Pacing::RealTime && !clock.is_mock();
    let linux_fifo = real_time && request_realtime_priority();
    let os_timing = clock.real_time_thread(pacing == Pacing::RealTime);
    // Real-time scheduling is SCHED_FIFO on Linux, the thread in MMCSS on Windows.
    let realtime_priority = linux_fifo || (real_time && os_timing.mmcss_task().is_some());
    let pinned = pacing == Pacing::RealTime && isolate_core && cores::pin_haptic_thread();
    if isolate_core {
        tracing::info!(pinned, "haptic thread pinned to the last core");
    }
    let spin = if pinned {
        spin_on_own_core()
    } else {
        Duration::ZERO
    };
    if pacing == Pacing::RealTime && !realtime_priority && !clock.is_mock() {
        tracing::warn!(
            "real-time scheduling (Linux: SCHED_FIFO; Windows: MMCSS) not granted: the haptic loop runs with normal priority and more jitter"
        );
    }
    let period_ns = (plant.dt_s() * 1e9).round() as u64;
    let max_fade_ticks = (MAX_FADE_S / plant.dt_s()).ceil() as u64;
    let start = clock.now_ns();
    let mut slots = Slots::new(start, period_ns);
    let mut last_wake = start;
    let mut dropped = 0u64;
    let mut stopping_since: Option<u64> = None;
    let mut stopped_early = false;
    let mut tick = 0u64;
    let mut breaks = BreakClock::new(plant.break_settings(), plant.dt_s());
    loop {
        // The session's length counts exercise time: a pause lengthens it.
        let active = plant.active_ticks();
        if stopping_since.is_none()
            && (active >= total_ticks
                || plant.course_done()
                || plant.wheel_fault().is_some()
                || breaks.paused_too_long
                || breaks.arm_sensor_unplugged
                || controls.stop.load(Ordering::Relaxed))
        {
            stopped_early = active < total_ticks && !plant.course_done();
            if active >= total_ticks {
                plant.time_up();
            }
            stopping_since = Some(tick);
            plant.request_stop();
        }
        if let Some(since) = stopping_since
            && (plant.stopped() || tick - since >= max_fade_ticks)
        {
            break;
        }
        let deadline = slots.deadline_ns();
        if pacing == Pacing::RealTime {
            clock.sleep_until_ns(deadline, spin);
        }
        let wake = clock.now_ns();
        // A stop overrides a pause. (The recorder thread logs the changes: no I/O here.)
        if stopping_since.is_none() {
            plant.set_paused(breaks.before_tick(plant, controls));
            plant.set_pedals(controls.pedals());
        }
        let mut rec = plant.tick();
        breaks.after_tick(&rec, plant, controls);
        let done = clock.now_ns();
        // For the live summaries and the log (the recorder thread tells them).
        controls
            .wheel_away
            .store(plant.wheel_away(), Ordering::Relaxed);
        controls
            .wheel_replugs
            .store(plant.wheel_replugs(), Ordering::Relaxed);
        rec.timing = TimingSample {
            lateness_ns: if pacing == Pacing::RealTime {
                wake.saturating_sub(deadline)
            } else {
                0
            },
            period_ns: wake.saturating_sub(last_wake),
            work_ns: done.saturating_sub(wake),
            dropped_records: dropped,
        };
        last_wake = wake;
        // After a stall, skip the deadlines already past instead of bursting through them.
        slots.advance(done, pacing == Pacing::RealTime);
        match pacing {
            Pacing::RealTime => {
                if out.push(rec).is_err() {
                    dropped += 1;
                }
            }
            Pacing::Max => {
                let mut pending = rec;
                while let Err(rtrb::PushError::Full(r)) = out.push(pending) {
                    pending = r;
                    std::thread::yield_now();
                }
            }
        }
        tick += 1;
    }
    plant.zero_torque();
    HapticOutcome {
        ticks: tick,
        dropped_records: dropped,
        stopped_early,
        realtime_priority,
        wall_s: clock.now_ns().saturating_sub(start) as f64 * 1e-9,
        range_of_motion_rad: plant.range_of_motion_rad(),
        // Told in words by the caller, after the loop (`Plant::arm_failure`).
        arm_failure: None,
        wheel_fault: plant.wheel_fault(),
        wheel_replugs: plant.wheel_replugs(),
        write_failures: plant.write_failures(),
        skipped_deadlines: slots.skipped,
        ceiling: Some(plant.ceiling()),
        motor_update_policy_hz: Some(plant.motor_update_policy_hz()),
        rests: breaks.rests,
        rest_s: breaks.rest_s(),
        paused_too_long: breaks.paused_too_long,
        arm_sensor_unplugged: breaks.arm_sensor_unplugged,
        window_lost: controls.window_lost.load(Ordering::Relaxed),
        exercise_scores: plant.exercise_scores(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: u64 = 1_000_000;

    #[cfg(target_os = "linux")]
    #[test]
    fn the_window_thread_and_those_it_starts_run_at_nice_10() {
        std::thread::spawn(|| {
            let now = rustix::process::getpriority_process(Some(rustix::thread::gettid()));
            if now.is_ok_and(|n| n > WINDOW_NICE) {
                // Raising a thread's priority needs CAP_SYS_NICE.
                println!("SKIPPED: the tests run above nice {WINDOW_NICE} already ({now:?})");
                return;
            }
            assert!(request_background_priority());
            let mine = rustix::process::getpriority_process(Some(rustix::thread::gettid()));
            assert_eq!(mine.unwrap(), WINDOW_NICE);
            // A rasteriser's worker started afterwards inherits it.
            let child = std::thread::spawn(|| {
                rustix::process::getpriority_process(Some(rustix::thread::gettid())).unwrap()
            });
            assert_eq!(child.join().unwrap(), WINDOW_NICE);
        })
        .join()
        .unwrap();
    }

    #[test]
    fn deadlines_are_absolute_and_lateness_is_measured_against_them() {
        let (clock, mock) = Clock::mock();
        mock.advance_ns(5 * MS);
        let mut slots = Slots::new(clock.now_ns(), MS);
        // On time: each tick finishes within its period, the next is due one period later.
        for k in 0..3 {
            assert_eq!(slots.deadline_ns(), 5 * MS + k * MS);
            clock.sleep_until_ns(slots.deadline_ns(), Duration::ZERO);
            mock.advance_ns(200_000); // the tick's work
            slots.advance(clock.now_ns(), true);
        }
        assert_eq!(slots.deadline_ns(), 8 * MS, "no drift from the work time");
        // A late wake-up: 30 µs past the deadline, measured against the deadline, and the
        // next deadline does not move.
        mock.set_ns(8 * MS + 30_000);
        assert_eq!(clock.now_ns().saturating_sub(slots.deadline_ns()), 30_000);
        slots.advance(clock.now_ns(), true);
        assert_eq!((slots.deadline_ns(), slots.skipped), (9 * MS, 0));
    }

    #[test]
    fn a_stall_skips_the_deadlines_already_past_instead_of_bursting_through_them() {
        let (clock, mock) = Clock::mock();
        let mut slots = Slots::new(clock.now_ns(), MS);
        slots.advance(300_000, true);
        assert_eq!((slots.next, slots.skipped), (1, 0));
        // A tick merely late for the next slot (slot 1 ends at 1.2 ms) is jitter: slot 2 runs.
        slots.advance(1_200_000, true);
        assert_eq!((slots.deadline_ns(), slots.skipped), (2 * MS, 0));
        // The tick of slot 2 stalls until 4.5 ms: slots 3 and 4 are past; 4, the latest, runs
        // at once and 3 is skipped.
        mock.set_ns(4_500_000);
        slots.advance(clock.now_ns(), true);
        assert_eq!((slots.deadline_ns(), slots.skipped), (4 * MS, 1));
        // The tick of slot 4 finishes exactly at 7 ms: 5 and 6 are skipped, 7 runs now.
        slots.advance(7 * MS, true);
        assert_eq!((slots.deadline_ns(), slots.skipped), (7 * MS, 3));
        // As fast as possible (no real-time pacing), nothing is ever skipped.
        let mut max = Slots::new(0, MS);
        max.advance(10 * MS, false);
        assert_eq!((max.next, max.skipped), (1, 0));
    }
}
