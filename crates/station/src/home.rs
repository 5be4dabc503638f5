//! The station's home directory: its pairing with a clinic's hub (the hub's CA and this
//! station's own certificate and key), the queue of summaries not yet delivered, and its
//! recordings. Health data and keys: the owner's only ([`session::platform::owner_only`]: files
//! 0600 in 0700 directories on Linux).
//!
//! Where: `--home DIR`, else `$TELEREHAB_HOME`, else `$XDG_CONFIG_HOME/telerehab`, else
//! `~/.config/telerehab` (on Windows `%APPDATA%\telerehab\config`). Two stations on one
//! machine (and every test) use their own.

use anyhow::{Context, bail};
use netlink::pairing::Credential;
use netlink::{ClientTls, Identity};
use serde::{Deserialize, Serialize};
use session::files::write_private;
use std::path::{Path, PathBuf};

/// `--home` (with `TELEREHAB_HOME`), shared by the station's commands.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct HomeArg {
    /// The station's home directory (pairing, queue, recordings); default
    /// `$XDG_CONFIG_HOME/telerehab` or `~/.config/telerehab` (Windows: `%APPDATA%\telerehab\config`).
    #[arg(long, env = "TELEREHAB_HOME", value_name = "DIR")]
    pub home: Option<PathBuf>,
}

impl HomeArg {
    /// The home named by `TELEREHAB_HOME` (a command without the `--home` flag, such as
    /// `telerehab` with no arguments); an empty value names none.
    pub fn from_env() -> Self {
        Self {
            home: std::env::var_os("TELEREHAB_HOME")
                .filter(|v| !v.is_empty())
                .map(PathBuf::from),
        }
    }
}

/// A station's home directory.
#[derive(Debug, Clone)]
pub struct Home {
    dir: PathBuf,
}

/// What pairing left in the home directory (`pairing/hub.toml`), besides the PEM files.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pairing {
    /// The hub's address for stations, `host:port`.
    pub hub: String,
    /// The name on the hub's certificate.
    pub server_name: String,
    /// This station's identity at the hub.
    pub station_id: String,
    /// The patient this station speaks for.
    pub patient_id: String,
    /// When it was paired, ms since the Unix epoch.
    pub paired_unix_ms: u64,
    /// The patient's pseudonym as the clinic knows it (absent when the hub did not say it,
    /// and in pairings made before it did).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub patient_pseudonym: Option<String>,
}

impl Pairing {
    /// Whom this station's sessions are for in the clinic's words, for their recordings: the
    /// pseudonym (empty if the hub did not say it) and the clinic by its hub's name. The
    /// therapist is not known at pairing.
    pub fn clinic_note(&self) -> record::ClinicNote {
        record::ClinicNote {
            patient_pseudonym: self.patient_pseudonym.clone().unwrap_or_default(),
            clinic: self.server_name.clone(),
            therapist: String::new(),
        }
    }
}

/// Creates `dir` (and parents) as its owner's only (0700 on Linux) if missing, and makes it so
/// if it exists.
pub fn private_dir(dir: &Path) -> anyhow::Result<()> {
    session::platform::owner_only_dir(dir)
        .with_context(|| format!("cannot create {} for its owner only", dir.display()))
}

impl Home {
    /// The home named by `arg`, the environment or the platform default.
    pub fn resolve(arg: &HomeArg) -> anyhow::Result<Self> {
        if let Some(dir) = &arg.home {
            return Ok(Self { dir: dir.clone() });
        }
        // The platform's configuration directory (XDG on Linux), never the working directory.
        let dirs = directories::ProjectDirs::from("", "", "telerehab")
            .context("no home directory: set --home or TELEREHAB_HOME")?;
        Ok(Self {
            dir: dirs.config_dir().to_path_buf(),
        })
    }

    /// A home at `dir`.
    pub fn at(dir: impl Into<PathBuf>) -> Self {
        Self { dir: dir.into() }
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn pairing_dir(&self) -> PathBuf {
        self.dir.join("pairing")
    }

    /// Summaries not yet acknowledged by the hub, one file per session.
    pub fn queue_dir(&self) -> PathBuf {
        self.dir.join("queue")
    }

    /// Recordings waiting to be uploaded to the hub.
    pub fn uploads_dir(&self) -> PathBuf {
        self.dir.join("uploads")
    }

    /// Recordings of sessions (a paired station records every session).
    pub fn recordings_dir(&self) -> PathBuf {
        self.dir.join("recordings")
    }

    /// The therapist's messages the hub sent, and which were shown ([`crate::messages`]).
    pub fn messages_path(&self) -> PathBuf {
        self.dir.join("messages.json")
    }

    /// The clinic's pain threshold and phone number as the hub last sent them
    /// ([`crate::checkin::care::CareSettings`]).
    pub fn care_path(&self) -> PathBuf {
        self.dir.join("care.json")
    }

    /// The last pain at or over the clinic's threshold ([`crate::checkin::care::PainStop`]).
    pub fn pain_stop_path(&self) -> PathBuf {
        self.dir.join("pain-stop.json")
    }

    /// The regimen the clinic prescribed last (validated when it arrived), used by a session
    /// started without `--regimen`.
    pub fn regimen_path(&self) -> PathBuf {
        self.dir.join("regimen.toml")
    }

    /// Who prescribed the kept regimen (the clinic's e-mail for them), beside it.
    pub fn regimen_prescriber_path(&self) -> PathBuf {
        self.dir.join("regimen-prescriber.txt")
    }

    /// Keeps a regimen the hub sent (already validated) for the next sessions, with who
    /// prescribed it; a regimen from a hub that did not say leaves no prescriber.
    pub fn keep_regimen(&self, r: &netlink::Regimen) -> anyhow::Result<()> {
        write_private(&self.regimen_path(), r.toml.as_bytes())?;
        let by = self.regimen_prescriber_path();
        match &r.prescribed_by {
            Some(name) => write_private(&by, name.as_bytes()),
            None => match std::fs::remove_file(&by) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    Err(e).with_context(|| format!("cannot remove {}", by.display()))
                }
                _ => Ok(()),
            },
        }
    }

    /// Who prescribed the kept regimen, if the hub said (a damaged file names nobody).
    pub fn regimen_prescriber(&self) -> Option<String> {
        let text = std::fs::read_to_string(self.regimen_prescriber_path()).ok()?;
        let name = text.trim();
        let fits = !name.is_empty() && name.len() <= netlink::frame::MAX_TEXT_LEN;
        (fits && !name.chars().any(char::is_control)).then(|| name.to_owned())
    }

    /// The pairing, if this station is paired.
    pub fn pairing(&self) -> anyhow::Result<Option<Pairing>> {
        let path = self.pairing_dir().join("hub.toml");
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(e).with_context(|| format!("cannot read {}", path.display())),
        };
        let pairing = toml::from_str(&text)
            .with_context(|| format!("{} is damaged; pair again", path.display()))?;
        Ok(Some(pairing))
    }

    /// Stores what pairing gave (replacing an earlier pairing).
    pub fn save_pairing(
        &self,
        hub: &str,
        cred: &Credential,
        now_unix_ms: u64,
    ) -> anyhow::Result<Pairing> {
        let dir = self.pairing_dir();
        private_dir(&self.dir)?;
        private_dir(&dir)?;
        write_private(&dir.join("ca.pem"), cred.ca_pem.as_bytes())?;
        write_private(&dir.join("station.crt"), cred.cert_pem.as_bytes())?;
        write_private(&dir.join("station.key"), cred.key_pem.as_bytes())?;
        let pairing = Pairing {
            hub: hub.to_owned(),
            server_name: cred.server_name.clone(),
            station_id: cred.station_id.clone(),
            patient_id: cred.patient_id.clone(),
            paired_unix_ms: now_unix_ms,
            patient_pseudonym: cred.patient_pseudonym.clone(),
        };
        let text = toml::to_string(&pairing).context("cannot write the pairing")?;
        write_private(&dir.join("hub.toml"), text.as_bytes())?;
        Ok(pairing)
    }

    /// TLS to the paired hub: its CA only, and this station's certificate.
    pub fn client_tls(&self, pairing: &Pairing) -> ClientTls {
        let dir = self.pairing_dir();
        ClientTls {
            ca_pem_path: dir.join("ca.pem"),
            server_name: pairing.server_name.clone(),
            identity: Some(Identity {
                cert_pem_path: dir.join("station.crt"),
                key_pem_path: dir.join("station.key"),
            }),
        }
    }

    /// Refuses a home whose key is readable by others (someone could speak for the patient).
    pub fn check_private(&self) -> anyhow::Result<()> {
        let key = self.pairing_dir().join("station.key");
        if let Ok(meta) = std::fs::metadata(&key)
            && let Some(mode) = session::platform::open_to_others(&meta)
        {
            bail!(
                "{} is readable by other users (mode {mode:o}); run `chmod 600` on it",
                key.display(),
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn credential() -> Credential {
        Credential {
            station_id: "st-1".into(),
            patient_id: "p-0042".into(),
            ca_pem: "CA".into(),
            cert_pem: "CERT".into(),
            key_pem: "KEY".into(),
            server_name: "clinic.example".into(),
            patient_pseudonym: Some("P-0042".into()),
        }
    }

    #[test]
    fn the_pseudonym_is_kept_and_a_pairing_made_before_it_was_sent_still_reads() {
        let tmp = tempfile::tempdir().unwrap();
        let home = Home::at(tmp.path().join("home"));
        let saved = home
            .save_pairing("clinic.example:7878", &credential(), 1)
            .unwrap();
        let note = home.pairing().unwrap().unwrap().clinic_note();
        assert_eq!(
            (note.patient_pseudonym.as_str(), note.clinic.as_str()),
            ("P-0042", "clinic.example")
        );
        let old = toml::to_string(&Pairing {
            patient_pseudonym: None,
            ..saved
        })
        .unwrap();
        assert!(!old.contains("pseudonym"), "{old}");
        std::fs::write(home.dir().join("pairing/hub.toml"), old).unwrap();
        let read = home.pairing().unwrap().unwrap();
        assert_eq!(read.patient_pseudonym, None);
        assert_eq!(read.clinic_note().patient_pseudonym, "");
    }

    #[cfg(unix)]
    #[test]
    fn a_saved_pairing_reads_back_and_its_files_are_private() {
        use std::os::unix::fs::PermissionsExt;
        let tmp = tempfile::tempdir().unwrap();
        let home = Home::at(tmp.path().join("home"));
        assert_eq!(home.pairing().unwrap(), None);
        let saved = home
            .save_pairing("clinic.example:7878", &credential(), 1_795_000_000_000)
            .unwrap();
        assert_eq!(home.pairing().unwrap(), Some(saved));
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(home.dir()), 0o700);
        assert_eq!(mode(&home.dir().join("pairing")), 0o700);
        for f in ["ca.pem", "station.crt", "station.key", "hub.toml"] {
            assert_eq!(mode(&home.dir().join("pairing").join(f)), 0o600, "{f}");
        }
        home.check_private().unwrap();
        std::fs::set_permissions(
            home.dir().join("pairing/station.key"),
            std::fs::Permissions::from_mode(0o644),
        )
        .unwrap();
        assert!(
            home.check_private()
                .unwrap_err()
                .to_string()
                .contains("chmod 600")
        );
    }

    #[test]
    fn a_kept_regimen_names_its_prescriber_until_a_regimen_without_one_replaces_it() {
        let tmp = tempfile::tempdir().unwrap();
        let home = Home::at(tmp.path());
        let regimen = |by: Option<&str>| netlink::Regimen {
            id: "p-v1".into(),
            toml: "[[exercise]]\nkind = \"sine\"\n".into(),
            prescribed_by: by.map(str::to_owned),
        };
        assert_eq!(home.regimen_prescriber(), None);
        home.keep_regimen(&regimen(Some("ana@clinic.example")))
            .unwrap();
        assert_eq!(
            home.regimen_prescriber().as_deref(),
            Some("ana@clinic.example")
        );
        assert!(
            std::fs::read_to_string(home.regimen_path())
                .unwrap()
                .contains("sine")
        );
        // An older hub's regimen says nobody: the earlier prescriber is not carried over.
        home.keep_regimen(&regimen(None)).unwrap();
        assert_eq!(home.regimen_prescriber(), None);
        // A damaged file (a control character) names nobody.
        std::fs::write(home.regimen_prescriber_path(), "ana\u{1b}[31m").unwrap();
        assert_eq!(home.regimen_prescriber(), None);
    }

    #[test]
    fn a_damaged_pairing_file_says_to_pair_again() {
        let tmp = tempfile::tempdir().unwrap();
        let home = Home::at(tmp.path());
        std::fs::create_dir_all(tmp.path().join("pairing")).unwrap();
        std::fs::write(tmp.path().join("pairing/hub.toml"), "hub = 3").unwrap();
        assert!(format!("{:#}", home.pairing().unwrap_err()).contains("pair again"));
    }
}
