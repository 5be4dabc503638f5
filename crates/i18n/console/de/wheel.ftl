# Das Lenkrad des Patienten im Verordnungsformular.

wheel-none = Noch kein Lenkrad gemeldet: Die Grenzen sind das Gerätemaximum (die Station begrenzt sie auf die Grenze ihres eigenen Lenkrads).
wheel-line = { $known ->
    [no] Lenkrad: { $model }, Nennmoment { $rated }, wirksame Grenze { $ceiling } (ein Modell, das die Station nicht kennt: seine Kraft bleibt niedrig).
   *[yes] Lenkrad: { $model }, Nennmoment { $rated }, wirksame Grenze { $ceiling }.
}
