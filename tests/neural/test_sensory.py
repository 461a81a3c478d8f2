"""Science tests of the sensory network (DESIGN §3) against an independent reference."""

import math
import re
import reprlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from neurowalk.neural.plasticity import fixed_point
from neurowalk.neural.sensory import SensoryParams, distance_to_input, simulate

P = SensoryParams()
B_STAR = fixed_point(P.mu_b, P.gamma_b, P.k)
Q_STAR = fixed_point(P.mu_q, P.gamma_q, P.k)


def reference(inputs, b0, q0, o0, learn=True, p=P):
    """DESIGN §3 written out in plain Python, one equation per line."""
    o, o_prev = list(o0), list(o0)
    b, q = list(b0), list(q0)
    rows = []
    for i in inputs:
        c = -(q[0] + q[1]) / 2
        new = [math.tanh(b[0] * o[0] + c * o[1] + p.a * i[0]), math.tanh(b[1] * o[1] + c * o[0] + p.a * i[1])]
        if learn:
            nu = [(x + 1) / 2 for x in o]
            nu_prev = [(x + 1) / 2 for x in o_prev]
            t = [1.0 if x > -0.5 else 0.0 for x in i]
            b = [b[j] + p.mu_b * nu_prev[j] * nu[j] * t[j] + p.gamma_b * (p.k - nu[j]) * b[j] ** 2 for j in (0, 1)]
            q = [q[j] + p.mu_q * nu_prev[j] * nu[j] * t[j] + p.gamma_q * (p.k - nu[j]) * q[j] ** 2 for j in (0, 1)]
        o_prev, o = o, new
        rows.append((*new, *b, *q))
    return np.array(rows)


@pytest.mark.parametrize(
    "mode,b,q,learn",
    [
        ("plastic", (0.7, 2.0), (1.0, 3.0), True),
        ("static", (2.4, 2.4), (3.5, 3.5), False),
        ("braitenberg", (0.0, 0.0), (0.0, 0.0), False),
    ],
)
def test_simulate_follows_design_to_the_letter(mode, b, q, learn):
    rng = np.random.default_rng(1)
    x = np.clip(rng.normal(-0.3, 0.6, size=(400, 2)), -1, 1)
    o0 = (0.2, -0.4)
    kw = {"b0": b, "q0": q} if mode == "plastic" else {}
    tr = simulate(x, mode=mode, o0=o0, **kw)
    ref = reference(x, b, q, o0, learn=learn)
    np.testing.assert_allclose(tr.outputs, ref[:, 0:2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(tr.b, ref[:, 2:4], rtol=0, atol=1e-12)
    np.testing.assert_allclose(tr.q, ref[:, 4:6], rtol=0, atol=1e-12)
    # Row 0 is the state after the first update: O(1) from O(0) = o0 and I(0).
    assert tr.outputs[0, 0] == pytest.approx(math.tanh(b[0] * 0.2 - (q[0] + q[1]) / 2 * -0.4 + 4.7 * x[0, 0]))


@settings(max_examples=25, deadline=None)
@given(b0=st.floats(0, 10), q0=st.floats(0, 12))
def test_held_stimulus_converges_to_fixed_points_from_any_start(b0, q0):
    tr = simulate(np.tile([1.0, -1.0], (6000, 1)), b0=b0, q0=q0)
    assert tr.b[-1, 0] == pytest.approx(B_STAR, rel=1e-3)
    assert tr.q[-1, 0] == pytest.approx(Q_STAR, rel=1e-3)
    assert round(B_STAR, 2) == 4.63 and round(Q_STAR, 2) == 7.04


def test_silent_side_barely_changes():
    tr = simulate(np.tile([1.0, -1.0], (3000, 1)), b0=2.4, q0=3.5)
    assert abs(tr.b[-1, 1] - 2.4) < 0.1 * 2.4  # b2: only the slow forgetting term
    assert tr.b[-1, 0] - 2.4 > 10 * abs(tr.b[-1, 1] - 2.4)


def test_decay_is_slow_once_input_is_gone():
    held = np.tile([1.0, -1.0], (3000, 1))
    gone = np.tile([-1.0, -1.0], (6000, 1))
    tr = simulate(np.vstack([held, gone]), b0=2.4, q0=3.5)
    db = np.diff(tr.b[2999:, 0])
    assert np.all(db <= 0), "with no input the weights never grow"
    off = tr.outputs[2999:-1, 0] < -0.99  # nu(t) of the update from inputs[t]
    assert off.any(), "the neuron eventually switches off"
    # Neuron off: only gamma*|k|*b^2 remains, at least 100x slower than the learning rate mu_b.
    assert np.max(-db[off]) < P.mu_b / 100
    growth = np.max(np.diff(tr.b[:3000, 0]))
    assert growth > 100 * np.max(-db[off])


@settings(max_examples=40, deadline=None)
@given(
    x=arrays(np.float64, st.tuples(st.integers(1, 300), st.just(2)), elements=st.floats(-1, 1)),
    b0=st.floats(0, 20),
    q0=st.floats(0, 20),
)
def test_weights_keep_sign_and_outputs_stay_bounded(x, b0, q0):
    tr = simulate(x, b0=b0, q0=q0)
    assert np.all(tr.b >= 0) and np.all(tr.q >= 0)
    assert np.all(np.abs(tr.outputs) <= 1.0)
    assert np.all(tr.c <= 0)


def test_static_and_braitenberg_weights_are_frozen():
    x = np.tile([0.5, -1.0], (200, 1))
    s = simulate(x, mode="static")
    assert np.all(s.b == 2.4) and np.all(s.c == -3.5)
    br = simulate(x, mode="braitenberg")
    assert np.all(br.b == 0) and np.all(br.q == 0)
    np.testing.assert_allclose(br.outputs[-1], np.tanh(4.7 * x[-1]))  # no recurrence: O = tanh(a I)


def test_ablations_learn_one_weight_only():
    x = np.tile([1.0, -1.0], (3000, 1))
    b_only = simulate(x, params=SensoryParams(learn_q=False))
    assert np.all(b_only.q == 3.5) and b_only.b[-1, 0] > 4.0
    q_only = simulate(x, params=SensoryParams(learn_b=False))
    assert np.all(q_only.b == 2.4) and q_only.q[-1, 0] > 6.5


def test_original_code_reflex_threshold_learns_earlier():
    # I = -0.51: the neuron (b = 2, c = -3) switches on; US = 0.245 > 0.2, but I < -0.5.
    x = np.tile([-0.51, -1.0], (500, 1))
    assert np.all(np.diff(simulate(x, b0=2.0, q0=3.0).b[:, 0]) <= 0)
    orig = simulate(x, b0=2.0, q0=3.0, params=SensoryParams.original_code())
    assert orig.b[-1, 0] > 2.0


@pytest.mark.parametrize(
    "inputs,match",
    [
        (np.zeros((5, 3)), "shape"),
        (np.zeros(4), "shape"),
        (np.zeros((0, 2)), "shape"),
        (np.array([[0.0, np.nan]]), "finite"),
        (np.array([[0.0, 1.5]]), r"\[-1, 1\]"),
        ([[0.0, 0.0], [0.0]], r"rows of equal length\), got \[\[0.0, 0.0\], \[0.0\]\]"),  # ragged
        ([[0.0, "left"]], "'left'"),
        ([[0.0, {}]], "array of numbers"),
        ("abc", "'abc'"),
        ([[0.0, 10**400]], "array of numbers"),
        (None, "shape"),
    ],
)
def test_bad_inputs_raise_naming_the_problem(inputs, match):
    with pytest.raises(ValueError, match=match):
        simulate(inputs)


def test_bad_options_raise():
    with pytest.raises(ValueError, match="mode"):
        simulate(np.zeros((2, 2)), mode="hebbian")
    with pytest.raises(ValueError, match="q0"):
        simulate(np.zeros((2, 2)), q0=-1.0)
    with pytest.raises(ValueError, match="fixed weights"):
        simulate(np.zeros((2, 2)), mode="static", b0=1.0)
    with pytest.raises(ValueError, match="o0"):
        simulate(np.zeros((2, 2)), o0=(2.0, 0.0))
    with pytest.raises(ValueError, match=r"b0 must be a number or two, got \[1, \[2\]\]"):
        simulate(np.zeros((2, 2)), b0=[1, [2]])
    with pytest.raises(ValueError, match="o0 must be a number or two, got 'x'"):
        simulate(np.zeros((2, 2)), o0="x")


@pytest.mark.parametrize("params", ["x", "", 3, {"mu_b": 0.01}, SensoryParams])
def test_params_that_are_not_sensory_params_raise_a_type_error_naming_them(params):
    from neurowalk.neural.sensory import SensoryNetwork

    with pytest.raises(TypeError, match=r"params must be a SensoryParams.*got " + re.escape(reprlib.repr(params))):
        simulate(np.zeros((2, 2)), params=params)
    with pytest.raises(TypeError, match="params must be a SensoryParams"):
        SensoryNetwork(params=params)


def test_distance_mapping():
    d = np.array([0.0, 0.05, 0.225, 0.40, 0.5, np.inf, -1.0])
    np.testing.assert_allclose(distance_to_input(d), [1, 1, 0, -1, -1, -1, -1], atol=1e-12)
    ramp = distance_to_input(np.linspace(0.05, 0.4, 50))
    assert np.all(np.diff(ramp) < 0)
