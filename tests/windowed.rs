//! A windowed simulated station session driven as a patient would under a display (Xvfb):
//! its log read line by line, its patient window ("telerehab") pressed with xdotool.

use crate::{telerehab_bin, xdotool_in};
use std::collections::VecDeque;
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

/// How long the exercise must run with no pause said before a test goes on after starting it.
const SETTLE: Duration = Duration::from_millis(1500);

/// A running `telerehab run --sim` with its window.
pub struct WindowedStation {
    child: Child,
    stdout: BufReader<ChildStdout>,
    lines: mpsc::Receiver<String>,
    /// Lines read while starting the exercise, for [`Self::wait_for`] to read first.
    backlog: VecDeque<String>,
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
            backlog: VecDeque::new(),
            _display: display,
        }
    }

    /// Waits for a log line containing `what` (each line within a minute); the line.
    pub fn wait_for(&mut self, what: &str) -> String {
        let mut seen = Vec::new();
        loop {
            let next = match self.backlog.pop_front() {
                Some(line) => Ok(line),
                None => self.lines.recv_timeout(PATIENCE),
            };
            match next {
                Ok(line) if line.contains(what) => return line,
                Ok(line) => seen.push(line),
                Err(e) => panic!(
                    "waited for {what:?}: {e}; the log said:\n{}",
                    seen.join("\n")
                ),
            }
        }
    }

    /// Presses Space until the exercise runs, and keeps it running: a key sent before the
    /// window maps and takes keys is lost, so Space is pressed again after a wait that doubles
    /// (2, 4, 8 s …); a loaded machine may then deliver two presses late, the second pausing
    /// what the first started, so a pause seen here is answered with one more press. Returns
    /// once the exercise has run for `SETTLE` (1.5 s) since it last started; what the log said after
    /// the start is kept for [`Self::wait_for`].
    pub fn start_the_exercise(&mut self) {
        let mut line = String::new();
        while self.stdout.read_line(&mut line).unwrap_or(0) > 0 && !line.contains("render: adapter")
        {
            line.clear();
        }
        let give_up = Instant::now() + 2 * PATIENCE;
        let mut wait = Duration::from_secs(2);
        // The exercise opens paused, waiting for Space (that first pause is not answered);
        // `settled`: when it will have run for SETTLE since it last started.
        let mut started = false;
        let mut settled: Option<Instant> = None;
        press(&["space"]);
        loop {
            let quiet = match settled {
                Some(at) => at.saturating_duration_since(Instant::now()),
                None => wait,
            };
            match self.lines.recv_timeout(quiet) {
                Ok(l) if l.contains("paused=false") => {
                    started = true;
                    settled = Some(Instant::now() + SETTLE);
                }
                Ok(l) if started && l.contains("paused=true") => {
                    settled = None;
                    press(&["space"]);
                }
                Ok(l) if started => self.backlog.push_back(l),
                Ok(_) => {}
                Err(mpsc::RecvTimeoutError::Timeout) if settled.is_some() => return,
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    assert!(Instant::now() < give_up, "Space never started the exercise");
                    press(&["space"]);
                    wait = (wait * 2).min(PATIENCE / 4);
                }
                Err(e) => panic!("the station's log ended before the exercise started: {e}"),
            }
            if settled.is_some_and(|at| Instant::now() >= at) {
                return;
            }
        }
    }

    /// Waits for the session to end in order; its report.
    pub fn finish(mut self) -> String {
        let mut report = String::new();
        self.stdout.read_to_string(&mut report).unwrap_or(0);
        assert!(self.child.wait().is_ok_and(|s| s.success()), "{report}");
        report
    }
}

/// A test that fails (or ends) before [`WindowedStation::finish`] takes its station and window
/// down: a window left on the display would take the next test's key presses (xdotool finds
/// windows by name).
impl Drop for WindowedStation {
    fn drop(&mut self) {
        if self.child.try_wait().is_ok_and(|status| status.is_none()) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
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
