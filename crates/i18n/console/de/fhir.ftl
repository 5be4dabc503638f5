# Die Texte des FHIR-Exports (crates/hub-care/src/fhir/narrative.rs).

fhir-patient = Patient { $pseudonym }. Exportiert wird nur das Pseudonym der Klinik.
fhir-regimen = Heimübungsplan, Version { $version }, verordnet am { $day }.
fhir-request = Übungstherapie zu Hause an der Telerehab-Station: { $exercises } Übungen.
fhir-request-week = { $sessions } Einheiten pro Woche, je etwa { $minutes } Minuten.
fhir-session = Einheit am { $start } (UTC): { $exercise }.
fhir-session-open = Die Einheit war beim Export noch nicht beendet.
fhir-duration = Übungszeit der Einheit am { $start } (UTC): { $minutes } Minuten.
fhir-measure = Messgröße
fhir-value = Wert
fhir-scale = { $scale } am { $day }: { $value }.
fhir-code-system = { $title }: { $count } Codes, jeder mit Definition und Einheit.
fhir-questionnaire = Die Fragen, die der Patient nach jeder Einheit an der Station beantwortet.
fhir-checkin = Rückmeldung nach der Einheit am { $start } (UTC).
fhir-answer-skipped = übersprungen
fhir-answer-score = { $value } von 10
fhir-device = Telerehab-Station { $station }, Software { $version }: ein Lenkrad mit Kraftrückmeldung und Armsensoren.
fhir-therapist = Therapeut der Klinik ({ $id }).

# Der Standardtest (crates/hub-care/src/fhir/assessment.rs).
fhir-assessment-title = Standardtest am Lenkrad
fhir-assessment = Standardtest am { $start } (UTC), Protokollversion { $protocol }, die Zielsprünge gezogen aus Startwert { $seed }. Seine Teile: { $parts }.
fhir-assessment-part = { $part }: Teil des Standardtests am { $start } (UTC), Protokollversion { $protocol }.
fhir-assessment-method = Standardtest, Protokollversion { $protocol }, Zielsprünge gezogen aus Startwert { $seed }
# Kurze Texte neben den Codes.
fhir-session-text = Telereha-Einheit: { $exercise }
fhir-regimen-title = Heimübungsplan, Version { $version }
fhir-request-text = { $title }: { $exercises } Übungen an der Telerehab-Station
fhir-device-type = Reha-Station für zu Hause: Lenkrad mit Kraftrückmeldung und Armsensoren
