# Pies de foto (crates/station/src/render/pictures). Cada uno también se dice en voz alta.
picture-road-winding = Gire el volante a la izquierda y a la derecha.
picture-road-straight = Mantenga el coche en el centro de la carretera.
picture-road-zigzag = Siga la carretera en zigzag con el volante.
picture-road-tightening = La curva se cierra. Gire un poco más.
picture-road-sharp-turns = Gire en las curvas cerradas.
picture-road-s-bend = Pase la curva en forma de S.
picture-road-lane-change = Cambie de carril. Luego quédese en él.
picture-road-slalom = Pase entre los conos.
picture-dial = Gire el volante. La aguja negra sigue a la roja.
picture-strength = Empuje el volante con fuerza. No se moverá.
picture-rest = Descanse ahora. Suelte el volante.
picture-pause = En pausa. Tómese su tiempo.
picture-buttons = Pulse un botón del volante.
picture-yes = Sí
picture-no = No
picture-done = Muy bien. Eso es todo por hoy.
picture-today = Sus ejercicios de hoy.
