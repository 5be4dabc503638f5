-- Familiar places of an account (issue 44): the client addresses (IPv4, IPv6 /64) from which
-- it logged in successfully. A login from one of them without a device cookie — a new
-- browser at the clinic or at home — is throttled on its own counter
-- (`place:<sha256 of account and address>` in login_throttle) instead of the account's, which
-- an attacker rotating addresses keeps at its longest delay. `account_key` is the account
-- throttle's key (`acct:<sha256 of the e-mail>`), so a place is found before the password is
-- checked. Places are forgotten after 90 days without a success, and only the most recent few
-- of an account are kept.
CREATE TABLE login_places (
    account_key TEXT NOT NULL,
    address_key TEXT NOT NULL,
    last_success_ms BIGINT NOT NULL,
    PRIMARY KEY (account_key, address_key)
);
CREATE INDEX login_places_by_success ON login_places (last_success_ms);
