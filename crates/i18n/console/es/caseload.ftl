# La lista de pacientes (#/patients): quién necesita atención primero, el entrenamiento de la
# semana, las tendencias, confirmar avisos y permitir de nuevo el entrenamiento tras una parada
# por dolor.

caseload-title = Pacientes
caseload-order = Orden
caseload-order-need = Primero quien más atención necesita
caseload-order-last-session = Primero quien lleva más tiempo sin sesión
caseload-order-pseudonym = Por seudónimo
caseload-show = Mostrar
caseload-show-all = Todos los pacientes
caseload-show-only = Solo: { $kind }
caseload-mine = Solo mis pacientes
caseload-caption-need = Sus pacientes, primero quien más atención necesita. Abra un paciente para seguir una sesión en curso, ver la evolución o prescribir.
caseload-caption-chosen = Sus pacientes, en el orden elegido. Abra un paciente para seguir una sesión en curso, ver la evolución o prescribir.
caseload-col-patient = Paciente
caseload-col-needs = Necesita atención
caseload-col-last-session = Última sesión
caseload-col-last-7-days = Últimos 7 días
caseload-col-trend = Tendencia
caseload-none = Todavía no hay pacientes.
caseload-none-with-alert = Ningún paciente tiene este aviso ahora.
caseload-add-patient = Añadir un paciente
caseload-add-patient-note = (e imprimir la hoja de emparejamiento)
caseload-thresholds-link = Umbrales de aviso
caseload-nothing-needed = Nada requiere atención
caseload-more = { $count } más
caseload-acknowledged = { $count ->
        [one] { $count } aviso confirmado
       *[other] { $count } avisos confirmados
    }
caseload-week = { $sessionsPrescribed ->
        [none] { $sessions ->
            [one] { $sessions } sesión
           *[other] { $sessions } sesiones
        }
       *[other] { $sessions } de { $sessionsPrescribed } sesiones prescritas
    }, { $minutesPrescribed ->
        [none] { $minutes ->
            [one] { $minutes } min activo
           *[other] { $minutes } min activos
        }
       *[other] { $minutes } de { $minutesPrescribed } min activos prescritos
    }
# The week's repetitions (wheel movements) in the caseload's week column.
caseload-repetitions = { $repetitions ->
        [one] { $repetitions } repetición
       *[other] { $repetitions } repeticiones
    }
caseload-trend-kind = Sesiones de { $kind }:
caseload-trend-pct-in-lane = Tiempo en el carril
caseload-trend-wheel-rom-deg = Recorrido del volante
caseload-trend-sparc-median = Fluidez
caseload-trend-better = mejor
caseload-trend-worse = peor
caseload-trend-steady = estable
caseload-acknowledge = Confirmar
caseload-quiet-former = un terapeuta que ya no está en la clínica
caseload-quiet-snoozed = aplazado hasta el { $until } por { $who } el { $at }: { $note }
caseload-quiet-acknowledged = confirmado (en silencio hasta que haya algo nuevo) por { $who } el { $at }: { $note }

## Confirmar un aviso

caseload-ack-legend = Silenciar
caseload-ack-until-new = Hasta que ocurra algo nuevo
caseload-ack-until-day = Hasta un día:
caseload-ack-snooze-until = Aplazar hasta
caseload-ack-note = Nota
caseload-ack-note-hint = (qué se hizo, p. ej., «Llamado: descansa, ve al médico de cabecera el lunes»)
caseload-ack-no-day = Elija el día en que el aviso puede volver.
caseload-save = Guardar
caseload-cancel = Cancelar

## Permitir de nuevo el entrenamiento tras una parada por dolor

caseload-allow-training = Permitir entrenar hoy
caseload-allow-question = ¿Permitir entrenar de nuevo hoy pese al dolor indicado?
caseload-allow-explain = La estación detuvo el entrenamiento de hoy tras esta respuesta de dolor. Si ha hablado con el paciente y es seguro entrenar, la estación le deja entrenar de nuevo hoy. Queda registrado en el registro de auditoría.
caseload-allow-confirm = Sí, permitir entrenar hoy
caseload-allow-done = Entrenamiento permitido de nuevo ({ $at }). La estación lo sabrá enseguida o en su próxima conexión.
caseload-training-allowed = Entrenamiento permitido de nuevo el { $at }.
