# The assistance of an exercise in the prescribe form (crates/hub/console/assist.js).

assist-label = Assistance
assist-mode-station = The station's setting (nothing prescribed here)
assist-mode-none = None: the wheel gives no help
assist-mode-resist = Resist: spring and damper against the movement (strengthening)
assist-mode-motion = Motion: the wheel guides the hands along the ideal path
assist-mode-force = Force: the wheel adds a share of the patient's own effort
assist-mode-hybrid = Hybrid: free within a range, guided back at its edges
assist-mode-assist_as_needed = As needed: help that grows where the patient errs and fades where they do not
assist-level-guidance = Level: share of the torque ceiling the guidance may use
assist-level-effort = Level: share of the patient's effort the wheel adds
