"""telerehab: arm calibration, gyro integration and movement metrics for analysts.

The heavy lifting is in Rust (the same code the patient station runs); this package is a
thin, typed facade over the private native module ``telerehab._native``.

Submodules: :mod:`telerehab.calib` (arm calibration), :mod:`telerehab.imu` (gyro
integration, bias estimation, orientation fusion), :mod:`telerehab.metrics` (movement
smoothness by SPARC and LDLJ, movement segmentation, speed profile, session measures),
:mod:`telerehab.session` (a recorded session as numpy columns with units, its measures).
"""

from telerehab._native import __version__
from telerehab import calib, imu, metrics, session

__all__ = ["__version__", "calib", "imu", "metrics", "session"]
