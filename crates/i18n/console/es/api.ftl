# Los rechazos del hub en el idioma de la consola (crates/hub/console/api.js refusalWords).

## Los rechazos del hub en el idioma de la consola; las palabras del hub (el campo o la cosa)
## siguen en inglés cuando aportan algo.

api-error-400 = El hub no ha aceptado esto.
api-error-401 = No ha iniciado sesión, o el correo o la contraseña no son correctos.
api-error-403 = Solo un administrador de la clínica puede hacer esto.
api-error-404 = No se encuentra. Puede que se haya eliminado.
api-error-409 = Esto contradice lo que el hub tiene guardado.
api-error-413 = Es demasiado grande para el hub.
api-error-415 = El hub no ha entendido esta petición.
api-error-422 = Rechazado: fuera de los valores permitidos o de los límites de seguridad.
api-error-429 = Demasiados intentos. Vuelva a intentarlo en { $seconds } s.
api-error-503 = El hub está ocupado. Vuelva a intentarlo en { $seconds } s.
api-error-other = Algo ha fallado en el hub. Su registro tiene los detalles.

## Por qué el hub lo rechazó, según su código (crates/hub-store/src/refusal.rs): una frase clara cada uno.
## $field y $what llegan ya en las palabras de la consola.

api-why-field-refused = El hub no aceptó el campo «{ $field }».
api-why-empty = El campo «{ $field }» está vacío. Escriba unas palabras.
api-why-too-long = El campo «{ $field }» es demasiado largo: como máximo { $max } caracteres.
api-why-control-characters = El campo «{ $field }» tiene caracteres de control ocultos. Use texto simple.
api-why-missing = Falta el campo «{ $field }».
api-why-not-one-of = El campo «{ $field }» no tiene uno de los valores posibles.
api-why-out-of-range = El campo «{ $field }» debe estar entre { $min } y { $max }.
api-why-bad-date = El campo «{ $field }» no es un día válido. Escríbalo como año-mes-día.
api-why-future-date = El campo «{ $field }» está en el futuro. Elija el día en que ocurrió.
api-why-bad-id = La dirección nombra un identificador de «{ $field }» que no puede existir.
api-why-bad-email = Esto no es una dirección de correo. Se parece a nombre@clinica.es.
api-why-bad-pseudonym = Use hasta { $max } letras, cifras, puntos, guiones o guiones bajos. Nunca un nombre.
api-why-password-invisible = La contraseña tiene caracteres invisibles. Escriba solo lo que se ve.
api-why-password-length = La contraseña necesita al menos { $min } caracteres.
api-why-password-spaces = La contraseña es casi solo espacios.
api-why-password-email = La contraseña no puede ser su dirección de correo.
api-why-password-common = Esta contraseña es de las más comunes. Elija otra.
api-why-password-repeated = La contraseña se repite. Use al menos { $min } caracteres distintos.
api-why-password-sequence = La contraseña es una serie como abcdef o 123456. Elija otra.
api-why-password-guessable = La contraseña es demasiado fácil de adivinar. Unas palabras sin relación funcionan bien.
api-why-password-same = La contraseña nueva debe ser distinta de la actual.
api-why-snooze-past = Un aplazamiento debe terminar en el futuro. Elija un día posterior.
api-why-not-found = { $what } no está. Quizá se eliminó.
api-why-already-exists = { $what } ya existe. Elija otro.
api-why-no-endpoint = El hub no tiene esa página.
api-why-login-refused = Correo o contraseña incorrectos.
api-why-log-in-first = Inicie sesión primero.
api-why-one-time-password = Cambie primero su contraseña de un solo uso.
api-why-admin-only = Solo un administrador de la clínica puede hacer esto.
api-why-own-care-only = Solo puede añadir pacientes a su propio cuidado. Un administrador puede elegir a otro terapeuta.
api-why-no-therapist-email = Ningún terapeuta tiene esta dirección de correo.
api-why-throttled = Demasiados intentos. Vuelva a intentarlo en { $seconds } s.
api-why-alert-gone = Esta alerta ya se resolvió. Vuelva a cargar la lista de pacientes.
api-why-alert-changed = Ha pasado algo nuevo desde que se mostró esta alerta. Mírela otra vez. No se guardó nada.
api-why-regimen-shape = El hub no pudo leer esta prescripción.
api-why-regimen-text = El texto de la prescripción tiene un error en la línea { $line }.
api-why-regimen-unreadable = El texto de la prescripción no se puede leer.
api-why-regimen-exercise = El ejercicio { $exercise } tiene un valor fuera de su rango permitido.
api-why-above-wheel = El ejercicio { $exercise } pide más fuerza de la que da el volante de este paciente: como máximo { $max_nm } N·m.
api-why-recording-not-arrived = La grabación de esta sesión aún no ha llegado entera.
api-why-recording-unreadable = La grabación de esta sesión no se puede leer en el hub.
api-why-recording-too-large = Esta grabación tiene { $mb } MB. El hub reproduce como máximo { $max_mb } MB.
api-why-replay-pending = Su última reproducción aún se está preparando. Espere a que aparezca.
api-why-replay-busy = El hub está ocupado con otras reproducciones. Inténtelo de nuevo en un momento.
api-why-live-streams = Como máximo { $max } vistas en directo a la vez. Cierre una primero.
api-why-unknown-language = La consola no tiene palabras en este idioma.
api-why-unknown-time-zone = El hub no conoce esta zona horaria.
api-why-body-malformed = El hub no pudo leer esta petición.
api-why-body-too-large = Esto es demasiado grande para el hub.
api-why-body-not-json = El hub no entendió esta petición.
api-why-internal = Algo falló en el hub. Su registro tiene los detalles.

## Los campos y las cosas que nombra un rechazo.

api-field-text = texto
api-field-note = nota
api-field-password = contraseña
api-field-email = correo electrónico
api-field-pseudonym = seudónimo
api-field-snooze-until-ms = fin del aplazamiento
api-field-setting = ajuste
api-field-scale = escala
api-field-assessed-on = día de la evaluación
api-field-score = puntuación
api-field-affected-blocks-per-min = bloques por minuto, lado afectado
api-field-unaffected-blocks-per-min = bloques por minuto, lado no afectado
api-field-sort = orden
api-field-alert = alerta
api-field-query = búsqueda
api-field-key = alerta
api-field-regimen = prescripción
api-field-path = dirección
api-field-patient-id = paciente
api-field-session-id = sesión
api-field-station-id = estación
api-field-scale-id = evaluación
api-thing-patient = Este paciente
api-thing-station = Esta estación
api-thing-session = Esta sesión
api-thing-therapist = Este terapeuta
api-thing-scale = Esta evaluación
api-thing-pseudonym = Este seudónimo
api-thing-email = Esta dirección de correo
api-thing-clinical-scale = Esta evaluación
api-thing-station-or-certificate = Esta estación
