-- Issue 28 (messages from the therapist). Same portable SQL subset as 0001 (TEXT ids, BIGINT
-- ms times, NULL: not yet).
--
-- A therapist's short note to a patient: plain text, 1 to 500 characters, no control
-- characters (netlink::check_message_text). Pushed to the patient's station when it connects
-- (netlink `Message`, protocol 2) until the station says it was shown (`MessageSeen`).
CREATE TABLE patient_messages (
    id TEXT PRIMARY KEY,
    patient_id TEXT NOT NULL REFERENCES patients (id),
    therapist_id TEXT NOT NULL REFERENCES therapists (id),
    body TEXT NOT NULL,
    created_at_ms BIGINT NOT NULL,
    -- First time the hub queued it for a station of the patient.
    delivered_at_ms BIGINT,
    -- When the station showed it on the patient's screen (station clock).
    seen_at_ms BIGINT
);
CREATE INDEX patient_messages_by_patient ON patient_messages (patient_id, created_at_ms);
