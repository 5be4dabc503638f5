# Los textos de la exportación FHIR (crates/hub-care/src/fhir/narrative.rs).

fhir-patient = Paciente { $pseudonym }. Solo se exporta el seudónimo de la clínica.
fhir-regimen = Programa de ejercicios en casa, versión { $version }, prescrito el { $day }.
fhir-request = Terapia de ejercicio en casa con la estación telerehab: { $exercises } ejercicios.
fhir-request-week = { $sessions } sesiones por semana, de unos { $minutes } minutos cada una.
fhir-session = Sesión del { $start } (UTC): { $exercise }.
fhir-session-open = La sesión no había terminado cuando se exportó este registro.
fhir-duration = Tiempo de ejercicio de la sesión del { $start } (UTC): { $minutes } minutos.
fhir-measure = Medida
fhir-value = Valor
fhir-scale = { $scale } el { $day }: { $value }.
fhir-code-system = { $title }: { $count } códigos, cada uno con su definición y unidad.
fhir-questionnaire = Las preguntas que el paciente responde en la estación después de cada sesión.
fhir-checkin = Respuestas después de la sesión del { $start } (UTC).
fhir-answer-skipped = omitida
fhir-answer-score = { $value } de 10
fhir-device = Estación telerehab { $station }, software { $version }: un volante con retroalimentación de fuerza y sensores de brazo.
fhir-therapist = Terapeuta de la clínica ({ $id }).

# La evaluación estándar (crates/hub-care/src/fhir/assessment.rs).
fhir-assessment-title = Evaluación estándar con el volante
fhir-assessment = Evaluación estándar del { $start } (UTC), versión { $protocol } del protocolo, con los saltos del objetivo sacados de la semilla { $seed }. Sus partes: { $parts }.
fhir-assessment-part = { $part }: parte de la evaluación estándar del { $start } (UTC), versión { $protocol } del protocolo.
fhir-assessment-method = Evaluación estándar, versión { $protocol } del protocolo, saltos del objetivo sacados de la semilla { $seed }
# Textos cortos junto a los códigos.
fhir-session-text = Sesión de telerrehabilitación: { $exercise }
fhir-regimen-title = Programa de ejercicios en casa, versión { $version }
fhir-request-text = { $title }: { $exercises } ejercicios en la estación telerehab
fhir-device-type = Estación de rehabilitación en casa: volante con retroalimentación de fuerza y sensores de brazo
