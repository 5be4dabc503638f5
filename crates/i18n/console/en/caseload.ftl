# The caseload (#/patients): who needs attention first, the week's training, the trends, and
# acknowledging an alert or allowing training again after a pain stop.

caseload-title = Patients
caseload-order = Order
caseload-order-need = Who needs attention first
caseload-order-last-session = Longest without a session first
caseload-order-pseudonym = By pseudonym
caseload-show = Show
caseload-show-all = Every patient
# $kind is an alert kind's name (attention-kind-…).
caseload-show-only = Only: { $kind }
caseload-mine = Only my own patients
caseload-caption-need = Your caseload, who needs attention first. Open a patient to watch a running session, see progress or prescribe.
caseload-caption-chosen = Your caseload, in the order chosen. Open a patient to watch a running session, see progress or prescribe.
caseload-col-patient = Patient
caseload-col-needs = Needs attention
caseload-col-last-session = Last session
caseload-col-last-7-days = Last 7 days
caseload-col-trend = Trend
caseload-none = No patients yet.
caseload-none-with-alert = No patient has this alert now.
caseload-add-patient = Add a patient
caseload-add-patient-note = (and print the pairing sheet)
caseload-thresholds-link = Alert thresholds
caseload-nothing-needed = Nothing needs attention
caseload-more = { $count } more
caseload-acknowledged = { $count ->
        [one] { $count } alert acknowledged
       *[other] { $count } alerts acknowledged
    }
# The week's training; $sessionsPrescribed and $minutesPrescribed are "none" when nothing is
# prescribed.
caseload-week = { $sessionsPrescribed ->
        [none] { $sessions ->
            [one] { $sessions } session
           *[other] { $sessions } sessions
        }
       *[other] { $sessions } of { $sessionsPrescribed } prescribed sessions
    }, { $minutesPrescribed ->
        [none] { $minutes } active min
       *[other] { $minutes } of { $minutesPrescribed } prescribed active min
    }
# The week's repetitions (wheel movements) in the caseload's week column.
caseload-repetitions = { $repetitions ->
        [one] { $repetitions } repetition
       *[other] { $repetitions } repetitions
    }
# The Trend column: each exercise kind's trends under its name.
caseload-trend-kind = { $kind } sessions:
caseload-trend-pct-in-lane = Time in lane
caseload-trend-wheel-rom-deg = Wheel range
caseload-trend-sparc-median = Smoothness
caseload-trend-better = better
caseload-trend-worse = worse
caseload-trend-steady = steady
caseload-acknowledge = Acknowledge
caseload-quiet-former = a therapist no longer at the clinic
caseload-quiet-snoozed = snoozed until { $until } by { $who } on { $at }: { $note }
caseload-quiet-acknowledged = acknowledged (quiet until something new) by { $who } on { $at }: { $note }

## Acknowledging an alert

caseload-ack-legend = Keep it quiet
caseload-ack-until-new = Until something new happens
caseload-ack-until-day = Until a day:
caseload-ack-snooze-until = Snooze until
caseload-ack-note = Note
caseload-ack-note-hint = (what was done, e.g. "Called: resting, sees the GP Monday")
caseload-ack-no-day = Choose the day the alert may come back.
caseload-save = Save
caseload-cancel = Cancel

## Allowing training again after a pain stop

caseload-allow-training = Allow training today
caseload-allow-question = Allow training again today despite the pain reported?
caseload-allow-explain = The station stopped training for today after this pain answer. If you have spoken with the patient and training is safe, the station lets them train again today. This is recorded in the audit log.
caseload-allow-confirm = Yes, allow training today
caseload-allow-done = Training allowed again ({ $at }). The station is told at once, or when it next connects.
caseload-training-allowed = Training allowed again on { $at }.
