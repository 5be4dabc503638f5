//! A windowed simulated station session driven as a patient would under a display (Xvfb):
//! its log read line by line, its patient window ("telerehab") pressed with xdotool.

use crate::{telerehab_bin, xdotool_in};
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::{Mutex, MutexGuard, PoisonError, mpsc};
use std::time::{Duration, Instant};

/// One window at a time on the display: the tests press keys with xdotool into the focused
/// window, so two windowed tests of one binary running at once would press into each other's.
static DISPLAY: Mutex<()> = Mutex::new(());

/// How long a loaded machine may take to say the next thing (it draws slowly).
const PATIENCE: Duration = Duration::from_secs(60);

/// A running `telerehab run --sim` with its window.
pub struct WindowedStation {
    child: Child,
    stdout: BufReader<ChildStdout>,
    lines: mpsc::Receiver<String>,
    /// The display, held while this station's window is up (a failed test's is taken back).
    _display: MutexGuard<'static, ()>,
}

impl WindowedStation {
    /// `telerehab run --sim --seed 7 --home HOME ARGS` with its window.
    pub fn start(home: &Path, args: &[&str]) -> Self {
        let display = DISPLAY.lock().unwrap_or_else(PoisonError::into_inner);
        let mut child = Command::new(telerehab_bin())
            .args(["run", "--sim", "--seed", "7", "--home"])
            .arg(home)
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the telerehab binary");
        let (tx, lines) = mpsc::channel();
        let stderr = BufReader::new(child.stderr.take().expect("piped"));
        std::thread::spawn(move || {
            for line in stderr.lines().map_while(Result::ok) {
                let _ = tx.send(line);
            }
        });
        let stdout = BufReader::new(child.stdout.take().expect("piped"));
        Self {
            child,
            stdout,
            lines,
            _display: display,
        }
    }

    /// Waits for a log line containing `what` (each line within a minute); the line.
    pub fn wait_for(&self, what: &str) -> String {
        let mut seen = Vec::new();
        loop {
            match self.lines.recv_timeout(PATIENCE) {
                Ok(line) if line.contains(what) => return line,
                Ok(line) => seen.push(line),
                Err(e) => panic!(
                    "waited for {what:?}: {e}; the log said:\n{}",
                    seen.join("\n")
                ),
            }
        }
    }

    /// Presses Space until the exercise starts (a key sent before the window maps and takes
    /// keys is lost: press again until the log says it started).
    pub fn start_the_exercise(&mut self) {
        let mut line = String::new();
        while self.stdout.read_line(&mut line).unwrap_or(0) > 0 && !line.contains("render: adapter")
        {
            line.clear();
        }
        let started = (0..30).any(|_| {
            press(&["space"]);
            let deadline = Instant::now() + Duration::from_secs(2);
            while let Some(left) = deadline.checked_duration_since(Instant::now()) {
                match self.lines.recv_timeout(left) {
                    Ok(l) if l.contains("paused=false") => return true,
                    Ok(_) => {}
                    Err(_) => break,
                }
            }
            false
        });
        assert!(started, "Space never started the exercise");
    }

    /// Waits for the session to end in order; its report.
    pub fn finish(mut self) -> String {
        let mut report = String::new();
        self.stdout.read_to_string(&mut report).unwrap_or(0);
        assert!(self.child.wait().is_ok_and(|s| s.success()), "{report}");
        report
    }
}

/// Presses `keys` in the patient window, one after the other.
pub fn press(keys: &[&str]) {
    for key in keys {
        xdotool_in("^telerehab$", &["key", key]);
        std::thread::sleep(Duration::from_millis(300));
    }
}

/// Saves what the screen shows as `$TELEREHAB_SCREENSHOTS/NAME.png` (for docs/screenshots),
/// or nowhere without that variable.
pub fn screenshot(name: &str) {
    if let Some(dir) = std::env::var_os("TELEREHAB_SCREENSHOTS") {
        let path = Path::new(&dir).join(format!("{name}.png"));
        let ok = Command::new("import")
            .args(["-window", "root"])
            .arg(&path)
            .status()
            .is_ok_and(|s| s.success());
        assert!(ok, "cannot take the screenshot {}", path.display());
    }
}
