-- Issue 28 part C. Same portable SQL subset as 0001 (TEXT ids, BIGINT ms times, NULL: not
-- answered / not yet).
--
-- The patient's answers on a session's end screen (netlink `Bye.checkin`), one row per
-- session; each answer optional. A repeated Bye writes the same row again.
CREATE TABLE session_checkins (
    session_id TEXT PRIMARY KEY REFERENCES sessions (session_id),
    patient_id TEXT NOT NULL REFERENCES patients (id),
    started_unix_ms BIGINT NOT NULL,
    pain_0_10 BIGINT,
    tiredness_0_10 BIGINT,
    difficulty TEXT,
    received_at_ms BIGINT NOT NULL
);
CREATE INDEX session_checkins_by_patient ON session_checkins (patient_id, started_unix_ms);

-- A therapist's short note to a patient (plain text, at most 500 characters), pushed to the
-- patient's station and shown on the start card of the next session; the station says when.
CREATE TABLE patient_messages (
    id TEXT PRIMARY KEY,
    patient_id TEXT NOT NULL REFERENCES patients (id),
    therapist_id TEXT NOT NULL REFERENCES therapists (id),
    body TEXT NOT NULL,
    created_at_ms BIGINT NOT NULL,
    seen_at_ms BIGINT
);
CREATE INDEX patient_messages_by_patient ON patient_messages (patient_id, created_at_ms);
