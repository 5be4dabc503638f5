# La señal antes de un ejercicio, en el lado desatendido.
neglect-look-here = Mire hacia aquí.
