-- Issue 28 (the end screen's check-in). Same portable SQL subset as 0001 (TEXT ids,
-- BIGINT ms times, NULL: not answered).
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
