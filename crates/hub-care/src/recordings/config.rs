//! `hub.toml`'s `[recordings]`: where the hub keeps recordings. Absent, or `store = "local"`:
//! the data directory. `store = "s3"`: an S3-compatible store, e.g.
//!
//! ```toml
//! [recordings]
//! store = "s3"
//! bucket = "telerehab"
//! prefix = "clinic-nord"                 # optional: keys under it
//! endpoint = "https://s3.clinic.example" # optional: AWS itself when absent
//! region = "eu-central-1"                # optional: us-east-1
//! credentials_file = "/etc/telerehab/s3.toml" # optional, else the environment
//!
//! [recordings.requests]                  # optional, these are the defaults
//! max_retries = 3          # of a failed request (5xx, timeout, connection lost)
//! retry_timeout_s = 30     # no retry starts later than this after the first attempt
//! request_timeout_s = 60   # one request's deadline
//! connect_timeout_s = 5
//! ```
//!
//! Credentials never sit in `hub.toml`: `credentials_file` is a TOML file of
//! `access_key_id` and `secret_access_key` (readable by the hub's user only), else the
//! environment's `AWS_ACCESS_KEY_ID` and `AWS_SECRET_ACCESS_KEY`.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use object_store::ObjectStore;
use serde::{Deserialize, Serialize};

use super::StoreTimeouts;
use hub_store::HubError;

/// `hub.toml`'s `[recordings]` (see the module's documentation).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordingsConfig {
    /// `"local"` (the data directory) or `"s3"`.
    pub store: String,
    /// The S3 bucket (must exist).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bucket: Option<String>,
    /// Keys start with this (`prefix/<station>/<session>.mcap`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prefix: Option<String>,
    /// The S3 endpoint (`https://…`); absent: AWS.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub endpoint: Option<String>,
    /// The region (`us-east-1` when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<String>,
    /// A TOML file of `access_key_id` and `secret_access_key`; absent: the environment.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub credentials_file: Option<PathBuf>,
    /// Allow an `http://` endpoint (a private network only: recordings are health data).
    #[serde(default)]
    pub allow_http: bool,
    /// Retries and deadlines of the store's requests (`[recordings.requests]`).
    #[serde(default)]
    pub requests: StoreTimeouts,
}

/// `credentials_file`'s content.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Credentials {
    access_key_id: String,
    secret_access_key: String,
}

fn bad(field: &str, why: impl std::fmt::Display) -> HubError {
    HubError::Config(format!("hub.toml's [recordings] {field}: {why}"))
}

impl RecordingsConfig {
    /// The local directory (the default), not S3.
    pub fn is_local(&self) -> bool {
        self.store == "local"
    }

    /// An S3 configuration of `bucket` at `endpoint` (tests and `hub bench`).
    pub fn s3(bucket: &str, endpoint: &str) -> Self {
        Self {
            store: "s3".into(),
            bucket: Some(bucket.into()),
            prefix: None,
            endpoint: Some(endpoint.into()),
            region: None,
            credentials_file: None,
            allow_http: endpoint.starts_with("http://"),
            requests: StoreTimeouts::default(),
        }
    }

    fn credentials(&self) -> Result<(String, String), HubError> {
        if let Some(path) = &self.credentials_file {
            let text = std::fs::read_to_string(path)
                .map_err(|e| bad("credentials_file", format!("{}: {e}", path.display())))?;
            let c: Credentials = toml::from_str(&text)
                .map_err(|e| bad("credentials_file", format!("{}: {e}", path.display())))?;
            return Ok((c.access_key_id, c.secret_access_key));
        }
        let var = |name: &str| {
            std::env::var(name).map_err(|_| {
                bad(
                    "credentials",
                    format!("no credentials_file and no {name} in the environment"),
                )
            })
        };
        Ok((var("AWS_ACCESS_KEY_ID")?, var("AWS_SECRET_ACCESS_KEY")?))
    }

    /// The S3 store this configures, and its `s3://bucket/prefix` for the records; an error
    /// naming the setting that is missing or wrong.
    pub(super) fn s3_store(&self) -> Result<(Arc<dyn ObjectStore>, String), HubError> {
        if self.store != "s3" {
            return Err(bad(
                "store",
                format!("{:?} is neither \"local\" nor \"s3\"", self.store),
            ));
        }
        let bucket = self
            .bucket
            .as_deref()
            .filter(|b| !b.is_empty())
            .ok_or_else(|| bad("bucket", "missing (store = \"s3\" needs one)"))?;
        if let Some(endpoint) = &self.endpoint {
            if endpoint.starts_with("http://") && !self.allow_http {
                return Err(bad(
                    "endpoint",
                    format!(
                        "{endpoint} is plain HTTP: recordings are health data; use https, or \
                         set allow_http = true on a private network only"
                    ),
                ));
            }
            if !endpoint.starts_with("http://") && !endpoint.starts_with("https://") {
                return Err(bad(
                    "endpoint",
                    format!("{endpoint:?} is not an http(s) URL"),
                ));
            }
        }
        let t = &self.requests;
        if t.request_timeout_s == 0 || t.connect_timeout_s == 0 {
            return Err(bad(
                "request_timeout_s/connect_timeout_s",
                "must be at least 1 s",
            ));
        }
        let (key_id, secret) = self.credentials()?;
        // reqwest's TLS is rustls on the ring provider the rest of the hub uses.
        let _ = rustls::crypto::ring::default_provider().install_default();
        let options = object_store::ClientOptions::new()
            .with_allow_http(self.allow_http)
            .with_timeout(Duration::from_secs(t.request_timeout_s))
            .with_connect_timeout(Duration::from_secs(t.connect_timeout_s));
        let mut builder = object_store::aws::AmazonS3Builder::new()
            .with_bucket_name(bucket)
            .with_region(self.region.as_deref().unwrap_or("us-east-1"))
            .with_access_key_id(key_id)
            .with_secret_access_key(secret)
            .with_client_options(options)
            .with_retry(t.retry());
        if let Some(endpoint) = &self.endpoint {
            builder = builder.with_endpoint(endpoint);
        }
        let s3 = builder.build().map_err(|e| bad("settings", e))?;
        let prefix = self
            .prefix
            .as_deref()
            .map(|p| p.trim_matches('/'))
            .filter(|p| !p.is_empty());
        let url = match prefix {
            Some(p) => format!("s3://{bucket}/{p}"),
            None => format!("s3://{bucket}"),
        };
        let store: Arc<dyn ObjectStore> = match prefix {
            Some(p) => Arc::new(object_store::prefix::PrefixStore::new(s3, p)),
            None => Arc::new(s3),
        };
        Ok((store, url))
    }
}

#[cfg(test)]
mod tests {
    use super::RecordingsConfig;

    fn error_of(c: &RecordingsConfig) -> String {
        c.s3_store().expect_err("refused").to_string()
    }

    #[test]
    fn a_bad_or_missing_s3_setting_is_refused_naming_it() {
        let good = RecordingsConfig {
            credentials_file: Some("/nonexistent/telerehab-s3.toml".into()),
            ..RecordingsConfig::s3("recordings", "https://s3.clinic.example")
        };
        let mut c = good.clone();
        c.store = "nfs".into();
        assert!(
            error_of(&c).contains("[recordings] store"),
            "{}",
            error_of(&c)
        );
        let mut c = good.clone();
        c.bucket = None;
        assert!(
            error_of(&c).contains("[recordings] bucket"),
            "{}",
            error_of(&c)
        );
        let mut c = good.clone();
        c.endpoint = Some("http://10.0.0.5:8333".into());
        assert!(
            error_of(&c).contains("[recordings] endpoint"),
            "{}",
            error_of(&c)
        );
        c.endpoint = Some("s3.clinic.example".into());
        c.allow_http = true;
        assert!(
            error_of(&c).contains("not an http(s) URL"),
            "{}",
            error_of(&c)
        );
        let mut c = good.clone();
        c.requests.request_timeout_s = 0;
        assert!(
            error_of(&c).contains("request_timeout_s"),
            "{}",
            error_of(&c)
        );
        // Everything else right: the credentials file that cannot be read is named.
        let e = error_of(&good);
        assert!(e.contains("[recordings] credentials_file"), "{e}");
        assert!(e.contains("/nonexistent/telerehab-s3.toml"), "{e}");
    }

    #[test]
    fn the_requests_table_keeps_its_defaults_and_an_unknown_key_is_refused_by_name() {
        let parsed: RecordingsConfig =
            toml::from_str("store = \"s3\"\nbucket = \"b\"\n[requests]\nmax_retries = 5\n")
                .unwrap();
        assert_eq!(parsed.requests.max_retries, 5);
        assert_eq!(
            parsed.requests.retry_timeout_s, 30,
            "the rest keep their defaults"
        );
        let unknown = toml::from_str::<RecordingsConfig>("store = \"s3\"\nbuckit = \"b\"\n");
        assert!(unknown.unwrap_err().to_string().contains("buckit"));
    }
}
