//! `telerehab doctor`: is this station ready for a session? One line per check in words a
//! patient or a clinic's support understands, each with what to do when it fails; `--json`
//! prints the same as one object. Exit status 0 ready, 1 not ready, 2 could not check (its
//! home cannot be read).
//!
//! Every check uses what the session itself uses: the wheel scan of `telerehab devices`, the
//! wheel profiles and ceilings, the IMU listing, the renderer's adapter request, the haptic
//! thread's real-time request, the recorder's disk-space figures and the pairing in the home.
//! A check's line and the device-permission check are [`crate::readiness`] (the front door's
//! device check runs that one too).

pub mod pulse;

use std::fmt::Write as _;
use std::io::{ErrorKind, IsTerminal as _};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use anyhow::Context;
use serde::Serialize;

use crate::home::{Home, HomeArg, Pairing};
use crate::link::hub_status::{HubStatus, check_hub};
use crate::readiness::{Check, Status, check, permissions_check};
use session::config::StationConfig;
use session::disk_space;

/// How long the graphics adapter request may take before the check is skipped, s.
const ADAPTER_TIMEOUT_S: u64 = 10;
/// How long connecting to the hub (`--hub`) may take, s.
const HUB_TIMEOUT_S: u64 = 3;
/// A clock further than this from the hub's is a warning, ms.
const CLOCK_WARN_MS: u64 = 5_000;
/// A station certificate expiring within this many days is a warning.
const CERT_WARN_DAYS: i64 = 30;
/// The session length the disk check plans for, s (one hour of recording).
const PLANNED_SESSION_S: f64 = 3600.0;
/// Below room for this long a recording, s, the disk check fails (above it, under an hour, warns).
const SHORTEST_SESSION_S: f64 = 900.0;

/// `telerehab doctor`.
#[derive(Debug, clap::Args)]
pub struct DoctorArgs {
    /// Print one JSON object (`ready`, `checks`: name, status, detail, fix) instead of lines.
    #[arg(long)]
    pub json: bool,
    /// Also try a TLS connection to the paired hub (3 s at most).
    #[arg(long)]
    pub hub: bool,
    /// Also push the wheel gently left then right (a tenth of its torque, 0.3 s each way,
    /// through the session's safety chain) and check that it turns. Asks first that nobody
    /// holds the wheel.
    #[arg(long)]
    pub pulse: bool,
    /// With --pulse: nobody is holding the wheel; do not ask (needed with --json or without a
    /// terminal).
    #[arg(long, requires = "pulse")]
    pub yes_hands_off: bool,
    /// Station configuration (TOML): its `[wheel]` section and patient ceiling decide the
    /// torque ceiling shown.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// The station's home (pairing, recordings).
    #[command(flatten)]
    pub home: HomeArg,
}

/// Everything `doctor` found.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// No check failed and everything could be checked.
    pub ready: bool,
    /// The checks, in the order printed.
    pub checks: Vec<Check>,
    /// Something could not be checked at all (exit status 2).
    #[serde(skip)]
    pub could_not_check: bool,
}

impl Report {
    fn new(checks: Vec<Check>, could_not_check: bool) -> Self {
        let ready = !could_not_check && checks.iter().all(|c| c.status != Status::Fail);
        Self {
            ready,
            checks,
            could_not_check,
        }
    }

    /// The process exit status: 0 ready, 1 not ready, 2 could not check.
    pub fn exit_code(&self) -> u8 {
        match (self.could_not_check, self.ready) {
            (true, _) => 2,
            (false, true) => 0,
            (false, false) => 1,
        }
    }

    /// One line per check, then the verdict.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        for c in &self.checks {
            let _ = write!(s, "{}  {}: {}", c.status.tag(), c.name, c.detail);
            if !c.fix.is_empty() && c.status != Status::Pass {
                let _ = write!(s, " → {}", c.fix);
            }
            s.push('\n');
        }
        let problems = self
            .checks
            .iter()
            .filter(|c| c.status == Status::Fail)
            .count();
        s.push_str(match self.exit_code() {
            0 => "Ready for a session.",
            1 => "Not ready for a session:",
            _ => "Could not check everything:",
        });
        if self.exit_code() != 0 {
            let _ = write!(s, " {problems} problem(s) to fix above.");
        }
        s.push('\n');
        s
    }
}

/// The wheel: found (named, with its profile, force-feedback effects and torque ceiling) or
/// what to plug in.
fn wheel_check(report: &wheel_devices::DeviceReport) -> Check {
    let Some(w) = report.wheels.first() else {
        return check(
            "wheel",
            Status::Fail,
            "no force-feedback wheel found",
            "plug in the wheel and turn it on (most wheels need their own power supply for \
             force feedback), switch it to PC mode if it has one, then run `telerehab doctor` \
             again",
        );
    };
    let mut detail = w.traits.name.clone();
    if let Some((v, p)) = w.usb_id {
        let _ = write!(detail, " [{v:04x}:{p:04x}]");
    }
    let _ = write!(
        detail,
        "; force feedback: {} (up to {} effects)",
        w.traits.ff_effects.join(", "),
        w.max_ff_effects
    );
    if let Some(p) = &w.profile {
        let _ = write!(detail, "; profile: {}", p.name);
    }
    let assumed = w.ceiling.as_ref().is_some_and(|c| c.assumed);
    if let Some(c) = &w.ceiling {
        let _ = write!(
            detail,
            "; torque ceiling {:.1} N·m (motor {:.1} N·m{})",
            c.ceiling_nm,
            c.motor_nm,
            if c.assumed { ", assumed" } else { "" }
        );
    }
    if report.wheels.len() > 1 {
        let _ = write!(
            detail,
            "; {} wheels connected, the first is used",
            report.wheels.len()
        );
    }
    if assumed {
        let fix = "this wheel has no built-in profile: its torque is capped low until the clinic \
                   enters its rated torque (`[wheel] rated_torque_nm` in the station's \
                   configuration) or measures it with `telerehab wheel calibrate`";
        return check(
            "wheel",
            Status::Warn,
            format!("unknown wheel: {detail}"),
            fix,
        );
    }
    check("wheel", Status::Pass, detail, "")
}

/// Whether the patient confirms nobody holds the wheel: `--yes-hands-off`, or "y" typed at
/// the prompt (never asked with `--json` or without a terminal). `Err`: why not asked.
fn hands_off(args: &DoctorArgs) -> Result<bool, &'static str> {
    if args.yes_hands_off {
        return Ok(true);
    }
    if args.json || !std::io::stdin().is_terminal() {
        return Err(
            "not asked without a terminal or with --json: add --yes-hands-off once \
                    nobody holds the wheel",
        );
    }
    eprint!("Test pulse: take your hands off the wheel. Is nobody touching it? [y/N] ");
    let mut answer = String::new();
    let _ = std::io::stdin().read_line(&mut answer);
    Ok(matches!(answer.trim(), "y" | "Y" | "yes" | "Yes"))
}

/// Words for a pulse's outcome.
pub fn pulse_check_for(outcome: &pulse::PulseOutcome, plan: &pulse::PulsePlan) -> Check {
    let detail = format!(
        "{:.2} N·m for {:.1} s each way: turned {:.1}° left, {:.1}° right (largest torque sent \
         {:.2} N·m)",
        plan.torque_nm,
        plan.each_s,
        -outcome.left_rad.to_degrees(),
        outcome.right_rad.to_degrees(),
        outcome.peak_nm
    );
    if outcome.moved() {
        return check("test pulse", Status::Pass, detail, "");
    }
    check(
        "test pulse",
        Status::Fail,
        format!("the wheel did not turn: {detail}"),
        "check the wheel's power supply (force feedback needs it), that nothing blocks the \
         wheel, and that nobody holds it; then run `telerehab doctor --pulse` again",
    )
}

/// The test pulse (`--pulse`), after the patient confirms hands off.
fn pulse_check(args: &DoctorArgs, cfg: &StationConfig, wheel_found: bool) -> Check {
    if !wheel_found {
        return check("test pulse", Status::Skip, "no wheel to pulse", "");
    }
    match hands_off(args) {
        Err(why) => return check("test pulse", Status::Skip, why, ""),
        Ok(false) => {
            return check("test pulse", Status::Skip, "not confirmed hands off", "");
        }
        Ok(true) => {}
    }
    match run_real_pulse(cfg) {
        Ok((plan, outcome)) => pulse_check_for(&outcome, &plan),
        Err(e) => check(
            "test pulse",
            Status::Fail,
            format!("{e:#}"),
            "check the device permissions above",
        ),
    }
}

#[cfg(target_os = "linux")]
fn run_real_pulse(cfg: &StationConfig) -> anyhow::Result<(pulse::PulsePlan, pulse::PulseOutcome)> {
    use haptic_wheel::Wheel as _;
    use wheel_devices::evdev_wheel::EvdevWheel;
    let clock = clock::Clock::real();
    let mut wheel = EvdevWheel::open_first(cfg.wheel.clone(), clock.clone())
        .context("cannot open the wheel")?;
    let safety = cfg.haptic.safety;
    let ceiling_nm = safety.effective_ceiling_nm(wheel.max_torque_nm());
    let plan = pulse::PulsePlan::for_wheel(&wheel.profile(), ceiling_nm, &safety);
    let outcome = pulse::run_pulse(&mut wheel, &plan, safety, |_| {
        std::thread::sleep(Duration::from_secs_f64(pulse::TICK_S));
        clock.now_ns()
    })?;
    Ok((plan, outcome))
}

#[cfg(not(target_os = "linux"))]
fn run_real_pulse(_: &StationConfig) -> anyhow::Result<(pulse::PulsePlan, pulse::PulseOutcome)> {
    anyhow::bail!("pulsing a wheel needs the Linux kernel force-feedback API")
}

/// How long each arm sensor's samples are counted, s.
const IMU_LISTEN_S: f64 = 1.0;
/// Below this share of its nominal rate an arm sensor fails the check.
const IMU_RATE_FLOOR: f64 = 0.5;

/// The rate a controller's IMU reports at, samples/s: Sony's 250 Hz reports (more over
/// Bluetooth), Nintendo's three samples in each of 66.7 reports a second.
pub fn nominal_imu_rate_hz(kind: gyro_imu::device::ImuKind) -> f64 {
    use gyro_imu::device::ImuKind;
    match kind {
        ImuKind::DualShock4 | ImuKind::DualSense => 250.0,
        _ => 200.0,
    }
}

/// One arm sensor's measured rate against its nominal one.
pub fn imu_rate_check_for(name: &str, measured_hz: f64, nominal_hz: f64) -> Check {
    let detail = format!("{name}: {measured_hz:.0} samples/s (nominal {nominal_hz:.0})");
    if measured_hz >= IMU_RATE_FLOOR * nominal_hz {
        return check("arm sensor rate", Status::Pass, detail, "");
    }
    check(
        "arm sensor rate",
        Status::Fail,
        format!("{detail}: too slow to follow the arm"),
        "charge the controller, bring it closer to the computer (Bluetooth) or plug it in with \
         its USB cable, and close other programs that read it",
    )
}

/// Counts `info`'s samples for [`IMU_LISTEN_S`], samples/s.
fn measure_imu_rate_hz(info: &gyro_imu::device::ImuDeviceInfo) -> anyhow::Result<f64> {
    use gyro_imu::device::Imu as _;
    let (mut imu, _) = gyro_imu::device::hid::HidImu::open(info, clock::monotonic_ns)
        .map_err(|e| anyhow::anyhow!("cannot open {}: {e}", info.name))?;
    let mut buf = [gyro_imu::device::ImuSample {
        t_ns: 0,
        rate_rad_s: Default::default(),
        acc_m_s2: None,
    }; 64];
    // Reports queued before the open are not counted: from the first poll on.
    let _ = imu.poll(&mut buf);
    let start = std::time::Instant::now();
    let mut n = 0usize;
    while start.elapsed().as_secs_f64() < IMU_LISTEN_S {
        n += imu
            .poll(&mut buf)
            .map_err(|e| anyhow::anyhow!("{}: {e}", info.name))?;
        std::thread::sleep(Duration::from_millis(2));
    }
    Ok(n as f64 / start.elapsed().as_secs_f64())
}

/// Arm sensors (controller IMUs): optional, a session runs without arm sensing. Each one
/// found is listened to for a second and its sample rate reported.
fn imu_checks() -> Vec<Check> {
    let fix = "pair or plug in the arm sensor (DualShock 4, DualSense, Joy-Con or Pro \
               Controller) and check the device permissions above";
    let list = match gyro_imu::device::enumerate() {
        Ok(list) if list.is_empty() => {
            return vec![check(
                "arm sensors",
                Status::Warn,
                "no arm sensor found: sessions run without arm sensing",
                fix,
            )];
        }
        Ok(list) => list,
        Err(e) => {
            return vec![check(
                "arm sensors",
                Status::Warn,
                format!("cannot list HID devices ({e}): sessions run without arm sensing"),
                fix,
            )];
        }
    };
    let names: Vec<String> = list
        .iter()
        .map(|d| {
            let bt = if d.bluetooth { ", Bluetooth" } else { "" };
            format!("{} ({:?}{bt})", d.name, d.kind)
        })
        .collect();
    let mut checks = vec![check("arm sensors", Status::Pass, names.join(", "), "")];
    for info in list.iter().take(2) {
        checks.push(match measure_imu_rate_hz(info) {
            Ok(hz) => imu_rate_check_for(&info.name, hz, nominal_imu_rate_hz(info.kind)),
            Err(e) => check(
                "arm sensor rate",
                Status::Fail,
                format!("{e:#}"),
                "check the device permissions above",
            ),
        });
    }
    checks
}

/// The graphics adapter the patient's window would get; software rendering named.
fn graphics_check() -> Check {
    let (tx, rx) = mpsc::channel();
    let spawned = std::thread::Builder::new()
        .name("doctor-adapter".into())
        .spawn(move || {
            let _ = tx.send(render::probe_adapter());
        });
    if let Err(e) = spawned {
        return check(
            "graphics",
            Status::Skip,
            format!("cannot start the adapter probe: {e}"),
            "",
        );
    }
    match rx.recv_timeout(Duration::from_secs(ADAPTER_TIMEOUT_S)) {
        Ok(Ok(a)) if a.device_type == "Cpu" => check(
            "graphics",
            Status::Warn,
            format!("software rendering only: {a}; the window draws slowly"),
            "install the graphics card's driver (Mesa's radeonsi/iris or the vendor's) for \
             smoother pictures; sessions run as they are",
        ),
        Ok(Ok(a)) => check("graphics", Status::Pass, a.to_string(), ""),
        Ok(Err(e)) => check(
            "graphics",
            Status::Fail,
            e.to_string(),
            "install Mesa's drivers (`mesa-vulkan-drivers` or `libgl1-mesa-dri`)",
        ),
        Err(_) => check(
            "graphics",
            Status::Skip,
            format!("the graphics driver did not answer within {ADAPTER_TIMEOUT_S} s"),
            "",
        ),
    }
}

/// Whether the haptic thread would get real-time scheduling, asked from a throwaway thread:
/// SCHED_FIFO on Linux, the Multimedia Class Scheduler (MMCSS) on Windows.
fn realtime_check() -> Check {
    let granted = std::thread::Builder::new()
        .name("doctor-rt".into())
        .spawn(|| {
            if session::haptic::request_realtime_priority() {
                return Some("SCHED_FIFO");
            }
            clock::Clock::real().real_time_thread(true).mmcss_task()
        })
        .ok()
        .and_then(|t| t.join().ok())
        .flatten();
    if let Some(how) = granted {
        return check(
            "real-time scheduling",
            Status::Pass,
            format!("granted ({how})"),
            "",
        );
    }
    let fix = if cfg!(windows) {
        "check that the Multimedia Class Scheduler service (MMCSS) runs: Windows \
         services, \"Multimedia Class Scheduler\""
    } else {
        "allow this user real-time priority (e.g. `@audio - rtprio 95` in \
         /etc/security/limits.d/ and the user in the `audio` group, then log in again)"
    };
    check(
        "real-time scheduling",
        Status::Warn,
        "not granted: the wheel's force loop runs at normal priority, with more jitter",
        fix,
    )
}

/// The nearest existing directory at or above `dir` (the home may not exist yet).
fn existing_ancestor(dir: &Path) -> &Path {
    dir.ancestors()
        .find(|a| a.is_dir())
        .unwrap_or_else(|| Path::new("/"))
}

/// Room for a session's recording given `free_bytes` on the home's filesystem.
pub fn disk_check_for(free_bytes: u64, where_: &Path) -> Check {
    let mb = |n: u64| format!("{:.0} MB", n as f64 / 1e6);
    let hour = disk_space::needed_bytes(PLANNED_SESSION_S);
    let minutes = free_bytes.saturating_sub(disk_space::RESERVE_BYTES) as f64
        / disk_space::RECORDING_BYTES_PER_S as f64
        / 60.0;
    let detail = format!(
        "{} free at {} (room for {minutes:.0} min of recording; an hour needs {})",
        mb(free_bytes),
        where_.display(),
        mb(hour)
    );
    let fix = "free some disk space (old recordings already sent to the clinic can go)";
    if free_bytes >= hour {
        check("disk space", Status::Pass, detail, "")
    } else if free_bytes >= disk_space::needed_bytes(SHORTEST_SESSION_S) {
        check("disk space", Status::Warn, detail, fix)
    } else {
        check("disk space", Status::Fail, detail, fix)
    }
}

fn disk_check(home: &Home) -> Check {
    let at = existing_ancestor(home.dir());
    match disk_space::free_bytes(at) {
        Ok(free) => disk_check_for(free, at),
        Err(e) => check(
            "disk space",
            Status::Skip,
            format!("cannot measure free space at {}: {e}", at.display()),
            "",
        ),
    }
}

/// Days from `now_unix_s` until the PEM certificate's expiry.
pub fn days_left(cert_pem: &str, now_unix_s: i64) -> anyhow::Result<i64> {
    let der = netlink::pki::first_certificate_der(cert_pem)?;
    let (_, cert) = x509_parser::parse_x509_certificate(&der)
        .map_err(|e| anyhow::anyhow!("not a readable certificate: {e}"))?;
    Ok((cert.validity().not_after.timestamp() - now_unix_s).div_euclid(86_400))
}

/// The station certificate's expiry, given the days left.
pub fn certificate_check_for(days: i64, pairing: &Pairing) -> Check {
    let who = format!(
        "paired with {} as station {} (patient {})",
        pairing.hub, pairing.station_id, pairing.patient_id
    );
    let renew = "ask the clinic for a new pairing code, then `telerehab pair`";
    if days < 0 {
        return check(
            "clinic pairing",
            Status::Fail,
            format!("{who}; its certificate expired {} day(s) ago", -days),
            renew,
        );
    }
    if days < CERT_WARN_DAYS {
        return check(
            "clinic pairing",
            Status::Warn,
            format!("{who}; its certificate expires in {days} day(s)"),
            renew,
        );
    }
    check(
        "clinic pairing",
        Status::Pass,
        format!("{who}; certificate valid for {days} more days"),
        "",
    )
}

fn pairing_check(home: &Home, pairing: Option<&Pairing>) -> Check {
    let Some(p) = pairing else {
        return check(
            "clinic pairing",
            Status::Warn,
            "not paired: sessions are not sent to a clinic",
            "ask the clinic for a code, then `telerehab pair`",
        );
    };
    let now_s = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64);
    let cert_path = home.client_tls(p).identity.map(|i| i.cert_pem_path);
    let days = cert_path
        .as_deref()
        .context("no station certificate")
        .and_then(|path| {
            let pem = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            days_left(&pem, now_s)
        });
    match days {
        Ok(d) => certificate_check_for(d, p),
        Err(e) => check(
            "clinic pairing",
            Status::Fail,
            format!("paired with {}, but the station certificate: {e:#}", p.hub),
            "ask the clinic for a new pairing code, then `telerehab pair`",
        ),
    }
}

/// The paired hub's answer (only with `--hub`): `None` when not paired or not asked.
fn ask_hub(home: &Home, pairing: Option<&Pairing>, try_hub: bool) -> Option<HubStatus> {
    let p = pairing.filter(|_| try_hub)?;
    Some(check_hub(home, p, Duration::from_secs(HUB_TIMEOUT_S)))
}

/// The hub: reachable, or why not (not paired, not asked for, unreachable, refusing).
pub fn hub_check_for(pairing: Option<&Pairing>, status: Option<&HubStatus>) -> Check {
    let Some(p) = pairing else {
        return check("hub", Status::Skip, "not paired: no hub to reach", "");
    };
    let fix = "check the internet connection; sessions still run and are sent later \
               (`telerehab sync`)";
    match status {
        None => check(
            "hub",
            Status::Skip,
            format!("not tried (add --hub to connect to {})", p.hub),
            "",
        ),
        Some(HubStatus::Reachable { .. }) => {
            check("hub", Status::Pass, format!("{} answers (TLS)", p.hub), "")
        }
        // The hub answered: the versions line says what to do.
        Some(HubStatus::UpdateRequired(_)) => check(
            "hub",
            Status::Pass,
            format!("{} answers (TLS), but refuses this version", p.hub),
            "",
        ),
        Some(HubStatus::Unreachable(why)) => check(
            "hub",
            Status::Warn,
            format!("cannot reach the hub: {why}"),
            fix,
        ),
    }
}

/// The clock difference from the hub, when it told its time.
pub fn clock_check_for(status: Option<&HubStatus>) -> Option<Check> {
    let Some(HubStatus::Reachable { clock_offset_ms }) = status else {
        return None;
    };
    let Some(offset_ms) = *clock_offset_ms else {
        return Some(check(
            "clock",
            Status::Skip,
            "the hub does not tell its time (older hub)",
            "",
        ));
    };
    let ahead = if offset_ms >= 0 { "ahead of" } else { "behind" };
    let detail = format!(
        "the hub's clock is {:.1} s {ahead} this station's",
        offset_ms.unsigned_abs() as f64 / 1000.0
    );
    if offset_ms.unsigned_abs() <= CLOCK_WARN_MS {
        Some(check("clock", Status::Pass, detail, ""))
    } else {
        Some(check(
            "clock",
            Status::Warn,
            detail,
            "turn on automatic time (`timedatectl set-ntp true`) so session times at the clinic \
             are right",
        ))
    }
}

/// This station's version, and whether the hub serves it (when asked).
pub fn versions_check_for(status: Option<&HubStatus>) -> Check {
    let ours = format!("telerehab {}", crate::version::version());
    match status {
        Some(HubStatus::UpdateRequired(message)) => check(
            "versions",
            Status::Fail,
            format!("{message} ({ours})"),
            "install the newest telerehab package; sessions still run and are recorded here \
             meanwhile",
        ),
        Some(HubStatus::Reachable { .. }) => check(
            "versions",
            Status::Pass,
            format!("{ours}; the hub serves it"),
            "",
        ),
        _ => check("versions", Status::Pass, ours, ""),
    }
}

/// Whether the home can be looked at: missing is fine (a station never run), anything else
/// that stops reading it is the reason.
fn home_problem(home: &Home) -> Option<String> {
    let dir = home.dir();
    match std::fs::read_dir(dir) {
        Ok(_) => None,
        Err(e) if e.kind() == ErrorKind::NotFound => None,
        Err(e) => Some(format!(
            "cannot read the station's home {}: {e}",
            dir.display()
        )),
    }
}

/// Run every check.
pub fn examine(args: &DoctorArgs) -> Report {
    let cfg = match &args.config {
        Some(p) => StationConfig::load(p).map_err(|e| format!("{e:#}")),
        None => Ok(StationConfig::default()),
    };
    let mut devices = wheel_devices::enumerate_devices();
    let mut checks = Vec::new();
    match &cfg {
        Ok(cfg) => devices.apply_config(&cfg.wheel, cfg.haptic.safety.ceiling_nm),
        Err(e) => checks.push(check(
            "configuration",
            Status::Fail,
            e.clone(),
            "correct the station configuration file",
        )),
    }
    checks.push(wheel_check(&devices));
    if args.pulse {
        // The patient's ceiling comes from the configuration: none readable, no pulse.
        checks.push(match &cfg {
            Ok(cfg) => pulse_check(args, cfg, !devices.wheels.is_empty()),
            Err(_) => check(
                "test pulse",
                Status::Skip,
                "not pulsed: the configuration (the patient's torque ceiling) is unreadable",
                "",
            ),
        });
    }
    checks.push(permissions_check(&devices));
    checks.extend(imu_checks());
    checks.push(graphics_check());
    checks.push(realtime_check());
    let home = Home::resolve(&args.home).map_err(|e| format!("{e:#}"));
    let home = home.and_then(|h| match home_problem(&h) {
        Some(p) => Err(p),
        None => Ok(h),
    });
    let home_fix = "give --home (or TELEREHAB_HOME) a directory this user can read and write";
    let mut could_not_check = false;
    let mut hub = None;
    match home {
        Ok(home) => {
            checks.push(disk_check(&home));
            match home.pairing() {
                Ok(pairing) => {
                    checks.push(pairing_check(&home, pairing.as_ref()));
                    hub = ask_hub(&home, pairing.as_ref(), args.hub);
                    checks.push(hub_check_for(pairing.as_ref(), hub.as_ref()));
                    checks.extend(clock_check_for(hub.as_ref()));
                }
                Err(e) => checks.push(check(
                    "clinic pairing",
                    Status::Fail,
                    format!("{e:#}"),
                    "ask the clinic for a new pairing code, then `telerehab pair`",
                )),
            }
        }
        Err(e) => {
            could_not_check = true;
            checks.push(check("station home", Status::Fail, e, home_fix));
        }
    }
    checks.push(versions_check_for(hub.as_ref()));
    Report::new(checks, could_not_check)
}

/// Print the report and exit with its status (0 ready, 1 not ready, 2 could not check).
pub fn run(args: &DoctorArgs) -> anyhow::Result<()> {
    let report = examine(args);
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        print!("{}", report.to_text());
    }
    use std::io::Write as _;
    std::io::stdout().flush()?;
    std::process::exit(i32::from(report.exit_code()));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::readiness::tests::found_wheel;

    fn pairing() -> Pairing {
        Pairing {
            hub: "127.0.0.1:7000".into(),
            server_name: "hub.clinic".into(),
            station_id: "st-1".into(),
            patient_id: "p-0042".into(),
            paired_unix_ms: 0,
            patient_pseudonym: None,
        }
    }

    #[test]
    fn doctor_exit_code_is_0_ready_1_on_a_failure_2_when_it_could_not_check() {
        let pass = check("a", Status::Pass, "", "");
        let warn = check("b", Status::Warn, "", "x");
        let fail = check("c", Status::Fail, "", "y");
        assert_eq!(
            Report::new(vec![pass.clone(), warn.clone()], false).exit_code(),
            0
        );
        assert_eq!(Report::new(vec![pass.clone(), fail], false).exit_code(), 1);
        let r = Report::new(vec![pass], true);
        assert_eq!((r.exit_code(), r.ready), (2, false));
    }

    #[test]
    fn doctor_text_has_one_line_per_check_and_the_fix_of_each_problem() {
        let r = Report::new(
            vec![
                check("wheel", Status::Fail, "none", "plug it in"),
                check("versions", Status::Pass, "1.0", "ignored"),
            ],
            false,
        );
        let text = r.to_text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3, "{text}");
        assert_eq!(lines[0], "FAIL  wheel: none → plug it in");
        assert_eq!(lines[1], "PASS  versions: 1.0");
        assert!(lines[2].starts_with("Not ready"), "{text}");
    }

    #[test]
    fn doctor_disk_check_passes_an_hour_warns_a_quarter_hour_and_fails_less() {
        let at = Path::new("/home");
        let hour = disk_space::needed_bytes(PLANNED_SESSION_S);
        let quarter = disk_space::needed_bytes(SHORTEST_SESSION_S);
        assert_eq!(disk_check_for(hour, at).status, Status::Pass);
        assert_eq!(disk_check_for(hour - 1, at).status, Status::Warn);
        assert_eq!(disk_check_for(quarter, at).status, Status::Warn);
        assert_eq!(disk_check_for(quarter - 1, at).status, Status::Fail);
        assert!(disk_check_for(hour, at).detail.contains("60 min"));
    }

    #[test]
    fn doctor_reads_the_station_certificate_expiry_and_warns_under_30_days() {
        let (clock, _mock) = clock::Clock::mock();
        let ca = netlink::pki::ClinicCa::create_with_clock("Clinic", clock).unwrap();
        let cert = ca.issue_server(&["hub.clinic".into()]).unwrap();
        let days = days_left(&cert.cert_pem, 0).unwrap();
        assert!(days > CERT_WARN_DAYS, "{days}");
        let expiry_s = days * 86_400;
        let near = days_left(&cert.cert_pem, expiry_s - 10 * 86_400).unwrap();
        assert!((9..=10).contains(&near), "{near}");
        let p = pairing();
        assert_eq!(certificate_check_for(days, &p).status, Status::Pass);
        assert_eq!(certificate_check_for(near, &p).status, Status::Warn);
        assert_eq!(certificate_check_for(-1, &p).status, Status::Fail);
    }

    #[test]
    fn doctor_names_a_missing_wheel_as_a_failure_with_what_to_plug_in() {
        let c = wheel_check(&wheel_devices::DeviceReport::default());
        assert_eq!(c.status, Status::Fail);
        assert!(
            c.fix.contains("plug in the wheel and turn it on"),
            "{}",
            c.fix
        );
    }

    #[test]
    fn doctor_names_a_known_wheel_with_its_effects_and_ceiling_and_an_unknown_one_as_such() {
        let g29 = wheel_check(&found_wheel("Some Wheel", (0x046d, 0xc24f)));
        assert_eq!(g29.status, Status::Pass, "{g29:?}");
        assert!(
            g29.detail.contains("Some Wheel [046d:c24f]"),
            "{}",
            g29.detail
        );
        assert!(
            g29.detail.contains("force feedback: constant, gain"),
            "{}",
            g29.detail
        );
        assert!(g29.detail.contains("N·m"), "{}", g29.detail);
        let odd = wheel_check(&found_wheel("Some Wheel", (0x1234, 0x5678)));
        assert_eq!(odd.status, Status::Warn, "{odd:?}");
        assert!(odd.detail.starts_with("unknown wheel: "), "{}", odd.detail);
        assert!(odd.detail.contains("assumed"), "{}", odd.detail);
        assert!(odd.fix.contains("rated_torque_nm"), "{}", odd.fix);
    }

    #[test]
    fn doctor_fails_versions_with_the_hubs_update_required_words_and_still_reaches_the_hub() {
        let words = "update required: this station speaks link protocol 1, the hub needs ≥ 2 — \
                     install the newest telerehab package";
        let refused = HubStatus::UpdateRequired(words.into());
        let v = versions_check_for(Some(&refused));
        assert_eq!(v.status, Status::Fail);
        assert!(v.detail.starts_with(words), "{}", v.detail);
        let h = hub_check_for(Some(&pairing()), Some(&refused));
        assert_eq!(h.status, Status::Pass, "{h:?}");
        assert_eq!(clock_check_for(Some(&refused)), None);
    }

    #[test]
    fn doctor_warns_of_a_clock_more_than_5_s_from_the_hubs_and_names_the_direction() {
        let at = |ms| HubStatus::Reachable {
            clock_offset_ms: Some(ms),
        };
        let near = clock_check_for(Some(&at(-1_200))).unwrap();
        assert_eq!(near.status, Status::Pass);
        assert!(near.detail.contains("1.2 s behind"), "{}", near.detail);
        let far = clock_check_for(Some(&at(90_000))).unwrap();
        assert_eq!(far.status, Status::Warn);
        assert!(far.detail.contains("90.0 s ahead of"), "{}", far.detail);
        let old_hub = HubStatus::Reachable {
            clock_offset_ms: None,
        };
        assert_eq!(
            clock_check_for(Some(&old_hub)).unwrap().status,
            Status::Skip
        );
        let gone = HubStatus::Unreachable("no answer".into());
        assert_eq!(
            hub_check_for(Some(&pairing()), Some(&gone)).status,
            Status::Warn
        );
        assert_eq!(versions_check_for(Some(&gone)).status, Status::Pass);
    }

    #[test]
    fn doctor_fails_an_arm_sensor_under_half_its_nominal_rate() {
        use gyro_imu::device::ImuKind;
        let ds4 = nominal_imu_rate_hz(ImuKind::DualShock4);
        let ok = imu_rate_check_for("DualShock 4", 0.9 * ds4, ds4);
        assert_eq!(ok.status, Status::Pass, "{ok:?}");
        assert!(ok.detail.contains("samples/s"), "{}", ok.detail);
        let slow = imu_rate_check_for(
            "Joy-Con (R)",
            60.0,
            nominal_imu_rate_hz(ImuKind::JoyConRight),
        );
        assert_eq!(slow.status, Status::Fail, "{slow:?}");
    }

    #[test]
    fn doctor_passes_a_pulse_that_turned_the_wheel_both_ways_and_fails_one_that_did_not() {
        let plan = pulse::PulsePlan {
            torque_nm: 0.23,
            settle_s: 1.1,
            each_s: 0.3,
        };
        let turned = pulse::PulseOutcome {
            left_rad: -0.2,
            right_rad: 0.3,
            peak_nm: 0.23,
        };
        let c = pulse_check_for(&turned, &plan);
        assert_eq!(c.status, Status::Pass, "{c:?}");
        assert!(c.detail.contains("11.5° left"), "{}", c.detail);
        let stuck = pulse::PulseOutcome {
            left_rad: 0.0,
            right_rad: 0.0,
            peak_nm: 0.23,
        };
        let c = pulse_check_for(&stuck, &plan);
        assert_eq!(c.status, Status::Fail, "{c:?}");
        assert!(c.fix.contains("power supply"), "{}", c.fix);
    }

    #[test]
    fn doctor_never_pulses_with_json_unless_told_hands_off_and_never_without_a_wheel() {
        let mut args = DoctorArgs {
            json: true,
            hub: false,
            pulse: true,
            yes_hands_off: false,
            config: None,
            home: HomeArg::default(),
        };
        let refused = hands_off(&args).unwrap_err();
        assert!(refused.contains("--yes-hands-off"), "{refused}");
        args.yes_hands_off = true;
        assert_eq!(hands_off(&args), Ok(true));
        let c = pulse_check(&args, &StationConfig::default(), false);
        assert_eq!(
            (c.status, c.detail.as_str()),
            (Status::Skip, "no wheel to pulse")
        );
    }
}
