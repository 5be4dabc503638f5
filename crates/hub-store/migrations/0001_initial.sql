-- The hub's schema, version 1. Portable SQL: the same file runs on SQLite and PostgreSQL.
-- Ids are TEXT made in Rust, times are BIGINT milliseconds since the Unix epoch, flags are
-- BIGINT 0/1, floats DOUBLE PRECISION. Never edit an applied migration: add a new file.

CREATE TABLE therapists (
    id TEXT PRIMARY KEY,
    email TEXT NOT NULL UNIQUE,
    password_hash TEXT NOT NULL,
    role TEXT NOT NULL CHECK (role IN ('admin', 'therapist')),
    created_at_ms BIGINT NOT NULL,
    failed_logins BIGINT NOT NULL DEFAULT 0,
    locked_until_ms BIGINT
);

CREATE TABLE patients (
    id TEXT PRIMARY KEY,
    pseudonym TEXT NOT NULL UNIQUE,
    therapist_id TEXT REFERENCES therapists (id),
    created_at_ms BIGINT NOT NULL
);
CREATE INDEX patients_by_therapist ON patients (therapist_id);

CREATE TABLE pairing_codes (
    -- The public half of the code; the secret half is the SPAKE2 password the hub needs in
    -- clear to run the exchange (a code lives at most its TTL and pairs once).
    code_id TEXT PRIMARY KEY,
    secret TEXT NOT NULL,
    patient_id TEXT NOT NULL REFERENCES patients (id),
    created_at_ms BIGINT NOT NULL,
    expires_at_ms BIGINT NOT NULL,
    used_at_ms BIGINT,
    failed_attempts BIGINT NOT NULL DEFAULT 0
);

CREATE TABLE stations (
    station_id TEXT PRIMARY KEY,
    patient_id TEXT NOT NULL REFERENCES patients (id),
    cert_fingerprint TEXT NOT NULL UNIQUE,
    paired_at_ms BIGINT NOT NULL,
    last_seen_ms BIGINT,
    revoked_at_ms BIGINT
);

CREATE TABLE sessions (
    session_id TEXT PRIMARY KEY,
    station_id TEXT NOT NULL REFERENCES stations (station_id),
    patient_id TEXT NOT NULL REFERENCES patients (id),
    exercise TEXT NOT NULL,
    started_unix_ms BIGINT NOT NULL,
    software_version TEXT NOT NULL,
    opened_at_ms BIGINT NOT NULL,
    closed_at_ms BIGINT,
    end_reason TEXT,
    final_seq BIGINT,
    last_seq BIGINT
);
CREATE INDEX sessions_by_patient ON sessions (patient_id, started_unix_ms);

CREATE TABLE summaries (
    session_id TEXT NOT NULL REFERENCES sessions (session_id),
    seq BIGINT NOT NULL,
    t_s DOUBLE PRECISION NOT NULL,
    body TEXT NOT NULL,
    stored_at_ms BIGINT NOT NULL,
    PRIMARY KEY (session_id, seq)
);

CREATE TABLE session_metrics (
    session_id TEXT NOT NULL REFERENCES sessions (session_id),
    name TEXT NOT NULL,
    value DOUBLE PRECISION NOT NULL,
    PRIMARY KEY (session_id, name)
);

CREATE TABLE regimens (
    patient_id TEXT NOT NULL REFERENCES patients (id),
    version BIGINT NOT NULL,
    toml TEXT NOT NULL,
    prescribed_by TEXT NOT NULL REFERENCES therapists (id),
    prescribed_at_ms BIGINT NOT NULL,
    PRIMARY KEY (patient_id, version)
);

CREATE TABLE recordings (
    session_id TEXT PRIMARY KEY REFERENCES sessions (session_id),
    sha256 TEXT NOT NULL,
    size_bytes BIGINT NOT NULL,
    received_bytes BIGINT NOT NULL,
    path TEXT NOT NULL,
    complete BIGINT NOT NULL DEFAULT 0
);

CREATE TABLE audit_log (
    id TEXT PRIMARY KEY,
    at_ms BIGINT NOT NULL,
    actor TEXT NOT NULL,
    action TEXT NOT NULL,
    target TEXT NOT NULL,
    detail TEXT NOT NULL
);
CREATE INDEX audit_log_by_time ON audit_log (at_ms);

CREATE TABLE web_sessions (
    token_hash TEXT PRIMARY KEY,
    therapist_id TEXT NOT NULL REFERENCES therapists (id),
    created_at_ms BIGINT NOT NULL,
    expires_at_ms BIGINT NOT NULL
);
