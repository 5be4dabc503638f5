# Avisos de la lista de pacientes: nombre de cada tipo, gravedad, la frase de cada aviso (el
# hub envía su identificador y argumentos) y los umbrales de la clínica.

attention-severity-urgent = Urgente
attention-severity-warning = Revisar hoy
attention-severity-notice = Nota
attention-severity-label = { $severity }:

## Tipos de aviso (filtro)

attention-kind-pain-high = Dolor
attention-kind-pain-rising = Dolor en aumento
attention-kind-station-revoked = Estación retirada
attention-kind-no-session = Sin sesiones
attention-kind-decline = Empeoramiento
attention-kind-safety-stop = Parada de seguridad
attention-kind-ended-early = Terminada antes de tiempo
attention-kind-effort = Esfuerzo alto
attention-kind-low-activity = Poco entrenamiento
attention-kind-wheel-unplugged = Volante desconectado
attention-kind-sensor-unplugged = Sensor del brazo desconectado
attention-kind-wheel-unseen = Volante no detectado
attention-kind-sensors-lost = Sensores del brazo perdidos
attention-kind-station-silent = Estación sin conexión
attention-kind-torque-at-ceiling = Par en el límite

## Los avisos

attention-pain-high = Dolor { $pain_0_10 }/10 tras la sesión del { $at }{ $sessions_since ->
        [0] {""}
        [one] {" "}(sin respuesta de dolor tras la sesión siguiente)
       *[other] {" "}(sin respuesta de dolor en las { $sessions_since } sesiones posteriores)
    }
attention-pain-rising = Dolor en aumento: { $first_0_10 }, luego { $middle_0_10 }, luego { $pain_0_10 }/10 tras la sesión del { $at }
attention-station-revoked = Estación retirada el { $at }: el paciente no puede entrenar hasta que se empareje una nueva
attention-no-session-yet = Todavía sin sesiones (añadido el { $at })
attention-no-session = Sin sesiones desde hace { $days } días (la última: { $at })
attention-decline = { $measure } peor en las sesiones de { $exercise_kind }: { $latest } frente a { $usual } antes ({ $worse_percent } % peor)
attention-safety-stop = Parada de seguridad en la sesión del { $at }
attention-ended-early = { $ended_early } de las últimas { $sessions } sesiones terminaron antes de tiempo
attention-effort-high = Esfuerzo { $effort_0_10 }/10 (Borg CR10) tras la sesión del { $at }
attention-effort-too-hard = «Demasiado difícil» en las últimas { $too_hard_sessions } sesiones
attention-low-sessions = { $sessions } de { $sessions_prescribed } sesiones prescritas esta semana
attention-low-minutes = { $active_minutes } de { $minutes_prescribed } minutos activos prescritos esta semana
attention-low-unprescribed = { $active_minutes ->
        [one] { $active_minutes } minuto activo
       *[other] { $active_minutes } minutos activos
    } esta semana; todavía nada prescrito (la clínica espera al menos { $minimum_minutes })
attention-wheel-unplugged = Sesión del { $at }: { $end }
attention-sensor-unplugged = Sesión del { $at }: { $end }
attention-wheel-unseen = Volante no detectado durante { $days } días con la estación encendida
attention-sensors-lost = Sensores del brazo perdidos en { $sessions ->
        [one] la última sesión
       *[other] las últimas { $sessions } sesiones
    }
attention-station-silent = Estación sin dar señales desde hace { $days } días (la última: { $at })
attention-torque-at-ceiling = Par mantenido en su límite durante el { $percent } % o más de la sesión del { $at }

## Umbrales de aviso de la clínica (#/attention-settings)

attention-settings-title = Umbrales de aviso
attention-settings-intro = Cuándo indica la lista que un paciente necesita atención.
attention-settings-admin = Los cambios se aplican de inmediato a todos los terapeutas de la clínica y quedan en el registro de auditoría.
attention-settings-not-admin = Un administrador puede cambiarlos.
attention-settings-save = Guardar los umbrales
attention-settings-saved = Guardado.
attention-settings-out-of-range = Un valor está fuera de su intervalo (indicado a su lado).
attention-setting-range = ({ $min }–{ $max }; por defecto { $default })
attention-setting-changed = Cambiado por { $who } el { $at }.
attention-setting-default = Sin cambios de la clínica: el valor por defecto.
attention-setting-pain-threshold-0-10 = Dolor urgente, 0–10 (desde)
    .why = Un dolor de 7 o más en la escala 0–10 es dolor intenso; quien lo indique no debería seguir entrenando sin la clínica.
attention-setting-pain-rise-points = Dolor en aumento: puntos en tres respuestas
    .why = Dos puntos es aproximadamente el menor cambio de dolor que un paciente percibe como real.
attention-setting-no-session-days = Días sin sesión
    .why = Tres días sin entrenar rompen el ritmo de un programa en casa; una prescripción con menos sesiones por semana espera su propio intervalo (7 días si es una vez por semana).
attention-setting-min-active-minutes-week = Minutos activos por semana cuando no hay nada prescrito (mínimo)
    .why = Media hora por semana está muy por debajo de lo que los pacientes logran en casa (unas 2 horas por semana de media); menos significa que la estación apenas se usa.
attention-setting-decline-percent = Empeoramiento: porcentaje por debajo de las sesiones anteriores del mismo tipo
    .why = Las medidas de movimiento varían hasta un 10 % de una sesión a otra; un 15 % supera esa variación.
attention-setting-ended-early-sessions = Sesiones terminadas antes de tiempo, de las últimas 5
    .why = Una vez puede ser una llamada de teléfono; dos veces en cinco sesiones es un patrón por el que conviene preguntar.
attention-setting-effort-threshold-0-10 = Esfuerzo que merece una revisión, Borg CR10 0–10 (desde)
    .why = Los programas en casa pierden a los pacientes a quienes el entrenamiento les resulta duro; 7 de 10 está muy por encima de «duro».
attention-setting-devices-unseen-days = Días con la estación encendida sin su volante
    .why = Un volante que falta tres días suele deberse a un cable o a la fuente de alimentación, no a una decisión.
attention-setting-station-silent-days = Días que una estación puede estar sin conexión
    .why = Una estación con la que se entrena se conecta en cada sesión; tres días sin señales significan que está apagada, desenchufada o sin red.
