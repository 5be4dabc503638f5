# The Windows installer's own words (see en/installer.ftl).
installer-shortcut-comment = Sus ejercicios de conducción de la clínica.
installer-finish = telerehab está listo. Conecte el volante. Después abra telerehab desde el menú Inicio.
