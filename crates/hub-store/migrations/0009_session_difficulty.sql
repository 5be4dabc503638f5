-- Issue 28 (difficulty that follows the patient). Same portable SQL subset as 0001 (TEXT ids,
-- BIGINT ms times, floats DOUBLE PRECISION, NULL: not known).
--
-- The difficulty a session ran at (netlink `Bye.difficulty`, sent when its regimen has a
-- `[difficulty]` table), its change from the session before and why, with the session's
-- success rate; one row per session. A repeated Bye writes the same row again.
CREATE TABLE session_difficulty (
    session_id TEXT PRIMARY KEY REFERENCES sessions (session_id),
    patient_id TEXT NOT NULL REFERENCES patients (id),
    started_unix_ms BIGINT NOT NULL,
    difficulty DOUBLE PRECISION NOT NULL,
    change DOUBLE PRECISION NOT NULL,
    reason TEXT NOT NULL,
    success_rate DOUBLE PRECISION,
    received_at_ms BIGINT NOT NULL
);
CREATE INDEX session_difficulty_by_patient ON session_difficulty (patient_id, started_unix_ms);
