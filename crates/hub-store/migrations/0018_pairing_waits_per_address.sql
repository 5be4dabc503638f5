-- Issue 44: the wait between attempts at a pairing code is kept per code and address, not per
-- code, so whoever knows a code's public half cannot keep it waiting for everyone: the right
-- station from another address still gets its real try. The code's own failed_attempts keeps
-- counting every attempt; next_attempt_at_ms of 0003 is no longer read.
-- address: the client's IPv4 address, or its IPv6 /64 (db::logins::address_key).
CREATE TABLE pairing_attempt_waits (
    code_id TEXT NOT NULL,
    address TEXT NOT NULL,
    attempts BIGINT NOT NULL,
    next_attempt_at_ms BIGINT NOT NULL,
    PRIMARY KEY (code_id, address)
);
