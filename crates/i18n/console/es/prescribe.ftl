# El formulario de prescripción (crates/hub/console/prescribe.js).

prescribe-heading = Pauta de ejercicios
prescribe-version = Versión { $version }, prescrita por { $by } el { $when }.
prescribe-version-gone = un terapeuta que ya no está en la clínica
prescribe-version-none = Aún no hay nada prescrito: la estación ejecuta su ejercicio predeterminado.
prescribe-version-now = Versión { $version }, prescrita por { $by } ahora mismo.
prescribe-sessions-label = Sesiones por semana
prescribe-assessment-label = Evaluación estándar cada … días (vacío: ninguna)
prescribe-trunk-cue-label = Recordar sentarse derecho cuando el tronco se mueve más de … grados (vacío: nunca)
prescribe-no-exercise = Aún no hay ejercicios: añada uno.
prescribe-add-label = Añadir un ejercicio
prescribe-add-button = Añadir
prescribe-full = Como máximo { $max } ejercicios en una pauta, contando las series.
prescribe-message-note = Para informar a { $name } del cambio, escriba en el cuadro de mensajes de abajo. Se envía con la prescripción al guardar.
prescribe-save = Guardar como nueva versión
prescribe-saving = Guardando…
prescribe-saved = { $message ->
    [yes] Guardada como versión { $version }, con el mensaje.
   *[no] Guardada como versión { $version }.
}
prescribe-message-problem = El mensaje: { $problem }
prescribe-out-of-bounds = Un valor está fuera de sus límites (indicados a su lado).
prescribe-too-many = { $count } ejercicios contando las series: como máximo { $max }.
prescribe-total = { $untimed ->
    [0] Unos { $minutes } min de ejercicio y { $rests } min de descanso.
    [one] Unos { $minutes } min de ejercicio y { $rests } min de descanso, y un ejercicio sin minutos (se recorre una vez o lo cronometra el propio ejercicio).
   *[other] Unos { $minutes } min de ejercicio y { $rests } min de descanso, y { $untimed } ejercicios sin minutos (se recorren una vez o los cronometra el propio ejercicio).
}

prescribe-exercise-legend = Ejercicio { $n }: { $name }
prescribe-kind-unknown = Un tipo de ejercicio que este hub no conoce: edítelo en la versión de texto.
prescribe-remove = Quitar el ejercicio { $n }
prescribe-levels-legend = Dificultad
prescribe-level-easy = Fácil
prescribe-level-medium = Medio
prescribe-level-hard = Difícil
prescribe-level-own = Ajustes propios
prescribe-level-own-note = distintos de los niveles (vea los detalles)
prescribe-minutes-label = Minutos
prescribe-minutes-road = una vez a lo largo de la carretera
prescribe-sets-label = Series (el ejercicio repetido tras un descanso)
prescribe-rest-label = Descanso tras cada serie, segundos
prescribe-rest-default = solo la tarjeta breve
prescribe-dial-other = El objetivo se mueve con otro patrón que una oscilación: sus ajustes están en la versión de texto.
prescribe-dial-range-label = Cuánto gira el volante a cada lado, grados
prescribe-dial-pace-label = Una oscilación de ida y vuelta, segundos
prescribe-dial-words = El volante gira hasta { $degrees }° a cada lado ({ $range ->
    [small] un giro pequeño
    [quarter] hasta un cuarto de vuelta
   *[more] más de un cuarto de vuelta
}), una oscilación de ida y vuelta cada { $seconds } s ({ $pace ->
    [slow] lenta
    [moderate] moderada
   *[brisk] rápida
}).
prescribe-dial-sine = El objetivo: un seno de { $degrees }° a { $rate } rad/s (amplitude_deg, frequency_rad_s).
prescribe-ceiling-label = Empuje máximo del volante (límite de par), N·m (vacío: el de la estación)
prescribe-pedals-label = El paciente fija la velocidad con los pedales (requiere minutos; sin marcar, velocidad automática)
prescribe-details-summary = Detalles: los ajustes detrás del nivel

prescribe-text-summary = Editar como texto (todos los ajustes, como en la carpeta regimens de la estación)
prescribe-text-label = Pauta (TOML)
prescribe-text-save = Guardar el texto como nueva versión

prescribe-bounds-heading = Límites de seguridad que aplica la estación
prescribe-bounds-ceiling = Límite de par
prescribe-bounds-ceiling-text = Como máximo { $nm } N·m en una prescripción ({ $wheel ->
    [patient] lo que puede dar el volante de este paciente
   *[consumer] el volante comercial más potente
}); por encima, se rechaza. La estación lo limita después al tope de su propio volante: una prescripción puede bajar el límite del paciente, nunca subirlo.
prescribe-bounds-slew = Cambios de par
prescribe-bounds-slew-text = Limitados en su velocidad de cambio por la cadena de seguridad de la estación, sea cual sea la prescripción.
prescribe-bounds-session = Sesión
prescribe-bounds-session-text = Como máximo { $max } ejercicios (cada serie cuenta como uno), planificados para durar como máximo { $minutes } min en total, incluidos los descansos y las tarjetas entre ejercicios.
prescribe-bounds-levels = Niveles
prescribe-bounds-levels-text = El validador de la propia estación comprueba cada nivel fácil, medio y difícil.
prescribe-bounds-other = Cualquier otro ajuste
prescribe-bounds-other-text = Dentro del intervalo indicado a su lado.
prescribe-bounds-note = Los intervalos del formulario vienen del esquema de la pauta, que el hub deriva del validador de la estación. El hub comprueba la pauta entera con ese validador antes de guardarla; la estación toma la nueva versión en su próxima sesión.

prescribe-difficulty-legend = Dificultad que se adapta al paciente
prescribe-difficulty-adapt = Adaptar la dificultad de cada sesión al paciente (buscando la tasa de éxito objetivo y respetando «demasiado fácil» y «demasiado difícil»)
prescribe-difficulty-changes = Cambia:
prescribe-difficulty-note = La dificultad 1 es la pauta tal como está escrita; 0 es la mitad de su velocidad y de su forma, con toda su asistencia. Nunca más allá de la prescripción; el límite de par no cambia nunca.
prescribe-difficulty-target_success = La tasa de éxito que busca la adaptación
prescribe-difficulty-lowest = La dificultad más fácil permitida
prescribe-difficulty-highest = La dificultad más difícil permitida
prescribe-difficulty-start = La dificultad de la primera sesión
prescribe-aspect-speed = velocidad
prescribe-aspect-shape = forma
prescribe-aspect-assist = asistencia

prescribe-kind-straight = Carretera recta
prescribe-kind-sine = Carretera sinusoidal
prescribe-kind-triangle = Carretera triangular
prescribe-kind-clothoid = Carretera clotoide
prescribe-kind-sharp-turns = Giros cerrados
prescribe-kind-s-bend = Curva en S
prescribe-kind-lane-change = Cambio de carril
prescribe-kind-slalom = Eslalon
prescribe-kind-dial = Dial
prescribe-kind-strength = Fuerza
prescribe-kind-haptic-sweep = Barrido háptico

prescribe-preset-straight-easy = Un carril ancho, a poca velocidad.
prescribe-preset-straight-medium = Un carril normal a velocidad urbana.
prescribe-preset-straight-hard = Un carril estrecho, más rápido.
prescribe-preset-sine-easy = Ondas largas y suaves en un carril ancho, despacio.
prescribe-preset-sine-medium = La carretera con curvas de la tesis.
prescribe-preset-sine-hard = Ondas grandes y más juntas en un carril estrecho.
prescribe-preset-triangle-easy = Zigzags poco marcados con esquinas amplias, despacio.
prescribe-preset-triangle-medium = Zigzags con esquinas redondeadas.
prescribe-preset-triangle-hard = Zigzags pronunciados con esquinas cerradas.
prescribe-preset-clothoid-easy = Una curva que se cierra un poco, despacio.
prescribe-preset-clothoid-medium = Una curva que se cierra de forma continua.
prescribe-preset-clothoid-hard = Una curva que se cierra mucho en un carril estrecho.
prescribe-preset-sharp-turns-easy = Algunos medios giros en curvas amplias.
prescribe-preset-sharp-turns-medium = Giros en ángulo recto, a izquierda y derecha.
prescribe-preset-sharp-turns-hard = Más giros en ángulo recto, más cerrados y seguidos.
prescribe-preset-s-bend-easy = Dos curvas suaves en un carril ancho.
prescribe-preset-s-bend-medium = Una curva a la izquierda y luego a la derecha.
prescribe-preset-s-bend-hard = Dos curvas cerradas en un carril estrecho.
prescribe-preset-lane-change-easy = Tres cambios de carril lentos y largos.
prescribe-preset-lane-change-medium = Cuatro cambios de carril a velocidad urbana.
prescribe-preset-lane-change-hard = Seis cambios de carril rápidos.
prescribe-preset-slalom-easy = Seis conos muy separados, despacio.
prescribe-preset-slalom-medium = Ocho conos.
prescribe-preset-slalom-hard = Diez conos muy juntos en un carril estrecho.
prescribe-preset-dial-easy = Giros pequeños a cada lado, despacio.
prescribe-preset-dial-medium = Giros de un cuarto de vuelta o más a cada lado.
prescribe-preset-dial-hard = Giros grandes a cada lado, más rápido.
prescribe-preset-strength-easy = Una prueba suave: el muelle se endurece despacio.
prescribe-preset-strength-medium = La prueba estándar.
prescribe-preset-strength-hard = Una prueba más rápida: el muelle se endurece antes.
prescribe-preset-haptic-sweep-easy = Tres pasos de medio minuto, oscilaciones pequeñas y lentas.
prescribe-preset-haptic-sweep-medium = Los seis pasos de un minuto de la tesis.
prescribe-preset-haptic-sweep-hard = Seis pasos de un minuto, oscilaciones más rápidas.

## Los ajustes detrás del nivel de un ejercicio (detalles), uno por campo de la pauta: unidades como en la pauta.
prescribe-field-lane-width-m = Ancho del carril, m
prescribe-field-length-m = Longitud del tramo de ejercicio, m
prescribe-field-speed-m-s = Velocidad objetivo, m/s
prescribe-field-amplitude-m = Amplitud de las curvas, m
prescribe-field-periods = Número de ondas completas
prescribe-field-wavelength-m = Longitud de onda, m
prescribe-field-corner-radius-m = Radio de las esquinas redondeadas, m
prescribe-field-end-curvature-1-m = Curvatura al final, 1/m (positiva: hacia la izquierda)
prescribe-field-unwind-m = Longitud de la curva que se abre, m
prescribe-field-angle-deg = Ángulo de giro, °
prescribe-field-count = Número de giros o cambios
prescribe-field-radius-m = Radio de giro, m
prescribe-field-straight-m = Recta entre giros, m
prescribe-field-hold-m = Recta tras cada cambio, m
prescribe-field-offset-m = Desplazamiento lateral, m
prescribe-field-transition-m = Longitud de un cambio, m
prescribe-field-cone-count = Número de conos
prescribe-field-cone-spacing-m = Distancia entre conos, m
prescribe-field-weave-m = Distancia lateral del recorrido a cada cono, m
prescribe-field-drift-deg = Lo que el objetivo se desplaza hacia el lado desatendido, ° de giro del volante
prescribe-field-ramp-nm-per-s = Rapidez con que el límite del muelle sube al máximo, N·m/s
prescribe-field-side-s = Tiempo máximo por lado, s
prescribe-field-stiffness-nm-per-rad = Rigidez del muelle que sujeta el volante en el centro, N·m/rad
prescribe-field-amplitude-deg = Amplitud a cada lado, °
prescribe-field-frequency-rad-s = Frecuencia del movimiento, rad/s
prescribe-field-level-s = Tiempo en cada nivel, s
