-- A wrong pairing secret no longer kills a code (anyone knowing its public half could burn a
-- patient's code); each attempt makes the code wait before the next (see db/pairing.rs).
-- `failed_attempts` now counts every attempt begun.
ALTER TABLE pairing_codes ADD COLUMN next_attempt_at_ms BIGINT;
