# Las pantallas de la sesión. Trato de «usted». Cada frase, 12 palabras como máximo.

## Nombres de los ejercicios
exercise-straight-road = Carretera recta
exercise-sine-road = Carretera con curvas
exercise-triangle-road = Carretera en zigzag
exercise-clothoid-road = Curvas cada vez más cerradas
exercise-sharp-turns = Curvas cerradas
exercise-s-bend = Curva doble
exercise-lane-change = Cambiar de carril
exercise-slalom = Conducir entre los conos
exercise-dial-sine = Seguir la aguja
exercise-dial-multi-sine = Seguir la aguja que va y viene
exercise-dial-step = Seguir la aguja que salta
exercise-dial-ramp = Seguir la aguja lenta
exercise-dial-chirp = Seguir la aguja cada vez más rápida
exercise-strength = Empujar el volante
exercise-haptic-sweep = Sentir el volante
exercise-assessment-range = Prueba: cuánto puede girar
exercise-assessment-tracking-slow = Prueba: seguir la aguja lenta
exercise-assessment-tracking-medium = Prueba: seguir la aguja
exercise-assessment-tracking-fast = Prueba: seguir la aguja rápida
exercise-assessment-steps = Prueba: seguir la aguja que salta
exercise-assessment-strength = Prueba: empujar el volante
exercise-other = Ejercicio

## Lo que pide cada ejercicio
instruction-dial = Gire el volante. Mantenga la aguja negra sobre la roja.
instruction-strength = Empuje el volante a la izquierda y luego a la derecha. Con la fuerza que le resulte cómoda.
instruction-slalom = Pase entre los conos. No se salga de la carretera.
instruction-lane-change = Cuando la carretera se desvíe, cambie de carril.
instruction-straight-road = Mantenga el coche en el centro del carril.
instruction-bends = Tome las curvas. Manténgase en su carril.
instruction-road = Siga la carretera. Manténgase en su carril.
instruction-pedals = Sus pies marcan la velocidad. Pedal derecho: avanzar. Izquierdo: frenar.
instruction-assessment-range = Gire el volante al máximo: primero a la izquierda, luego a la derecha. Manténgalo ahí.
instruction-assessment-tracking = Esto es una prueba. El volante no ayuda. Mantenga la aguja negra sobre la roja.
instruction-assessment-steps = La aguja roja salta. Sígala lo más rápido que pueda.

## La tarjeta antes de cada ejercicio y entre ejercicios
card-get-ready = Prepárese
card-rest-then-back = Descanso. Después, otra vez:
card-rest-then-next = Descanso. Después:
card-next = Siguiente
card-exercise-of = Ejercicio { $number } de { $total }: { $name }
card-start-key = Espacio o un botón del volante: empezar
card-go-on-now-key = Espacio o un botón del volante: seguir ahora
card-message-from-therapist = Un mensaje de su terapeuta:

## La pausa y la pregunta antes de terminar
pause-title = En pausa
end-confirm-title = ¿Terminar la sesión?
end-confirm-yes = Pulse Esc otra vez para terminar.
end-confirm-no = Pulse Espacio para seguir.

## Tarjetas sencillas
card-press-space-to-start = Pulse Espacio para empezar.
card-all-done = ¡Terminado!

## Preparar los sensores del brazo
setup-hold-still = Mantenga el volante quieto
setup-hold-still-how = Ponga las dos manos en el volante. Relájese.
setup-turn-slowly = Gire el volante despacio
setup-turn-slowly-how = A izquierda y derecha, hasta donde le resulte cómodo.
setup-thank-you = Gracias
setup-getting-ready = Preparando los sensores del brazo…
setup-seconds-left = { $seconds } s

## Lo que se ve durante el ejercicio
hud-time-left = Tiempo restante
hud-in-lane = En el carril: { $percent } %
hud-middle-close = Cerca del centro
hud-middle-off = Un poco fuera del centro
hud-middle-far = Lejos del centro
hud-needle-close = Justo sobre la aguja roja
hud-needle-near = Cerca de la aguja roja
hud-needle-behind = Intente no quedarse atrás
hud-push-left = Empuje el volante a la izquierda, con la fuerza que le resulte cómoda.
hud-push-right = Empuje el volante a la derecha, con la fuerza que le resulte cómoda.
hud-let-go = Suelte el volante y descanse.
hud-speed = { $kmh } km/h
hud-help = Ayuda: { $percent } %
hud-press-pedal = Pise el pedal derecho para avanzar.
hud-sit-up = Vuelva a sentarse derecho.
hud-wheel-working = Volante: funciona
hud-wheel-resting = Volante: en reposo
hud-wheel-stopping = Volante: parando
hud-wheel-problem = Volante: no funciona, sin fuerza
hud-wheel-simulated = Volante: de práctica
hud-gentle-force = Solo fuerza suave
hud-arm-working = Sensores del brazo: funcionan
hud-arm-setting-up = Sensores del brazo: preparándose
hud-arm-not-working = Sensores del brazo: no funcionan
hud-arm-not-answering = Sensores del brazo: sin señal
hud-arm-simulated = Sensores del brazo: de práctica
hud-your-arm = Su brazo
hud-your-wheel = Su volante
hud-target = Objetivo
hud-your-arm-measured = Su brazo, medido

## Cuando la sesión no puede empezar
cannot-start-title = La sesión aún no puede empezar
cannot-start-then = Después, vuelva a abrir telerehab.
cannot-start-close-key = Pulse cualquier tecla para cerrar.

## Cuando la pantalla se reinició
pause-screen-restarted = La pantalla se reinició y el ejercicio está en pausa.
