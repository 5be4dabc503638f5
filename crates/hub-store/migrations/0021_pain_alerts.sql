-- Issue 41 (pain that reaches someone). Same portable SQL subset as 0001 (TEXT ids, BIGINT
-- ms times).
--
-- A check-in's pain at or over the clinic's threshold is mailed to the patient's therapist
-- (admins when the patient has none). The mail waits here until the SMTP server has taken
-- it: one row per session, retried with a growing delay, never dropped.
CREATE TABLE pain_mail_outbox (
    session_id TEXT PRIMARY KEY REFERENCES sessions (session_id),
    patient_id TEXT NOT NULL REFERENCES patients (id),
    pain_0_10 BIGINT NOT NULL,
    created_at_ms BIGINT NOT NULL,
    attempts BIGINT NOT NULL DEFAULT 0,
    next_attempt_at_ms BIGINT NOT NULL,
    last_error TEXT,
    sent_at_ms BIGINT
);
CREATE INDEX pain_mail_outbox_pending ON pain_mail_outbox (sent_at_ms, next_attempt_at_ms);

-- The therapist cleared a patient to train again after a pain stop on the station (the
-- newest clearance per patient).
CREATE TABLE pain_clearances (
    patient_id TEXT PRIMARY KEY REFERENCES patients (id),
    cleared_at_ms BIGINT NOT NULL,
    therapist_id TEXT NOT NULL REFERENCES therapists (id)
);
