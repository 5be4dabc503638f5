//! `telerehab bench soak`: one long simulated, recorded session watched for what grows when it
//! should not. Every `--every` seconds of session time the recorder thread samples the
//! process's resident memory (`VmRSS` in `/proc/self/status`), its open file descriptors
//! (`/proc/self/fd`) and the recording's size on disk; every tick it keeps the loop's lateness
//! and period. At the end: a table, and verdicts — memory and descriptors flat after the
//! warm-up, the recording growing linearly with session time (least-squares fit and its
//! residual), no tick later than the watchdog allows (real time only).

use clock::Clock;
use record::TickRecord;
use session::{self, BodyKind, SessionObserver, SessionOptions, haptic::Pacing};
use station::commands::run::{self, RunArgs};
use std::path::{Path, PathBuf};

/// `telerehab bench soak`.
#[derive(Debug, clap::Args)]
pub struct BenchSoakArgs {
    /// Session length, s of exercise (1 h by default).
    #[arg(long, default_value_t = 3600.0)]
    pub duration: f64,
    /// `max` (as fast as the machine allows) or `1` (real time).
    #[arg(long, default_value = "max")]
    pub speed: String,
    /// Sample memory, descriptors and the file every this many seconds of session time.
    #[arg(long, default_value_t = 5.0)]
    pub every: f64,
    /// Session time before memory and descriptors must be flat, s.
    #[arg(long, default_value_t = 60.0)]
    pub warmup: f64,
    /// Exercise to run.
    #[arg(long, default_value = "sine-road")]
    pub exercise: String,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
    /// Directory of the recording (default: the system's temporary directory); it is deleted
    /// at the end unless `--keep`.
    #[arg(long)]
    pub dir: Option<PathBuf>,
    /// Keep the recording.
    #[arg(long)]
    pub keep: bool,
}

/// One sample, at session time `t_s`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Sample {
    t_s: f64,
    rss_kib: u64,
    fds: u64,
    file_bytes: u64,
    /// Largest lateness of a tick since the previous sample, µs (real time only).
    max_late_us: f64,
    /// Largest period between two ticks since the previous sample, µs.
    max_period_us: f64,
}

/// Open file descriptors of this process, if readable.
fn open_fds() -> Option<u64> {
    Some(std::fs::read_dir("/proc/self/fd").ok()?.count() as u64)
}

/// Watches the session from the recorder thread.
struct Sampler {
    every_ns: u64,
    next_ns: u64,
    path: PathBuf,
    samples: Vec<Sample>,
    late_ns: u64,
    period_ns: u64,
    /// Ticks whose period exceeded the watchdog's largest tick gap.
    past_watchdog: u64,
    watchdog_ns: u64,
}

impl SessionObserver for Sampler {
    fn on_tick(&mut self, rec: &TickRecord) {
        self.late_ns = self.late_ns.max(rec.timing.lateness_ns);
        self.period_ns = self.period_ns.max(rec.timing.period_ns);
        self.past_watchdog += u64::from(rec.timing.period_ns > self.watchdog_ns);
        if rec.t_ns < self.next_ns {
            return;
        }
        self.next_ns += self.every_ns;
        self.samples.push(Sample {
            t_s: rec.t_ns as f64 * 1e-9,
            rss_kib: session::resident::status_kib("VmRSS").unwrap_or(0),
            fds: open_fds().unwrap_or(0),
            file_bytes: std::fs::metadata(&self.path).map_or(0, |m| m.len()),
            max_late_us: self.late_ns as f64 * 1e-3,
            max_period_us: self.period_ns as f64 * 1e-3,
        });
        (self.late_ns, self.period_ns) = (0, 0);
    }
}

/// Least-squares line through `(x, y)` ([`common::line_fit`]): slope, intercept and the RMS
/// residual.
fn fit(points: &[(f64, f64)]) -> (f64, f64, f64) {
    let (slope, intercept) = common::line_fit(points);
    let residual_sq: f64 = points
        .iter()
        .map(|p| (p.1 - slope * p.0 - intercept).powi(2))
        .sum();
    let rms = (residual_sq / points.len().max(1) as f64).sqrt();
    (slope, intercept, rms)
}

/// What the samples say, in words and as pass/fail.
struct Verdicts {
    lines: Vec<(bool, String)>,
}

/// Memory may wander by this much after the warm-up and still be flat, KiB (allocator
/// noise: a few arenas and pages).
const RSS_FLAT_KIB: u64 = 4096;
/// The recording is linear when its residual is at most this share of its final size.
const LINEAR_RESIDUAL_SHARE: f64 = 0.01;

fn verdicts(samples: &[Sample], warmup_s: f64, past_watchdog: u64, real_time: bool) -> Verdicts {
    let settled: Vec<&Sample> = samples.iter().filter(|s| s.t_s >= warmup_s).collect();
    let range = |f: fn(&Sample) -> u64| {
        let v = settled.iter().map(|s| f(s));
        (v.clone().min().unwrap_or(0), v.max().unwrap_or(0))
    };
    let mut lines = Vec::new();
    let (rss_lo, rss_hi) = range(|s| s.rss_kib);
    let rss_points: Vec<(f64, f64)> = settled
        .iter()
        .map(|s| (s.t_s / 3600.0, s.rss_kib as f64 / 1024.0))
        .collect();
    let (rss_slope, _, _) = fit(&rss_points);
    lines.push((
        rss_hi - rss_lo <= RSS_FLAT_KIB,
        format!(
            "resident memory after {warmup_s:.0} s: {:.1} to {:.1} MiB (spread {:.1} MiB, fit {rss_slope:+.2} MiB per hour; flat within {:.0} MiB)",
            rss_lo as f64 / 1024.0,
            rss_hi as f64 / 1024.0,
            (rss_hi - rss_lo) as f64 / 1024.0,
            RSS_FLAT_KIB as f64 / 1024.0
        ),
    ));
    let (fd_lo, fd_hi) = range(|s| s.fds);
    lines.push((
        fd_lo == fd_hi,
        format!("open descriptors after {warmup_s:.0} s: {fd_lo} to {fd_hi}"),
    ));
    let size_points: Vec<(f64, f64)> = samples
        .iter()
        .map(|s| (s.t_s, s.file_bytes as f64))
        .collect();
    let (slope, _, rms) = fit(&size_points);
    let last = samples.last().map_or(0.0, |s| s.file_bytes as f64);
    lines.push((
        last > 0.0 && rms <= LINEAR_RESIDUAL_SHARE * last,
        format!(
            "recording {:.1} MB: {:.1} MB per hour of session, RMS residual {:.3} MB ({:.2} % of its size; linear within {:.0} %)",
            last / 1e6,
            slope * 3600.0 / 1e6,
            rms / 1e6,
            100.0 * rms / last.max(1.0),
            100.0 * LINEAR_RESIDUAL_SHARE
        ),
    ));
    if real_time {
        let late = samples.iter().map(|s| s.max_late_us).fold(0.0, f64::max);
        let period = samples.iter().map(|s| s.max_period_us).fold(0.0, f64::max);
        lines.push((
            past_watchdog == 0,
            format!(
                "tick lateness at most {late:.0} µs, longest period {period:.0} µs; {past_watchdog} ticks later than the watchdog's tick gap"
            ),
        ));
    }
    Verdicts { lines }
}

/// Run `telerehab bench soak`.
pub(super) fn soak(args: BenchSoakArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.duration.is_finite() && (10.0..=4.0 * 3600.0).contains(&args.duration),
        "--duration must be 10 to 14400 s"
    );
    anyhow::ensure!(
        args.every.is_finite() && (0.1..=600.0).contains(&args.every),
        "--every must be 0.1 to 600 s"
    );
    let pacing = match args.speed.as_str() {
        "max" => Pacing::Max,
        "1" => Pacing::RealTime,
        other => anyhow::bail!("--speed {other:?}: write max or 1"),
    };
    let run_args = RunArgs {
        exercise: Some(args.exercise.clone()),
        ..RunArgs::simulated(args.duration, args.seed)
    };
    let (cfg, regimen) = run::plan(&run_args)?;
    let dir = match &args.dir {
        Some(d) => d.clone(),
        None => std::env::temp_dir(),
    };
    let path = dir.join(format!("telerehab-soak-{}.mcap", std::process::id()));
    let watchdog_ns = (cfg.haptic.safety.max_tick_gap_s * 1e9) as u64;
    let opts = SessionOptions {
        config: cfg,
        pacing,
        record: Some(path.clone()),
        body: BodyKind::Simulated,
        regimen,
        isolate_core: false,
        difficulty: None,
        clock: Clock::real(),
    };
    let every_ns = (args.every * 1e9).round() as u64;
    let mut sampler = Sampler {
        every_ns,
        next_ns: 0,
        path: path.clone(),
        samples: Vec::with_capacity((args.duration / args.every) as usize + 16),
        late_ns: 0,
        period_ns: 0,
        past_watchdog: 0,
        watchdog_ns,
    };
    let started = std::time::Instant::now();
    let report = session::run(&opts, &session::Controls::default(), &mut sampler);
    let wall_s = started.elapsed().as_secs_f64();
    let final_bytes = std::fs::metadata(&path).map_or(0, |m| m.len());
    if !args.keep {
        let _ = std::fs::remove_file(&path);
    }
    let report = report?;
    print_table(&sampler.samples, &path, args.keep);
    let v = verdicts(
        &sampler.samples,
        args.warmup,
        sampler.past_watchdog,
        pacing == Pacing::RealTime,
    );
    println!(
        "session {:.0} s at {} in {wall_s:.0} s of wall time, {} ticks, {} records dropped; finished recording {:.1} MB",
        args.duration,
        if pacing == Pacing::Max {
            "--speed max"
        } else {
            "real time"
        },
        report.haptic.ticks,
        report.haptic.dropped_records,
        final_bytes as f64 / 1e6
    );
    for (ok, line) in &v.lines {
        println!("{}  {line}", if *ok { "PASS" } else { "FAIL" });
    }
    anyhow::ensure!(
        v.lines.iter().all(|(ok, _)| *ok),
        "the soak found something growing or late (above)"
    );
    Ok(())
}

/// About 30 rows of the samples, evenly spaced, and the last.
fn print_table(samples: &[Sample], path: &Path, kept: bool) {
    println!("   t (s)   RSS (MiB)   fds   file (MB)   max late (µs)   max period (µs)");
    let step = samples.len().div_ceil(30).max(1);
    for (i, s) in samples.iter().enumerate() {
        if i % step == 0 || i + 1 == samples.len() {
            println!(
                "{:8.0}   {:9.1}   {:3}   {:9.2}   {:13.0}   {:15.0}",
                s.t_s,
                s.rss_kib as f64 / 1024.0,
                s.fds,
                s.file_bytes as f64 / 1e6,
                s.max_late_us,
                s.max_period_us
            );
        }
    }
    if kept {
        println!("recording kept: {}", path.display());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_is_fitted_exactly_and_its_residual_is_the_noise_around_it() {
        let line: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 3.0 + 2.0 * i as f64)).collect();
        let (slope, intercept, rms) = fit(&line);
        assert!((slope - 2.0).abs() < 1e-12 && (intercept - 3.0).abs() < 1e-12 && rms < 1e-12);
        let zigzag: Vec<(f64, f64)> = (0..10)
            .map(|i| (i as f64, if i % 2 == 0 { 1.0 } else { -1.0 }))
            .collect();
        let (_, _, rms) = fit(&zigzag);
        assert!((rms - 1.0).abs() < 0.02, "{rms}");
    }

    fn sample(t_s: f64, rss_mib: u64, fds: u64, mb: f64) -> Sample {
        Sample {
            t_s,
            rss_kib: rss_mib * 1024,
            fds,
            file_bytes: (mb * 1e6) as u64,
            ..Sample::default()
        }
    }

    #[test]
    fn growing_memory_or_descriptors_after_the_warm_up_fail_and_a_flat_run_passes() {
        let flat: Vec<Sample> = (0..100)
            .map(|i| sample(i as f64 * 10.0, if i < 5 { 40 } else { 60 }, 12, i as f64))
            .collect();
        let v = verdicts(&flat, 60.0, 0, true);
        assert!(v.lines.iter().all(|(ok, _)| *ok), "{:?}", v.lines);
        let leaking: Vec<Sample> = (0..100)
            .map(|i| sample(i as f64 * 10.0, 60 + i / 10, 12 + i / 50, i as f64))
            .collect();
        let v = verdicts(&leaking, 60.0, 3, true);
        let failed: Vec<bool> = v.lines.iter().map(|(ok, _)| !ok).collect();
        assert_eq!(failed, [true, true, false, true], "{:?}", v.lines);
    }
}
