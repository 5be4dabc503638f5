# Los ajustes de la estación del paciente en el formulario de prescripción (tabla [patient]).

patient-legend = Estación del paciente
patient-intro = Estos ajustes viajan con la prescripción: la estación los aplica desde su próxima sesión.
patient-language-label = Idioma de las pantallas y de la voz de la estación
patient-language-station = El elegido en la estación
patient-side-legend = Lado con negligencia
patient-side-none = Ninguno
patient-side-none-note = Las pantallas se muestran como siempre.
patient-side-left = Izquierdo
patient-side-left-note = Nada esencial en la parte izquierda de la pantalla. Antes de cada ejercicio, una barra naranja que late en el borde izquierdo y un «Mire aquí» hablado desde la izquierda.
patient-side-right = Derecho
patient-side-right-note = Nada esencial en la parte derecha de la pantalla. Antes de cada ejercicio, una barra naranja que late en el borde derecho y un «Mire aquí» hablado desde la derecha.
patient-speech-label = Leer en voz alta la frase principal de cada página
patient-volume-label = Volumen de la voz, %
patient-countdown-label = Tras un descanso, iniciar el siguiente ejercicio tras esta cuenta atrás, segundos
patient-countdown-wait = esperar al paciente
patient-saved-words = En la estación: { $language }; lado con negligencia: { $side ->
    [left] izquierdo
    [right] derecho
   *[none] ninguno
}; voz { $speech ->
    [off] desactivada
   *[on] activada, volumen { $volume } %
}; tras un descanso: { $countdown ->
    [count] el siguiente ejercicio empieza a los { $seconds } s
   *[wait] la estación espera al paciente
}.
