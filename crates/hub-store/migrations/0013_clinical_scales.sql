-- Issue 32 (clinical scales beside the station's measures). Same portable SQL subset as 0001
-- (TEXT ids, BIGINT ms times).
--
-- A standard assessment a therapist took at the clinic, with the date it was taken:
--   fugl_meyer_ue  Fugl-Meyer Assessment, upper extremity motor: score 0-66 points
--   arat           Action Research Arm Test: score 0-57 points
--   box_and_block  Box and Block Test: blocks moved in one minute, affected and unaffected
--                  side, 0-150 each
-- The hub checks the bounds before storing (crates/hub/src/db/scales.rs); the CHECKs keep a
-- row written by hand from holding a score outside them.
CREATE TABLE clinical_scales (
    id TEXT PRIMARY KEY,
    patient_id TEXT NOT NULL REFERENCES patients (id),
    scale TEXT NOT NULL CHECK (scale IN ('fugl_meyer_ue', 'arat', 'box_and_block')),
    assessed_on TEXT NOT NULL,
    score BIGINT CHECK (score BETWEEN 0 AND 66),
    affected_blocks_per_min BIGINT CHECK (affected_blocks_per_min BETWEEN 0 AND 150),
    unaffected_blocks_per_min BIGINT CHECK (unaffected_blocks_per_min BETWEEN 0 AND 150),
    therapist_id TEXT NOT NULL REFERENCES therapists (id),
    created_at_ms BIGINT NOT NULL
);
CREATE INDEX clinical_scales_by_patient ON clinical_scales (patient_id, assessed_on);
