-- Issue 29 (session notes by the therapist). Same portable SQL subset as 0001 (TEXT ids,
-- BIGINT ms times).
--
-- A therapist's note on one session, for the clinic's own record (never sent to the
-- station): plain text, 1 to 2 000 characters, no control characters but line breaks.
CREATE TABLE session_notes (
    id TEXT PRIMARY KEY,
    session_id TEXT NOT NULL REFERENCES sessions (session_id),
    therapist_id TEXT NOT NULL REFERENCES therapists (id),
    body TEXT NOT NULL,
    created_at_ms BIGINT NOT NULL
);
CREATE INDEX session_notes_by_session ON session_notes (session_id, created_at_ms);
