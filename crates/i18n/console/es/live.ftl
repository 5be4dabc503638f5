# La vista en directo de una sesión en curso.

live-waiting = Esperando a que empiece una sesión…
live-arm-heading = Brazo y volante
live-arm-canvas = Vista 3D del brazo del paciente y del volante; arrastre o use las flechas para girarla
live-tracking = Seguimiento
live-torque-heading = Par y asistencia
live-joints-heading = Ángulos articulares
live-scene-road = Carretera y carril alrededor del coche
live-scene-dial = Dial: objetivo y volante
live-scene-strength = Prueba de fuerza: cada lado
live-tracking-road = Desviación lateral
live-tracking-dial = Objetivo del dial y ángulo del volante
live-tracking-strength = Fuerza: el empuje frente al límite
live-axis-time = tiempo de sesión (s)
live-axis-deviation = desviación (m)
live-axis-angle = ángulo (°)
live-axis-torque = par (N·m)
live-series-deviation = desviación lateral (m)
live-series-wheel = ángulo del volante (°)
live-series-target = objetivo (°)
live-series-push = empuje actual (N·m)
live-series-peak = empuje máximo, este lado (N·m)
live-series-ceiling = límite (N·m)
live-series-motor = motor (N·m)
live-series-assist = asistencia (N·m)
live-series-shoulder = elevación del hombro (°)
live-series-elbow = flexión del codo (°)

live-just-now = ahora mismo
live-status-session = Sesión del { $when }
live-status-seconds = { $seconds } s
live-state-running = en curso
live-state-paused = en pausa
live-state-fault = fallo de seguridad: el par baja a cero
live-status-torque = par { $nm } de { $ceiling } N·m de límite
live-status-lane = en el carril { $pct } %
live-status-push = empuje { $nm } N·m
live-status-dial-off = a { $degrees }° del objetivo del dial
live-status-delay = retardo { $seconds } s
live-recording-stopped = grabación detenida a los { $seconds } s
live-no-arm-sensors = Sin sensores de brazo en esta sesión.
live-angles = Elevación del hombro { $shoulder }°, flexión del codo { $elbow }°, pronación del antebrazo { $forearm }°
live-delayed-silent = con retraso: nada de la estación desde hace { $seconds } s (su conexión de casa puede estar caída); la vista muestra los últimos datos recibidos
live-delayed-late = con retraso: estos datos llegaron { $seconds } s tarde (la estación se está poniendo al día tras un corte de su conexión)
live-lagged = { $count ->
    [one] La vista se retrasó y omitió un resumen.
   *[other] La vista se retrasó y omitió { $count } resúmenes.
}
live-stopped-login-ended = Vista en directo detenida: su sesión terminó. Vuelva a iniciar sesión para verla.
live-stopped-login-unchecked = Vista en directo detenida: el hub no puede comprobar su sesión ahora. Inténtelo de nuevo pronto.
live-stopped-not-your-patient = Vista en directo detenida: este paciente ya no está a su cuidado.
live-ended-unknown = terminada (no consta cómo)
live-ended-complete = terminada: completa, según lo prescrito
live-path-note = El recorrido del coche en los últimos { $seconds } s

live-road-not-sent = Esta estación no envía la carretera: el recorrido del coche en los últimos { $seconds } s
live-road-note = Carril de { $lane } m de ancho, de { $behind } m detrás del coche a { $ahead } m por delante (barra de escala { $bar } m); azul: su recorrido.
live-road-car-side = { $side ->
    [left] El coche está { $metres } m a la izquierda del centro.
    [right] El coche está { $metres } m a la derecha del centro.
   *[centre] El coche está en el centro del carril.
}
live-path-none = Un ejercicio de dial: no hay coche en una carretera.
live-path-across = { $what } ({ $metres } m de ancho).
live-dial-waiting = El ejercicio de dial: esperando al volante.
live-dial-note = Objetivo { $target }° (naranja, discontinuo), volante del paciente { $wheel }° (azul): { $side ->
    [left] { $off }° a la izquierda del objetivo.
    [right] { $off }° a la derecha del objetivo.
   *[on] sobre el objetivo.
}

live-strength-left = Empujando a la izquierda
live-strength-right = Empujando a la derecha
live-strength-now-label = { $side } (ahora)
live-strength-resting = Prueba de fuerza: descanso entre lados, o terminada. El límite es { $ceiling }.
live-strength-note = Prueba de fuerza, { $side ->
    [left] empujando a la izquierda
   *[right] empujando a la derecha
}: { $now } ahora{ $share }, máximo { $peak } hasta ahora, frente al límite de { $ceiling } (azul: ahora; marca naranja: máximo; línea verde: límite).
live-strength-share = ({ $pct } % del límite)
live-strength-caption = Los números de la prueba de fuerza
live-strength-col-side = Lado
live-strength-col-now = Empuje actual
live-strength-col-peak = Máximo hasta ahora
live-strength-col-ceiling = Límite
live-strength-not-yet = aún no
