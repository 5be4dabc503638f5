//! `telerehab hub backup` and `hub restore` (the work is `hub::backup`'s): what was saved or
//! restored, in numbers a clinic's administrator can check.

use std::path::Path;

use hub::backup::Manifest;
use hub::clinic::Clinic;

/// The tables a clinic recognises, with the words for their rows, as a restore reports them.
const TABLES_SAID: [(&str, &str); 6] = [
    ("patients", "patients"),
    ("sessions", "sessions"),
    ("summaries", "summaries"),
    ("regimens", "regimen versions"),
    ("recordings", "recordings stored"),
    ("audit_log", "audit entries"),
];

/// What a manifest holds, in one line.
fn contents(m: &Manifest) -> String {
    let mut parts: Vec<String> = TABLES_SAID
        .iter()
        .filter(|(t, _)| m.rows.contains_key(*t))
        .map(|(t, words)| format!("{words} {}", m.rows_of(t)))
        .collect();
    parts.push(format!(
        "recording files {} ({:.1} MB)",
        m.recordings.len(),
        m.recording_bytes() as f64 / 1e6
    ));
    parts.join(", ")
}

/// `hub backup`: back the clinic at `data` up into `out`, and audit it.
pub async fn backup(data: &Path, db: Option<&str>, out: &Path) -> anyhow::Result<()> {
    let clinic = Clinic::at(data);
    let m = hub::backup::backup(&clinic, db, out).await?;
    let size = std::fs::metadata(out).map(|m| m.len()).unwrap_or(0);
    let audit = clinic.open_db(db).await?;
    audit
        .audit(
            "cli",
            "backup",
            &out.display().to_string(),
            &format!("{} database, schema {}", m.backend, m.schema_version),
            super::hub::now_ms(),
        )
        .await?;
    audit.close().await;
    println!(
        "backup {} ({:.1} MB): {} database (schema {}; {} tables), {}",
        out.display(),
        size as f64 / 1e6,
        m.backend,
        m.schema_version,
        m.rows.len(),
        contents(&m)
    );
    println!(
        "it holds the clinic's CA key: keep it where only the clinic's administrators can read it"
    );
    Ok(())
}

/// `hub restore`: restore `from` into the new data directory `data`.
pub async fn restore(from: &Path, data: &Path, db: Option<&str>) -> anyhow::Result<()> {
    let m = hub::backup::restore(from, data, db).await?;
    println!(
        "restored into {}: {} database (schema {}), {}; every table's rows and every recording's checksum match the backup",
        data.display(),
        m.backend,
        m.schema_version,
        contents(&m)
    );
    println!(
        "serve it with: telerehab hub serve --data {}",
        data.display()
    );
    Ok(())
}
