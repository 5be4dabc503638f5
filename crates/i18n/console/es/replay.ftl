# La reproducción de una sesión guardada y la lista de sesiones.

replay-loading = Cargando la grabación…
replay-none-sent = el hub no envió ninguna reproducción
replay-heading = Reproducción de la sesión del { $when } ({ $exercise })
replay-unknown-time = momento desconocido
replay-receiving = Recibiendo la grabación…
replay-playback = Reproducción
replay-play = Reproducir
replay-pause = Pausa
replay-position = Posición
replay-speed = Velocidad
replay-marks-label = Dónde termina cada ejercicio y empieza el siguiente
replay-car-heading = El coche visto desde arriba (30 s antes del cursor)
replay-car-canvas = El recorrido del coche visto desde arriba
replay-chart-tracking = Desviación lateral y error del dial
replay-axis-tracking = desviación (m) / error (°)
replay-series-dial-error = error de seguimiento del dial (°)
replay-chart-torque = Par en el volante
replay-series-motor = par del motor (N·m)
replay-series-assist = par de asistencia (N·m)
replay-series-ceiling = límite de par (N·m)
replay-mark = { $named ->
    [yes] { $seconds } s: fin del ejercicio { $ended }, luego el ejercicio { $next } ({ $name })
   *[no] { $seconds } s: fin del ejercicio { $ended }, luego el ejercicio { $next }
}
replay-cut-short = la grabación dejó de llegar antes de su final
replay-frames = { $frames } fotogramas a { $rate } por segundo.
replay-stopped = La reproducción se detuvo: { $reason }

replay-list-heading = Reproducir una sesión
replay-list-running = Aún en curso: su grabación llega cuando termina la sesión.
replay-list-not-arrived = Su grabación aún no ha llegado. La estación la sube tras la sesión, cuando puede conectar con el hub.
replay-list-arriving = Su grabación está llegando: { $percent } % hasta ahora. La repetición se abre cuando haya llegado entera.
replay-list-stalled = Su grabación dejó de llegar al { $percent } %: nada desde { $at }. La estación enviará el resto cuando vuelva a estar en línea.
replay-list-ready = Grabación lista: ábrala por su fecha y hora.
replay-list-note = { $count ->
    [one] { $ready } de 1 sesión se puede reproducir desde la grabación que subió la estación: el brazo, el coche y las gráficas tal como fueron, con reproducir, pausa y avance.
   *[other] { $ready } de { $count } sesiones se pueden reproducir desde la grabación que subió la estación: el brazo, el coche y las gráficas tal como fueron, con reproducir, pausa y avance.
}
replay-list-none = Aún no hay sesiones: una sesión se puede reproducir cuando la estación haya subido su grabación.
replay-list-caption = Las sesiones del paciente, de la más reciente a la más antigua
replay-list-col-started = Inicio
replay-list-col-exercise = Ejercicio
replay-list-col-recording = Grabación
