# The FHIR export's narratives (crates/hub-care/src/fhir/narrative.rs): the words an electronic
# health record shows of each exported resource, in the language the export is asked in (the
# therapist's); the codes' own names stay the code systems' English.

fhir-patient = Patient { $pseudonym }. Only the clinic's pseudonym is exported.
fhir-regimen = Home exercise regimen, version { $version }, prescribed on { $day }.
fhir-request = Exercise therapy at home on the telerehab station: { $exercises } exercises.
fhir-request-week = { $sessions } sessions a week, each about { $minutes } minutes.
fhir-session = Session on { $start } (UTC): { $exercise }.
fhir-session-open = The session had not ended when this record was exported.
fhir-duration = Exercise time of the session on { $start } (UTC): { $minutes } minutes.
fhir-measure = Measure
fhir-value = Value
fhir-scale = { $scale } on { $day }: { $value }.
fhir-code-system = { $title }: { $count } codes, each with its definition and unit.
fhir-questionnaire = The questions the patient answers on the station after each session.
fhir-checkin = Check-in after the session on { $start } (UTC).
fhir-answer-skipped = skipped
fhir-answer-score = { $value } of 10
fhir-device = Telerehab station { $station }, software { $version }: a force-feedback steering wheel and arm sensors.
fhir-therapist = Therapist of the clinic ({ $id }).

# The standard assessment (crates/hub-care/src/fhir/assessment.rs).
fhir-assessment-title = Standard assessment on the wheel
fhir-assessment = Standard assessment on { $start } (UTC), protocol version { $protocol }, its target steps drawn from seed { $seed }. Its parts: { $parts }.
fhir-assessment-part = { $part }: part of the standard assessment on { $start } (UTC), protocol version { $protocol }.
fhir-assessment-method = Standard assessment, protocol version { $protocol }, target steps drawn from seed { $seed }
# Short texts beside the codes.
fhir-session-text = Telerehabilitation session: { $exercise }
fhir-regimen-title = Home exercise regimen, version { $version }
fhir-request-text = { $title }: { $exercises } exercises on the telerehab station
fhir-device-type = Home rehabilitation station: force-feedback steering wheel and arm sensors
