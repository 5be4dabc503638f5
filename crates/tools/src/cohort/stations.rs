//! The cohort's stations: each a home of its own, paired with `telerehab pair` and running
//! its weekly sessions as `telerehab run --sim --headless --speed max --no-record` child
//! processes, the real session code and link: the assessment runs because the regimen's
//! `[assessment]` makes it due, its results reach the hub in the session's `Bye`. Nothing is
//! recorded: the results are all in the `Bye`, and a 26 MB recording a session would take
//! longer to upload than the session to run.
//!
//! **A week passes.** The station decides whether the assessment is due from its history
//! (`assessments.jsonl`: when each assessment ended). Between two occasions the cohort moves
//! every entry of that history back by [`WEEK_MS`], which is what the history would say had
//! the station's clock moved on a week: the results themselves are never touched.

use std::path::{Path, PathBuf};
use std::process::Stdio;

use anyhow::{Context, bail};
use assist::human::HumanArmParams;

use session::assessment::{Entry, history_path};

/// A week, ms.
pub const WEEK_MS: u64 = 7 * 86_400_000;

/// The regimen every cohort station runs: the assessment weekly, then a short dial (a
/// regimen needs an exercise of its own).
pub const REGIMEN: &str =
    "[assessment]\nevery_days = 7\n\n[[exercise]]\nkind = \"dial\"\nduration_s = 10.0\n";

/// One cohort station.
#[derive(Debug, Clone)]
pub struct Station {
    /// The `telerehab` binary.
    pub exe: PathBuf,
    /// Its home.
    pub home: PathBuf,
    /// The regimen file.
    pub regimen: PathBuf,
}

/// The station configuration of one occasion: the simulated patient's arm.
#[derive(serde::Serialize)]
struct OccasionConfig<'a> {
    sim_patient: &'a HumanArmParams,
}

impl Station {
    async fn telerehab(&self, args: &[&str], log: &Path) -> anyhow::Result<()> {
        let out = std::fs::File::create(log)
            .with_context(|| format!("cannot write {}", log.display()))?;
        let status = tokio::process::Command::new(&self.exe)
            .args(args)
            .arg("--home")
            .arg(&self.home)
            .env_remove("TELEREHAB_HOME")
            .stdin(Stdio::null())
            .stdout(Stdio::from(out.try_clone()?))
            .stderr(Stdio::from(out))
            .kill_on_drop(true)
            .status()
            .await
            .with_context(|| format!("cannot start {}", self.exe.display()))?;
        if !status.success() {
            let said = std::fs::read_to_string(log).unwrap_or_default();
            let tail: Vec<&str> = said.lines().rev().take(5).collect();
            bail!(
                "`telerehab {}` failed ({status}): {}",
                args.join(" "),
                tail.into_iter().rev().collect::<Vec<_>>().join(" | ")
            );
        }
        Ok(())
    }

    /// Pairs with the hub at `hub` by `code` (retried for up to 30 s while the hub starts).
    pub async fn pair(&self, hub: &str, code: &str) -> anyhow::Result<()> {
        station::home::private_dir(&self.home)?;
        let log = self.home.join("pair.log");
        let mut tries = 0;
        loop {
            match self
                .telerehab(&["pair", "--hub", hub, "--code", code], &log)
                .await
            {
                Ok(()) => return Ok(()),
                Err(e) if tries < 60 && format!("{e:#}").contains("cannot reach the hub") => {
                    tries += 1;
                    tokio::time::sleep(std::time::Duration::from_millis(500)).await;
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// Runs occasion `week`: the patient's arm of that day, the session's seed; the
    /// assessment must have run whole (a new line in the history).
    pub async fn run_week(
        &self,
        week: usize,
        arm: &HumanArmParams,
        seed: u64,
    ) -> anyhow::Result<()> {
        let config = self.home.join(format!("week-{week}.toml"));
        let text = toml::to_string(&OccasionConfig { sim_patient: arm })
            .context("cannot write the occasion's configuration")?;
        session::files::write_private(&config, text.as_bytes())?;
        let before = history_len(&self.home);
        let (config, regimen, seed) = (
            config.display().to_string(),
            self.regimen.display().to_string(),
            seed.to_string(),
        );
        let args = [
            "run",
            "--sim",
            "--headless",
            "--speed",
            "max",
            "--no-record",
            "--config",
            &config,
            "--regimen",
            &regimen,
            "--seed",
            &seed,
        ];
        self.telerehab(&args, &self.home.join(format!("week-{week}.log")))
            .await?;
        if history_len(&self.home) != before + 1 {
            bail!(
                "week {week} of {}: the session ran no whole assessment (see its log)",
                self.home.display()
            );
        }
        Ok(())
    }

    /// Delivers what the sessions left in the station's queue (`telerehab sync`): a session
    /// at full speed outruns the hub, and the station keeps on disk what the hub has not
    /// acknowledged when the session ends (the next session sends it first; the last one's
    /// waits for this). Tried three times.
    pub async fn sync(&self) -> anyhow::Result<()> {
        let log = self.home.join("sync.log");
        let mut tries = 0;
        loop {
            match self.telerehab(&["sync"], &log).await {
                Ok(()) => return Ok(()),
                Err(e) if tries < 2 => {
                    tries += 1;
                    tracing::warn!("{}: {e:#}; again", self.home.display());
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// A week passes: the history's assessments ended a week earlier than it says.
    pub fn a_week_passes(&self) -> anyhow::Result<()> {
        let path = history_path(&self.home);
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let mut out = String::new();
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            let mut e: Entry = serde_json::from_str(line)
                .with_context(|| format!("{}: unreadable line {line:?}", path.display()))?;
            e.unix_ms = e.unix_ms.saturating_sub(WEEK_MS);
            out.push_str(&serde_json::to_string(&e)?);
            out.push('\n');
        }
        session::files::write_private(&path, out.as_bytes())
    }
}

/// Assessments in the history of the home at `dir`.
fn history_len(dir: &Path) -> usize {
    std::fs::read_to_string(history_path(dir))
        .map_or(0, |t| t.lines().filter(|l| !l.trim().is_empty()).count())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_week_passing_moves_every_assessment_of_the_history_back_a_week_and_makes_it_due() {
        let dir = tempfile::tempdir().unwrap();
        let now = 1_800_000_000_000;
        let entry = Entry {
            unix_ms: now,
            patient_id: "p1".into(),
            protocol: 1,
            seed: 3,
        };
        let path = history_path(dir.path());
        std::fs::write(
            &path,
            format!("{}\n", serde_json::to_string(&entry).unwrap()),
        )
        .unwrap();
        let schedule = regimen::Regimen::from_toml(REGIMEN, "cohort")
            .unwrap()
            .assessment
            .unwrap();
        let last = session::assessment::last_unix_ms(&path, "p1");
        assert!(!schedule.is_due(last, now + 1_000));
        let station = Station {
            exe: PathBuf::new(),
            home: dir.path().to_owned(),
            regimen: PathBuf::new(),
        };
        station.a_week_passes().unwrap();
        let last = session::assessment::last_unix_ms(&path, "p1");
        assert_eq!(last, Some(now - WEEK_MS));
        assert!(schedule.is_due(last, now + 1_000));
        assert_eq!(history_len(dir.path()), 1);
    }
}
