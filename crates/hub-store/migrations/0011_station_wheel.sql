-- Issue 29 (the patient's own bounds). Same portable SQL subset as 0001 (TEXT, DOUBLE
-- PRECISION N·m, BIGINT 0/1 flag and ms time; NULL: no wheel told yet).
--
-- The wheel a station last told the hub in its Hello (netlink `Hello.wheel`): its model, the
-- motor's rated torque and the ceiling the station's safety chain allows at the motor. The
-- console's prescribe form bounds every torque by the patient's newest one, and the hub
-- refuses a regimen above it.
ALTER TABLE stations ADD COLUMN wheel_model TEXT;
ALTER TABLE stations ADD COLUMN wheel_rated_torque_nm DOUBLE PRECISION;
ALTER TABLE stations ADD COLUMN wheel_ceiling_nm DOUBLE PRECISION;
ALTER TABLE stations ADD COLUMN wheel_unknown BIGINT;
ALTER TABLE stations ADD COLUMN wheel_seen_at_ms BIGINT;
