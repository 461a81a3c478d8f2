"""Bodies that carry the controller, and their one registry (:mod:`neurowalk.body.registry`, ``neurowalk bodies``).

``amosii``: the hexapod in MuJoCo (``amosii_params`` holds its numbers and MJCF names, ``amosii`` writes the MJCF,
``amosii_sensors`` reads its sensors, ``physics`` steps it). ``wheeled``: a differential-drive robot in MuJoCo with
AMOSII's footprint, speed and rangefinders (``wheeled`` writes the MJCF, ``wheeled_body`` steps it). ``surrogate``:
the planar, calibrated AMOSII (``surrogate``, ``surrogate_kernel``); ``surrogate-wheeled`` the same model calibrated
on the wheeled robot (``data/calibration-wheeled.json``).
"""
