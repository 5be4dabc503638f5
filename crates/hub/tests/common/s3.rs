//! A real S3 server for the tests: SeaweedFS (`weed mini`, built from the Go module proxy by
//! `scripts/setup.sh` into `~/.local/bin/weed`; `TELEREHAB_WEED` names another binary), started
//! on free loopback ports in a temp dir with one identity and one bucket, stopped (and
//! restartable on the same ports and data) by the test. A test that cannot start it fails.

use std::io::Write;
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hub::recordings::{RecordingStore, RecordingsConfig};

/// The bucket every test server has.
pub const BUCKET: &str = "recordings";
const ACCESS_KEY: &str = "telerehab-test";
const SECRET_KEY: &str = "telerehab-test-secret-key";

/// How long SeaweedFS may take to answer after its start (a loaded 2-core machine).
const START_WITHIN: Duration = Duration::from_secs(90);

/// The SeaweedFS binary: `TELEREHAB_WEED`, else `~/.local/bin/weed`, else `weed` on the PATH.
pub fn weed_binary() -> PathBuf {
    if let Some(p) = std::env::var_os("TELEREHAB_WEED") {
        return PathBuf::from(p);
    }
    if let Some(home) = std::env::var_os("HOME") {
        let p = Path::new(&home).join(".local/bin/weed");
        if p.is_file() {
            return p;
        }
    }
    PathBuf::from("weed")
}

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free loopback port")
        .port()
}

/// One running (or stopped) SeaweedFS.
pub struct SeaweedS3 {
    dir: tempfile::TempDir,
    args: Vec<String>,
    child: Option<Child>,
    /// `http://127.0.0.1:<port>`.
    pub endpoint: String,
}

impl SeaweedS3 {
    /// Starts a SeaweedFS with [`BUCKET`] and waits until its S3 port lists the bucket;
    /// panics (the test fails) when it cannot.
    pub async fn start() -> Self {
        let dir = tempfile::tempdir().expect("temp dir");
        let config = dir.path().join("s3.json");
        let identities = serde_json::json!({
            "identities": [{
                "name": "hub",
                "credentials": [{"accessKey": ACCESS_KEY, "secretKey": SECRET_KEY}],
                "actions": ["Admin", "Read", "Write", "List", "Tagging"]
            }]
        });
        std::fs::write(&config, identities.to_string()).expect("s3.json");
        let mut creds = std::fs::File::create(dir.path().join("credentials.toml")).unwrap();
        writeln!(
            creds,
            "access_key_id = \"{ACCESS_KEY}\"\nsecret_access_key = \"{SECRET_KEY}\""
        )
        .unwrap();
        let data = dir.path().join("data");
        std::fs::create_dir_all(&data).unwrap();
        let s3_port = free_port();
        let mut args: Vec<String> = vec![
            "mini".into(),
            format!("-dir={}", data.display()),
            "-ip=127.0.0.1".into(),
            "-ip.bind=127.0.0.1".into(),
            format!("-s3.config={}", config.display()),
            format!("-bucket={BUCKET}"),
            "-webdav=false".into(),
            "-admin.ui=false".into(),
            "-master.telemetry=false".into(),
            "-s3.port.iceberg=0".into(),
            "-s3.port.lance=0".into(),
            format!("-s3.port={s3_port}"),
        ];
        for flag in [
            "master.port",
            "master.port.grpc",
            "volume.port",
            "volume.port.grpc",
            "filer.port",
            "filer.port.grpc",
            "s3.port.grpc",
        ] {
            args.push(format!("-{flag}={}", free_port()));
        }
        let mut s3 = Self {
            dir,
            args,
            child: None,
            endpoint: format!("http://127.0.0.1:{s3_port}"),
        };
        s3.restart().await;
        s3
    }

    /// The hub's `[recordings]` for this server (credentials from a file in its temp dir).
    pub fn config(&self) -> RecordingsConfig {
        let mut c = RecordingsConfig::s3(BUCKET, &self.endpoint);
        c.credentials_file = Some(self.dir.path().join("credentials.toml"));
        c.requests.max_retries = 2;
        c.requests.retry_timeout_s = 5;
        c.requests.request_timeout_s = 20;
        c.requests.connect_timeout_s = 2;
        c
    }

    /// A recording store on this server, its partial uploads under `data/recordings`.
    pub fn store(&self, data: &Path) -> RecordingStore {
        RecordingStore::open(data, Some(&self.config())).expect("the S3 recording store")
    }

    /// (Re)starts the server on the same ports and data, and waits until it answers.
    pub async fn restart(&mut self) {
        let log = std::fs::File::create(self.dir.path().join("weed.log")).unwrap();
        let binary = weed_binary();
        let child = Command::new(&binary)
            .args(&self.args)
            .stdin(Stdio::null())
            .stdout(log.try_clone().unwrap())
            .stderr(log)
            .spawn()
            .unwrap_or_else(|e| {
                panic!(
                    "cannot start SeaweedFS ({}): {e}; scripts/setup.sh installs it",
                    binary.display()
                )
            });
        self.child = Some(child);
        let store = self.store(&self.dir.path().join("probe"));
        let started = Instant::now();
        loop {
            if store.finished().await.is_ok() {
                return;
            }
            if let Some(status) = self
                .child
                .as_mut()
                .and_then(|c| c.try_wait().ok().flatten())
            {
                panic!("SeaweedFS exited ({status}):\n{}", self.log_tail());
            }
            assert!(
                started.elapsed() < START_WITHIN,
                "SeaweedFS did not answer within {START_WITHIN:?}:\n{}",
                self.log_tail()
            );
            tokio::time::sleep(Duration::from_millis(250)).await;
        }
    }

    /// Kills the server at once (a store gone mid-request).
    pub fn stop(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }

    fn log_tail(&self) -> String {
        let log = std::fs::read_to_string(self.dir.path().join("weed.log")).unwrap_or_default();
        let lines: Vec<&str> = log.lines().collect();
        lines[lines.len().saturating_sub(30)..].join("\n")
    }
}

impl Drop for SeaweedS3 {
    fn drop(&mut self) {
        self.stop();
    }
}
