# Los rechazos del hub en el idioma de la consola (crates/hub/console/api.js refusalWords).

## Los rechazos del hub en el idioma de la consola; las palabras del hub (el campo o la cosa)
## siguen en inglés cuando aportan algo.

api-error-400 = El hub no ha aceptado esto.
api-error-401 = No ha iniciado sesión, o el correo o la contraseña no son correctos.
api-error-403 = Solo un administrador de la clínica puede hacer esto.
api-error-404 = No se encuentra. Puede que se haya eliminado.
api-error-409 = Esto contradice lo que el hub tiene guardado.
api-error-413 = Es demasiado grande para el hub.
api-error-415 = El hub no ha entendido esta petición.
api-error-422 = Rechazado: fuera de los valores permitidos o de los límites de seguridad.
api-error-429 = Demasiados intentos. Vuelva a intentarlo en { $seconds } s.
api-error-503 = El hub está ocupado. Vuelva a intentarlo en { $seconds } s.
api-error-other = Algo ha fallado en el hub. Su registro tiene los detalles.
api-error-detail = { $lead } El hub dice: { $detail }
