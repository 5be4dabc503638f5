-- Issue 44 (a paired station held to its prescription). Same portable SQL subset as 0001.
--
-- The recording bytes taken from each station on each UTC day (days since the Unix epoch),
-- so that the daily cap (max_upload_bytes_per_station_day) holds across hub restarts. Only
-- today's row is read; older rows are a record of what each station sent.
CREATE TABLE station_upload_days (
    station_id TEXT NOT NULL,
    day BIGINT NOT NULL,
    bytes BIGINT NOT NULL CHECK (bytes >= 0),
    PRIMARY KEY (station_id, day)
);

-- The sessions a station started on one day are counted at every new session's Hello.
CREATE INDEX sessions_station_started ON sessions (station_id, started_unix_ms);
