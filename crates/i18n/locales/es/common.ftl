common-yes = Sí
common-no = No
common-ok = Vale
common-back = Atrás
common-minutes = { $minutes ->
    [one] { $minutes } minuto
   *[other] { $minutes } minutos
}
