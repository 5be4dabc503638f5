//! `telerehab bench loop`: the station's haptic loop against the platform's floor, back to
//! back in one run so that the noise of a shared machine hits every phase alike.
//!
//! - **A, the station**: a real-time simulated session as `telerehab run` runs it with the
//!   patient's window (recorder on, the haptic thread pinned to the last core with the other
//!   threads kept off it), optionally with the window process (`--with-window`) and a link to a
//!   hub (`--with-hub`: `telerehab therapist` on loopback, a separate process).
//! - **B, the reference**: a minimal loop of the same period on a thread of its own —
//!   SCHED_FIFO at the haptic thread's priority, pinned to the same core, `mlockall`, and
//!   `clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME)` to absolute deadlines.
//! - **C, `cyclictest`** (Debian's rt-tests) when it is on the `PATH`: `cyclictest -m -p 80 -i
//!   <period> -a <cpu> -D <s> -q -h <N>`, read from its histogram.
//!
//! Lateness is the same quantity in every phase: the time read on `CLOCK_MONOTONIC` just after
//! the thread wakes, minus the absolute deadline it slept to (the station's
//! `TimingSample::lateness_ns`; cyclictest's latency). The first [`WARMUP_S`] of A and B are
//! left out (window and shader start-up); cyclictest counts all its cycles.
//!
//! `--load` runs one busy child process per core beside every phase (`sh -c 'while :; do :;
//! done'`, nice 0, not pinned): both cores loaded, as a build beside the station would.

use anyhow::Context;
use clock::Clock;
use record::TickRecord;
use render::window::WindowOptions;
use session::haptic::{self, Pacing};
use session::{self, BodyKind, SessionObserver, SessionOptions};
use station::commands::run::{self, RunArgs};
use station::link::Link;
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// `telerehab bench loop`.
#[derive(Debug, clap::Args)]
pub struct BenchLoopArgs {
    /// Length of each phase, s.
    #[arg(long, default_value_t = 30.0)]
    pub seconds: f64,
    /// Run the patient's window process beside the station (needs a display).
    #[arg(long)]
    pub with_window: bool,
    /// Link the station to a hub: `telerehab therapist` started on loopback.
    #[arg(long)]
    pub with_hub: bool,
    /// Load every core with a busy process through all phases.
    #[arg(long)]
    pub load: bool,
    /// Busy-wait the station's haptic thread this long before each deadline instead of its
    /// own 300 µs, µs (0: sleep to the deadline, as the reference does).
    #[arg(long)]
    pub spin_us: Option<u64>,
    /// Leave out phase C even when `cyclictest` is installed.
    #[arg(long)]
    pub no_cyclictest: bool,
    /// Exercise the station runs.
    #[arg(long, default_value = "sine-road")]
    pub exercise: String,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
}

/// Lateness of the first this many seconds of phases A and B is not counted.
pub const WARMUP_S: f64 = 1.0;

/// The real-time priority of the haptic thread, the reference loop and cyclictest.
const RT_PRIORITY: u8 = 80;

/// Largest lateness cyclictest's histogram holds, µs (later ones are overflows).
const CYCLICTEST_HISTOGRAM_US: u64 = 10_000;

/// A lateness distribution, ns (nearest-rank percentiles).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lateness {
    /// Deadlines counted.
    pub n: u64,
    /// Median, ns.
    pub p50_ns: u64,
    /// 99th percentile, ns.
    pub p99_ns: u64,
    /// 99.9th percentile, ns.
    pub p999_ns: u64,
    /// Largest, ns.
    pub max_ns: u64,
    /// Deadlines skipped after a stall (`None`: not counted by that loop).
    pub skipped: Option<u64>,
    /// The loop thread's time on the CPU over the wall time counted (`None`: not measured).
    pub cpu_share: Option<f64>,
}

impl Lateness {
    /// The distribution of `values` (sorted here), ns.
    pub fn of(mut values: Vec<u64>, skipped: Option<u64>) -> Self {
        values.sort_unstable();
        let q = |p| common::quantile(&values, p).unwrap_or(0);
        Self {
            n: values.len() as u64,
            p50_ns: q(0.5),
            p99_ns: q(0.99),
            p999_ns: q(0.999),
            max_ns: values.last().copied().unwrap_or(0),
            skipped,
            cpu_share: None,
        }
    }

    /// The distribution of a histogram of `counts[v]` values of `v · unit_ns`, and
    /// `overflows` values beyond it, of which the largest is `max_ns` (they are counted at
    /// `max_ns`).
    pub fn of_histogram(counts: &[u64], unit_ns: u64, overflows: u64, max_ns: u64) -> Self {
        let n = counts.iter().sum::<u64>() + overflows;
        let q = |p: f64| {
            if n == 0 {
                return 0;
            }
            let rank = ((p * n as f64).ceil() as u64).clamp(1, n);
            let mut seen = 0;
            for (v, &c) in counts.iter().enumerate() {
                seen += c;
                if seen >= rank {
                    return v as u64 * unit_ns;
                }
            }
            max_ns
        };
        let top = counts
            .iter()
            .rposition(|&c| c > 0)
            .map_or(0, |v| v as u64 * unit_ns);
        Self {
            n,
            p50_ns: q(0.5),
            p99_ns: q(0.99),
            p999_ns: q(0.999),
            max_ns: max_ns.max(top),
            skipped: None,
            cpu_share: None,
        }
    }

    /// This distribution's percentiles over `base`'s: p50, p99, p99.9 and max (∞ over 0).
    pub fn ratio(&self, base: &Self) -> [f64; 4] {
        let r = |a: u64, b: u64| a as f64 / b as f64;
        [
            r(self.p50_ns, base.p50_ns),
            r(self.p99_ns, base.p99_ns),
            r(self.p999_ns, base.p999_ns),
            r(self.max_ns, base.max_ns),
        ]
    }
}

/// The table of the phases measured, then each one's ratio to the reference.
pub fn table(rows: &[(&str, Lateness)]) -> String {
    let us = |ns: u64| ns as f64 / 1e3;
    let mut out = format!(
        "{:<22} {:>8} {:>9} {:>9} {:>9} {:>9} {:>8} {:>6}\n",
        "lateness (µs)", "ticks", "p50", "p99", "p99.9", "max", "skipped", "CPU"
    );
    for (name, l) in rows {
        out += &format!(
            "{name:<22} {:>8} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>8} {:>6}\n",
            l.n,
            us(l.p50_ns),
            us(l.p99_ns),
            us(l.p999_ns),
            us(l.max_ns),
            l.skipped.map_or("-".to_owned(), |s| s.to_string()),
            l.cpu_share
                .map_or("-".to_owned(), |c| format!("{:.1}%", 100.0 * c))
        );
    }
    if let Some((_, reference)) = rows.iter().find(|(name, _)| name.starts_with("reference")) {
        for (name, l) in rows
            .iter()
            .filter(|(name, _)| !name.starts_with("reference"))
        {
            let [p50, p99, p999, max] = l.ratio(reference);
            out += &format!(
                "{:<22} {:>8} {p50:>9.2} {p99:>9.2} {p999:>9.2} {max:>9.2}\n",
                format!("{} / reference", name.split(' ').next().unwrap_or(name)),
                "ratio"
            );
        }
        let station = rows.iter().find(|(name, _)| name.starts_with("station"));
        if let Some((_, s)) = station {
            out += &format!(
                "station p50 − reference p50: {:+.1} µs\n",
                (s.p50_ns as f64 - reference.p50_ns as f64) / 1e3
            );
        }
    }
    out
}

/// Keeps each tick's lateness (from the recorder thread) after the warm-up, and the haptic
/// thread's CPU time over the ticks counted before the fade-out.
struct Collect {
    warmup_ticks: u64,
    last_tick: u64,
    lateness_ns: Vec<u64>,
    /// The haptic thread's CPU time and the wall time at the first tick counted, ns.
    cpu_from: Option<(u64, u64)>,
    cpu_share: Option<f64>,
}

/// The CPU time of this process's thread named `name`, ns (`/proc/self/task/*/schedstat`).
fn thread_cpu_ns(name: &str) -> Option<u64> {
    std::fs::read_dir("/proc/self/task")
        .ok()?
        .flatten()
        .find_map(|task| {
            let comm = std::fs::read_to_string(task.path().join("comm")).ok()?;
            if comm.trim_end() != name {
                return None;
            }
            let stat = std::fs::read_to_string(task.path().join("schedstat")).ok()?;
            stat.split_whitespace().next()?.parse().ok()
        })
}

impl SessionObserver for Collect {
    fn on_tick(&mut self, rec: &TickRecord) {
        if rec.tick < self.warmup_ticks {
            return;
        }
        self.lateness_ns.push(rec.timing.lateness_ns);
        if rec.tick == self.warmup_ticks {
            self.cpu_from = thread_cpu_ns("haptic").map(|c| (c, clock::monotonic_ns()));
        } else if rec.tick == self.last_tick
            && let (Some((cpu0, wall0)), Some(cpu1)) = (self.cpu_from, thread_cpu_ns("haptic"))
        {
            let wall = clock::monotonic_ns().saturating_sub(wall0).max(1);
            self.cpu_share = Some(cpu1.saturating_sub(cpu0) as f64 / wall as f64);
        }
    }
}

/// Child processes ended (killed and reaped) when dropped: the load and the hub.
#[derive(Default)]
struct Children(Vec<Child>);

impl Drop for Children {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// One busy process per core.
fn start_load(children: &mut Children) -> anyhow::Result<usize> {
    let n = std::thread::available_parallelism().map_or(1, usize::from);
    for _ in 0..n {
        let child = Command::new("sh")
            .args(["-c", "while :; do :; done"])
            .stdin(Stdio::null())
            .spawn()
            .context("cannot start the load (sh)")?;
        children.0.push(child);
    }
    Ok(n)
}

/// `telerehab therapist` on a free loopback port with a temporary store; its address.
fn start_hub(children: &mut Children, store: &std::path::Path) -> anyhow::Result<String> {
    let exe = std::env::current_exe().context("cannot find the telerehab program")?;
    let mut child = Command::new(exe)
        .args(["therapist", "--listen", "127.0.0.1:0", "--store"])
        .arg(store)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .context("cannot start the hub (telerehab therapist)")?;
    let stdout = child.stdout.take().context("the hub's output")?;
    children.0.push(child);
    let mut lines = BufReader::new(stdout).lines();
    let first = lines
        .next()
        .context("the hub ended before it listened")?
        .context("the hub's output")?;
    let addr = first
        .strip_prefix("listening on ")
        .and_then(|r| r.split_whitespace().next())
        .with_context(|| format!("the hub said {first:?}, not where it listens"))?
        .to_owned();
    // Its lines of events, read so that it never blocks on a full pipe.
    std::thread::spawn(move || for _ in lines {});
    Ok(addr)
}

/// Phase A: the station's session in real time, recorded to `dir`, as `telerehab run`
/// runs it with the window; each tick's lateness after the warm-up.
fn station(
    args: &BenchLoopArgs,
    hub: Option<&str>,
    dir: &std::path::Path,
) -> anyhow::Result<Lateness> {
    let run_args = RunArgs {
        headless: !args.with_window,
        exercise: Some(args.exercise.clone()),
        therapist: hub.map(str::to_owned),
        ..RunArgs::simulated(args.seconds + WARMUP_S, args.seed)
    };
    let (cfg, regimen) = run::plan(&run_args)?;
    let rate = cfg.session.loop_rate_hz;
    let clock = Clock::real();
    let opts = SessionOptions {
        config: cfg.clone(),
        pacing: Pacing::RealTime,
        record: Some(dir.join("bench-loop.mcap")),
        body: BodyKind::Simulated,
        regimen,
        isolate_core: true,
        difficulty: None,
        clock: clock.clone(),
    };
    let warmup_ticks = (WARMUP_S * rate).round() as u64;
    let mut collect = Collect {
        warmup_ticks,
        last_tick: warmup_ticks + (args.seconds * rate).round() as u64 - 1,
        lateness_ns: Vec::with_capacity(((args.seconds + 2.0) * rate) as usize),
        cpu_from: None,
        cpu_share: None,
    };
    let controls = session::Controls::default();
    let mut link = Link::start(&cfg, &clock, None)?;
    link.session_starts_now(&clock);
    let report = if args.with_window {
        let window = WindowOptions::new("telerehab bench loop");
        let (report, account) = session::window::run_with_window(
            &opts,
            &controls,
            &window,
            &mut (&link, &mut collect),
            true,
        )?;
        anyhow::ensure!(
            account.is_some(),
            "the window did not open (is there a display? try xvfb-run -a)"
        );
        report
    } else {
        // As the window's session does: the recorder and the rest off the haptic core.
        haptic::cores::keep_off_the_haptic_core();
        session::run(&opts, &controls, &mut (&link, &mut collect))?
    };
    let link_report = link.finish(
        report.summaries,
        &report.recorder.measures.named,
        None,
        &report.end_reason(),
    );
    if let Some(l) = link_report {
        println!(
            "station link to {}: {} summaries sent, {} acknowledged",
            l.address, l.sent, l.acked
        );
    }
    if !report.haptic.realtime_priority {
        println!(
            "the station's haptic thread was NOT granted SCHED_FIFO (run as root or with CAP_SYS_NICE): its figures are not the product's"
        );
    }
    Ok(Lateness {
        cpu_share: collect.cpu_share,
        ..Lateness::of(collect.lateness_ns, Some(report.haptic.skipped_deadlines))
    })
}

/// The calling thread's real-time scheduling, pinning and locked memory, as the reference
/// loop takes them.
struct Granted {
    fifo: bool,
    pinned: bool,
    locked: bool,
}

/// Phase B: the reference loop on a thread of its own, `ticks` deadlines `period_ns` apart
/// after the warm-up of `warmup_ticks`.
fn reference(period_ns: u64, warmup_ticks: u64, ticks: u64) -> anyhow::Result<(Lateness, Granted)> {
    std::thread::Builder::new()
        .name("reference".into())
        .spawn(move || {
            let granted = Granted {
                locked: rustix::mm::mlockall(
                    rustix::mm::MlockAllFlags::CURRENT | rustix::mm::MlockAllFlags::FUTURE,
                )
                .is_ok(),
                fifo: haptic::request_realtime_priority(),
                pinned: haptic::cores::pin_haptic_thread(),
            };
            let l = reference_loop(period_ns, warmup_ticks, ticks);
            let _ = rustix::mm::munlockall();
            (l, granted)
        })
        .context("cannot start the reference thread")?
        .join()
        .map_err(|_| anyhow::anyhow!("the reference thread panicked"))
}

/// `CLOCK_MONOTONIC` now, ns.
fn monotonic_now_ns() -> u64 {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::Monotonic);
    t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64
}

/// The reference loop itself: sleep to each absolute deadline, read the clock, count the
/// lateness; after a stall skip the deadlines already past as the station does.
fn reference_loop(period_ns: u64, warmup_ticks: u64, ticks: u64) -> Lateness {
    let cpu_ns = || {
        let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
        t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64
    };
    let mut from = (0, 0);
    let mut lateness_ns = Vec::with_capacity(ticks as usize);
    let start_ns = monotonic_now_ns() + period_ns;
    let (mut slot, mut skipped) = (0u64, 0u64);
    for k in 0..warmup_ticks + ticks {
        let deadline_ns = start_ns + slot * period_ns;
        let at = rustix::time::Timespec {
            tv_sec: (deadline_ns / 1_000_000_000) as _,
            tv_nsec: (deadline_ns % 1_000_000_000) as _,
        };
        // Again after a signal only: another error must not spin a SCHED_FIFO thread forever.
        while let Err(rustix::io::Errno::INTR) =
            rustix::thread::clock_nanosleep_absolute(rustix::thread::ClockId::Monotonic, &at)
        {
        }
        let wake_ns = monotonic_now_ns();
        if k == warmup_ticks {
            from = (cpu_ns(), wake_ns);
        }
        if k >= warmup_ticks {
            lateness_ns.push(wake_ns.saturating_sub(deadline_ns));
        }
        slot += 1;
        let latest_past = wake_ns.saturating_sub(start_ns) / period_ns;
        if latest_past > slot {
            if k >= warmup_ticks {
                skipped += latest_past - slot;
            }
            slot = latest_past;
        }
    }
    let wall_ns = monotonic_now_ns().saturating_sub(from.1).max(1);
    Lateness {
        cpu_share: Some(cpu_ns().saturating_sub(from.0) as f64 / wall_ns as f64),
        ..Lateness::of(lateness_ns, Some(skipped))
    }
}

/// Phase C: `cyclictest` on `cpu` for `seconds` at `period_ns`, when it is installed.
fn cyclictest(cpu: usize, period_ns: u64, seconds: f64) -> anyhow::Result<Option<Lateness>> {
    let out = match Command::new("cyclictest")
        .args(["-m", "-q", "-p", &RT_PRIORITY.to_string()])
        .args(["-i", &(period_ns / 1000).to_string()])
        .args(["-a", &cpu.to_string()])
        .args(["-D", &format!("{}", seconds.ceil() as u64)])
        .args(["-h", &CYCLICTEST_HISTOGRAM_US.to_string()])
        .stdin(Stdio::null())
        .output()
    {
        Ok(out) => out,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e).context("cannot run cyclictest"),
    };
    if !out.status.success() {
        // Not root, or no real-time scheduling: phases A and B still stand.
        println!(
            "cyclictest failed, left out: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        );
        return Ok(None);
    }
    parse_cyclictest(&String::from_utf8_lossy(&out.stdout)).map(Some)
}

/// The distribution in cyclictest's `-h` output: one `bucket count` line per µs, then
/// `# Max Latencies:` and `# Histogram Overflows:`.
pub fn parse_cyclictest(text: &str) -> anyhow::Result<Lateness> {
    let mut counts = Vec::with_capacity(CYCLICTEST_HISTOGRAM_US as usize + 1);
    let (mut max_us, mut overflows) = (None, 0u64);
    let field = |line: &str| -> Option<u64> { line.split_whitespace().nth(3)?.parse().ok() };
    for line in text.lines() {
        if line.starts_with("# Max Latencies:") {
            max_us = field(line);
        } else if line.starts_with("# Histogram Overflows:") {
            overflows = field(line).unwrap_or(0);
        } else if let Some((bucket, count)) = line.split_once(char::is_whitespace)
            && let (Ok(bucket), Ok(count)) = (bucket.parse::<usize>(), count.trim().parse::<u64>())
        {
            if counts.len() <= bucket {
                counts.resize(bucket + 1, 0);
            }
            counts[bucket] = count;
        }
    }
    let max_us = max_us.context("no `# Max Latencies:` line in cyclictest's output")?;
    Ok(Lateness::of_histogram(
        &counts,
        1000,
        overflows,
        max_us * 1000,
    ))
}

/// Run `telerehab bench loop`.
pub(super) fn bench_loop(args: BenchLoopArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.seconds.is_finite() && (0.5..=3600.0).contains(&args.seconds),
        "--seconds must be 0.5 to 3600"
    );
    print!("{}", measure(&args)?);
    Ok(())
}

/// The three phases, one after the other; the report.
pub fn measure(args: &BenchLoopArgs) -> anyhow::Result<String> {
    let mut children = Children::default();
    let mut out = String::new();
    if args.load {
        let n = start_load(&mut children)?;
        out += &format!("load: {n} busy processes (sh -c 'while :; do :; done', nice 0)\n");
    }
    let dir = tempfile::tempdir().context("cannot make a temporary directory")?;
    let hub = if args.with_hub {
        Some(start_hub(&mut children, &dir.path().join("hub"))?)
    } else {
        None
    };
    let cpu = haptic::cores::haptic_core();
    let rate = run::resolve_config(&RunArgs::simulated(1.0, args.seed))?
        .session
        .loop_rate_hz;
    let period_ns = (1e9 / rate).round() as u64;
    let ticks = (args.seconds * rate).round() as u64;
    let warmup_ticks = (WARMUP_S * rate).round() as u64;
    if let Some(us) = args.spin_us {
        haptic::set_spin_on_own_core(std::time::Duration::from_micros(us));
    }
    let a = station(args, hub.as_deref(), dir.path())?;
    let (b, granted) = reference(period_ns, warmup_ticks, ticks)?;
    let c = match (args.no_cyclictest, cpu) {
        (false, Some(cpu)) => cyclictest(cpu, period_ns, args.seconds)?,
        _ => None,
    };
    drop(children);
    out += &format!(
        "period {:.0} µs, {:.0} s per phase after {WARMUP_S:.0} s of warm-up, CPU {}; station with recorder{}{}, spin {} µs; reference SCHED_FIFO {}{}{}\n",
        period_ns as f64 / 1e3,
        args.seconds,
        cpu.map_or("unpinned".to_owned(), |c| c.to_string()),
        if args.with_window { ", window" } else { "" },
        if args.with_hub { ", hub link" } else { "" },
        haptic::spin_on_own_core().as_micros(),
        if granted.fifo {
            RT_PRIORITY.to_string()
        } else {
            "NOT granted".to_owned()
        },
        if granted.pinned {
            ", pinned"
        } else {
            ", NOT pinned"
        },
        if granted.locked {
            ", mlockall"
        } else {
            ", memory NOT locked"
        },
    );
    let mut rows = vec![("station (haptic loop)", a), ("reference (same CPU)", b)];
    if let Some(c) = c {
        rows.push(("cyclictest", c));
    }
    out += &table(&rows);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_are_nearest_rank_and_ratios_are_per_percentile() {
        // 1..=1000 µs: p50 500, p99 990, p99.9 999, max 1000.
        let values: Vec<u64> = (1..=1000).rev().map(|v| v * 1000).collect();
        let l = Lateness::of(values, Some(2));
        assert_eq!(
            (l.n, l.p50_ns, l.p99_ns, l.p999_ns, l.max_ns),
            (1000, 500_000, 990_000, 999_000, 1_000_000)
        );
        let half = Lateness::of((1..=1000).map(|v| v * 500).collect(), None);
        assert_eq!(l.ratio(&half), [2.0; 4]);
        // The same values as a histogram of 1 µs buckets.
        let mut counts = vec![0u64; 1001];
        counts[1..].fill(1);
        let h = Lateness::of_histogram(&counts, 1000, 0, 1_000_000);
        assert_eq!(
            (h.n, h.p50_ns, h.p99_ns, h.p999_ns, h.max_ns),
            (1000, 500_000, 990_000, 999_000, 1_000_000)
        );
        // Overflows count at the maximum, beyond every bucket.
        let h = Lateness::of_histogram(&counts[..991], 1000, 10, 25_000_000);
        assert_eq!(
            (h.p99_ns, h.p999_ns, h.max_ns),
            (990_000, 25_000_000, 25_000_000)
        );
        let t = table(&[("station (haptic loop)", l), ("reference (same CPU)", half)]);
        assert!(t.contains("station / reference"), "{t}");
        assert!(t.contains("station p50 − reference p50: +250.0 µs"), "{t}");
    }

    #[test]
    fn cyclictests_histogram_is_read_with_its_overflows_and_maximum() {
        let text = "# /dev/cpu_dma_latency set to 0us\n000000 000000\n000001 000005\n000002 000090\n000003 000004\n# Total: 000000100\n# Min Latencies: 00001\n# Avg Latencies: 00002\n# Max Latencies: 00042\n# Histogram Overflows: 00001\n# Histogram Overflow at cycle number:\n# Thread 0: 00017\n";
        let l = parse_cyclictest(text).unwrap();
        assert_eq!(
            (l.n, l.p50_ns, l.p99_ns, l.max_ns),
            (100, 2000, 3000, 42_000)
        );
        assert!(parse_cyclictest("nothing").is_err());
    }
}
