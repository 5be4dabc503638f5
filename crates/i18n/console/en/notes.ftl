# The therapist's notes on a session (crates/hub/console/notes.js): the clinic's record only.

notes-empty = The note is empty: write a few words.
notes-too-long = The note is too long: { $chars } characters, at most { $max }.
notes-control = The note holds control characters: plain text only.
notes-by = { $by }, { $when }
notes-by-gone = a therapist no longer at the clinic
notes-none = No note yet.
notes-add-label = Add a note on { $session } (for the clinic's record; the patient does not see it)
notes-save = Save the note
notes-saved = Note saved.
notes-cell = Note
notes-heading = Notes on this session
notes-this-session = this session
