# Las notas del terapeuta sobre una sesión (solo para el registro de la clínica).

notes-empty = La nota está vacía: escriba unas palabras.
notes-too-long = La nota es demasiado larga: { $chars } caracteres, como máximo { $max }.
notes-control = La nota contiene caracteres de control: solo texto sin formato.
notes-by = { $by }, { $when }
notes-by-gone = un terapeuta que ya no está en la clínica
notes-none = Aún no hay notas.
notes-add-label = Añadir una nota sobre { $session } (para el registro de la clínica; el paciente no la ve)
notes-save = Guardar la nota
notes-saved = Nota guardada.
notes-cell = Nota
notes-heading = Notas sobre esta sesión
notes-this-session = esta sesión
