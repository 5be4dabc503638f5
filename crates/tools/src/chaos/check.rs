//! The end of the chaos day: what the stations owe (their ledger) against what the clinic's
//! database and recordings hold: the data directory, or the S3 store read through a
//! [`RecordingStore`] of the check's own (`--s3`: verified from the store, not a hub's disk).

use std::collections::{HashMap, HashSet};

use hub::db::Db;
use hub::recordings::RecordingStore;

use super::station::StationLedger;

/// The figures and the violations.
#[derive(Debug, Default)]
pub struct Verdict {
    /// Stations paired (credential saved).
    pub paired: usize,
    /// Stations that finished their day.
    pub finished: usize,
    /// The slowest finish, s.
    pub slowest_s: f64,
    /// Sessions with summaries.
    pub sessions: usize,
    /// Summaries produced by the stations.
    pub produced: u64,
    /// Summaries stored exactly once (of those produced).
    pub stored_once: u64,
    /// Summaries produced and not stored.
    pub missing: u64,
    /// Summaries stored more than once, or stored and never produced.
    pub extra: u64,
    /// Recordings the stations wrote.
    pub recordings: usize,
    /// Of them, stored with the station's SHA-256, re-hashed from where they are kept.
    pub recordings_verified: usize,
    /// Where they were re-hashed from.
    pub verified_from: &'static str,
    /// Audit entries found: pairings, uploads.
    pub audited: (usize, usize),
    /// Every broken promise, one line each.
    pub violations: Vec<String>,
}

/// Checks everything; database errors are violations too (the check must not hide them).
pub async fn check(db: &Db, ledger: &[StationLedger], store: Option<&RecordingStore>) -> Verdict {
    let mut v = Verdict {
        verified_from: if store.is_some() {
            "from the S3 store"
        } else {
            "from the data directory"
        },
        ..Verdict::default()
    };
    let audit = match db.audit_log(10_000).await {
        Ok(entries) => {
            if entries.len() >= 10_000 {
                v.violations
                    .push("the audit log has 10 000 entries or more: not all were read".into());
            }
            entries
                .into_iter()
                .map(|e| (e.action, e.target))
                .collect::<HashSet<_>>()
        }
        Err(e) => {
            v.violations.push(format!("audit log unreadable: {e}"));
            HashSet::new()
        }
    };
    for (i, st) in ledger.iter().enumerate() {
        match &st.finished_s {
            Some(t) => {
                v.finished += 1;
                v.slowest_s = v.slowest_s.max(*t);
            }
            None => v.violations.push(format!(
                "station {i} stuck ({}); last error: {}",
                st.phase,
                st.last_error.as_deref().unwrap_or("none")
            )),
        }
        let Some(station_id) = &st.station_id else {
            v.violations.push(format!("station {i} never paired"));
            continue;
        };
        v.paired += 1;
        if audit.contains(&("station_paired".to_owned(), station_id.clone())) {
            v.audited.0 += 1;
        } else {
            v.violations.push(format!(
                "station {i} ({station_id}): no station_paired entry in the audit log"
            ));
        }
        check_sessions(db, (i, station_id), st, (&audit, store), &mut v).await;
    }
    v
}

async fn check_sessions(
    db: &Db,
    (i, station_id): (usize, &str),
    st: &StationLedger,
    (audit, store): (&HashSet<(String, String)>, Option<&RecordingStore>),
    v: &mut Verdict,
) {
    let known: HashMap<&str, u64> = st
        .sessions
        .iter()
        .map(|s| (s.session_id.as_str(), s.produced))
        .collect();
    match db.sessions_of(&st.patient_id).await {
        Ok(rows) => {
            for row in rows
                .iter()
                .filter(|r| !known.contains_key(r.session_id.as_str()))
            {
                v.violations.push(format!(
                    "station {i}: the hub holds session {} that no station ran",
                    row.session_id
                ));
            }
        }
        Err(e) => v
            .violations
            .push(format!("station {i}: sessions unreadable: {e}")),
    }
    for s in &st.sessions {
        v.produced += s.produced;
        if s.produced > 0 {
            v.sessions += 1;
        }
        match db.summaries_of(&s.session_id).await {
            Ok(stored) => {
                let seqs: Vec<u64> = stored.iter().map(|x| x.seq).collect();
                let distinct: HashSet<u64> = seqs.iter().copied().collect();
                let once = (0..s.produced).filter(|q| distinct.contains(q)).count() as u64;
                let extra = seqs.len() as u64 - once;
                v.stored_once += once;
                v.missing += s.produced - once;
                v.extra += extra;
                if once != s.produced || extra > 0 {
                    v.violations.push(format!(
                        "session {}: {} produced, {} stored ({} distinct, {} missing, {} extra)",
                        s.session_id,
                        s.produced,
                        seqs.len(),
                        distinct.len(),
                        s.produced - once,
                        extra
                    ));
                }
            }
            Err(e) => v.violations.push(format!(
                "session {}: summaries unreadable: {e}",
                s.session_id
            )),
        }
        if let Some((sha, size)) = &s.recording {
            v.recordings += 1;
            let at = (station_id, s.session_id.as_str());
            check_recording(db, at, (sha, *size), (audit, store), v).await;
        }
    }
}

async fn check_recording(
    db: &Db,
    (station_id, session_id): (&str, &str),
    (sha, size): (&str, u64),
    (audit, store): (&HashSet<(String, String)>, Option<&RecordingStore>),
    v: &mut Verdict,
) {
    if audit.contains(&("recording_uploaded".to_owned(), session_id.to_owned())) {
        v.audited.1 += 1;
    } else {
        v.violations.push(format!(
            "recording of {session_id}: no recording_uploaded entry in the audit log"
        ));
    }
    let row = match db.recording(session_id).await {
        Ok(Some(r)) => r,
        Ok(None) => {
            v.violations.push(format!(
                "recording of {session_id}: the station was told it is stored, the database has no row"
            ));
            return;
        }
        Err(e) => {
            v.violations
                .push(format!("recording of {session_id}: unreadable: {e}"));
            return;
        }
    };
    let on_disk = match store {
        Some(store) => match store.held(station_id, session_id).await {
            Ok(Some(held)) => Ok(held),
            Ok(None) => Err("not in the store".to_owned()),
            Err(e) => Err(e.to_string()),
        },
        None => {
            netlink::upload::file_sha256(std::path::Path::new(&row.path)).map_err(|e| e.to_string())
        }
    };
    let size_ok = u64::try_from(row.size_bytes).is_ok_and(|s| s == size);
    match on_disk {
        Ok((n, h)) if row.complete && row.sha256 == sha && size_ok && h == sha && n == size => {
            v.recordings_verified += 1;
        }
        Ok((n, h)) => v.violations.push(format!(
            "recording of {session_id}: the station sent {size} bytes sha256 {sha}; the database \
             says {} bytes sha256 {} (complete {}), what is kept has {n} bytes sha256 {h}",
            row.size_bytes, row.sha256, row.complete
        )),
        Err(e) => v.violations.push(format!(
            "recording of {session_id}: {} unreadable: {e}",
            row.path
        )),
    }
}
