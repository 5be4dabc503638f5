//! The haptic loop's timing done the Windows way (issue 46; DESIGN.md, "Two systems"):
//!
//! - [`WaitableTimer`]: each thread that sleeps on the real clock sleeps on a waitable timer of
//!   its own, high-resolution (`CREATE_WAITABLE_TIMER_HIGH_RESOLUTION`, Windows 10 1803 and
//!   later: wakes within about 0.5 ms without touching the system's timer period) or, where the
//!   system refuses that flag (older Windows, Wine 8), a plain one whose resolution is the
//!   system timer period — 1 ms while a [`TimerPeriod`] is held, 15.6 ms otherwise.
//! - [`TimerPeriod`]: `timeBeginPeriod(1)` for as long as a session runs, `timeEndPeriod` on
//!   drop (the period is system-wide on Windows before 10 2004: holding it for a whole process
//!   lifetime costs every laptop battery power).
//! - [`MmcssTask`]: the calling thread in the Multimedia Class Scheduler ("Pro Audio", else
//!   "Games"), the real-time class a user may ask for without administrator rights — Windows'
//!   counterpart of the SCHED_FIFO priority the loop asks for on Linux; reverted on drop.
//!
//! Why not `std::thread::sleep`: since Rust 1.75 it, too, sleeps on a high-resolution timer
//! where the system has one (rust-lang/rust#116461), but makes and closes one per call (two
//! more system calls a tick) and otherwise falls back to `Sleep`, whole milliseconds that can
//! round down (rust-lang/rust#149935); here a plain waitable timer (100 ns units, never early)
//! under the 1 ms period is the fallback.
//!
//! The loop's deadlines stay absolute on the monotonic clock ([`crate::monotonic_ns`], QPC);
//! each wait arms the timer with the time left to the deadline, read just before arming, and
//! waits again if it woke early. An absolute `SetWaitableTimer` due time is UTC wall-clock
//! time (FILETIME), which a clock adjustment moves under a running session; a relative one is
//! not, and the deadlines never drift because they are never summed from waits.

use crate::monotonic_ns;
use std::time::Duration;
use windows_sys::Win32::Foundation::{CloseHandle, HANDLE, WAIT_OBJECT_0};
use windows_sys::Win32::Media::{TIMERR_NOERROR, timeBeginPeriod, timeEndPeriod};
use windows_sys::Win32::System::Threading::{
    AvRevertMmThreadCharacteristics, AvSetMmThreadCharacteristicsW,
    CREATE_WAITABLE_TIMER_HIGH_RESOLUTION, CreateWaitableTimerExW, INFINITE, SetWaitableTimer,
    TIMER_ALL_ACCESS, WaitForSingleObject,
};

/// Which kind of waitable timer a thread sleeps on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimerKind {
    /// `CREATE_WAITABLE_TIMER_HIGH_RESOLUTION`: resolution independent of the system's timer
    /// period.
    HighResolution,
    /// A plain waitable timer: resolution is the system's timer period (1 ms under a
    /// [`TimerPeriod`]).
    Plain,
}

/// One waitable timer (a kernel object), closed on drop. Not `Send`: each thread owns its own.
#[derive(Debug)]
pub struct WaitableTimer {
    handle: HANDLE,
    kind: TimerKind,
}

impl WaitableTimer {
    /// A high-resolution timer, or a plain one where the system refuses the high-resolution
    /// flag; `None` when the system gives neither.
    pub fn new() -> Option<Self> {
        Self::of_kind(TimerKind::HighResolution).or_else(|| Self::of_kind(TimerKind::Plain))
    }

    /// A timer of exactly `kind`; `None` when the system refuses it.
    #[expect(
        unsafe_code,
        reason = "CreateWaitableTimerExW, which std does not wrap"
    )]
    pub fn of_kind(kind: TimerKind) -> Option<Self> {
        let flags = match kind {
            TimerKind::HighResolution => CREATE_WAITABLE_TIMER_HIGH_RESOLUTION,
            TimerKind::Plain => 0,
        };
        // SAFETY: no security attributes and no name (both may be null); the returned handle
        // is owned by the `WaitableTimer` and closed once, on drop.
        let handle = unsafe {
            CreateWaitableTimerExW(std::ptr::null(), std::ptr::null(), flags, TIMER_ALL_ACCESS)
        };
        (!handle.is_null()).then_some(Self { handle, kind })
    }

    /// The kind this timer is.
    pub fn kind(&self) -> TimerKind {
        self.kind
    }

    /// Sleep until [`monotonic_ns`] reads at least `wake_ns`: arm the timer with the time
    /// left (rounded up to the timer's 100 ns unit, so it never fires early on its own
    /// account), wait, and again if the wait ended early. False when the system refused to
    /// arm or wait (the caller sleeps another way).
    #[expect(
        unsafe_code,
        reason = "SetWaitableTimer and WaitForSingleObject on our own timer"
    )]
    pub fn sleep_until_ns(&self, wake_ns: u64) -> bool {
        loop {
            let left_ns = wake_ns.saturating_sub(monotonic_ns());
            if left_ns == 0 {
                return true;
            }
            // Negative: relative to now, in 100 ns units.
            let due_100ns = -i64::try_from(left_ns.div_ceil(100)).unwrap_or(i64::MAX);
            // SAFETY: `self.handle` is a live timer handle with TIMER_ALL_ACCESS; the due
            // time is a valid i64 for the duration of the call; no period, no completion
            // routine (null) and no resume from suspend.
            let armed =
                unsafe { SetWaitableTimer(self.handle, &due_100ns, 0, None, std::ptr::null(), 0) };
            if armed == 0 {
                return false;
            }
            // SAFETY: a live handle we own; INFINITE is bounded by the timer just armed.
            if unsafe { WaitForSingleObject(self.handle, INFINITE) } != WAIT_OBJECT_0 {
                return false;
            }
        }
    }
}

impl Drop for WaitableTimer {
    #[expect(unsafe_code, reason = "CloseHandle on the handle this timer owns")]
    fn drop(&mut self) {
        // SAFETY: the handle came from CreateWaitableTimerExW and is closed only here, once.
        unsafe {
            CloseHandle(self.handle);
        }
    }
}

thread_local! {
    /// The calling thread's timer, made on its first real sleep (or by [`warm_up_timer`]).
    static TIMER: Option<WaitableTimer> = WaitableTimer::new();
}

/// The kind of timer the calling thread sleeps on (making it now if it has none yet); `None`
/// when the system gives no waitable timer (the thread then sleeps with `std::thread::sleep`).
pub fn thread_timer_kind() -> Option<TimerKind> {
    TIMER.with(|t| t.as_ref().map(WaitableTimer::kind))
}

/// Make the calling thread's timer now, so that its first tick does not pay for it.
pub(crate) fn warm_up_timer() {
    let _ = thread_timer_kind();
}

/// Sleep until [`monotonic_ns`] reads at least `wake_ns`, on the calling thread's waitable
/// timer; `std::thread::sleep` when the system gives none or refuses it.
pub(crate) fn sleep_until_ns(wake_ns: u64) {
    let slept = TIMER.with(|t| t.as_ref().is_some_and(|t| t.sleep_until_ns(wake_ns)));
    if !slept {
        let now = monotonic_ns();
        std::thread::sleep(Duration::from_nanos(wake_ns.saturating_sub(now)));
    }
}

/// The system's timer period held at `period_ms` (`timeBeginPeriod`) until [`TimerPeriod::end`]
/// or drop (`timeEndPeriod` with the same value, as the two calls must pair).
#[derive(Debug)]
pub struct TimerPeriod {
    period_ms: u32,
    held: bool,
}

impl TimerPeriod {
    /// Ask for a system timer period of `period_ms`; `None` when the system refuses it
    /// (`TIMERR_NOCANDO`: out of its range).
    #[expect(unsafe_code, reason = "timeBeginPeriod, which std does not wrap")]
    pub fn begin(period_ms: u32) -> Option<Self> {
        // SAFETY: a plain value argument; a refusal is a return code.
        let code = unsafe { timeBeginPeriod(period_ms) };
        (code == TIMERR_NOERROR).then_some(Self {
            period_ms,
            held: true,
        })
    }

    /// The period held, ms.
    pub fn period_ms(&self) -> u32 {
        self.period_ms
    }

    /// Give the period back now; true when the system accepted `timeEndPeriod`.
    pub fn end(mut self) -> bool {
        self.release()
    }

    #[expect(unsafe_code, reason = "timeEndPeriod, which std does not wrap")]
    fn release(&mut self) -> bool {
        if !std::mem::replace(&mut self.held, false) {
            return true;
        }
        // SAFETY: pairs the one successful timeBeginPeriod of this guard, same value.
        unsafe { timeEndPeriod(self.period_ms) == TIMERR_NOERROR }
    }
}

impl Drop for TimerPeriod {
    fn drop(&mut self) {
        let _ = self.release();
    }
}

/// The MMCSS tasks the haptic thread asks to join, in order: "Pro Audio" (the shortest
/// latency class: priority 1 in the "High" scheduling category), then "Games" (also "High").
pub const MMCSS_TASKS: [&str; 2] = ["Pro Audio", "Games"];

/// The calling thread in an MMCSS task until [`MmcssTask::leave`] or drop. Not `Send`: the
/// membership is the calling thread's, and only it may revert it.
#[derive(Debug)]
pub struct MmcssTask {
    handle: HANDLE,
    name: &'static str,
}

impl MmcssTask {
    /// Join the first of [`MMCSS_TASKS`] the system grants; `None` when it grants none (the
    /// MMCSS service stopped, or a system without it).
    pub fn join() -> Option<Self> {
        MMCSS_TASKS.iter().find_map(|&name| Self::join_task(name))
    }

    #[expect(
        unsafe_code,
        reason = "AvSetMmThreadCharacteristicsW, which std does not wrap"
    )]
    fn join_task(name: &'static str) -> Option<Self> {
        let wide: Vec<u16> = name.encode_utf16().chain(std::iter::once(0)).collect();
        let mut task_index = 0u32;
        // SAFETY: `wide` is a NUL-terminated UTF-16 string and `task_index` a live u32, both
        // outliving the call; the returned handle is reverted once, by this guard.
        let handle = unsafe { AvSetMmThreadCharacteristicsW(wide.as_ptr(), &mut task_index) };
        (!handle.is_null()).then_some(Self { handle, name })
    }

    /// The task joined ("Pro Audio" or "Games").
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// Leave the task now; true when the system accepted the revert.
    pub fn leave(mut self) -> bool {
        self.release()
    }

    #[expect(
        unsafe_code,
        reason = "AvRevertMmThreadCharacteristics on our own task handle"
    )]
    fn release(&mut self) -> bool {
        let handle = std::mem::replace(&mut self.handle, std::ptr::null_mut());
        if handle.is_null() {
            return true;
        }
        // SAFETY: the handle AvSetMmThreadCharacteristicsW returned to this thread, reverted
        // only here, once (it is null afterwards).
        unsafe { AvRevertMmThreadCharacteristics(handle) != 0 }
    }
}

impl Drop for MmcssTask {
    fn drop(&mut self) {
        let _ = self.release();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sleep to `count` deadlines `period_ns` apart on `timer`; the wake times.
    fn wakes_on(timer: &WaitableTimer, count: u64, period_ns: u64) -> Vec<(u64, u64)> {
        let start = monotonic_ns();
        (1..=count)
            .map(|k| {
                let deadline = start + k * period_ns;
                assert!(
                    timer.sleep_until_ns(deadline),
                    "the system refused the timer"
                );
                (deadline, monotonic_ns())
            })
            .collect()
    }

    #[test]
    fn each_kind_of_timer_wakes_at_or_after_every_deadline_and_in_order() {
        let _period = TimerPeriod::begin(1);
        let kinds: Vec<WaitableTimer> = [TimerKind::HighResolution, TimerKind::Plain]
            .into_iter()
            .filter_map(WaitableTimer::of_kind)
            .collect();
        assert!(
            kinds.iter().any(|t| t.kind() == TimerKind::Plain),
            "a plain waitable timer exists on every Windows"
        );
        for timer in &kinds {
            let wakes = wakes_on(timer, 50, 1_000_000);
            for &(deadline, woke) in &wakes {
                assert!(
                    woke >= deadline,
                    "{:?} woke before its deadline",
                    timer.kind()
                );
            }
            for pair in wakes.windows(2) {
                assert!(pair[1].1 >= pair[0].1, "wakes out of order");
            }
        }
    }

    #[test]
    fn a_deadline_already_past_returns_without_arming_the_timer() {
        let timer = WaitableTimer::new().expect("a waitable timer");
        let now = monotonic_ns();
        assert!(timer.sleep_until_ns(now.saturating_sub(1_000_000)));
        assert!(timer.sleep_until_ns(0));
    }

    #[test]
    fn a_thread_sleeps_on_a_timer_of_its_own() {
        let here = thread_timer_kind();
        let there = std::thread::spawn(thread_timer_kind)
            .join()
            .expect("thread");
        assert!(here.is_some(), "no waitable timer on this system");
        assert_eq!(here, there, "every thread gets the same kind of timer");
    }

    #[test]
    fn the_timer_period_guard_pairs_its_begin_with_an_end_and_nests() {
        let outer = TimerPeriod::begin(1).expect("a 1 ms period");
        let inner = TimerPeriod::begin(1).expect("a second 1 ms period");
        assert_eq!((outer.period_ms(), inner.period_ms()), (1, 1));
        assert!(inner.end(), "the system refused to end the inner period");
        assert!(outer.end(), "the system refused to end the outer period");
        assert!(
            TimerPeriod::begin(0).is_none(),
            "a 0 ms period is out of every system's range"
        );
    }

    #[test]
    fn a_thread_joins_mmcss_and_leaves_it() {
        let task = MmcssTask::join().expect("MMCSS grants one of its tasks");
        assert_eq!(task.name(), MMCSS_TASKS[0]);
        assert!(task.leave(), "the system refused to revert the thread");
    }
}
