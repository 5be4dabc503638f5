# Los mensajes del terapeuta al paciente.

messages-empty = El mensaje está vacío.
messages-too-long = El mensaje es demasiado largo: { $chars } caracteres, como máximo { $max }.
messages-control = El mensaje tiene un salto de línea u otro carácter de control: escríbalo en una sola línea.
messages-sent-at = enviado { $when }
messages-not-seen = aún no visto
messages-seen-at = visto { $when }
messages-none = Aún no hay mensajes.
messages-count = { $chars } de { $max } caracteres
messages-label = Un mensaje para el paciente, que verá en letra grande al empezar su próxima sesión
messages-send = Enviar el mensaje
messages-refresh = Actualizar
messages-sent = Enviado: el paciente lo verá al empezar su próxima sesión.
messages-heading = Mensajes al paciente
