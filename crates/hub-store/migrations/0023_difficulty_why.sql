-- Issue 40 (the console in every language). Same portable SQL subset as 0001.
--
-- Why a session's difficulty was chosen, for words in any language: the station's
-- `DifficultyWhy` as JSON (`{"code": "success-above", "success_pct": 82, …}`); NULL from
-- stations older than it, whose English `reason` the console shows as it is.
ALTER TABLE session_difficulty ADD COLUMN why_json TEXT;
