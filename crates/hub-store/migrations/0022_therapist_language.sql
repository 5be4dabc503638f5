-- Issue 40 (the console in every language). Same portable SQL subset as 0001.
--
-- The language a therapist chose for the console (`en`, `de`, `es`, `zh`, or the pseudo-locale
-- `en-XA`); NULL until they choose, when the console follows the browser's languages.
ALTER TABLE therapists ADD COLUMN language TEXT;
