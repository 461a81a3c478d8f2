r"""Synaptic plasticity of the sensory network: correlation-based learning with synaptic scaling.

The rule of the paper's Eq. 3-4 (Tetzlaff et al. 2011), as an increment:

.. math::

    \Delta w(t) = \mu\,\nu(t-1)\,\nu(t)\,T(t) + \gamma\,(k - \nu(t))\,w(t)^2

where :math:`\nu = (O + 1)/2 \in [0, 1]` is the neuron's output mapped to a positive activity and
:math:`T \in \{0, 1\}` the reflex signal (Eq. 6). The first term is correlation-based learning,
gated by the reflex; the second is synaptic scaling, which with :math:`k < 0` always depresses
and so bounds the weight. Under a held stimulus (:math:`\nu = T = 1`) the weight converges to
:math:`w^* = \sqrt{\mu / (\gamma (1 - k))}`, whatever its start.

The functions return the change; the caller applies it (so several rules can read the same,
not-yet-updated weights). They are numba-compiled scalar functions, callable from Python too.
"""

from __future__ import annotations

import math

from neurowalk.compiled import jit


@jit
def correlation_scaling_delta(
    w: float, nu_prev: float, nu: float, reflex: float, mu: float, gamma: float, k: float
) -> float:
    r"""Return :math:`\Delta w = \mu\,\nu(t-1)\,\nu(t)\,T(t) + \gamma\,(k - \nu(t))\,w^2`.

    Args:
        w: the weight at t (self weight b, or inhibition magnitude q >= 0).
        nu_prev: activity :math:`\nu(t-1) \in [0, 1]`.
        nu: activity :math:`\nu(t) \in [0, 1]`.
        reflex: reflex signal :math:`T(t) \in \{0, 1\}`.
        mu: learning rate of correlation-based learning (per control step).
        gamma: rate of synaptic scaling (per control step).
        k: scaling offset (negative: forgetting).
    """
    return mu * nu_prev * nu * reflex + gamma * (k - nu) * w * w


@jit
def activity(output: float, cutoff: float) -> float:
    """Map a neuron output in [-1, 1] to the activity nu = (O + 1) / 2 in [0, 1].

    Activities below ``cutoff`` are set to 0 (the original code's cut-off is 0.009; default 0).
    """
    nu = 0.5 * (output + 1.0)
    return 0.0 if nu < cutoff else nu


@jit
def reflex_signal(stimulus: float, threshold: float) -> float:
    """Reflex signal T of Eq. 6: 1 where the input exceeds ``threshold`` (default -0.5), else 0."""
    return 1.0 if stimulus > threshold else 0.0


def fixed_point(mu: float, gamma: float, k: float) -> float:
    r"""Weight at which learning and scaling balance under a held stimulus (nu = T = 1).

    :math:`w^* = \sqrt{\mu / (\gamma (1 - k))}`: 4.63 for the self weights b, 7.04 for q.
    """
    if mu < 0 or gamma <= 0 or k >= 1:
        raise ValueError(f"no fixed point for mu={mu!r}, gamma={gamma!r}, k={k!r}")
    return math.sqrt(mu / (gamma * (1.0 - k)))
