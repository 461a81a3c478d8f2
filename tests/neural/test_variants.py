"""The ``original`` variant, point by point against hand-computed steps of the authors' code (facts §3.2-3.3)."""

import math

import numpy as np
import pytest

from neurowalk.neural.cpg import CpgParams, simulate_cpg
from neurowalk.neural.sensory import SensoryNetwork, SensoryParams, distance_input, distance_to_input, simulate
from neurowalk.neural.variants import TUNABLE, get_variant, read_params_file, variant_names

ORIG = SensoryParams.original_code()


def nu(o, cut=0.009):
    v = (o + 1) / 2
    return 0.0 if v < cut else v


def original_reference(x, steps_b=(2.0, 2.0), steps_c=(3.0, 3.0)):
    """The authors' code written out from facts §3.2-3.3, with their indices: x[k] is the k-th reading.

    o[k] = tanh(4.7 x[k-1] + b[k] o[k-1] - c[k] o_other[k-1]), c = (c1 + c2)/2; u = nu(o[k-1]), v = nu(o[k]);
    G = [US(x[k-1]) > 0.2]; b += mu u v G + gamma (vT - v) b^2 (same for c with mu2, gamma2); steering
    S[k] = o[k-2]. The constructor runs one step of the network with x = 0 first (that reading is x[0]); the
    learning rule lives in the obstacle-avoidance step, so that first step does not learn.
    """
    x = np.vstack([np.zeros((1, 2)), x])  # the constructor's zero-input reading
    b, c = list(steps_b), list(steps_c)
    o = {-1: [0.0, 0.0], 0: [0.0, 0.0]}  # outputs start at 0; o[0] is the constructor step's output
    xin = [0.0, 0.0]  # the input neuron's output before the constructor step
    rows = []
    for k in range(len(x)):
        prev = o[k - 1] if k >= 1 else [0.0, 0.0]
        cc = (c[0] + c[1]) / 2
        new = [math.tanh(4.7 * xin[0] + b[0] * prev[0] - cc * prev[1]),
               math.tanh(4.7 * xin[1] + b[1] * prev[1] - cc * prev[0])]  # fmt: skip
        for i in (0, 1) if k >= 1 else ():  # the constructor's step does not learn
            u, v = nu(prev[i]), nu(new[i])
            g = 1.0 if (xin[i] + 1) / 2 > 0.2 else 0.0
            b[i] += 0.0065 * u * v * g + 0.0003 * (-0.01 - v) * b[i] ** 2
            c[i] += 0.015 * u * v * g + 0.0003 * (-0.01 - v) * c[i] ** 2
        o[k] = new
        xin = list(x[k])
        steer = o.get(k - 2, [0.0, 0.0])
        rows.append((*new, *b, *c, *steer))
    return np.array(rows[1:])  # without the constructor's step


def test_original_matches_the_authors_code_written_out():
    rng = np.random.default_rng(3)
    x = np.clip(np.cumsum(rng.normal(0, 0.3, size=(400, 2)), axis=0) / 5, -1, 1)
    ref = original_reference(x)
    tr = simulate(x, params=ORIG)
    np.testing.assert_allclose(tr.outputs, ref[:, 0:2], atol=1e-12)
    np.testing.assert_allclose(tr.b, ref[:, 2:4], atol=1e-12)
    np.testing.assert_allclose(tr.q, ref[:, 4:6], atol=1e-12)
    np.testing.assert_allclose(tr.steering, ref[:, 6:8], atol=1e-12)


def test_point_1_learning_uses_activity_before_and_after_the_update():
    p = SensoryParams(post_learning=True, b_start=2.0, q_start=3.0)
    tr = simulate(np.array([[0.5, -1.0]]), params=p, o0=(0.2, 0.0))
    o_new = math.tanh(2.0 * 0.2 - 3.0 * 0.0 + 4.7 * 0.5)
    u, v = (0.2 + 1) / 2, (o_new + 1) / 2
    assert tr.b[0, 0] == pytest.approx(2.0 + 0.0065 * u * v + 0.0003 * (-0.01 - v) * 4.0, abs=1e-15)
    paper = simulate(np.array([[0.5, -1.0]]), b0=2.0, q0=3.0, o0=(0.2, 0.0))
    v_paper = (0.2 + 1) / 2  # Eq. 3: nu(t) is the output before the update
    assert paper.b[0, 0] == pytest.approx(2.0 + 0.0065 * v_paper * v_paper + 0.0003 * (-0.01 - v_paper) * 4.0)
    assert abs(tr.b[0, 0] - paper.b[0, 0]) > 1e-3


def test_point_2_steering_follows_the_reading_by_three_control_steps():
    x = np.full((12, 2), -1.0)
    x[5:, 0] = 1.0  # an obstacle on the left from reading 5 on
    orig = simulate(x, mode="static", params=ORIG)
    paper = simulate(x, mode="static")
    first = lambda s: int(np.argmax(s[:, 0] > 0))  # noqa: E731
    assert first(paper.steering) == 5  # the same step
    assert first(orig.steering) == 5 + 3


def test_point_3_the_constructor_runs_one_zero_input_step_that_does_not_learn():
    net = SensoryNetwork("plastic", params=ORIG)
    # the zero-input step moves the network (outputs tanh(0) = 0, the input neurons now hold 0) ...
    np.testing.assert_array_equal(net.state[0:4], 0.0)
    np.testing.assert_array_equal(net.state[10:12], 0.0)
    # ... but leaves the plastic weights exactly at their start: learning is not part of the network's step
    np.testing.assert_array_equal(net.b, [2.0, 2.0])
    np.testing.assert_array_equal(net.q, [3.0, 3.0])
    net.step(0.3, -1.0)
    net.reset()  # a reset runs the same step again: the weights are back at b = 2, q = 3 exactly
    np.testing.assert_array_equal(net.b, [2.0, 2.0])
    np.testing.assert_array_equal(net.q, [3.0, 3.0])


@pytest.mark.parametrize("reading", [(0.3, -1.0), (-1.0, -1.0), (1.0, 0.5)])
def test_point_3_the_steps_after_the_constructors_learn_from_b2_q3(reading):
    """The first real step is one learning update from (b, q) = (2, 3), from the documented rule (facts §3.3):
    the neurons still see the constructor's zero input (input neuron), so o goes 0 -> tanh(0) = 0, u = v = 0.5,
    and the gate is on (US = 0.5 > 0.2); the next step sees the reading and learns again."""
    net = SensoryNetwork("plastic", params=ORIG)
    net.step(*reading)
    v = 0.5
    assert net.b[0] == pytest.approx(2.0 + 0.0065 * v * v + 0.0003 * (-0.01 - v) * 2.0**2, abs=1e-15)
    assert net.q[0] == pytest.approx(3.0 + 0.015 * v * v + 0.0003 * (-0.01 - v) * 3.0**2, abs=1e-15)
    assert net.b[0] == net.b[1] and net.q[0] == net.q[1]  # the same zero input on both sides
    b1, q1, o = net.b.copy(), net.q.copy(), net.state[0:2].copy()
    net.step(0.0, 0.0)
    for i in (0, 1):  # the second update: this step's input is the first reading, the weights move from (b1, q1)
        new = math.tanh(4.7 * reading[i] + b1[i] * o[i] - 0.5 * (q1[0] + q1[1]) * o[1 - i])
        assert net.state[i] == pytest.approx(new, abs=1e-15)
        u, v = nu(o[i]), nu(new)
        g = 1.0 if (reading[i] + 1) / 2 > 0.2 else 0.0
        assert net.b[i] == pytest.approx(b1[i] + 0.0065 * u * v * g + 0.0003 * (-0.01 - v) * b1[i] ** 2, abs=1e-15)
        assert net.q[i] == pytest.approx(q1[i] + 0.015 * u * v * g + 0.0003 * (-0.01 - v) * q1[i] ** 2, abs=1e-15)
    # from outputs 0 and input neurons 0, a zero-input step that does not learn changes nothing: the whole trace
    # equals that of the network started without it
    x = np.array([reading, (0.0, 0.0), (1.0, 1.0), (-1.0, 0.2)])
    primed, plain = simulate(x, params=ORIG), simulate(x, params=SensoryParams.original_code(prime_step=False))
    for name in ("outputs", "b", "q", "steering"):
        np.testing.assert_array_equal(getattr(primed, name), getattr(plain, name))


def test_point_4_distance_to_input_is_one_minus_2d_over_range():
    d = np.array([0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, np.inf])
    np.testing.assert_allclose(distance_to_input(d, near=ORIG.us_near), np.clip(1 - 2 * np.minimum(d, 1) / 0.4, -1, 1))
    assert distance_input(0.2, ORIG.us_near) == pytest.approx(0.0)
    assert distance_input(0.2) == pytest.approx(1 - 2 * 0.15 / 0.35)  # paper: +1 from 0.05 m
    net = SensoryNetwork("plastic", params=ORIG)
    assert net.input(0.1) == pytest.approx(0.5)


def test_point_5_pcpg_stores_its_first_partial_phase():
    full = simulate_cpg(600)[1]
    part = simulate_cpg(600, CpgParams(pcpg_first_partial=True))[1]
    differ = np.flatnonzero(np.any(full != part, axis=1))
    assert len(differ) > 0 and differ[-1] < 260  # the legs differ only at the start
    np.testing.assert_array_equal(full[300:], part[300:])


def test_point_6_learning_starts_from_b2_q3():
    assert get_variant("original").sensory.b_start == 2.0 and get_variant("original").sensory.q_start == 3.0
    tr = simulate(np.full((1, 2), -1.0), params=SensoryParams.original_code(prime_step=False))
    assert tr.b[0, 0] == pytest.approx(2.0, abs=2e-3) and tr.q[0, 0] == pytest.approx(3.0, abs=4e-3)
    assert simulate(np.full((1, 2), -1.0)).b[0, 0] == 0.0  # paper: from zero


def test_paper_variant_is_the_default_network():
    v = get_variant("paper")
    assert v.sensory == SensoryParams() and not v.pcpg_first_partial
    assert get_variant("original").pcpg_first_partial
    assert "paper" in variant_names() and "original" in variant_names()


@pytest.mark.parametrize(
    "name,overrides,message",
    [
        ("nope", None, "unknown variant 'nope'"),
        ("paper", {"mu_x": 1.0}, "unknown field 'mu_x'"),
        ("paper", {"mu_b": float("nan")}, "mu_b must be a finite number"),
        ("paper", {"gamma_q": -0.1}, "gamma_q must be >= 0"),
        ("original", {"mu_q": "fast"}, "mu_q must be a finite number"),
        ("paper", {"input_delay": 1}, "input_delay must be true or false"),
        ("paper", {"steer_delay": 3}, "steer_delay must be 0, 1 or 2"),
        ("paper", {"steer_delay": True}, "steer_delay must be 0, 1 or 2"),
        ("paper", {"pcpg_first_partial": "yes"}, "pcpg_first_partial must be true or false"),
    ],
)
def test_bad_variants_and_params_name_the_value(name, overrides, message):
    with pytest.raises(ValueError, match=message):
        get_variant(name, overrides)


def test_params_file_round_trip_and_errors(tmp_path):
    f = tmp_path / "p.json"
    f.write_text('{"params": {"mu_b": 0.01, "k": -0.02}, "variant": "original", "found_by": "hand"}')
    data = read_params_file(f)
    v = get_variant(data["variant"], data["params"])
    assert v.sensory.mu_b == 0.01 and v.sensory.k == -0.02 and v.sensory.input_delay
    f.write_text('{"params": {"bogus": 1}}')
    with pytest.raises(ValueError, match="unknown field 'bogus'"):
        read_params_file(f)
    f.write_text("{not json")
    with pytest.raises(ValueError, match="is not JSON"):
        read_params_file(f)
    assert set(TUNABLE) <= set(SensoryParams.__dataclass_fields__)


def test_each_code_option_switches_alone_and_all_of_them_make_the_code():
    from neurowalk.neural.variants import CODE_OPTIONS, SWITCHES

    paper, original = get_variant("paper"), get_variant("original")
    assert len(CODE_OPTIONS) == 10 and set(SWITCHES) <= set(CODE_OPTIONS)
    for option, (on_paper, on_code) in CODE_OPTIONS.items():
        on = get_variant("paper", {option: on_code})
        off = get_variant("original", {option: on_paper})
        if option == "pcpg_first_partial":
            assert on.pcpg_first_partial and not off.pcpg_first_partial and on.sensory == paper.sensory
            continue
        changed = {f for f in SensoryParams.__dataclass_fields__ if getattr(on.sensory, f) != getattr(paper.sensory, f)}
        # b_start/q_start None read as 0 in a plastic network: 0 is the paper's value, set explicitly
        assert changed == {option}, option
        assert getattr(off.sensory, option) == on_paper and off.pcpg_first_partial
    every = get_variant("paper", {o: code for o, (_, code) in CODE_OPTIONS.items()})
    assert every.sensory == original.sensory and every.pcpg_first_partial


def test_a_params_file_sets_a_switch(tmp_path):
    f = tmp_path / "p.json"
    f.write_text('{"params": {"steer_delay": 2, "input_delay": true}}')
    v = get_variant("paper", read_params_file(f)["params"])
    assert v.sensory.steer_delay == 2 and isinstance(v.sensory.steer_delay, int) and v.sensory.input_delay
