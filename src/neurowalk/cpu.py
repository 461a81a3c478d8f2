"""The CPU as the numbers see it: what, besides the versions, decides the last bits of a result.

numba compiles neurowalk's kernels for the host CPU (``NUMBA_CPU_NAME`` names another target), numpy picks the SIMD
kernels of its functions (``sin``, ``arctan2``, sums) when it loads (``NPY_DISABLE_CPU_FEATURES`` turns some off),
and numpy's bundled OpenBLAS picks the kernels of its products (their order of summation; ``OPENBLAS_CORETYPE``).
The same seed gives the same bits where all three and the versions are the same (``docs/usage.md``, "Same seed,
same result").
"""

from __future__ import annotations

import ctypes
from pathlib import Path

import numba
import numpy as np

__all__ = ["cpu_fingerprint"]


def cpu_fingerprint() -> dict[str, str | list[str]]:
    """``numba_cpu``: numba's target CPU; ``numpy_simd``: numpy's enabled SIMD dispatch targets; ``openblas_core``:
    the kernels numpy's OpenBLAS chose ("none" where numpy carries no OpenBLAS of its own)."""
    import llvmlite.binding as llvm
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    return {
        "numba_cpu": numba.config.CPU_NAME or llvm.get_host_cpu_name(),
        "numpy_simd": [name for name in __cpu_dispatch__ if __cpu_features__.get(name)],
        "openblas_core": _openblas_core(),
    }


def _openblas_core() -> str:
    for lib in sorted((Path(np.__file__).parent.parent / "numpy.libs").glob("*openblas*")):
        dll = ctypes.CDLL(str(lib))
        for name in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename", "openblas_get_corename"):
            get = getattr(dll, name, None)
            if get is not None:
                get.restype = ctypes.c_char_p
                return get().decode()
    return "none"
