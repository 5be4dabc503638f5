# The patient's wheel in the prescribe form (crates/hub/console/wheel.js).

wheel-none = No wheel seen yet: bounds are the device maximum (the station caps them at its own wheel's ceiling).
wheel-line = { $known ->
    [no] Wheel: { $model }, rated { $rated }, effective ceiling { $ceiling } (a model the station does not know: its force is kept low).
   *[yes] Wheel: { $model }, rated { $rated }, effective ceiling { $ceiling }.
}
