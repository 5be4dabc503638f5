# El volante del paciente en el formulario de prescripción.

wheel-none = Aún no se ha visto ningún volante: los límites son el máximo del dispositivo (la estación los limita al tope de su propio volante).
wheel-line = { $known ->
    [no] Volante: { $model }, par nominal { $rated }, límite efectivo { $ceiling } (un modelo que la estación no conoce: su fuerza se mantiene baja).
   *[yes] Volante: { $model }, par nominal { $rated }, límite efectivo { $ceiling }.
}
