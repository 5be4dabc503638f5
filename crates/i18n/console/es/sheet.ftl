# Las palabras de la hoja de mediciones (crates/hub-care/src/sheet_words.rs): su primera línea
# de encabezado y sus palabras para personas; la segunda línea conserva los nombres técnicos.

sheet-col-patient = Paciente
sheet-col-session = Referencia de la sesión
sheet-col-started-local = Inicio (hora local, { $zone })
sheet-col-started-utc = Inicio (UTC)
sheet-col-exercises = Ejercicios
sheet-col-ended = Cómo terminó
sheet-col-as-prescribed = Según lo prescrito
sheet-col-pain = Dolor después (0–10)
sheet-col-effort = Esfuerzo después (Borg CR10 0–10)
sheet-col-felt = Qué tan difícil le pareció
sheet-yes = sí
sheet-no = no

# La hoja de la evaluación estándar: una fila por medida de cada parte.
sheet-assessment-col-protocol = Versión del protocolo
sheet-assessment-col-seed = Semilla de los saltos del objetivo
sheet-assessment-col-part-key = Parte (código)
sheet-assessment-col-part = Parte
sheet-assessment-col-measure-key = Medida (código)
sheet-assessment-col-measure = Medida
sheet-assessment-col-value = Valor
sheet-assessment-col-unit = Unidad
