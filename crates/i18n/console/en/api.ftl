# The hub's refusals in the console's language (crates/hub/console/api.js refusalWords).

## The hub's refusals in the console's language (api.js refusalWords): the hub's own words,
## which name the field or the thing refused, follow in English where they add something.

api-error-400 = The hub did not accept this.
api-error-401 = Not signed in, or a wrong e-mail or password.
api-error-403 = Only a clinic administrator can do this.
api-error-404 = Not found. It may have been removed.
api-error-409 = This conflicts with what the hub holds.
api-error-413 = This is too large for the hub.
api-error-415 = The hub did not understand this request.
api-error-422 = Refused: outside the allowed values or the safety bounds.
api-error-429 = Too many tries. Try again in { $seconds } s.
api-error-503 = The hub is busy. Try again in { $seconds } s.
api-error-other = Something went wrong on the hub. Its log has the details.

## Why the hub refused, by its code (crates/hub-store/src/refusal.rs): one plain sentence each.
## $field and $what arrive already in the console's words.

api-why-field-refused = The hub did not accept this: { $field }.
api-why-empty = { $field } is empty. Write a few words.
api-why-too-long = { $field } is too long: at most { $max } characters.
api-why-control-characters = { $field } has hidden control characters. Use plain text.
api-why-missing = { $field } is missing.
api-why-not-one-of = { $field } is not one of the choices.
api-why-out-of-range = { $field } must be from { $min } to { $max }.
api-why-bad-date = { $field } is not a real day. Write it as year-month-day.
api-why-future-date = { $field } is in the future. Choose the day it happened.
api-why-bad-id = The address names a { $field } that cannot exist.
api-why-bad-email = This is not an e-mail address. It looks like name@clinic.org.
api-why-bad-pseudonym = Use up to { $max } letters, digits, dots, dashes or underscores. Never a name.
api-why-password-invisible = The password has invisible characters. Type only what you can see.
api-why-password-length = The password needs at least { $min } characters.
api-why-password-spaces = The password is mostly spaces.
api-why-password-email = The password cannot be your e-mail address.
api-why-password-common = This password is one of the most common. Choose another.
api-why-password-repeated = The password repeats itself. Use at least { $min } different characters.
api-why-password-sequence = The password is a run like abcdef or 123456. Choose another.
api-why-password-guessable = The password is too easy to guess. A few unrelated words work well.
api-why-password-same = The new password must differ from the current one.
api-why-snooze-past = A snooze must end in the future. Choose a later day.
api-why-not-found = This { $what } is not here. It may have been removed.
api-why-already-exists = This { $what } already exists. Choose another.
api-why-no-endpoint = The hub has no such page.
api-why-login-refused = Wrong e-mail or password.
api-why-log-in-first = Please sign in first.
api-why-one-time-password = Change your one-time password first.
api-why-admin-only = Only a clinic administrator can do this.
api-why-own-care-only = You can add patients to your own care only. An administrator can choose another therapist.
api-why-no-therapist-email = No therapist has this e-mail address.
api-why-throttled = Too many tries. Try again in { $seconds } s.
api-why-alert-gone = This alert has cleared. Reload the caseload.
api-why-alert-changed = Something new happened since this alert was shown. Look at it again. Nothing was saved.
api-why-regimen-shape = The hub could not read this prescription.
api-why-regimen-text = The prescription text has a mistake on line { $line }.
api-why-regimen-unreadable = The prescription text cannot be read.
api-why-regimen-exercise = Exercise { $exercise } has a value outside its allowed range.
api-why-above-wheel = Exercise { $exercise } asks more force than this patient's wheel gives: at most { $max_nm } N·m.
api-why-recording-not-arrived = The recording of this session has not fully arrived yet.
api-why-recording-unreadable = The recording of this session cannot be read on the hub.
api-why-recording-too-large = This recording is { $mb } MB. The hub replays at most { $max_mb } MB.
api-why-replay-pending = Your last replay is still being prepared. Wait until it shows.
api-why-replay-busy = The hub is busy with other replays. Try again in a moment.
api-why-live-streams = At most { $max } live views at once. Close one first.
api-why-unknown-language = The console has no words in this language.
api-why-unknown-time-zone = The hub does not know this time zone.
api-why-body-malformed = The hub could not read this request.
api-why-body-too-large = This is too large for the hub.
api-why-body-not-json = The hub did not understand this request.
api-why-internal = Something went wrong on the hub. Its log has the details.

## The fields and things a refusal names.

api-field-text = The text
api-field-note = The note
api-field-password = The password
api-field-email = The e-mail address
api-field-pseudonym = The pseudonym
api-field-snooze-until-ms = The snooze's end
api-field-setting = The setting
api-field-scale = The scale
api-field-assessed-on = The day of the assessment
api-field-score = The score
api-field-affected-blocks-per-min = Blocks per minute, affected side
api-field-unaffected-blocks-per-min = Blocks per minute, unaffected side
api-field-sort = The order
api-field-alert = The alert
api-field-query = The search
api-field-key = The alert
api-field-regimen = The prescription
api-field-path = The address
api-field-patient-id = patient
api-field-session-id = session
api-field-station-id = station
api-field-scale-id = assessment
api-thing-patient = patient
api-thing-station = station
api-thing-session = session
api-thing-therapist = therapist
api-thing-scale = assessment
api-thing-pseudonym = pseudonym
api-thing-email = e-mail address
api-thing-clinical-scale = assessment
api-thing-station-or-certificate = station
