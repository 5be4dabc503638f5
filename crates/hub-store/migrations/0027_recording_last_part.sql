-- Issue 45: a recording on its way said "arriving" until its partial upload was swept a week
-- later, even when its station had long gone silent. When the hub last noted a part of it
-- arriving, ms since the Unix epoch (Db::note_recording_progress, every few seconds while
-- chunks arrive), lets the console and `hub patient show` say it stopped arriving.
-- NULL: never noted (stored whole at once, or noted before this column existed); read only
-- while the recording is not whole. Same portable SQL subset as 0001.
ALTER TABLE recordings ADD COLUMN last_part_ms BIGINT;
