# Los nombres de la clínica para sus seudónimos, guardados solo en este navegador.

names-display = { $name } ({ $pseudonym })
names-problem-cells = Línea { $line }: necesita el seudónimo y luego el nombre.
names-problem-long = Línea { $line }: el nombre tiene más de { $max } caracteres.
names-problem-twice = Línea { $line }: { $pseudonym } está dos veces en la lista; se conserva el primer nombre.
names-problem-many = Línea { $line }: más de { $max } nombres; el resto se omite.
names-in-caseload = en su lista de pacientes
names-not-in-caseload = no está en su lista de pacientes
names-heading = Los nombres de sus pacientes
names-stay-heading = Los nombres se quedan en este ordenador
names-stay-text = El hub conoce a sus pacientes solo por seudónimo. Puede dar a este navegador la lista de nombres de su clínica. La lista se queda en este navegador, en este ordenador, y nunca se envía al hub.
names-csv-text = Use una hoja de cálculo (CSV) con dos columnas: el seudónimo y luego el nombre. Importar un archivo sustituye la lista.
names-file-label = Importar una lista de nombres (archivo CSV)
names-shared-computer = En un ordenador que usan otras personas, borre los nombres al terminar.
names-forget = Borrar los nombres de este ordenador
names-list-heading = Nombres en este navegador
names-caption = { $count ->
    [one] Un nombre, por seudónimo
   *[other] { $count } nombres, por seudónimo
}
names-col-pseudonym = Seudónimo
names-col-name = Nombre
names-col-patient = Paciente
names-none = Aún no hay nombres en este navegador.
names-none-read = No se pudo leer ningún nombre del archivo; la lista no ha cambiado.
names-kept = { $count ->
    [one] Un nombre guardado en este navegador.
   *[other] { $count } nombres guardados en este navegador.
}
names-forgotten = Los nombres se han borrado de este ordenador.
