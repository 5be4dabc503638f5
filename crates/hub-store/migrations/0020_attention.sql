-- Issue 41 (needs attention today). Same portable SQL subset as 0001 (TEXT, BIGINT).
--
-- The clinic's thresholds for the caseload's alerts, one row a setting the clinic changed
-- (a missing key is at its default, crates/hub/src/attention/settings.rs). Other parts read
-- them too (the pain threshold: `hub::db::clinic_settings::pain_threshold`).
CREATE TABLE clinic_settings (
    key TEXT PRIMARY KEY,
    value BIGINT NOT NULL,
    updated_at_ms BIGINT NOT NULL,
    updated_by TEXT NOT NULL
);

-- A therapist's acknowledgement (until_ms NULL) or snooze (until_ms set) of one alert of
-- one patient: the alert stays quiet while its evidence (fingerprint) is unchanged, and a
-- snooze only until until_ms. The newest row of a (patient, alert) pair counts; older rows
-- are the record (each is audited too).
CREATE TABLE alert_acks (
    id TEXT PRIMARY KEY,
    patient_id TEXT NOT NULL REFERENCES patients (id),
    alert_key TEXT NOT NULL,
    fingerprint TEXT NOT NULL,
    until_ms BIGINT,
    note TEXT NOT NULL,
    therapist_id TEXT NOT NULL REFERENCES therapists (id),
    at_ms BIGINT NOT NULL
);
CREATE INDEX alert_acks_by_patient ON alert_acks (patient_id, alert_key, at_ms);
