"""``neurowalk calibrate``: a physics body measured so that a planar surrogate moves like it.

:mod:`.subjects` (what is measured, on which bodies), :mod:`.physics` (the measurements on the MuJoCo body),
:mod:`.fit` (the fits, pure functions of poses), :mod:`.calibrate` (the calibration put together, validated and
drawn).
"""
