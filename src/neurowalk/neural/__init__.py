"""Pure neural dynamics: the adaptive sensory network and the modular locomotion network.

Nothing here imports MuJoCo. Parameters are frozen dataclasses; state is small arrays; the hot
step functions are compiled with numba so that one code path serves a single robot and a batch.
"""
