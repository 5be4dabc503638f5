//! A clinic's hub run as its users run it (`hub init`, `hub patient add`, `hub serve`), for the
//! end-to-end tests: the one-time setup, the serving process and what `hub patient show` says.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

use crate::telerehab_bin;

/// `telerehab ARGS` with the station home `home` (none: the variable removed).
pub fn telerehab(args: &[&str], home: Option<&Path>) -> Output {
    let mut cmd = Command::new(telerehab_bin());
    cmd.args(args).env_remove("TELEREHAB_HOME");
    if let Some(h) = home {
        cmd.env("TELEREHAB_HOME", h);
    }
    cmd.output().unwrap()
}

/// [`telerehab()`], which must succeed; its standard output.
pub fn ok(args: &[&str], home: Option<&Path>) -> String {
    let out = telerehab(args, home);
    assert!(
        out.status.success(),
        "telerehab {args:?} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// `telerehab pair` of the station whose home is `home` with `hub`, using `code`; what it said.
pub fn pair(hub: &Hub, code: &str, home: &Path) -> String {
    ok(
        &["pair", "--hub", &hub.stations, "--code", code],
        Some(home),
    )
}

/// `hub patient regimen` of `regimens/NAME.toml` for P-0042 by the first admin; what it said.
pub fn prescribe(data: &Path, name: &str) -> String {
    let regimen = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../regimens")
        .join(format!("{name}.toml"));
    ok(
        &[
            "hub",
            "patient",
            "regimen",
            "--data",
            data.to_str().unwrap(),
            "P-0042",
            "--file",
            regimen.to_str().unwrap(),
            "--by",
            "ana@clinic.example",
        ],
        None,
    )
}

/// A clinic directory with one patient; the pairing code.
pub fn clinic(dir: &Path) -> (PathBuf, String) {
    clinic_on(dir, None)
}

/// [`clinic`] with its database at `db` (a PostgreSQL URL) instead of SQLite in the directory.
pub fn clinic_on(dir: &Path, db: Option<&str>) -> (PathBuf, String) {
    let made = NewClinic::make(dir, db);
    (made.data, made.code)
}

/// A clinic `hub init` and `hub patient add` made: its data directory, the patient P-0042's
/// pairing code and the admin's (ana@clinic.example) one-time password.
pub struct NewClinic {
    /// The data directory.
    pub data: PathBuf,
    /// P-0042's pairing code.
    pub code: String,
    /// The first admin's one-time password.
    pub admin_password: String,
}

impl NewClinic {
    /// Makes it in `dir/clinic`, its database at `db` (a PostgreSQL URL) or SQLite.
    pub fn make(dir: &Path, db: Option<&str>) -> Self {
        Self::make_named(dir, db, &[])
    }

    /// [`Self::make`] with the hub's certificate for `names` (`hub init --name`; none: its
    /// default, `localhost` and `127.0.0.1`).
    pub fn make_named(dir: &Path, db: Option<&str>, names: &[&str]) -> Self {
        let data = dir.join("clinic");
        let d = data.to_str().unwrap();
        let mut args = vec!["hub", "init", "--data", d, "--admin", "ana@clinic.example"];
        if let Some(url) = db {
            args.extend(["--db", url]);
        }
        for name in names {
            args.extend(["--name", name]);
        }
        let init = ok(&args, None);
        let admin_password = after(&init, "one-time password: ");
        let add = ok(
            &[
                "hub",
                "patient",
                "add",
                "--data",
                d,
                "--pseudonym",
                "P-0042",
            ],
            None,
        );
        let code = after(&add, "pairing code: ");
        Self {
            data,
            code,
            admin_password,
        }
    }
}

/// A running `hub serve`; killed when dropped.
pub struct Hub {
    /// The `hub serve` process.
    pub child: Child,
    /// Where stations reach it, `localhost:PORT`.
    pub stations: String,
    /// The console's address, `127.0.0.1:PORT`, when served.
    pub web: Option<String>,
    /// The operator's address (`/metrics`, `/healthz`, `/readyz`), when served
    /// (`--metrics-listen`).
    pub metrics: Option<String>,
}

impl Hub {
    /// `hub serve` on `data` with stations at `stations` (`127.0.0.1:0`: a free port).
    pub fn serve(data: &Path, stations: &str) -> Hub {
        Self::serve_with(data, stations, &[])
    }

    /// [`Self::serve`] with more arguments (`--web 127.0.0.1:0` serves the console too).
    pub fn serve_with(data: &Path, stations: &str, more: &[&str]) -> Hub {
        Self::serve_logging_to(data, stations, more, Stdio::null())
    }

    /// [`Self::serve_with`] writing its log (standard error) to `log`.
    pub fn serve_logging_to(data: &Path, stations: &str, more: &[&str], log: Stdio) -> Hub {
        let mut child = Command::new(telerehab_bin())
            .args(["hub", "serve", "--data", data.to_str().unwrap()])
            .args(["--stations", stations])
            .args(more)
            .stdout(Stdio::piped())
            .stderr(log)
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        let first = lines.next().expect("hub prints where it listens").unwrap();
        let addr = first
            .strip_prefix("stations listening on ")
            .and_then(|r| r.split_whitespace().next())
            .unwrap_or_else(|| panic!("unexpected first line {first:?}"));
        let port = addr.rsplit(':').next().unwrap();
        let web = more.contains(&"--web").then(|| {
            let line = lines
                .next()
                .expect("hub prints the console's address")
                .unwrap();
            line.strip_prefix("console API on https://")
                .and_then(|r| r.strip_suffix("/api/"))
                .unwrap_or_else(|| panic!("unexpected second line {line:?}"))
                .to_owned()
        });
        let metrics = more.contains(&"--metrics-listen").then(|| {
            let line = lines
                .next()
                .expect("hub prints the operator's address")
                .unwrap();
            line.strip_prefix("metrics on http://")
                .and_then(|r| r.strip_suffix("/metrics"))
                .unwrap_or_else(|| panic!("unexpected line {line:?}"))
                .to_owned()
        });
        std::thread::spawn(move || for _ in lines {});
        Hub {
            child,
            stations: format!("localhost:{port}"),
            web,
            metrics,
        }
    }

    /// `hub serve` with the console too (`--web` on a free loopback port).
    pub fn serve_console(data: &Path, stations: &str) -> Hub {
        Self::serve_with(data, stations, &["--web", "127.0.0.1:0"])
    }

    /// The port stations reach it on.
    pub fn stations_port(&self) -> String {
        self.stations.rsplit(':').next().unwrap().to_owned()
    }

    /// The console's address (`127.0.0.1:PORT`); panics if it serves none.
    pub fn web(&self) -> &str {
        self.web.as_deref().expect("hub serve --web")
    }

    /// The hub's peak resident memory so far (`VmHWM`), bytes.
    pub fn peak_rss_bytes(&self) -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap();
        let kb: u64 = after(&status, "VmHWM:").parse().unwrap();
        kb * 1024
    }

    /// Stops it as an operator does (SIGTERM) and waits for it to end.
    pub fn stop(mut self) {
        let _ = self.signal_and_wait("TERM", std::time::Duration::from_secs(60));
    }

    /// Sends `signal` (`INT`, `TERM`) and waits up to `limit` for the process to end; how long
    /// it took, or `None` if it was still running (then it is killed).
    pub fn signal_and_wait(
        &mut self,
        signal: &str,
        limit: std::time::Duration,
    ) -> Option<std::time::Duration> {
        signal_and_wait(&mut self.child, signal, limit)
    }
}

/// Sends `signal` (`INT`, `TERM`) to `child` and waits up to `limit` for it to end; how long it
/// took, or `None` if it was still running (then it is killed).
pub fn signal_and_wait(
    child: &mut Child,
    signal: &str,
    limit: std::time::Duration,
) -> Option<std::time::Duration> {
    let began = std::time::Instant::now();
    let _ = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status();
    while began.elapsed() < limit {
        if child.try_wait().ok().flatten().is_some() {
            return Some(began.elapsed());
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}

impl Drop for Hub {
    /// A failing test still ends its hub (after `stop` this finds it gone).
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `hub patient show --json`: (summaries stored per session, revoked stations).
pub fn show(data: &Path) -> (Vec<u64>, usize) {
    let v = show_json(data);
    let stored = v["sessions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["summaries_stored"].as_u64().unwrap())
        .collect();
    let revoked = v["stations"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| !s["revoked_at_ms"].is_null())
        .count();
    (stored, revoked)
}

/// `hub patient show --json` of the patient P-0042.
pub fn show_json(data: &Path) -> serde_json::Value {
    let json = ok(
        &[
            "hub",
            "patient",
            "show",
            "--data",
            data.to_str().unwrap(),
            "P-0042",
            "--json",
        ],
        None,
    );
    serde_json::from_str(&json).unwrap()
}

/// The number of summaries a run's report says it produced.
pub fn produced(report: &str) -> u64 {
    let line = report
        .lines()
        .find(|l| l.starts_with("therapist "))
        .unwrap_or_else(|| panic!("no therapist line in {report}"));
    line.split_whitespace()
        .find_map(|w| w.parse::<u64>().ok())
        .unwrap_or_else(|| panic!("no count in {line:?}"))
}

/// A simulated session of `seconds` at full speed from the station home `home`; its report.
pub fn run_session(home: &Path, seconds: &str) -> String {
    ok(
        &[
            "run",
            "--sim",
            "--headless",
            "--speed",
            "max",
            "--duration",
            seconds,
        ],
        Some(home),
    )
}

/// The one file ending in `.ext` in `dir` or its subdirectories, waited for up to 20 s.
pub fn wait_for_file(dir: &Path, ext: &str) -> PathBuf {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
    loop {
        let found: Vec<PathBuf> = std::fs::read_dir(dir)
            .into_iter()
            .flatten()
            .flatten()
            .flat_map(|e| match std::fs::read_dir(e.path()) {
                Ok(sub) => sub.flatten().map(|s| s.path()).collect(),
                Err(_) => vec![e.path()],
            })
            .filter(|p| p.extension().is_some_and(|e| e == ext))
            .collect();
        match found.as_slice() {
            [one] => return one.clone(),
            [] => assert!(
                std::time::Instant::now() < deadline,
                "no .{ext} in {} after 20 s",
                dir.display()
            ),
            many => panic!("several .{ext} files: {many:?}"),
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

/// The text after `prefix` on the line that has it, up to the next space.
pub fn after(text: &str, prefix: &str) -> String {
    text.lines()
        .find_map(|l| l.split(prefix).nth(1))
        .and_then(|r| r.split_whitespace().next())
        .unwrap_or_else(|| panic!("no {prefix:?} in {text:?}"))
        .to_owned()
}

/// A fresh database on the test PostgreSQL server (`scripts/with-postgres.sh` names it in
/// `TELEREHAB_TEST_PG_URL`), made with `psql`; `None` after saying SKIPPED without one.
pub fn fresh_postgres_database() -> Option<String> {
    let Ok(admin) = std::env::var("TELEREHAB_TEST_PG_URL") else {
        println!(
            "SKIPPED: TELEREHAB_TEST_PG_URL is not set (scripts/with-postgres.sh starts a server)"
        );
        return None;
    };
    let name = format!(
        "e2e_{}_{}",
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_nanos()
    );
    let out = Command::new("psql")
        .args([
            admin.as_str(),
            "-v",
            "ON_ERROR_STOP=1",
            "-c",
            &format!("CREATE DATABASE {name}"),
        ])
        .output()
        .expect("psql (installed with postgresql by scripts/setup.sh)");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let base = admin.rsplit_once('/').map_or(admin.as_str(), |(b, _)| b);
    Some(format!("{base}/{name}"))
}
