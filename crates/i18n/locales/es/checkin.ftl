# El final de una sesión: resultados, tres preguntas y la página tras un dolor fuerte.
# Palabras sencillas, frases cortas (12 palabras como mucho), «usted».
checkin-results-title = ¡Muy bien! Ha terminado.
checkin-results-stopped-title = La sesión terminó antes de tiempo.
checkin-results-wheel-stopped = El volante dejó de funcionar. Su fuerza está apagada. Avise a la clínica, por favor.
checkin-results-exercised = Ha hecho ejercicio durante { $time }.
checkin-results-lane = Se mantuvo en su carril el { $percent } % del tiempo.
checkin-results-dial = Su aguja estuvo a { $degrees }° del objetivo, de media.
checkin-results-better-lane = Más tiempo en su carril: { $percent } % (antes: { $was } %)
checkin-results-better-dial = Más cerca del objetivo: { $degrees }° (antes: { $was }°)
checkin-results-better-time = Ejercicio más largo: { $time } (antes: { $was })
checkin-results-first = La próxima vez verá cómo ha cambiado.
checkin-results-same = Más o menos igual que la última vez. ¡Bien hecho!
checkin-results-better = Mejor que la última vez:
checkin-seconds = { $seconds ->
    [one] { $seconds } segundo
   *[other] { $seconds } segundos
}
checkin-pain-question = ¿Cuánto dolor tiene ahora?
checkin-pain-0 = Sin dolor
checkin-pain-1 = Un poco de dolor
checkin-pain-2 = Algo de dolor
checkin-pain-3 = Mucho dolor
checkin-pain-4 = Dolor muy fuerte
checkin-pain-5 = El peor dolor
# Esfuerzo: las palabras de la escala CR10 de Borg en 0, 1, 2, 3, 4, 5, 7 y 10.
checkin-effort-question = ¿Cuánto esfuerzo le costó el ejercicio?
checkin-effort-0 = Nada en absoluto
checkin-effort-1 = Muy débil
checkin-effort-2 = Débil
checkin-effort-3 = Moderado
checkin-effort-4 = Algo fuerte
checkin-effort-5 = Fuerte
checkin-effort-7 = Muy fuerte
checkin-effort-10 = Extremadamente fuerte
checkin-difficulty-question = ¿Cómo fue el ejercicio de hoy?
checkin-difficulty-too-easy = Demasiado fácil
checkin-difficulty-just-right = Justo bien
checkin-difficulty-too-hard = Demasiado difícil
checkin-chosen-score = { $value } de 10: { $words }
checkin-choose-first = Gire el volante para elegir una respuesta.
checkin-key-turn = Gire el volante: elegir
checkin-key-press = Pulse: aceptar
checkin-key-hold = Mantenga pulsado: saltar
checkin-key-keyboard = Teclas: izquierda y derecha eligen, Enter acepta, Esc salta
checkin-key-start = Pulse: tres preguntas cortas
checkin-key-close = Pulse: cerrar
checkin-key-close-esc = Esc: cerrar
checkin-thanks-title = ¡Gracias!
checkin-thanks-text = Su terapeuta verá sus respuestas.
checkin-thanks-bye = Hasta la próxima.
checkin-stop-title = Por favor, pare y descanse.
checkin-stop-rest = Descanse el brazo ahora.
checkin-stop-no-more = No haga más ejercicio hoy.
checkin-stop-call = Por favor, llame a su clínica: { $phone }
checkin-stop-call-clinic = Por favor, llame hoy a su clínica.
checkin-stop-told = Su terapeuta sabrá de su dolor.
checkin-rest-today-title = Hoy, descanso
checkin-rest-today-pain = Hoy ha tenido mucho dolor.
checkin-rest-today-no-exercise = Por favor, no haga ejercicio hoy.
checkin-rest-today-wait = Su terapeuta puede dejarle volver a hacer ejercicio.
