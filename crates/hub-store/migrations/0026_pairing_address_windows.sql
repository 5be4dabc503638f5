-- Issue 45 (several hubs, no shared disk): the pairing attempts each address began in the last
-- minute and failed in the last hour were counted in each hub's memory, so an address spreading
-- its attempts over N hubs behind a balancer got N times the allowance. They are counted here,
-- one row per kind and address, advanced by one conditional upsert (… ON CONFLICT DO UPDATE …
-- RETURNING count) so that parallel attempts on several hubs cannot all pass a check made
-- before the count moved. Same portable SQL subset as 0001.
-- kind: 'begun' (a window of a minute) or 'failed' (a window of an hour).
-- address: the client's IPv4 address, or its IPv6 /64 (db::logins::address_key).
-- window_start_ms: when the window of this count began (its first event); a later event
-- after the window has passed starts a new one.
CREATE TABLE pairing_address_windows (
    kind TEXT NOT NULL,
    address TEXT NOT NULL,
    window_start_ms BIGINT NOT NULL,
    events BIGINT NOT NULL,
    PRIMARY KEY (kind, address)
);
CREATE INDEX pairing_address_windows_by_start ON pairing_address_windows (window_start_ms);
