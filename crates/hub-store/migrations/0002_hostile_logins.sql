-- Logins that cannot be turned against users or the clinic (issue 25). Same portable SQL
-- subset as 0001: TEXT keys, BIGINT milliseconds and 0/1 flags.

-- A one-time password (`hub init`, `hub therapist add`) must be changed at the first login;
-- until then the API answers 403 to everything but /api/me, /api/me/password and /api/logout.
ALTER TABLE therapists ADD COLUMN must_change_password BIGINT NOT NULL DEFAULT 0;

-- A revoked therapist can no longer log in; their login sessions (and live streams) end.
ALTER TABLE therapists ADD COLUMN revoked_at_ms BIGINT;

-- Login throttling with growing delays, one row per key: `addr:<address>` (the client's
-- address, IPv6 by /64), `acct:<sha256 of the e-mail>` (whether or not such an account
-- exists) and `dev:<sha256 of a device cookie>`. An attempt is evaluated only if it can
-- advance `failures` while `next_allowed_ms <= now` (one conditional upsert, before hashing);
-- a success gives the attempt back.
CREATE TABLE login_throttle (
    key TEXT PRIMARY KEY,
    failures BIGINT NOT NULL,
    next_allowed_ms BIGINT NOT NULL,
    updated_at_ms BIGINT NOT NULL
);
CREATE INDEX login_throttle_by_update ON login_throttle (updated_at_ms);

-- Device cookies (OWASP's "device cookie" defence): a browser that logged in to an account
-- before presents one, and is then throttled on its own instead of by the account's delay,
-- which an attacker elsewhere can keep up.
CREATE TABLE login_devices (
    token_hash TEXT PRIMARY KEY,
    therapist_id TEXT NOT NULL REFERENCES therapists (id),
    created_at_ms BIGINT NOT NULL,
    expires_at_ms BIGINT NOT NULL
);
CREATE INDEX login_devices_by_therapist ON login_devices (therapist_id);

CREATE INDEX web_sessions_by_therapist ON web_sessions (therapist_id);
