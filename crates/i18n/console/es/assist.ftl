# La asistencia de un ejercicio en el formulario de prescripción.

assist-label = Asistencia
assist-mode-station = El ajuste de la estación (aquí no se prescribe nada)
assist-mode-none = Ninguna: el volante no ayuda
assist-mode-resist = Resistencia: muelle y amortiguador contra el movimiento (fortalecimiento)
assist-mode-motion = Movimiento: el volante guía las manos por la trayectoria ideal
assist-mode-force = Fuerza: el volante añade una parte del esfuerzo del propio paciente
assist-mode-hybrid = Híbrida: libre dentro de un margen, guiada de vuelta en sus bordes
assist-mode-assist_as_needed = Según necesidad: ayuda que crece donde el paciente falla y se retira donde no
assist-level-guidance = Nivel: parte del límite de par que puede usar la guía
assist-level-effort = Nivel: parte del esfuerzo del paciente que añade el volante
