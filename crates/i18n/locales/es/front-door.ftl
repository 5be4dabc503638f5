# Las páginas antes de la primera sesión y la página de hoy. Frases cortas, trato de «usted».

## Elegir el idioma
front-language-title = Elija su idioma
front-language-how = Gire el volante para elegir. Pulse un botón.

## Conectar con la clínica
front-pairing-title = Bienvenido
front-pairing-card = La tarjeta de su clínica está aquí.
front-pairing-card-press = Pulse un botón del volante para conectar.
front-pairing-card-bad = No se puede leer la tarjeta de su clínica. Llame a su clínica.
front-pairing-ask-clinic = Este ordenador aún no conoce su clínica.
front-pairing-call-clinic = Llame a su clínica, por favor. Ellos lo preparan.
front-pairing-code-intro = Escriba el código de la carta de su clínica.
front-pairing-code-how = Gire el volante para elegir un signo. Pulse para tomarlo.
front-pairing-code-back = Mantenga el botón pulsado para borrar un signo.
front-pairing-code-label = Código
front-pairing-address-label = Dirección de la clínica
front-pairing-keys = Teclado: escriba, Intro para seguir, Tab para la dirección.
front-connecting-title = Conectando con su clínica
front-connecting-wait = Espere, por favor.
front-connected = Este ordenador ya está conectado con su clínica.

## Errores al conectar (el código se queda en la página)
front-error-code = Este código no es correcto. Compárelo con la carta.
front-error-code-length = El código tiene 8 signos. Compárelo con la carta.
front-error-unreachable = No se puede llegar a la clínica. Revise internet y pulse otra vez.
front-error-refused = La clínica no acepta este código. Compárelo con la carta.
front-error-not-authentic = La respuesta no vino de su clínica. No se guardó nada.
front-error-save = Conectado, pero no se pudo guardar. Llame a su clínica.
front-error-other = No se pudo conectar. Llame a su clínica, por favor.
front-error-no-address = Escriba primero la dirección de la clínica.

## Hoy
front-today-title = Sus ejercicios de hoy
front-today-summary = { $exercises ->
    [one] 1 ejercicio
   *[other] { $exercises } ejercicios
}, unos { $minutes ->
    [one] 1 minuto
   *[other] { $minutes } minutos
} con descansos
front-today-no-plan = Su clínica aún no ha enviado su plan.
front-today-unbuildable = Un ejercicio que este ordenador no puede mostrar
front-today-checking = Comprobando el volante…
front-today-how = Gire el volante para elegir. Pulse un botón.
front-today-wait-wheel = Podrá empezar cuando el volante esté listo.
front-today-start = Empezar
front-today-practice = Practicar
front-today-close = Cerrar
front-today-keys = Teclado: espacio empieza, F2 practica, Esc cierra.
front-today-offline = Ahora no se puede llegar a su clínica. Su sesión se guarda aquí.
front-today-message = Un mensaje de su terapeuta:

## Los aparatos
front-device-no-wheel = No hay volante. Conéctelo y enciéndalo.
front-device-wheel = Volante: { $name }
front-device-wheel-unknown = Su fuerza será baja hasta que su clínica la ajuste.
front-device-simulated = Volante: un volante de práctica en la pantalla
front-device-permission = Este ordenador aún no puede usar el volante. Llame a su clínica.
front-device-arm-sensors = Sensores del brazo: { $names }
front-device-no-arm-sensors = Sin sensores del brazo. La sesión funciona sin ellos.

## Práctica
front-practice-banner = Práctica · no se guarda nada
