# Las tarjetas de la sesión que responde el volante. Pulsar = corto; mantener = 1,5 segundos.

controls-paused-title = En pausa
controls-paused-go-on = Seguir
controls-paused-rest = Descansar
controls-paused-end = Terminar
controls-paused-how = Gire para elegir. Pulse un botón.
controls-paused-keys = Teclado: espacio sigue, R descansa, Esc termina.
controls-end-title = ¿Terminar ahora?
controls-end-press = Pulse el botón: terminar.
controls-end-hold = Mantenga el botón: seguir.
controls-end-keys = Teclado: Esc termina, espacio sigue.
controls-ready-title = ¿Listo?
controls-ready-press = Pulse un botón del volante para empezar.
controls-ready-countdown = { $seconds ->
    [one] Empieza en 1 segundo.
   *[other] Empieza en { $seconds } segundos.
}
controls-unplugged-title = Vuelva a conectar el volante
controls-unplugged-waits = El ejercicio le espera.
controls-unplugged-left = { $seconds ->
    [one] La sesión termina en 1 segundo.
   *[other] La sesión termina en { $seconds } segundos.
}
controls-unplugged-keys = El cable une el volante y el ordenador.
controls-arm-unplugged-title = Vuelva a conectar el sensor del brazo
controls-arm-unplugged-keys = El sensor de su brazo tiene un cable al ordenador.
controls-start = Pulse un botón del volante para empezar.
controls-go-on-now = Pulse un botón del volante para seguir ya.
