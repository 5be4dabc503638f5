-- A regimen's sessions a week, stored from the parsed regimen when it is prescribed
-- (`regimen::Regimen::sessions_per_week`), so the caseload reads a column instead of parsing
-- every patient's TOML. Same portable SQL subset as 0001 (BIGINT, NULL: none asked for).
-- Rows stored before this migration are filled in by `Db::open` with the regimen's parser.
ALTER TABLE regimens ADD COLUMN sessions_per_week BIGINT;
