//! A station driven from outside and followed by its log: the log's lines as they come, a wait
//! for a line saying something, the wheel's script a simulated station reads
//! (`TELEREHAB_WHEEL_SCRIPT`), and an X display of the test's own when none is set.

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

/// The lines `child` writes to its (piped) standard error, as they come.
pub fn stderr_lines(child: &mut Child) -> mpsc::Receiver<String> {
    let (tx, lines) = mpsc::channel();
    let stderr = BufReader::new(child.stderr.take().expect("standard error piped"));
    std::thread::spawn(move || {
        for line in stderr.lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    lines
}

/// Waits up to `within` for each next line, until one contains every one of `what`; the
/// lines seen before it are kept for the failure's message.
pub fn wait_for(lines: &mpsc::Receiver<String>, what: &[&str], within: Duration) -> String {
    first_line_with(lines, what, within, || within)
}

/// Waits at most `within` in all (not for each line, as [`wait_for`] does) for a line that
/// contains every one of `what`: for a test whose bound is itself the claim ("within its next
/// check").
pub fn wait_within(lines: &mpsc::Receiver<String>, what: &[&str], within: Duration) -> String {
    let deadline = std::time::Instant::now() + within;
    first_line_with(lines, what, within, || {
        deadline.saturating_duration_since(std::time::Instant::now())
    })
}

/// The first line containing every one of `what`, each next line waited for `left()`.
fn first_line_with(
    lines: &mpsc::Receiver<String>,
    what: &[&str],
    within: Duration,
    left: impl Fn() -> Duration,
) -> String {
    let mut seen = Vec::new();
    loop {
        match lines.recv_timeout(left()) {
            Ok(line) if what.iter().all(|w| line.contains(w)) => return line,
            Ok(line) => seen.push(line),
            Err(e) => panic!(
                "no log line with {what:?} within {within:?} ({e}); the log said:\n{}",
                seen.join("\n")
            ),
        }
    }
}

/// Appends wheel gestures (`press`, `hold`, `turn ±1`) to the script the station reads.
pub fn wheel(script: &Path, gestures: &[&str]) {
    let mut f = std::fs::OpenOptions::new()
        .append(true)
        .open(script)
        .unwrap();
    for g in gestures {
        writeln!(f, "{g}").unwrap();
    }
    f.sync_all().unwrap();
}

/// An X display of the test's own (Xvfb, which names its display on a pipe), stopped when
/// dropped.
pub struct Xvfb {
    child: Child,
    /// `:N`, for `DISPLAY`.
    pub display: String,
}

impl Xvfb {
    /// Starts one at 1280×720.
    pub fn start() -> Self {
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1280x720x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb (Debian's xvfb) to draw the patient's window");
        let mut number = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut number)
            .expect("Xvfb names its display");
        assert!(!number.trim().is_empty(), "Xvfb did not start");
        Xvfb {
            child,
            display: format!(":{}", number.trim()),
        }
    }

    /// The display set (`DISPLAY`), else one of the test's own: (its name, the Xvfb to keep).
    pub fn set_or_start() -> (String, Option<Xvfb>) {
        match std::env::var_os("DISPLAY").filter(|d| !d.is_empty()) {
            Some(d) => (d.to_string_lossy().into_owned(), None),
            None => {
                let own = Xvfb::start();
                (own.display.clone(), Some(own))
            }
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
