# Medidas, motivos de fin, tipos de ejercicio, tendencias y tiempos en palabras clínicas. Las
# claves, unidades, decimales e intervalos están solo en crates/metrics/src/words.rs.

## Nombres de las medidas

words-measure-active-s = Tiempo activo
words-measure-session-s = Duración de la sesión
words-measure-paused-s = Tiempo en pausa
words-measure-active-pct = Tiempo en movimiento
words-measure-movements = Movimientos
words-measure-movements-per-min = Movimientos por minuto
words-measure-reversals-per-min = Cambios de dirección de giro por minuto
words-measure-sparc-median = Fluidez (más cerca de 0 es más fluido)
words-measure-ldlj-median = Fluidez de la aceleración (más cerca de 0 es más fluido)
words-measure-movement-peak-speed-deg-s-median = Velocidad máxima de giro de un movimiento
words-measure-movement-time-s-median = Duración de un movimiento
words-measure-speed-peaks-median = Paradas y arranques en un movimiento
words-measure-speed-metric-median = Regularidad de la velocidad (1 es regular)
words-measure-reaction-time-s-median = Tiempo de reacción
words-measure-initial-direction-error-deg-mean = Inicio en la dirección equivocada
words-measure-reaction-time-left-s-median = Tiempo de reacción, objetivos a la izquierda
words-measure-reaction-time-right-s-median = Tiempo de reacción, objetivos a la derecha
words-measure-initial-direction-error-left-deg-mean = Inicio en la dirección equivocada, objetivos a la izquierda
words-measure-initial-direction-error-right-deg-mean = Inicio en la dirección equivocada, objetivos a la derecha
words-measure-path-length-ratio-median = Giro de más respecto a lo necesario (1 es nada)
words-measure-wheel-rom-deg = Recorrido de giro del volante
words-measure-shoulder-elevation-rom-deg = Recorrido de elevación del hombro
words-measure-elbow-flexion-rom-deg = Recorrido de flexión del codo
words-measure-trunk-flexion-max-deg = Tronco inclinado hacia delante, máximo
words-measure-trunk-flexion-mean-deg = Tronco inclinado hacia delante, promedio
words-measure-trunk-lean-max-deg = Tronco inclinado de lado, máximo
words-measure-trunk-lean-mean-deg = Tronco inclinado de lado, promedio
words-measure-trunk-rotation-max-deg = Tronco girado, máximo
words-measure-trunk-rotation-mean-deg = Tronco girado, promedio
words-measure-trunk-beyond-pct = Tiempo con el tronco demasiado movido
words-measure-trunk-compensated-movements-pct = Giros ayudados por el tronco
words-measure-pct-in-lane = Tiempo en el carril
words-measure-rms-lateral-m = Distancia al centro del carril
words-measure-heading-rms-error-deg = Desvío respecto a la dirección de la carretera
words-measure-cone-hits = Conos derribados
words-measure-completion-time-s = Tiempo hasta terminar
words-measure-tracking-rms-error-deg = Distancia al ángulo pedido
words-measure-dial-rms-error-deg = Dial: distancia al ángulo pedido
words-measure-dial-mean-abs-error-deg = Dial: distancia media al ángulo pedido
words-measure-strength-peak-left-nm = Fuerza al girar a la izquierda, máxima
words-measure-strength-sustained-left-nm = Fuerza al girar a la izquierda, mantenida 1 s
words-measure-strength-peak-right-nm = Fuerza al girar a la derecha, máxima
words-measure-strength-sustained-right-nm = Fuerza al girar a la derecha, mantenida 1 s
words-measure-assist-level-mean = Ayuda del volante (0 ninguna, 1 total)
words-measure-patient-work-pct = Parte del trabajo hecha por el paciente
words-name-unit = { $name } ({ $unit })

## Cómo terminó una sesión

words-end-complete = Completada
words-end-stopped-by-patient = Detenida antes de tiempo por el paciente
words-end-paused-too-long = Detenida antes de tiempo: pausa demasiado larga
words-end-screen-failed = Detenida antes de tiempo: falló la pantalla
words-end-wheel-unplugged = Detenida antes de tiempo: volante desconectado
words-end-arm-sensor-unplugged = Detenida antes de tiempo: sensor del brazo desconectado
words-end-safety-stop = Detenida antes de tiempo: parada de seguridad (se desactivó la fuerza del volante)
words-end-running = En curso
words-end-unreported = Terminada; no se indicó cómo
words-end-other = Detenida antes de tiempo
words-end-recording-stopped = { $end }; la grabación se detuvo antes de tiempo
words-not-in-trends = (no cuenta en las tendencias)

## Tipos de ejercicio

words-kind-road = carretera
words-kind-dial = dial
words-kind-strength = prueba de fuerza
words-kind-haptic-sweep = barrido háptico
words-kind-regimen = programa
words-kinds-and = { $first } y { $last }
words-regimen = { $count ->
        [one] Un programa de { $count } ejercicio
       *[other] Un programa de { $count } ejercicios
    }

## Tendencias, tiempos, estaciones

words-trend-better = mejor
words-trend-worse = peor
words-trend-steady = estable
words-seconds = { $n } s
words-minutes = { $n } min
words-of-prescribed = { $done } de { $prescribed } prescritos
words-station-paired = estación emparejada el { $day }

## Ejercicios por su nombre corto (el de la pauta) y los ejercicios de una sesión en orden

words-exercise-straight-road = Carretera recta
words-exercise-sine-road = Carretera sinusoidal
words-exercise-triangle-road = Carretera triangular
words-exercise-clothoid-road = Carretera clotoide
words-exercise-sharp-turns = Curvas cerradas
words-exercise-s-bend = Curva en S
words-exercise-lane-change = Cambio de carril
words-exercise-slalom = Eslalon
words-exercise-dial-sine = Dial sinusoidal
words-exercise-dial-multi-sine = Dial multisinusoidal
words-exercise-dial-step = Dial en escalón
words-exercise-dial-ramp = Dial en rampa
words-exercise-dial-chirp = Dial chirp
words-exercise-strength = Fuerza
words-exercise-haptic-sweep = Barrido háptico
words-exercises-then = { $first }, luego { $next }
