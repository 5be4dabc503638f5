# La pestaña «Evolución» de un paciente.

progress-list-separator = {", "}
progress-percent = { $n } %

## Dolor, adherencia y avisos

progress-summary-title = Dolor, adherencia y avisos
progress-pain-title = Dolor
progress-pain-latest = Dolor { $pain }/10
progress-pain-after = tras la sesión del { $at }.
progress-pain-before = Antes: { $list } (la más reciente primero).
progress-pain-none = Todavía no hay respuesta de dolor.
progress-pain-chart-label = Dolor tras cada sesión, de 0 a 10: los números están en la lista de sesiones
progress-pain-axis = dolor (0–10)
progress-checkin-pain = dolor { $pain }/10
progress-checkin-effort = esfuerzo { $effort }/10
progress-checkin-skipped = omitido
progress-felt = le pareció { $felt }
progress-felt-too-easy = demasiado fácil
progress-felt-about-right = adecuado
progress-felt-too-hard = demasiado difícil
progress-after-last = Tras la última sesión: { $answers }.
progress-adherence-title = Adherencia
progress-week = Últimos 7 días: { $sessionsPrescribed ->
        [none] { $sessions ->
            [one] { $sessions } sesión
           *[other] { $sessions } sesiones
        }
       *[other] { $sessions } de { $sessionsPrescribed } sesiones prescritas
    }, { $minutesPrescribed ->
        [none] { $minutes ->
            [one] { $minutes } minuto activo
           *[other] { $minutes } minutos activos
        }
       *[other] { $minutes } de { $minutesPrescribed } minutos activos prescritos
    }.
progress-week-repetitions = Repeticiones en los últimos 7 días: { $repetitions }.
progress-stopped-early = Terminadas antes de tiempo: { $stopped } de { $count ->
        [one] la última sesión
       *[other] las últimas { $count } sesiones
    }.
progress-alerts-title = Avisos
progress-alerts-none = Ningún aviso.

## La dosis: tiempo de entrenamiento activo y repeticiones por semana y día

progress-dose-title = Dosis: tiempo de entrenamiento y repeticiones
progress-dose-explain = El tiempo de entrenamiento activo no cuenta las pausas. Las repeticiones son los movimientos del volante. Las semanas se comparan con la prescripción actual.
progress-dose-weeks-caption = { $weeks ->
        [one] Por semana: los últimos 7 días
       *[other] Por semana, las últimas { $weeks } semanas
    }
progress-dose-days-caption = Por día, los últimos 7 días
progress-dose-col-week = Semana
progress-dose-col-day = Día
progress-dose-col-sessions = Sesiones
progress-dose-col-active = Entrenamiento activo
progress-dose-col-repetitions = Repeticiones
progress-dose-week-range = { $from } a { $to }
progress-dose-below = por debajo de la prescripción

## La última sesión frente a las anteriores

progress-latest-title = Ejercicios: la última sesión frente a las anteriores
progress-latest-title-kind = Ejercicios: la última sesión de { $kind } frente a las anteriores
progress-compared = { $early ->
        [included] La última sesión terminada (según lo prescrito o antes de tiempo) ({ $session }) frente al valor inicial del paciente ({ $baseline ->
            [one] la primera sesión de { $kind }
           *[other] la media de las primeras { $baseline } sesiones de { $kind }
        }), y su tendencia frente a hasta { $earlier } sesiones anteriores de { $kind }; un cambio dentro del ruido de medida de una medida se indica como «estable». Se incluyen las sesiones terminadas antes de tiempo.
       *[left-out] La última sesión realizada según lo prescrito ({ $session }) frente al valor inicial del paciente ({ $baseline ->
            [one] la primera sesión de { $kind }
           *[other] la media de las primeras { $baseline } sesiones de { $kind }
        }), y su tendencia frente a hasta { $earlier } sesiones anteriores de { $kind }; un cambio dentro del ruido de medida de una medida se indica como «estable». Las sesiones terminadas antes de tiempo están en la lista de abajo, sin comparar.
    }
progress-compared-none = Ninguna sesión se ha realizado aún según lo prescrito: nada que comparar.
progress-col-measure = Medida
progress-col-latest = Última
progress-col-baseline = Valor inicial
progress-col-trend = Tendencia
progress-against-prescription = frente a lo prescrito, no es una tendencia
progress-include-early = Incluir las sesiones terminadas antes de tiempo
progress-include-early-none = Incluir las sesiones terminadas antes de tiempo (no hay ninguna)

## Cada tipo de ejercicio

progress-kind-title = Sesiones de { $kind } ({ $count })
progress-kind-latest = : última { $list }
progress-headline-item = { $measure } { $value }
progress-kind-note = { $names }. Un gráfico por medida, un paso por sesión, la más antigua a la izquierda.
progress-kind-hollow = Puntos huecos: { $count ->
        [one] { $count } sesión terminada antes de tiempo
       *[other] { $count } sesiones terminadas antes de tiempo
    } ({ $early ->
        [included] incluidas
       *[left-out] no unidas a la línea
    }).
progress-kind-no-measures = No se registraron medidas en estas sesiones.
progress-prescribed-time = Tiempo prescrito ({ $unit })
progress-noise-band = La franja sombreada es el ruido de medida alrededor del valor inicial: un punto dentro de ella no es un cambio.
progress-chart-label = { $measure } por sesión: los números están en la tabla de abajo

## Dificultad

progress-difficulty-title = Dificultad que se adapta al paciente
progress-difficulty-now = : ahora { $now } (0 lo más fácil, 1 lo prescrito)
progress-difficulty-explain = 0: la mitad de la velocidad y la forma prescritas, con toda su ayuda; 1: el programa tal como se prescribió. La ajusta la estación dentro de los límites del programa.
progress-difficulty-axis = dificultad (0–1)
progress-difficulty-why-adapt-off = Adaptación desactivada: el ajuste del terapeuta.
progress-difficulty-why-first-start = Primera sesión: el inicio que fijó el terapeuta.
progress-difficulty-why-first-midway = Primera sesión: a medio camino entre los límites del terapeuta.
progress-difficulty-why-success-above = Un éxito del { $success } % quedó por encima del objetivo del { $target } %.
progress-difficulty-why-success-below = Un éxito del { $success } % quedó por debajo del objetivo del { $target } %.
progress-difficulty-why-success-at = Un éxito del { $success } % quedó justo en el objetivo del { $target } %.
progress-difficulty-why-no-rate = Sin tasa de éxito de la última sesión: se mantuvo igual.
progress-difficulty-why-felt-too-hard = El paciente dijo que era demasiado difícil.
progress-difficulty-why-felt-too-easy = El paciente dijo que era demasiado fácil.
progress-difficulty-held-highest = Se mantuvo en el máximo del terapeuta.
progress-difficulty-held-lowest = Se mantuvo en el mínimo del terapeuta.
progress-numbers-caption = Los números del gráfico, los más recientes primero
progress-col-started = Inicio
progress-col-difficulty = Dificultad
progress-col-change = Cambio
progress-col-success = Éxito
progress-col-why = Motivo

## Nombres técnicos

progress-technical-summary = Detalles: los nombres técnicos de estas medidas
progress-technical-caption = Tal como los nombran la segunda fila de encabezado de la hoja de cálculo y la exportación FHIR
progress-col-data-name = Nombre en los datos
progress-col-technical = Nombre técnico

progress-definitions-summary = Qué mide cada medida, y su fuente
progress-col-definition = Definición
progress-col-source = Fuente

## Lista de sesiones e impresión

progress-sessions-title = Sesiones ({ $count })
progress-col-exercise = Ejercicio
progress-col-ended = Cómo terminó
progress-col-checkin = Respuestas del paciente
progress-col-results = Resultados y grabación
progress-col-notes = Notas del terapeuta
progress-each-exercise = Cada ejercicio
progress-replay = Reproducción
progress-note-session = la sesión del { $at }
progress-range = sesiones del { $from } al { $to }
progress-range-none = todavía sin sesiones
progress-zone-utc = horas en UTC
progress-zone = horas en { $zone } y UTC
progress-clinic-unnamed = Nombre de la clínica sin definir
progress-print-of = Evolución de { $name }
progress-printed = impreso el { $day }
progress-print = Imprimir un resumen de una página
progress-download = Descargar la hoja de cálculo (CSV; { $zone })
progress-download-assessments = Descargar las evaluaciones estándar (CSV; { $zone })
progress-scales-failed = No se pudieron mostrar las escalas clínicas: { $error }

## La evaluación estándar (issue 42): la misma prueba corta cada vez, la primera en la página

progress-assessment-title = Evaluación estándar
progress-assessment-intro = La misma prueba corta cada vez, sin ayuda del volante (protocolo { $protocol }). La más reciente primero. Se guarda aparte de los ejercicios y sus tendencias.
progress-assessment-none = Todavía no hay evaluación estándar. Para programarla, indique en la pauta cada cuántos días se hace.
progress-assessment-col-measure = Parte y medida
progress-assessment-row = { $part }: { $measure }
progress-assessment-part-range = Amplitud activa
progress-assessment-part-tracking-slow = Seguimiento, lento
progress-assessment-part-tracking-medium = Seguimiento, medio
progress-assessment-part-tracking-fast = Seguimiento, rápido
progress-assessment-part-steps = Saltos
progress-assessment-part-strength = Fuerza

## Cambio real distinguido del ruido (issue 42): la evaluación más reciente frente a la primera

progress-assessment-col-change = Cambio desde la primera ({ $day })
progress-assessment-col-change-none = Cambio desde la primera
progress-assessment-band = ± { $band } ({ $source })
progress-assessment-verdict-better = mejor
progress-assessment-verdict-worse = peor
progress-assessment-verdict-changed = cambió (ninguna dirección es mejor)
progress-assessment-verdict-within-noise = dentro del ruido de medida
progress-assessment-verdict-no-noise-figure = aún sin cifra de ruido, así que sin valoración
progress-assessment-source-own = Banda de ruido de las { $repeats } evaluaciones del propio paciente
progress-assessment-source-cohort = Banda de ruido de pacientes simulados con la misma prueba
progress-assessment-source-published = Banda de ruido de un estudio publicado
progress-assessment-source-short-own = propia
progress-assessment-source-short-cohort = cohorte
progress-assessment-source-short-published = estudio
progress-assessment-change-sr = Cambio desde la primera evaluación: { $change }. Banda de ruido más o menos { $band } ({ $source }). Valoración: { $verdict }.
progress-assessment-change-sr-none = Cambio desde la primera evaluación: { $change }. Aún sin cifra de ruido, así que sin valoración.
progress-assessment-change-none = Solo hay una evaluación: aún no hay nada que comparar.
progress-assessment-change-missing = No hay cambio que mostrar: la medida falta en la evaluación más reciente o en la primera.
progress-assessment-noise-note = Mejor o peor solo cuando el cambio supera el ruido de medida (± el menor cambio real, MDC95). Desde 6 evaluaciones la banda de ruido es la del propio paciente (propia); antes procede de pacientes simulados (cohorte) o de un estudio publicado (estudio).
