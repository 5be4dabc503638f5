//! The chaos day's S3 recording store (`--s3`): a SeaweedFS of its own (`weed mini`, built by
//! `scripts/setup.sh` into `~/.local/bin/weed`; `TELEREHAB_WEED` names another binary) on
//! free loopback ports in a temporary directory, with one identity (its credentials in a file
//! the hubs' `[recordings]` names) and one bucket. A store kill is SIGKILL (a store gone
//! mid-request); the restart is on the same ports and data, and waits until the store lists
//! the bucket again. (The tests' own launcher, `crates/hub/tests/common/s3.rs`, is the same
//! recipe; product code does not depend on test code.)

use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};

use anyhow::{Context, bail};
use hub::recordings::{RecordingStore, RecordingsConfig};

use super::postgres::{free_port, log_tail};

/// The bucket of the day's recordings.
pub const BUCKET: &str = "recordings";
const ACCESS_KEY: &str = "telerehab-chaos";
const SECRET_KEY: &str = "telerehab-chaos-secret-key";

/// How long SeaweedFS may take to answer after a (re)start (a loaded 2-core machine).
pub const START_WITHIN: Duration = Duration::from_secs(90);

/// The SeaweedFS binary: `TELEREHAB_WEED`, else `~/.local/bin/weed`, else `weed` on the PATH.
pub(crate) fn weed_binary() -> PathBuf {
    if let Some(p) = std::env::var_os("TELEREHAB_WEED").filter(|p| !p.is_empty()) {
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

/// `weed mini`'s arguments for a SeaweedFS on loopback with its data in `data`, the identities
/// of `s3_json` and the bucket `bucket`, every internal port free (the caller adds its S3
/// port(s)); no WebDAV, admin UI, telemetry, Iceberg or Lance.
pub(crate) fn mini_args(data: &Path, s3_json: &Path, bucket: &str) -> anyhow::Result<Vec<String>> {
    let mut args: Vec<String> = vec![
        "mini".into(),
        format!("-dir={}", data.display()),
        "-ip=127.0.0.1".into(),
        "-ip.bind=127.0.0.1".into(),
        format!("-s3.config={}", s3_json.display()),
        format!("-bucket={bucket}"),
        "-webdav=false".into(),
        "-admin.ui=false".into(),
        "-master.telemetry=false".into(),
        "-s3.port.iceberg=0".into(),
        "-s3.port.lance=0".into(),
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
        args.push(format!("-{flag}={}", free_port()?));
    }
    Ok(args)
}

/// One SeaweedFS, running or killed.
pub struct Store {
    dir: tempfile::TempDir,
    args: Vec<String>,
    child: tokio::sync::Mutex<Option<tokio::process::Child>>,
    /// Its S3 endpoint, `http://127.0.0.1:<port>`.
    pub endpoint: String,
}

impl Store {
    /// Starts a SeaweedFS with [`BUCKET`] and waits until it lists the bucket.
    pub async fn start_new() -> anyhow::Result<Self> {
        let dir = tempfile::tempdir().context("cannot make the store's directory")?;
        let identities = serde_json::json!({
            "identities": [{
                "name": "hub",
                "credentials": [{"accessKey": ACCESS_KEY, "secretKey": SECRET_KEY}],
                "actions": ["Admin", "Read", "Write", "List", "Tagging"]
            }]
        });
        let config = dir.path().join("s3.json");
        std::fs::write(&config, identities.to_string()).context("writing s3.json")?;
        std::fs::write(
            dir.path().join("credentials.toml"),
            format!("access_key_id = \"{ACCESS_KEY}\"\nsecret_access_key = \"{SECRET_KEY}\"\n"),
        )
        .context("writing the store's credentials")?;
        let data = dir.path().join("data");
        std::fs::create_dir_all(&data).context("making the store's data directory")?;
        let s3_port = free_port()?;
        let mut args = mini_args(&data, &config, BUCKET)?;
        args.push(format!("-s3.port={s3_port}"));
        let store = Self {
            dir,
            args,
            child: tokio::sync::Mutex::new(None),
            endpoint: format!("http://127.0.0.1:{s3_port}"),
        };
        store.restart().await?;
        Ok(store)
    }

    /// The hubs' `[recordings]` for this store reached at `endpoint` (the store's own, or a
    /// relay in front of it): short deadlines, so a hub refuses an upload it cannot store
    /// within seconds and the station tries again later.
    pub fn config(&self, endpoint: &str) -> RecordingsConfig {
        let mut c = RecordingsConfig::s3(BUCKET, endpoint);
        c.credentials_file = Some(self.dir.path().join("credentials.toml"));
        c.requests.max_retries = 2;
        c.requests.retry_timeout_s = 5;
        c.requests.request_timeout_s = 20;
        c.requests.connect_timeout_s = 2;
        c
    }

    /// A recording store on this store (the end check reads through it), its staging under
    /// `data`.
    pub fn recordings(&self, data: &Path) -> anyhow::Result<RecordingStore> {
        RecordingStore::open(data, Some(&self.config(&self.endpoint)))
            .map_err(|e| anyhow::anyhow!("the S3 recording store: {e}"))
    }

    /// (Re)starts SeaweedFS on the same ports and data and waits until it lists the bucket.
    pub async fn restart(&self) -> anyhow::Result<()> {
        let log = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(self.dir.path().join("weed.log"))
            .context("the store's log")?;
        let binary = weed_binary();
        let child = tokio::process::Command::new(&binary)
            .args(&self.args)
            .stdin(Stdio::null())
            .stdout(Stdio::from(log.try_clone()?))
            .stderr(Stdio::from(log))
            .kill_on_drop(true)
            .spawn()
            .with_context(|| {
                format!(
                    "cannot start SeaweedFS ({}): scripts/setup.sh installs it",
                    binary.display()
                )
            })?;
        *self.child.lock().await = Some(child);
        let probe = self.recordings(&self.dir.path().join("probe"))?;
        let started = Instant::now();
        loop {
            if probe.finished().await.is_ok() {
                return Ok(());
            }
            if let Some(child) = self.child.lock().await.as_mut()
                && let Some(status) = child.try_wait()?
            {
                bail!("SeaweedFS exited ({status}):\n{}", self.log_tail());
            }
            if started.elapsed() > START_WITHIN {
                bail!(
                    "SeaweedFS did not answer within {START_WITHIN:?}:\n{}",
                    self.log_tail()
                );
            }
            tokio::time::sleep(Duration::from_millis(250)).await;
        }
    }

    /// SIGKILLs the store (gone mid-request); an error if it was not running.
    pub async fn kill(&self) -> anyhow::Result<()> {
        let Some(mut child) = self.child.lock().await.take() else {
            bail!("the store was not running");
        };
        child.kill().await.context("SIGKILL of SeaweedFS")?;
        Ok(())
    }

    /// Stops the store for good.
    pub async fn stop(self) {
        if let Some(mut child) = self.child.lock().await.take() {
            let _ = child.kill().await;
        }
    }

    fn log_tail(&self) -> String {
        log_tail(&self.dir.path().join("weed.log"), 30)
    }
}
