# Medidas, motivos de fin, tipos de ejercicio, tendencias y tiempos en palabras clínicas. Las
# claves, unidades, decimales e intervalos están solo en crates/metrics/src/words.rs.

## Nombres de las medidas

words-measure-active-s = Tiempo activo
words-measure-session-s = Duración de la sesión
words-measure-paused-s = Tiempo en pausa
words-measure-active-pct = Tiempo en movimiento
words-measure-movements = Movimientos
words-measure-discrete-movements = Movimientos de reposo a reposo
words-measure-movements-per-min = Movimientos por minuto
words-measure-reversals-per-min = Cambios de dirección de giro por minuto
words-measure-sparc-median = Fluidez (más cerca de 0 es más fluido)
words-measure-ldlj-median = Fluidez de la aceleración (más cerca de 0 es más fluido)
words-measure-movement-peak-speed-deg-s-median = Velocidad máxima de giro de un movimiento
words-measure-movement-time-s-median = Duración de un movimiento
words-measure-speed-peaks-median = Paradas y arranques en un movimiento
words-measure-speed-metric-median = Regularidad de la velocidad (1 es regular)
words-measure-reaction-time-s-median = Tiempo de reacción
words-measure-anticipation-pct = Cambios de carril empezados antes de llegar
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
words-measure-trunk-cues = Recordatorios para sentarse derecho
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

## Qué mide cada medida, para el profesional (words-definition-<key>; docs/MEASURES.md)

words-definition-active-s = Tiempo en que el volante se movió: la suma de las duraciones de los movimientos, sin pausas.
words-definition-session-s = Tiempo desde el inicio hasta el final de la sesión, con las pausas.
words-definition-paused-s = Tiempo en que la sesión estuvo en pausa por el paciente o para descansar.
words-definition-active-pct = Parte del tiempo de ejercicio en que el volante se movió.
words-definition-movements = Movimientos del volante: su velocidad por encima del 5 % de la máxima de la sesión (al menos 2,9 °/s), huecos de menos de 0,1 s unidos, tramos de menos de 0,2 s descartados.
words-definition-discrete-movements = Movimientos de reposo a reposo: al menos 0,2 s quieto antes y después, como mucho 5 s. Solo estos se puntúan por suavidad.
words-definition-movements-per-min = Movimientos por minuto de ejercicio: la dosis de práctica.
words-definition-reversals-per-min = Cambios del sentido de giro del volante de al menos 2° por minuto de ejercicio.
words-definition-sparc-median = Longitud de arco espectral de la velocidad del volante, mediana de los movimientos de reposo a reposo; ninguna en una tarea continua. Más cerca de 0 es más suave.
words-definition-ldlj-median = Logaritmo del tirón adimensional de la velocidad del volante, mediana de los movimientos de reposo a reposo; ninguno en una tarea continua. Más cerca de 0 es más suave.
words-definition-movement-peak-speed-deg-s-median = Velocidad de giro más alta dentro de un movimiento, mediana de los movimientos.
words-definition-movement-time-s-median = Duración de un movimiento, desde que su velocidad supera el umbral hasta que vuelve a bajar, mediana.
words-definition-speed-peaks-median = Picos de velocidad dentro de un movimiento (al menos el 10 % de su velocidad máxima), mediana; 1 es un único movimiento suave.
words-definition-speed-metric-median = Velocidad media de un movimiento entre su velocidad máxima, mediana; sube cuando los movimientos se completan con la recuperación.
words-definition-reaction-time-s-median = Tiempo desde un salto imprevisible del objetivo (el de la esfera) hasta que el volante empieza a moverse, mediana.
words-definition-anticipation-pct = Parte de los cambios de carril vistos de antemano cuyo giro empezó antes de 0,1 s tras el cambio: anticipados, no reacciones.
words-definition-initial-direction-error-deg-mean = Si un movimiento tras un salto del objetivo empieza en el sentido equivocado: 0° el correcto, 180° el equivocado, media.
words-definition-reaction-time-left-s-median = Tiempo de reacción a saltos imprevisibles del objetivo hacia la izquierda, mediana.
words-definition-reaction-time-right-s-median = Tiempo de reacción a saltos imprevisibles del objetivo hacia la derecha, mediana.
words-definition-initial-direction-error-left-deg-mean = Inicios en sentido equivocado hacia objetivos a la izquierda, media (0° el correcto, 180° el equivocado).
words-definition-initial-direction-error-right-deg-mean = Inicios en sentido equivocado hacia objetivos a la derecha, media (0° el correcto, 180° el equivocado).
words-definition-path-length-ratio-median = Giro recorrido tras un salto del objetivo entre el giro necesario para alcanzarlo, mediana; 1 es directo.
words-definition-wheel-rom-deg = Ángulo del volante más grande menos el más pequeño durante el ejercicio.
words-definition-shoulder-elevation-rom-deg = Ángulo de elevación del hombro más grande menos el más pequeño mientras los sensores del brazo seguían.
words-definition-elbow-flexion-rom-deg = Ángulo de flexión del codo más grande menos el más pequeño mientras los sensores del brazo seguían.
words-definition-trunk-flexion-max-deg = Mayor inclinación del tronco hacia delante desde la postura inicial, según el sensor del esternón.
words-definition-trunk-flexion-mean-deg = Inclinación media del tronco hacia delante desde la postura inicial, según el sensor del esternón.
words-definition-trunk-lean-max-deg = Mayor inclinación lateral del tronco desde la postura inicial, según el sensor del esternón.
words-definition-trunk-lean-mean-deg = Inclinación lateral media del tronco desde la postura inicial, según el sensor del esternón.
words-definition-trunk-rotation-max-deg = Mayor giro del tronco desde la postura inicial, según el sensor del esternón.
words-definition-trunk-rotation-mean-deg = Giro medio del tronco desde la postura inicial, según el sensor del esternón.
words-definition-trunk-beyond-pct = Parte del tiempo de ejercicio con algún ángulo del tronco por encima del umbral de la estación.
words-definition-trunk-compensated-movements-pct = Parte de los movimientos del volante en los que el tronco superó el umbral.
words-definition-trunk-cues = Veces que la estación pidió al paciente sentarse derecho: el tronco se mantuvo un segundo más allá del umbral de aviso del terapeuta; como mucho uno cada 20 s.
words-definition-pct-in-lane = Parte del tiempo de conducción con el coche dentro de su carril.
words-definition-rms-lateral-m = Media cuadrática de la distancia del coche al centro del carril.
words-definition-heading-rms-error-deg = Media cuadrática del ángulo entre la dirección del coche y la de la carretera.
words-definition-cone-hits = Conos que el coche tocó.
words-definition-completion-time-s = Tiempo hasta llegar al final del recorrido.
words-definition-tracking-rms-error-deg = Media cuadrática de la diferencia entre el ángulo del volante pedido y el del volante.
words-definition-dial-rms-error-deg = Media cuadrática de la diferencia entre el ángulo objetivo de la esfera y la aguja del volante.
words-definition-dial-mean-abs-error-deg = Media de la diferencia absoluta entre el ángulo objetivo de la esfera y la aguja del volante.
words-definition-strength-peak-left-nm = Par más alto girando a la izquierda contra el muelle del volante, con el volante casi quieto.
words-definition-strength-sustained-left-nm = Par más alto girando a la izquierda mantenido al menos 1 s.
words-definition-strength-peak-right-nm = Par más alto girando a la derecha contra el muelle del volante, con el volante casi quieto.
words-definition-strength-sustained-right-nm = Par más alto girando a la derecha mantenido al menos 1 s.
words-definition-assist-level-mean = Cuánto ayudó el volante, media del ejercicio: 0 sin ayuda, 1 ayuda completa.
words-definition-patient-work-pct = Parte del paciente en el trabajo mecánico hecho sobre el volante (el del paciente y la ayuda del volante juntos).
