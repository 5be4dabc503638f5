# A patient's Progress tab: pain, adherence and alerts; the latest session against the
# baseline; each exercise kind's charts; the difficulty history; the sessions' list; the
# one-page print.

progress-list-separator = {", "}
progress-percent = { $n } %

## Pain, adherence and alerts

progress-summary-title = Pain, adherence and alerts
progress-pain-title = Pain
progress-pain-latest = Pain { $pain }/10
progress-pain-after = after the session of { $at }.
progress-pain-before = Before: { $list } (newest first).
progress-pain-none = No pain answer yet.
progress-pain-chart-label = Pain after each session, 0 to 10: the numbers are in the sessions' list
progress-pain-axis = pain (0–10)
# The check-in's second answer is effort on Borg's CR10 scale (the wire calls it tiredness).
progress-checkin-pain = pain { $pain }/10
progress-checkin-effort = effort { $effort }/10
progress-checkin-skipped = skipped
progress-felt = felt { $felt }
progress-felt-too-easy = too easy
progress-felt-about-right = about right
progress-felt-too-hard = too hard
progress-after-last = After the last session: { $answers }.
progress-adherence-title = Adherence
progress-week = Last 7 days: { $sessionsPrescribed ->
        [none] { $sessions ->
            [one] { $sessions } session
           *[other] { $sessions } sessions
        }
       *[other] { $sessions } of { $sessionsPrescribed } prescribed sessions
    }, { $minutesPrescribed ->
        [none] { $minutes ->
            [one] { $minutes } active minute
           *[other] { $minutes } active minutes
        }
       *[other] { $minutes } of { $minutesPrescribed } prescribed active minutes
    }.
progress-week-repetitions = Repetitions in the last 7 days: { $repetitions }.
progress-stopped-early = Stopped early: { $stopped } of the last { $count ->
        [one] session
       *[other] { $count } sessions
    }.
progress-alerts-title = Alerts
progress-alerts-none = No alert.

## The dose: active training time and repetitions by week and day

progress-dose-title = Dose: training time and repetitions
progress-dose-explain = Active training time leaves out pauses and rests. Repetitions are the wheel movements made. Weeks are compared with the current prescription.
progress-dose-weeks-caption = { $weeks ->
        [one] By week: the last 7 days
       *[other] By week, the last { $weeks } weeks
    }
progress-dose-days-caption = By day, the last 7 days
progress-dose-col-week = Week
progress-dose-col-day = Day
progress-dose-col-sessions = Sessions
progress-dose-col-active = Active training
progress-dose-col-repetitions = Repetitions
progress-dose-week-range = { $from } to { $to }
progress-dose-below = below the prescription

## The latest session against the earlier ones

progress-latest-title = Exercises: the latest session against the earlier ones
progress-latest-title-kind = Exercises: the latest { $kind } session against the earlier ones
# $early: "included" when sessions that ended early count, else "left-out"; $baseline: how
# many first sessions make the baseline; $earlier: how many earlier sessions the trend uses.
progress-compared = { $early ->
        [included] The latest session that ended (as prescribed or early) ({ $session }) against the patient's baseline ({ $baseline ->
            [one] the first { $kind } session
           *[other] the mean of the first { $baseline } { $kind } sessions
        }), and its trend against up to { $earlier } earlier { $kind } sessions; a change within a measure's measurement noise reads "steady". Sessions ended early are included.
       *[left-out] The latest session that ran as prescribed ({ $session }) against the patient's baseline ({ $baseline ->
            [one] the first { $kind } session
           *[other] the mean of the first { $baseline } { $kind } sessions
        }), and its trend against up to { $earlier } earlier { $kind } sessions; a change within a measure's measurement noise reads "steady". Sessions ended early are in the list below, not compared.
    }
progress-compared-none = No session has run as prescribed yet: nothing to compare.
progress-col-measure = Measure
progress-col-latest = Latest
progress-col-baseline = Baseline
progress-col-trend = Trend
progress-against-prescription = against the prescription, not a trend
progress-include-early = Include sessions that ended early
progress-include-early-none = Include sessions that ended early (none did)

## Each kind of exercise

progress-kind-title = { $kind } sessions ({ $count })
progress-kind-latest = : latest { $list }
progress-headline-item = { $measure } { $value }
progress-kind-note = { $names }. One chart a measure, one step a session, oldest on the left.
progress-kind-hollow = Hollow points: { $count ->
        [one] { $count } session ended early
       *[other] { $count } sessions ended early
    } ({ $early ->
        [included] included
       *[left-out] not joined to the line
    }).
progress-kind-no-measures = No measures recorded for these sessions.
progress-prescribed-time = Prescribed time ({ $unit })
progress-noise-band = The shaded band is the measurement noise around the baseline: a point inside it is no change.
progress-chart-label = { $measure } by session: the numbers are in the table below

## Difficulty

progress-difficulty-title = Difficulty that follows the patient
progress-difficulty-now = : now { $now } (0 easiest, 1 as prescribed)
progress-difficulty-explain = 0: half the prescribed speed and shape with all its assistance; 1: the regimen as written. Set by the station within the regimen's bounds.
progress-difficulty-axis = difficulty (0–1)
progress-difficulty-why-adapt-off = Adaptation off: the therapist's setting.
progress-difficulty-why-first-start = First session: the therapist's start.
progress-difficulty-why-first-midway = First session: midway between the therapist's limits.
progress-difficulty-why-success-above = Success { $success } % was above the { $target } % target.
progress-difficulty-why-success-below = Success { $success } % was below the { $target } % target.
progress-difficulty-why-success-at = Success { $success } % was at the { $target } % target.
progress-difficulty-why-no-rate = No success rate from the last session: kept the same.
progress-difficulty-why-felt-too-hard = The patient said it was too hard.
progress-difficulty-why-felt-too-easy = The patient said it was too easy.
progress-difficulty-held-highest = Held at the therapist's highest.
progress-difficulty-held-lowest = Held at the therapist's lowest.
progress-numbers-caption = The numbers of the chart, newest first
progress-col-started = Started
progress-col-difficulty = Difficulty
progress-col-change = Change
progress-col-success = Success
progress-col-why = Why

## Technical names

progress-technical-summary = Details: the technical names of these measures
progress-technical-caption = As the spreadsheet's second header row and the FHIR export name them
progress-col-data-name = Name in the data
progress-col-technical = Technical name

progress-definitions-summary = What each measure measures, and its source
progress-col-definition = Definition
progress-col-source = Source

## The sessions' list and the print

progress-sessions-title = Sessions ({ $count })
progress-col-exercise = Exercise
progress-col-ended = How it ended
progress-col-checkin = Patient's check-in
progress-col-results = Results and recording
progress-col-notes = Therapist's notes
progress-each-exercise = Each exercise
progress-replay = Replay
progress-note-session = the session of { $at }
progress-range = sessions from { $from } to { $to }
progress-range-none = no session yet
progress-zone-utc = times in UTC
progress-zone = times in { $zone } and UTC
progress-clinic-unnamed = Clinic name not set
progress-print-of = Progress of { $name }
progress-printed = printed { $day }
progress-print = Print a one-page summary
progress-download = Download spreadsheet (CSV; { $zone })
progress-download-assessments = Download the standard assessments (CSV; { $zone })
progress-scales-failed = The clinical scales could not be shown: { $error }

## The standard assessment (issue 42): the same short test each time, first on the page

progress-assessment-title = Standard assessment
progress-assessment-intro = The same short test every time, without help from the wheel (protocol { $protocol }). Newest first. It is kept apart from the exercises and their trends.
progress-assessment-none = No standard assessment yet. To schedule one, set how often in the regimen (assessment, every so many days).
progress-assessment-col-measure = Part and measure
progress-assessment-row = { $part }: { $measure }
progress-assessment-part-range = Active range
progress-assessment-part-tracking-slow = Tracking, slow
progress-assessment-part-tracking-medium = Tracking, medium
progress-assessment-part-tracking-fast = Tracking, fast
progress-assessment-part-steps = Steps
progress-assessment-part-strength = Strength

## Real change told from noise (issue 42): the newest assessment against the first

progress-assessment-col-change = Change since the first ({ $day })
progress-assessment-col-change-none = Change since the first
progress-assessment-band = ± { $band } ({ $source })
progress-assessment-verdict-better = better
progress-assessment-verdict-worse = worse
progress-assessment-verdict-changed = changed (neither way is better)
progress-assessment-verdict-within-noise = within measurement noise
progress-assessment-verdict-no-noise-figure = no noise figure yet, so no verdict
progress-assessment-source-own = Noise band from the patient's own { $repeats } assessments
progress-assessment-source-cohort = Noise band from simulated patients doing the same test
progress-assessment-source-published = Noise band from a published study
progress-assessment-source-short-own = own
progress-assessment-source-short-cohort = cohort
progress-assessment-source-short-published = study
progress-assessment-change-sr = Change since the first assessment: { $change }. Noise band plus or minus { $band } ({ $source }). Verdict: { $verdict }.
progress-assessment-change-sr-none = Change since the first assessment: { $change }. No noise figure yet, so no verdict.
progress-assessment-change-none = Only one assessment so far: nothing to compare yet.
progress-assessment-change-missing = No change to show: the measure is missing from the newest or the first assessment.
progress-assessment-noise-note = Better or worse only when the change is larger than the measurement noise (± the smallest real change, MDC95). The noise band is the patient's own from 6 assessments on (own); before that it comes from simulated patients (cohort) or a published study (study).
