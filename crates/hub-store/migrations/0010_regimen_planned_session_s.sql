-- A regimen's planned session length, s, stored from the parsed regimen when it is prescribed
-- (`regimen::Regimen::planned_duration_s`), so the caseload's adherence in minutes reads a
-- column instead of parsing and building every patient's regimen at every load. NULL: not
-- known (a text the parser refuses). Rows stored before this migration are filled in by
-- `Db::open` with the regimen's parser, once.
ALTER TABLE regimens ADD COLUMN planned_session_s DOUBLE PRECISION;
