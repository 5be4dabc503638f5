# La consola: título, cabecera, navegación, menú de idioma, inicio de sesión, contraseña,
# las pestañas de un paciente, errores.

app-title = telerehab — consola del terapeuta
app-loading = Cargando…
app-nav =
    .aria-label = Menú principal
app-nav-clinic = Clínica
app-nav-names = Nombres
app-nav-audit = Registro de auditoría
app-nav-change-password = Cambiar la contraseña
app-nav-logout = Cerrar sesión
app-language-label = Idioma
app-who = { $email } ({ $role ->
        [admin] administrador
       *[other] terapeuta
    })
app-back-to-patients = Volver a los pacientes

## Inicio de sesión

app-login-title = Iniciar sesión
app-login-email = Correo electrónico
app-login-password = Contraseña
app-login-submit = Iniciar sesión

## Contraseñas

app-password-title = Cambiar la contraseña
app-password-title-forced = Elija su propia contraseña
app-password-forced = Ha iniciado sesión con una contraseña de un solo uso. Elija la suya antes de continuar.
app-password-one-time = Contraseña de un solo uso
app-password-current = Contraseña actual
app-password-new = Contraseña nueva
app-password-rules = (al menos 10 caracteres, no solo espacios, no su correo, no una contraseña o un patrón habituales; lo mejor son varias palabras sin relación)
app-password-repeat = Repita la contraseña nueva
app-password-submit = Cambiar la contraseña
app-password-differ = Las dos contraseñas nuevas no coinciden.

## Página de un paciente

app-patient-title = Paciente { $name }
app-tabs-label = Paciente
app-tab-live = En directo
app-tab-progress = Evolución
app-tab-replay = Reproducción
app-tab-prescribe = Prescribir
app-tab-exercises = Ejercicios
app-tab-stations = Estaciones y emparejamiento
