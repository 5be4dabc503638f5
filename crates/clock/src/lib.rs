//! The one injectable clock (DESIGN.md, "One injectable clock"; copper-rs's `RobotClock` with
//! its mock is the model).
//!
//! Everything in the station that needs the time — the haptic thread's deadlines, the real and
//! simulated devices' timestamps, the arm solver's time-out, the therapist link's wall-clock
//! stamps — takes a [`Clock`] instead of calling `Instant::now` or `SystemTime::now` itself.
//! A [`Clock::real`] reads the operating system; a [`Clock::mock`] returns a handle,
//! [`MockClock`], that tests move by hand, so deadline lateness, the watchdog and time-outs are
//! tested without sleeping. The pure crates never see a clock: they get `dt` or timestamps.
//!
//! Times are `u64` nanoseconds: monotonic since a process-wide epoch ([`Clock::now_ns`]), and
//! wall-clock since the Unix epoch ([`Clock::unix_ns`]).
//!
//! A real-time loop holds a [`ThreadTiming`] ([`Clock::real_time_thread`]) while it runs: on
//! Windows the system timer period at 1 ms and the thread in MMCSS, and the real clock sleeps on
//! a high-resolution waitable timer (module `windows`); on Linux the real clock sleeps with
//! `clock_nanosleep` to absolute deadlines and the station asks for SCHED_FIFO itself.
//!
//! ```
//! let (clock, mock) = clock::Clock::mock();
//! assert_eq!(clock.now_ns(), 0);
//! mock.advance_ns(1_000_000);
//! assert_eq!(clock.now_ns(), 1_000_000);
//! ```

use std::sync::Arc;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};
#[cfg(not(target_os = "linux"))]
use std::time::Instant;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

#[cfg(windows)]
pub mod windows;

/// Wall-clock time a mock clock starts at, ns since the Unix epoch (2026-01-01T00:00:00Z), so
/// that wall-clock stamps made under test are plausible dates.
pub const MOCK_UNIX_START_NS: u64 = 1_767_225_600_000_000_000;

/// The process-wide monotonic epoch every real clock counts from, so that two real clocks
/// (and [`monotonic_ns`]) agree.
#[cfg(not(target_os = "linux"))]
fn epoch() -> Instant {
    static EPOCH: OnceLock<Instant> = OnceLock::new();
    *EPOCH.get_or_init(Instant::now)
}

/// `CLOCK_MONOTONIC` (what `Instant` reads on Linux), ns since the system started.
#[cfg(target_os = "linux")]
fn clock_monotonic_ns() -> u64 {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::Monotonic);
    u64::try_from(t.tv_sec).unwrap_or(0) * 1_000_000_000 + u64::try_from(t.tv_nsec).unwrap_or(0)
}

/// The process-wide monotonic epoch every real clock counts from, so that two real clocks
/// (and [`monotonic_ns`]) agree: on Linux, `CLOCK_MONOTONIC` ns, so that a deadline converts
/// exactly to the absolute time `clock_nanosleep` sleeps to.
#[cfg(target_os = "linux")]
fn epoch_ns() -> u64 {
    static EPOCH: OnceLock<u64> = OnceLock::new();
    *EPOCH.get_or_init(clock_monotonic_ns)
}

/// Nanoseconds on the real monotonic clock since the process-wide epoch: what
/// [`Clock::real`]'s [`Clock::now_ns`] returns, for code handed a plain `fn() -> u64`.
pub fn monotonic_ns() -> u64 {
    #[cfg(target_os = "linux")]
    {
        let epoch = epoch_ns();
        clock_monotonic_ns().saturating_sub(epoch)
    }
    #[cfg(not(target_os = "linux"))]
    {
        u64::try_from(epoch().elapsed().as_nanos()).unwrap_or(u64::MAX)
    }
}

/// Sleep until `deadline_ns` on the real clock, less `spin`. On Linux: `clock_nanosleep` to
/// the absolute time on `CLOCK_MONOTONIC` (no relative sleep computed from a reading that is
/// already old when the kernel gets it), as `cyclictest` and `telerehab bench loop`'s
/// reference loop sleep. On Windows: the thread's waitable timer, high-resolution where the
/// system has it (module `windows`).
fn sleep_real_until_ns(deadline_ns: u64, spin: Duration) {
    let spin_ns = u64::try_from(spin.as_nanos()).unwrap_or(u64::MAX);
    let wake_ns = deadline_ns.saturating_sub(spin_ns);
    #[cfg(target_os = "linux")]
    {
        let at_ns = epoch_ns().saturating_add(wake_ns);
        let at = rustix::time::Timespec {
            tv_sec: i64::try_from(at_ns / 1_000_000_000).unwrap_or(i64::MAX),
            tv_nsec: i64::try_from(at_ns % 1_000_000_000).unwrap_or(0),
        };
        // Interrupted by a signal: sleep again to the same absolute time. Any other error
        // (a sandbox refusing the call): a relative sleep, never a busy-wait.
        while monotonic_ns() < wake_ns {
            match rustix::thread::clock_nanosleep_absolute(rustix::thread::ClockId::Monotonic, &at)
            {
                Err(rustix::io::Errno::INTR) => {}
                Ok(()) => break,
                Err(_) => {
                    let now = monotonic_ns();
                    std::thread::sleep(Duration::from_nanos(wake_ns.saturating_sub(now)));
                    break;
                }
            }
        }
    }
    #[cfg(windows)]
    windows::sleep_until_ns(wake_ns);
    #[cfg(not(any(target_os = "linux", windows)))]
    {
        let now = monotonic_ns();
        if wake_ns > now {
            std::thread::sleep(Duration::from_nanos(wake_ns - now));
        }
    }
}

#[derive(Debug)]
enum Source {
    Real,
    /// Monotonic time, ns since the mock's start, and its wall-clock time at that start, ns
    /// since the Unix epoch.
    Mock {
        ns: AtomicU64,
        unix_start_ns: u64,
    },
}

/// A monotonic and a wall clock, real or mock. Cheap to clone (one `Arc`); clones share the
/// same time.
#[derive(Clone, Debug)]
pub struct Clock {
    source: Arc<Source>,
}

impl Default for Clock {
    fn default() -> Self {
        Self::real()
    }
}

impl Clock {
    /// The operating system's clocks.
    pub fn real() -> Self {
        // Fix the epoch now, so that the first reading is near zero rather than whenever
        // somebody first asks.
        let _ = monotonic_ns();
        Self {
            source: Arc::new(Source::Real),
        }
    }

    /// A clock at 0 ns that moves only when the returned [`MockClock`] moves it; its wall
    /// clock starts at [`MOCK_UNIX_START_NS`].
    pub fn mock() -> (Self, MockClock) {
        Self::mock_at_unix_ns(MOCK_UNIX_START_NS)
    }

    /// A mock clock ([`Clock::mock`]) whose wall clock starts at `unix_ns`, ns since the Unix
    /// epoch: for code that stores or compares dates (the hub's logins, audit, adherence).
    pub fn mock_at_unix_ns(unix_ns: u64) -> (Self, MockClock) {
        let source = Arc::new(Source::Mock {
            ns: AtomicU64::new(0),
            unix_start_ns: unix_ns,
        });
        (
            Self {
                source: source.clone(),
            },
            MockClock { source },
        )
    }

    /// True for a mock clock.
    pub fn is_mock(&self) -> bool {
        matches!(*self.source, Source::Mock { .. })
    }

    /// Monotonic time, ns since the process-wide epoch (real) or since the mock's start.
    pub fn now_ns(&self) -> u64 {
        match &*self.source {
            Source::Real => monotonic_ns(),
            Source::Mock { ns, .. } => ns.load(Ordering::Acquire),
        }
    }

    /// Wall-clock time, ns since the Unix epoch (a mock starts where it was made to,
    /// [`MOCK_UNIX_START_NS`] by default, and moves with its monotonic time).
    pub fn unix_ns(&self) -> u64 {
        match &*self.source {
            Source::Real => SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)),
            Source::Mock { ns, unix_start_ns } => {
                unix_start_ns.saturating_add(ns.load(Ordering::Acquire))
            }
        }
    }

    /// The monotonic time at which something stamped with the wall-clock time `at` happened
    /// (e.g. a kernel input event), ns; never later than now. Times before the epoch map to 0.
    pub fn monotonic_of(&self, at: SystemTime) -> u64 {
        let at_unix = at
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX));
        let age = self.unix_ns().saturating_sub(at_unix);
        self.now_ns().saturating_sub(age)
    }

    /// Wait until monotonic time `deadline_ns`. A real clock sleeps, then busy-waits the last
    /// `spin` (a halted virtual CPU can take hundreds of µs to wake); a mock clock jumps to the
    /// deadline at once (tests run as fast as they can and time still adds up).
    pub fn sleep_until_ns(&self, deadline_ns: u64, spin: Duration) {
        match &*self.source {
            Source::Real => {
                sleep_real_until_ns(deadline_ns, spin);
                while monotonic_ns() < deadline_ns {
                    std::hint::spin_loop();
                }
            }
            Source::Mock { ns, .. } => {
                ns.fetch_max(deadline_ns, Ordering::AcqRel);
            }
        }
    }

    /// Ready the calling thread to run a loop paced on this clock until the returned guard
    /// drops: when `real_time` and the clock is real, on Windows the system timer period at
    /// 1 ms, the thread in MMCSS and its waitable timer made now (not on the first tick);
    /// otherwise, and on a mock clock (nothing waits on it), nothing.
    pub fn real_time_thread(&self, real_time: bool) -> ThreadTiming {
        if !real_time || self.is_mock() {
            return ThreadTiming::default();
        }
        #[cfg(windows)]
        {
            windows::warm_up_timer();
            ThreadTiming {
                period: windows::TimerPeriod::begin(1),
                mmcss: windows::MmcssTask::join(),
            }
        }
        #[cfg(not(windows))]
        {
            ThreadTiming::default()
        }
    }
}

/// What the operating system gives a thread that runs a real-time loop, held while the loop
/// runs and given back on drop ([`Clock::real_time_thread`]). On Windows: the system timer
/// period at 1 ms (`timeBeginPeriod(1)`, so that even a plain waitable timer wakes within
/// 1 ms) and the thread in MMCSS ("Pro Audio", else "Games"); elsewhere nothing (Linux's
/// SCHED_FIFO is the station's to ask for).
#[derive(Debug, Default)]
pub struct ThreadTiming {
    #[cfg(windows)]
    mmcss: Option<windows::MmcssTask>,
    #[cfg(windows)]
    period: Option<windows::TimerPeriod>,
}

impl ThreadTiming {
    /// The system timer period held, ms; `None` when none is (not Windows, a mock clock, or
    /// the system refused).
    pub fn timer_period_ms(&self) -> Option<u32> {
        #[cfg(windows)]
        {
            self.period.as_ref().map(windows::TimerPeriod::period_ms)
        }
        #[cfg(not(windows))]
        {
            None
        }
    }

    /// The MMCSS task the thread joined ("Pro Audio" or "Games"); `None` when it joined none.
    pub fn mmcss_task(&self) -> Option<&'static str> {
        #[cfg(windows)]
        {
            self.mmcss.as_ref().map(windows::MmcssTask::name)
        }
        #[cfg(not(windows))]
        {
            None
        }
    }
}

/// The hand that moves a mock [`Clock`]. Time never goes backwards.
#[derive(Clone, Debug)]
pub struct MockClock {
    source: Arc<Source>,
}

impl MockClock {
    fn cell(&self) -> &AtomicU64 {
        match &*self.source {
            Source::Mock { ns, .. } => ns,
            Source::Real => unreachable!("a MockClock is only made with a mock source"),
        }
    }

    /// The mock's wall-clock time at its start, ns since the Unix epoch.
    fn unix_start_ns(&self) -> u64 {
        match &*self.source {
            Source::Mock { unix_start_ns, .. } => *unix_start_ns,
            Source::Real => unreachable!("a MockClock is only made with a mock source"),
        }
    }

    /// Move the clock forward by `dt_ns`.
    pub fn advance_ns(&self, dt_ns: u64) {
        self.cell().fetch_add(dt_ns, Ordering::AcqRel);
    }

    /// Move the clock forward by `dt`.
    pub fn advance(&self, dt: Duration) {
        self.advance_ns(u64::try_from(dt.as_nanos()).unwrap_or(u64::MAX));
    }

    /// Set the clock to `t_ns` if that is later than now (time never goes backwards).
    pub fn set_ns(&self, t_ns: u64) {
        self.cell().fetch_max(t_ns, Ordering::AcqRel);
    }

    /// Set the clock so that its wall-clock time reads `unix_ns`, ns since the Unix epoch, if
    /// that is later than now (time never goes backwards).
    pub fn set_unix_ns(&self, unix_ns: u64) {
        self.set_ns(unix_ns.saturating_sub(self.unix_start_ns()));
    }

    /// The mock's monotonic time, ns.
    pub fn now_ns(&self) -> u64 {
        self.cell().load(Ordering::Acquire)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mock_clock_moves_only_when_told_and_its_clones_share_the_time() {
        let (clock, mock) = Clock::mock();
        let copy = clock.clone();
        assert_eq!(clock.now_ns(), 0);
        mock.advance(Duration::from_millis(3));
        assert_eq!(copy.now_ns(), 3_000_000);
        mock.set_ns(1_000);
        assert_eq!(clock.now_ns(), 3_000_000, "time never goes backwards");
        assert_eq!(clock.unix_ns(), MOCK_UNIX_START_NS + 3_000_000);
    }

    #[test]
    fn a_mock_clock_starts_at_the_date_it_is_given_and_is_set_by_its_wall_time() {
        // 2026-11-21 09:30 UTC.
        let start_ns = 1_795_253_400_000 * 1_000_000;
        let (clock, mock) = Clock::mock_at_unix_ns(start_ns);
        assert_eq!((clock.now_ns(), clock.unix_ns()), (0, start_ns));
        mock.set_unix_ns(start_ns + 7_000_000);
        assert_eq!(
            (clock.now_ns(), clock.unix_ns()),
            (7_000_000, start_ns + 7_000_000)
        );
        mock.set_unix_ns(start_ns + 1_000);
        assert_eq!(
            clock.unix_ns(),
            start_ns + 7_000_000,
            "time never goes backwards"
        );
        mock.set_unix_ns(0);
        assert_eq!(
            clock.now_ns(),
            7_000_000,
            "a date before its start: no move"
        );
        mock.advance_ns(3);
        assert_eq!(clock.unix_ns(), start_ns + 7_000_003);
    }

    #[test]
    fn sleeping_on_a_mock_clock_jumps_to_the_deadline() {
        let (clock, _mock) = Clock::mock();
        clock.sleep_until_ns(5_000_000, Duration::ZERO);
        assert_eq!(clock.now_ns(), 5_000_000);
        clock.sleep_until_ns(1_000, Duration::ZERO);
        assert_eq!(clock.now_ns(), 5_000_000);
    }

    #[test]
    fn a_wall_clock_stamp_maps_to_the_monotonic_time_it_happened() {
        let (clock, mock) = Clock::mock();
        mock.advance_ns(10_000_000);
        let stamp = UNIX_EPOCH + Duration::from_nanos(clock.unix_ns() - 4_000_000);
        assert_eq!(clock.monotonic_of(stamp), 6_000_000);
        // A stamp from the future is "now", never later.
        let future = UNIX_EPOCH + Duration::from_nanos(clock.unix_ns() + 1_000);
        assert_eq!(clock.monotonic_of(future), 10_000_000);
    }

    #[test]
    fn a_real_clock_sleeps_to_the_absolute_deadline_and_never_wakes_before_it() {
        let clock = Clock::real();
        for spin_us in [0, 200] {
            let deadline = clock.now_ns() + 2_000_000;
            clock.sleep_until_ns(deadline, Duration::from_micros(spin_us));
            assert!(clock.now_ns() >= deadline, "woke before the deadline");
        }
        // A deadline already past returns at once, without sleeping a period.
        let before = clock.now_ns();
        clock.sleep_until_ns(before.saturating_sub(1_000_000), Duration::ZERO);
        assert!(clock.now_ns() - before < 1_000_000_000);
    }

    #[test]
    fn a_real_time_thread_on_a_mock_clock_or_not_in_real_time_holds_nothing() {
        let (mock, _hand) = Clock::mock();
        for timing in [
            mock.real_time_thread(true),
            Clock::real().real_time_thread(false),
        ] {
            assert_eq!(
                (timing.timer_period_ms(), timing.mmcss_task()),
                (None, None)
            );
        }
    }

    #[cfg(windows)]
    #[test]
    fn a_real_time_thread_on_windows_holds_a_1_ms_period_and_mmcss_and_meets_its_deadlines() {
        let clock = Clock::real();
        let timing = clock.real_time_thread(true);
        assert_eq!(timing.timer_period_ms(), Some(1));
        assert_eq!(timing.mmcss_task(), Some(windows::MMCSS_TASKS[0]));
        let start = clock.now_ns();
        let mut last_wake = start;
        for k in 1..=100 {
            let deadline = start + k * 1_000_000;
            clock.sleep_until_ns(deadline, Duration::ZERO);
            let wake = clock.now_ns();
            assert!(
                wake >= deadline && wake >= last_wake,
                "tick {k} early or out of order"
            );
            last_wake = wake;
        }
    }

    #[test]
    fn real_clocks_agree_and_never_go_backwards() {
        let a = Clock::real();
        let b = Clock::real();
        let t0 = a.now_ns();
        let t1 = b.now_ns();
        let t2 = monotonic_ns();
        assert!(t1 >= t0 && t2 >= t1);
        assert!(a.unix_ns() > MOCK_UNIX_START_NS / 2);
    }
}
