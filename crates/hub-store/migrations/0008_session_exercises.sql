-- Issue 28 (per-exercise results). Same portable SQL subset as 0001 (TEXT ids, BIGINT
-- counts, DOUBLE PRECISION values).
--
-- Each exercise's own results in a session (netlink `Bye.exercises`), one row per exercise;
-- `scores_json` is the exercise's name → value object (units in the names). A repeated Bye
-- writes the same rows again.
CREATE TABLE session_exercises (
    session_id TEXT NOT NULL REFERENCES sessions (session_id),
    exercise_index BIGINT NOT NULL,
    kind TEXT NOT NULL,
    name TEXT NOT NULL,
    prescribed_s DOUBLE PRECISION NOT NULL,
    active_s DOUBLE PRECISION NOT NULL,
    scores_json TEXT NOT NULL,
    PRIMARY KEY (session_id, exercise_index)
);
