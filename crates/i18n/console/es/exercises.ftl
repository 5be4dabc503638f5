# Los resultados de una sesión ejercicio por ejercicio.

exercises-ended = Terminada
exercises-running = Aún en curso
exercises-heading = Sesión del { $when }, ejercicio por ejercicio
exercises-back = Volver a la evolución
exercises-none = No hay resultados por ejercicio: la estación de esta sesión era anterior a ellos, o la sesión no terminó con normalidad.
exercises-column = { $n }. { $name }
exercises-time-cell = { $active } de { $prescribed }
exercises-caption = Los resultados propios de cada ejercicio; los totales de la sesión están en la evolución.
exercises-col-result = Resultado
exercises-time-row = Tiempo: activo de lo prescrito (s)
exercises-sweep-spring = Barrido háptico: la rigidez del muelle en este nivel
exercises-sweep-damper = Barrido háptico: la amortiguación en este nivel
exercises-sweep-inertia = Barrido háptico: el peso añadido (inercia) en este nivel
exercises-sweep-frequency = Barrido háptico: la rapidez del dial (frecuencia) en este nivel
