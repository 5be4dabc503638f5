//! Helpers for the end-to-end tests: locate the `telerehab` binary, run it, read its MCAP files.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

pub mod balancer;
pub mod clinic;
pub mod console;
pub mod logged;
pub mod netns;
pub mod windowed;

/// Path of the `telerehab` binary under test: `$TELEREHAB_BIN` if set, else the one in this
/// target directory, (re)built once per test process with cargo so it is never stale.
pub fn telerehab_bin() -> PathBuf {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        if let Ok(p) = std::env::var("TELEREHAB_BIN") {
            return PathBuf::from(p);
        }
        let exe = std::env::current_exe().expect("test executable path");
        let dir = exe
            .parent()
            .and_then(|d| d.parent())
            .expect("target profile directory");
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let status = Command::new(cargo)
            .args(["build", "--quiet", "-p", "telerehab"])
            .status()
            .expect("run cargo build");
        assert!(status.success(), "cargo build of telerehab failed");
        dir.join(format!("telerehab{}", std::env::consts::EXE_SUFFIX))
    })
    .clone()
}

/// Run `telerehab` with `args`, panicking with its output if it fails.
pub fn run_ok(args: &[&str]) -> Output {
    let out = Command::new(telerehab_bin())
        .args(args)
        .output()
        .expect("run telerehab");
    assert!(
        out.status.success(),
        "telerehab {args:?} failed: {}\nstdout:\n{}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Run `telerehab` with `args`, expecting it to fail; returns its standard error.
pub fn run_err(args: &[&str]) -> String {
    let out = Command::new(telerehab_bin())
        .args(args)
        .output()
        .expect("run telerehab");
    assert!(
        !out.status.success(),
        "telerehab {args:?} should have failed"
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The arguments of a simulated headless session run as fast as possible for `seconds` of
/// exercise and recorded to `mcap`, then `extra` (`--seed`, `--exercise`, …).
pub fn sim_session_args<'a>(seconds: &'a str, mcap: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "run",
        "--sim",
        "--headless",
        "--speed",
        "max",
        "--duration",
        seconds,
        "--record",
        mcap.to_str().expect("utf-8 path"),
    ];
    args.extend_from_slice(extra);
    args
}

/// Start a 60 s real-time simulated session recording to `mcap`, output piped (tests stop it
/// early with a signal).
pub fn spawn_recording_session(mcap: &Path) -> std::process::Child {
    spawn_real_time_session("60", |c| c.arg("--record").arg(mcap))
}

/// Start a real-time simulated headless session of `seconds` (seed 7), output piped, set up
/// further by `with` (where it records, its home).
pub fn spawn_real_time_session(
    seconds: &str,
    with: impl FnOnce(&mut Command) -> &mut Command,
) -> std::process::Child {
    let mut cmd = Command::new(telerehab_bin());
    cmd.args([
        "run",
        "--sim",
        "--headless",
        "--duration",
        seconds,
        "--seed",
        "7",
    ])
    .stdout(std::process::Stdio::piped())
    .stderr(std::process::Stdio::piped());
    with(&mut cmd).spawn().expect("start telerehab")
}

/// Wait (up to 20 s) until the recording at `path` holds at least one closed chunk (the
/// recorder closes one every 1000 ticks), so a test's signal lands mid-session whatever the
/// machine's load.
pub fn wait_for_first_chunk(path: &Path) {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
    // 300 kB: past the first closed chunk (150–220 kB each at 1 kHz), so ≥ 1000 ticks are safe.
    while std::fs::metadata(path).map(|m| m.len()).unwrap_or(0) < 300_000 {
        assert!(
            std::time::Instant::now() < deadline,
            "no chunk in {} after 20 s",
            path.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

/// A real-time recording session to `path` (as [`spawn_recording_session`]) interrupted by
/// SIGINT 300 ms after its first chunk reached the disk; its output.
pub fn interrupted_recording_session(path: &Path) -> Output {
    let child = spawn_recording_session(path);
    wait_for_first_chunk(path);
    std::thread::sleep(std::time::Duration::from_millis(300));
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    child.wait_with_output().unwrap()
}

/// The recorded torque is a whole number of µN·m: the bounds allow that much rounding, N·m.
pub const RECORDED_NM: f64 = 1e-6;

/// Every tick of a recording: |commanded torque| ≤ that tick's ceiling, and no step between
/// two ticks larger than the slew limit `slew_nm_per_s` allows over the loop period `dt_s`
/// (the tick `gap.0` coming `gap.1` s late: a stalled loop, the limit holds over the real
/// time between two commands). Torques in N·m at the motor.
pub fn assert_within_ceiling_and_slew(
    commanded_nm: &[f64],
    ceiling_nm: &[f64],
    slew_nm_per_s: f64,
    dt_s: f64,
    gap: Option<(usize, f64)>,
) {
    assert_eq!(commanded_nm.len(), ceiling_nm.len());
    for (i, (&c, &lim)) in commanded_nm.iter().zip(ceiling_nm).enumerate() {
        assert!(
            c.is_finite() && c.abs() <= lim + RECORDED_NM,
            "tick {i}: {c} N·m over {lim}"
        );
    }
    for (i, w) in commanded_nm.windows(2).enumerate() {
        let late_s = gap.filter(|g| g.0 == i + 1).map_or(0.0, |g| g.1);
        let step = slew_nm_per_s * (dt_s + late_s) + 2.0 * RECORDED_NM;
        assert!(
            (w[1] - w[0]).abs() <= step,
            "tick {i}: {} → {} N·m",
            w[0],
            w[1]
        );
    }
}

/// [`assert_within_ceiling_and_slew`] over every `/wheel` tick of `rec`, with the slew limit
/// and loop period of the configuration it was recorded with.
pub fn assert_recording_within_ceiling_and_slew(rec: &record::Recording) {
    let cfg = session::config::StationConfig::from_toml(&rec.metadata.config_toml, "the recording")
        .expect("the recording's configuration");
    let commanded: Vec<f64> = rec.wheel.iter().map(|w| w.data.commanded_nm).collect();
    let ceilings: Vec<f64> = rec.wheel.iter().map(|w| w.data.ceiling_nm).collect();
    assert_within_ceiling_and_slew(
        &commanded,
        &ceilings,
        cfg.haptic.safety.slew_nm_per_s,
        1.0 / cfg.session.loop_rate_hz,
        None,
    );
}

/// One recorded sample: a JSON message, or one sample of a high-rate channel's block.
#[derive(Clone, Debug, PartialEq)]
pub struct Msg {
    /// Channel topic.
    pub topic: String,
    /// The sample's fields (`tick`, `t_s`, then its own).
    pub json: serde_json::Value,
}

/// Every sample of our channels in an MCAP file, read by the recording crate
/// ([`record::recorded_rows`]: JSON messages as they are, blocks unpacked with the layout their
/// channel declares; the Foxglove scene skipped), channel by channel, each in file order.
pub fn read_mcap(path: &Path) -> Vec<Msg> {
    let bytes = std::fs::read(path).expect("read mcap");
    let (_, rows) = record::recorded_rows(&bytes).expect("a readable recording");
    rows.into_iter()
        .flat_map(|(channel, rows)| {
            rows.into_iter().map(move |row| Msg {
                topic: channel.topic().to_owned(),
                json: serde_json::Value::Object(row),
            })
        })
        .collect()
}

/// Messages per topic.
pub fn by_topic(msgs: &[Msg]) -> BTreeMap<String, Vec<Msg>> {
    let mut map: BTreeMap<String, Vec<Msg>> = BTreeMap::new();
    for m in msgs {
        map.entry(m.topic.clone()).or_default().push(m.clone());
    }
    map
}

/// A small tmpfs mounted for one test, unmounted when dropped.
pub struct Tmpfs {
    dir: tempfile::TempDir,
}

impl Tmpfs {
    /// Mount `mib` MiB of tmpfs; `None`, having said SKIPPED and why, where it cannot be.
    pub fn mount_or_skip(mib: u64) -> Option<Self> {
        Self::mount(mib)
            .inspect_err(|why| println!("SKIPPED: {why}"))
            .ok()
    }

    /// Mount `mib` MiB of tmpfs, or say why not.
    fn mount(mib: u64) -> Result<Self, String> {
        let dir = tempfile::tempdir().unwrap();
        let out = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={mib}m"), "tmpfs"])
            .arg(dir.path())
            .output()
            .map_err(|e| format!("cannot run mount: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "cannot mount a tmpfs: {}",
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
        Ok(Self { dir })
    }

    /// Where it is mounted.
    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Something else fills the disk to 8 MB under the free space the recorder keeps
    /// ([`session::disk_space::RESERVE_BYTES`]).
    pub fn fill_under_the_reserve(&self) {
        let free = session::disk_space::free_bytes(self.path()).unwrap();
        let reserve = session::disk_space::RESERVE_BYTES;
        let filler = vec![0xA5u8; 1 << 20];
        let mut f = std::fs::File::create(self.path().join("filler")).unwrap();
        for _ in 0..(free - (reserve - 8_000_000)) >> 20 {
            std::io::Write::write_all(&mut f, &filler).unwrap();
        }
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

/// A running netlink hub (`telerehab therapist`) storing under a directory, and the address it
/// listens on; ended when dropped.
pub struct TherapistHub {
    child: std::process::Child,
    /// Where it listens (`127.0.0.1:PORT`).
    pub addr: String,
}

impl TherapistHub {
    /// Start a hub storing under `store`, on a free loopback port.
    pub fn start(store: &Path) -> Self {
        use std::io::BufRead;
        let mut child = Command::new(telerehab_bin())
            .args([
                "therapist",
                "--listen",
                "127.0.0.1:0",
                "--store",
                store.to_str().unwrap(),
            ])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let mut lines = std::io::BufReader::new(child.stdout.take().unwrap()).lines();
        let first = lines.next().expect("hub prints where it listens").unwrap();
        let addr = first
            .strip_prefix("listening on ")
            .and_then(|r| r.split_whitespace().next())
            .unwrap_or_else(|| panic!("unexpected first line {first:?}"))
            .to_string();
        // Keep draining the hub's live lines so it never blocks on a full pipe.
        std::thread::spawn(move || for _ in lines {});
        Self { child, addr }
    }

    /// Stop it as an operator does (SIGINT) and wait for it to end.
    pub fn interrupt(mut self) {
        let _ = Command::new("kill")
            .args(["-INT", &self.child.id().to_string()])
            .status();
        let _ = self.child.wait();
    }
}

impl TherapistHub {
    /// Sends `signal` (`INT`, `TERM`) and waits up to `limit` for it to end; how long it took,
    /// or `None` if it was still running (then it is killed).
    pub fn signal_and_wait(
        &mut self,
        signal: &str,
        limit: std::time::Duration,
    ) -> Option<std::time::Duration> {
        clinic::signal_and_wait(&mut self.child, signal, limit)
    }

    /// Kill it outright (SIGKILL, as a crash would) and wait for it to end.
    pub fn kill(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for TherapistHub {
    /// A failing test still ends its hub (after `interrupt` this finds it gone).
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Every summary seq a [`TherapistHub`] stored under `store` for `station_id`, per session.
pub fn stored_seqs(store: &Path, station_id: &str) -> Vec<Vec<u64>> {
    let mut sessions = Vec::new();
    for entry in std::fs::read_dir(store.join(station_id)).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "jsonl") {
            let text = std::fs::read_to_string(&path).unwrap();
            let seqs = text
                .lines()
                .map(|l| {
                    serde_json::from_str::<serde_json::Value>(l).unwrap()["seq"]
                        .as_u64()
                        .unwrap()
                })
                .collect();
            sessions.push(seqs);
        }
    }
    sessions
}

/// Kills a process and its children (a station and its window process) when dropped, so a
/// failing window test leaves no window behind for the next test's key presses to land in.
pub struct Reaper(pub u32);

impl Drop for Reaper {
    fn drop(&mut self) {
        let pid = self.0.to_string();
        // Both fail harmlessly when the process has already ended.
        let _ = Command::new("pkill").args(["-9", "-P", &pid]).status();
        let _ = Command::new("kill").args(["-9", &pid]).status();
    }
}

/// xdotool on the first window whose name matches `name` (a regular expression), waiting for it
/// to open: focus it (the X test path a real keyboard takes), then `args` (e.g. `key space`,
/// `type TEXT`).
pub fn xdotool_in(name: &str, args: &[&str]) {
    let search = Command::new("xdotool")
        .args(["search", "--sync", "--name", name])
        .output()
        .expect("xdotool (installed by scripts/setup.sh)");
    let window = String::from_utf8_lossy(&search.stdout)
        .lines()
        .next()
        .expect("the window")
        .to_owned();
    let focus = Command::new("xdotool")
        .args(["windowfocus", "--sync", &window])
        .status()
        .unwrap();
    assert!(focus.success(), "xdotool could not focus {name}");
    assert!(
        Command::new("xdotool")
            .args(args)
            .status()
            .unwrap()
            .success(),
        "xdotool {args:?}"
    );
}

/// Runs `telerehab hub chaos ARGS` and returns its report (stdout), having asserted that it
/// succeeded; `None`, after printing `SKIPPED: <why>`, when it found no PostgreSQL, Patroni or
/// S3 server to run on (`scripts/setup.sh` installs them; CI allows none of these skips).
pub fn chaos_day(args: &[&str]) -> Option<String> {
    let out = Command::new(telerehab_bin())
        .args(["hub", "chaos"])
        .args(args)
        .output()
        .expect("run telerehab hub chaos");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let unavailable = [
        "PostgreSQL unavailable",
        "Patroni unavailable",
        "S3 store unavailable",
    ];
    if !out.status.success() && unavailable.iter().any(|m| stderr.contains(m)) {
        println!("SKIPPED: {}", stderr.trim());
        return None;
    }
    assert!(
        out.status.success(),
        "telerehab hub chaos {} failed:\n{stdout}\n{stderr}",
        args.join(" ")
    );
    Some(stdout)
}

/// The restore drill's verdict in a chaos day's report: asserts "restore drill: OK" and returns
/// the summaries the restored database holds (from its "restore drill: restored" line).
pub fn restored_summaries(stdout: &str) -> u64 {
    assert!(
        stdout.contains("restore drill: OK"),
        "no restore drill verdict:\n{stdout}"
    );
    let restored = stdout
        .lines()
        .find(|l| l.starts_with("restore drill: restored"))
        .unwrap_or_else(|| panic!("no restored counts:\n{stdout}"));
    restored
        .split("summaries ")
        .nth(1)
        .and_then(|s| s.split(',').next())
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("no summary count in {restored:?}"))
}
