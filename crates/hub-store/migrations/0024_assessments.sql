-- Issue 42 (the standard assessment). Same portable SQL subset as 0001.
--
-- A part of the standard assessment (netlink `ExerciseResult.assessment`) is stored as an
-- exercise of its session, of the assessment kind: its protocol version and the seed its
-- steps were drawn from. NULL for an exercise (and for every row from before this). The
-- progress page's assessment section reads these rows; exercise trends leave them out.
ALTER TABLE session_exercises ADD COLUMN assessment_protocol BIGINT;
ALTER TABLE session_exercises ADD COLUMN assessment_seed BIGINT;
