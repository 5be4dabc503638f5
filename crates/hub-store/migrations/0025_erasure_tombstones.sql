-- Issue 45 (erasures that stay erased). Same portable SQL subset as 0001.
--
-- One row per patient erased (`hub patient erase`): the patient's internal id, the keyed hash
-- (HMAC-SHA-256, keyed from the clinic's CA key) of their pseudonym, when and by whom — none
-- of the patient's data. A restore of an older backup, and every hub start, erases again any
-- patient a tombstone names (crates/hub/src/patient_data/tombstones.rs). The same rows are
-- kept in the ledger file `erasures.ndjson` of the data directory, which a restore does not
-- overwrite. The column is `erased_patient_id`, not `patient_id`: a patient's export and
-- erasure find their rows by a `patient_id` column, and a tombstone is not one of them.
CREATE TABLE erasure_tombstones (
    erased_patient_id TEXT PRIMARY KEY,
    pseudonym_hmac TEXT NOT NULL,
    erased_at_ms BIGINT NOT NULL,
    erased_by TEXT NOT NULL
);
