//! `telerehab hub backup`, `hub restore`, `hub export --fhir`, `hub patient export` and `hub
//! patient erase` (the work is `crate::backup`'s, `hub_care::patients`' and `crate::patient_data`'s):
//! what was saved, restored, exported or erased, in numbers a clinic's administrator can check.

use std::path::Path;

use crate::backup::{Manifest, Sealing};
use crate::clinic::Clinic;

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

/// `hub backup`: back the clinic at `data` up into `out` (encrypted to hub.toml's recipients
/// unless `unencrypted`), and audit it.
pub async fn backup(
    data: &Path,
    db: Option<&str>,
    out: &Path,
    unencrypted: bool,
) -> anyhow::Result<()> {
    let clinic = Clinic::at(data);
    let sealing = if unencrypted {
        Sealing::Clear
    } else {
        Sealing::to_recipients(&clinic.config()?.backup_recipients, data)?
    };
    let m = crate::backup::backup(&clinic, db, out, &sealing).await?;
    let size = std::fs::metadata(out).map(|m| m.len()).unwrap_or(0);
    let sealed = match &sealing {
        Sealing::To(r) => format!("encrypted to {} recipients", r.len()),
        Sealing::Clear => "UNENCRYPTED".to_owned(),
    };
    let audit = clinic.open_db(db).await?;
    audit
        .audit(
            "cli",
            "backup",
            &out.display().to_string(),
            &format!(
                "{} database, schema {}, {sealed}",
                m.backend, m.schema_version
            ),
            super::now_ms(),
        )
        .await?;
    audit.close().await;
    println!(
        "backup {} ({:.1} MB, {sealed}): {} database (schema {}; {} tables), {}",
        out.display(),
        size as f64 / 1e6,
        m.backend,
        m.schema_version,
        m.rows.len(),
        contents(&m)
    );
    match sealing {
        Sealing::To(_) => println!(
            "restore it with the clinic's identity file: telerehab hub restore --from {} --identity FILE --data NEW_DIR (or decrypt it with `age -d -i FILE`)",
            out.display()
        ),
        Sealing::Clear => println!(
            "it is NOT encrypted and holds the clinic's CA key and every patient's data: keep it where only the clinic's administrators can read it"
        ),
    }
    Ok(())
}

/// `hub backup-key`: a new key pair (the identity into `identity_out`), or `recipient`, added
/// to hub.toml's backup recipients.
pub fn backup_key(
    data: &Path,
    identity_out: Option<&Path>,
    recipient: Option<&str>,
) -> anyhow::Result<()> {
    let clinic = Clinic::at(data);
    clinic.config()?;
    let recipient = match (identity_out, recipient) {
        (_, Some(r)) => r.trim().to_owned(),
        (Some(path), None) => {
            let (text, recipient) = crate::backup::new_key_pair();
            let mut options = std::fs::OpenOptions::new();
            options.write(true).create_new(true);
            #[cfg(unix)]
            std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
            let mut file = options.open(path).map_err(|e| {
                anyhow::anyhow!(
                    "cannot create {} ({e}); an identity file is never overwritten",
                    path.display()
                )
            })?;
            std::io::Write::write_all(&mut file, text.as_bytes())?;
            file.sync_all()?;
            println!("identity (secret key) written to {}", path.display());
            println!(
                "keep it OFFLINE, away from this machine (a USB key in the clinic's safe, a password manager): without it no backup can be restored, and with it anyone can read them"
            );
            recipient
        }
        (None, None) => anyhow::bail!("name --identity-out FILE or --recipient age1…"),
    };
    crate::backup::add_recipient(&clinic, &recipient)?;
    println!("backups are now encrypted to {recipient} (hub.toml's backup_recipients)");
    Ok(())
}

/// `hub restore`: restore `from` into the new data directory `data`.
pub async fn restore(
    from: &Path,
    data: &Path,
    how: crate::backup::RestoreFrom<'_>,
) -> anyhow::Result<()> {
    let r = crate::backup::restore(from, data, how, super::now_ms()).await?;
    let m = &r.manifest;
    if !r.encrypted {
        eprintln!(
            "warning: {} is not encrypted (format {}): anyone who had the file could read the clinic's CA key and every patient's data; make encrypted backups from now on (`telerehab hub backup-key`)",
            from.display(),
            m.format
        );
    }
    println!(
        "restored into {}: {} database (schema {}), {}; every table's rows and every recording's checksum match the backup",
        data.display(),
        m.backend,
        m.schema_version,
        contents(m)
    );
    println!(
        "erasures re-applied: {} (patients erased after this backup was taken, erased again); {} erasures on record",
        r.erasures.erased, r.erasures.tombstones
    );
    println!(
        "serve it with: telerehab hub serve --data {}",
        data.display()
    );
    Ok(())
}

/// What an export or erasure covered, in one line.
fn covered_said(c: &crate::patient_data::Covered) -> String {
    let rows: usize = c.rows.values().sum();
    format!(
        "sessions {}, summaries {}, regimen versions {}, messages {}, audit entries {}; {rows} rows in {} tables; recording files {} ({:.1} MB)",
        c.rows_of("sessions"),
        c.rows_of("summaries"),
        c.rows_of("regimens"),
        c.rows_of("patient_messages"),
        c.rows_of("audit_log"),
        c.rows.len(),
        c.recording_files,
        c.recording_bytes as f64 / 1e6
    )
}

/// `hub patient export`.
pub async fn export_patient(
    data: &Path,
    db: Option<&str>,
    pseudonym: &str,
    out: &Path,
) -> anyhow::Result<()> {
    let clinic = Clinic::at(data);
    let handle = clinic.open_db(db).await?;
    let done = crate::patient_data::export(&clinic, &handle, pseudonym, out, super::now_ms()).await;
    handle.close().await;
    let c = done?;
    println!(
        "exported {pseudonym} to {}: {}",
        out.display(),
        covered_said(&c)
    );
    Ok(())
}

/// `hub patient erase`: after the pseudonym is confirmed (`--confirm`, or typed on a terminal).
pub async fn erase_patient(
    data: &Path,
    db: Option<&str>,
    pseudonym: &str,
    confirm: Option<String>,
) -> anyhow::Result<()> {
    use std::io::IsTerminal;
    let confirmed = match confirm {
        Some(c) => c,
        None if std::io::stdin().is_terminal() => {
            println!(
                "This erases everything the hub holds about {pseudonym}, recordings included, and revokes their stations. It cannot be undone."
            );
            print!("Type the pseudonym to confirm: ");
            std::io::Write::flush(&mut std::io::stdout())?;
            let mut line = String::new();
            std::io::stdin().read_line(&mut line)?;
            line.trim().to_owned()
        }
        None => anyhow::bail!(
            "erasing {pseudonym} cannot be undone: confirm with --confirm {pseudonym} (export first if the patient wants a copy)"
        ),
    };
    anyhow::ensure!(
        confirmed == pseudonym,
        "not erased: the confirmation {confirmed:?} is not the pseudonym {pseudonym:?}"
    );
    let clinic = Clinic::at(data);
    let handle = clinic.open_db(db).await?;
    let done = crate::patient_data::erase(&clinic, &handle, pseudonym, super::now_ms()).await;
    handle.close().await;
    let c = done?;
    println!(
        "erased {pseudonym}: {}; their stations are revoked",
        covered_said(&c)
    );
    println!(
        "the erasure is recorded in {} (no data of theirs, a keyed hash of the pseudonym): keep a copy of it with the backups' identity file, and give it to `hub restore --erasures` when restoring a backup on another machine",
        crate::patient_data::tombstones::ledger_path(&clinic).display()
    );
    Ok(())
}

/// `hub export --fhir [--lang de]`: the patient's FHIR R4 bundle, its narratives in `language`
/// (English for none), into `out` (`-`: standard output).
pub async fn export_fhir(
    data: &super::DataArgs,
    pseudonym: &str,
    language: Option<&str>,
    out: &Path,
) -> anyhow::Result<()> {
    let clinic = Clinic::at(&data.data);
    let base = clinic.config()?.fhir_base()?;
    let db = clinic.open_db(data.db.as_deref()).await?;
    let done =
        hub_care::patients::export_fhir(&db, pseudonym, super::now_ms(), &base, language).await;
    db.close().await;
    let (bundle, sessions) = done?;
    if out == Path::new("-") {
        println!("{bundle}");
    } else {
        std::fs::write(out, &bundle)
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", out.display()))?;
        println!(
            "FHIR R4 bundle of {pseudonym} ({sessions} sessions) written to {}",
            out.display()
        );
    }
    Ok(())
}
