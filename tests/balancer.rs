//! A HAProxy of a test's own (Debian's `haproxy` in the foreground, never the system service)
//! in front of the hubs a test starts, on a configuration the test writes — what
//! docs/DEPLOY.md shows, on free ports.

use std::fs::File;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Longest the balancer may take to listen.
const LISTEN_WITHIN: Duration = Duration::from_secs(30);

/// A free TCP port on loopback (the OS's choice, released for the caller to bind).
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// A running balancer, killed when dropped.
pub struct Haproxy {
    child: Child,
    /// Its station port on 127.0.0.1.
    pub stations: u16,
    /// Its console port on 127.0.0.1.
    pub console: u16,
}

impl Haproxy {
    /// Starts haproxy on `config(stations, console)` (its two front ports, free ones) written
    /// to `dir/haproxy.cfg`, its log in `dir/haproxy.log`, and waits until the console port
    /// listens; `None` (SKIPPED printed) when haproxy is not installed.
    pub fn start(dir: &Path, config: impl FnOnce(u16, u16) -> String) -> Option<Self> {
        let (stations, console) = (free_port(), free_port());
        let cfg = dir.join("haproxy.cfg");
        std::fs::write(&cfg, config(stations, console)).unwrap();
        let child = match Command::new("haproxy")
            .arg("-db")
            .arg("-f")
            .arg(&cfg)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(File::create(dir.join("haproxy.log")).unwrap())
            .spawn()
        {
            Ok(c) => c,
            Err(e) => {
                println!("SKIPPED: cannot start haproxy ({e}); scripts/setup.sh installs it");
                return None;
            }
        };
        let began = Instant::now();
        while std::net::TcpStream::connect(("127.0.0.1", console)).is_err() {
            assert!(began.elapsed() < LISTEN_WITHIN, "haproxy did not listen");
            std::thread::sleep(Duration::from_millis(50));
        }
        Some(Self {
            child,
            stations,
            console,
        })
    }
}

impl Drop for Haproxy {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
