"""Bodies that carry the controller: AMOSII in MuJoCo (``amosii``), and later the surrogates.

``amosii_params`` holds the body's numbers and MJCF names (no MuJoCo import), ``amosii`` writes the
MJCF, and ``amosii_sensors`` reads a compiled model's sensors every control step.
"""
