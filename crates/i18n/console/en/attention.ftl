# Alerts on the caseload (issue 41): each alert kind's name, the severities, each alert's
# sentence (the hub sends its id and these arguments), and the clinic's alert thresholds.
# $at is the date and time of the evidence (already formatted).

attention-severity-urgent = Urgent
attention-severity-warning = Look today
attention-severity-notice = Note
attention-severity-label = { $severity }:

## The kinds, as the caseload's filter names them

attention-kind-pain-high = Pain
attention-kind-pain-rising = Rising pain
attention-kind-station-revoked = Station withdrawn
attention-kind-no-session = No session
attention-kind-decline = Getting worse
attention-kind-safety-stop = Safety stop
attention-kind-ended-early = Ended early
attention-kind-effort = High effort
attention-kind-low-activity = Little training
attention-kind-wheel-unplugged = Wheel unplugged
attention-kind-sensor-unplugged = Arm sensor unplugged
attention-kind-wheel-unseen = Wheel not seen
attention-kind-sensors-lost = Arm sensors lost
attention-kind-station-silent = Station silent
attention-kind-torque-at-ceiling = Torque at its limit

## The alerts

attention-pain-high = Pain { $pain_0_10 }/10 after the session of { $at }{ $sessions_since ->
        [0] {""}
        [one] {" "}(no pain answer after the next session)
       *[other] {" "}(no pain answer in the { $sessions_since } sessions since)
    }
attention-pain-rising = Pain rising: { $first_0_10 }, then { $middle_0_10 }, then { $pain_0_10 }/10 after the session of { $at }
attention-station-revoked = Station withdrawn on { $at }: the patient cannot train until a new one is paired
attention-no-session-yet = No session yet (added { $at })
attention-no-session = No session for { $days } days (the last: { $at })
# $measure is the measure's plain name, $exercise_kind the kind of exercise in words, $latest
# and $usual the values with their unit.
attention-decline = { $measure } worse in { $exercise_kind } sessions: { $latest } against { $usual } before ({ $worse_percent } % worse)
attention-safety-stop = Safety stop in the session of { $at }
attention-ended-early = { $ended_early } of the last { $sessions } sessions ended early
attention-effort-high = Effort { $effort_0_10 }/10 (Borg CR10) after the session of { $at }
attention-effort-too-hard = "Too hard" after the last { $too_hard_sessions } sessions
attention-low-sessions = { $sessions } of { $sessions_prescribed } prescribed sessions this week
attention-low-minutes = { $active_minutes } of { $minutes_prescribed } prescribed active minutes this week
attention-low-unprescribed = { $active_minutes ->
        [one] { $active_minutes } active minute
       *[other] { $active_minutes } active minutes
    } this week; nothing prescribed yet (the clinic looks for at least { $minimum_minutes })
# $end is how the session ended, in the one end-reason wording (words-end-…).
attention-wheel-unplugged = Session of { $at }: { $end }
attention-sensor-unplugged = Session of { $at }: { $end }
attention-wheel-unseen = Wheel not seen for { $days } days while the station was on
attention-sensors-lost = Arm sensors lost in the last { $sessions ->
        [one] session
       *[other] { $sessions } sessions
    }
attention-station-silent = Station not heard from for { $days } days (the last: { $at })
attention-torque-at-ceiling = Torque held at its limit for { $percent } % or more of the session of { $at }

## The clinic's alert thresholds (#/attention-settings)

attention-settings-title = Alert thresholds
attention-settings-intro = When the caseload says a patient needs attention.
attention-settings-admin = Changes apply to every therapist of the clinic at once and are recorded in the audit log.
attention-settings-not-admin = An administrator can change them.
attention-settings-save = Save the thresholds
attention-settings-saved = Saved.
attention-settings-out-of-range = A value is outside its range (shown beside it).
attention-setting-range = ({ $min }–{ $max }; default { $default })
attention-setting-changed = Changed by { $who } on { $at }.
attention-setting-default = Not changed by the clinic: the default.
attention-setting-pain-threshold-0-10 = Pain that is urgent, 0–10 (at or over)
    .why = Pain of 7 or more on the 0–10 scale is severe pain; a patient who reports it should not train on without the clinic.
attention-setting-pain-rise-points = Rising pain: points over three check-ins
    .why = Two points is about the smallest change in pain a patient feels as real.
attention-setting-no-session-days = Days without a session
    .why = Three days without training breaks the rhythm of a home programme; a prescription of fewer sessions a week waits its own gap (7 days for once a week).
attention-setting-min-active-minutes-week = Active minutes a week when nothing is prescribed (at least)
    .why = Half an hour a week is far below what patients manage at home (about 2 hours a week on average); less means the station is hardly used.
attention-setting-decline-percent = Getting worse: percent below the earlier sessions of the same kind
    .why = Movement measures vary by up to about 10 % from session to session; 15 % is beyond that noise.
attention-setting-ended-early-sessions = Sessions ended early, of the last 5
    .why = Once can be a phone call; twice in five sessions is a pattern worth a question.
attention-setting-effort-threshold-0-10 = Effort that needs a look, Borg CR10 0–10 (at or over)
    .why = Home programmes lose patients whose training feels hard; 7 of 10 is well past "hard".
attention-setting-devices-unseen-days = Days the station is on without its wheel
    .why = A wheel missing for three days usually means a cable or a power supply, not a choice.
attention-setting-station-silent-days = Days a station may stay silent
    .why = A station that trains connects at every session; three silent days mean it is off, unplugged or offline.
