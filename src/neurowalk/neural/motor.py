"""The modular locomotion network: CPG → PCPG → PSN → VRN(L, R) → PMN → delay lines → motor map.

All neurons step synchronously (each synapse adds one control step, as in the original ANN
framework): every new output is computed from the previous step's outputs. Numbers are those of
reference/original_code_facts.md §4-5:

* PSN (12 tanh neurons) with selector input 1: P10 follows PCPG channel 0, P11 channel 1.
* VRN per side (7 tanh neurons): X = 1.75·P11, Y = 5·S, four hidden neurons (w = 1.7246,
  bias = -2.48285) and an output V ≈ X·Y: the steering S sets the sign (direction) and, below
  |S| ≈ 0.3, the amplitude of that side's TC oscillation.
* PMN: TC_right = tanh(-2.5·V_right), TC_left = tanh(-2.5·V_left), CTr = tanh(5·P11 - 0.5),
  FTi = tanh(-5·P11 - 0.5) (front and hind legs), FTi_mid = tanh(5·P10 - 0.5).
* Delay lines: tau = 16 steps between ipsilateral neighbours, tau_L = 48 from right to left,
  hind to front: R3 → R2 → R1 → L3 → L2 → L1 (the wave gait). A CTr signal that falls is
  replaced by -1: only its rising part lifts the leg. Front FTi ×(+1.5·S), hind ×(-1.5·S),
  middle FTi -1.2·FTi_mid.
* Motor map (linear) to joint angles in rad, controller sign (anatomy): TC front 0..50°,
  middle -30..20°, hind -60..-10°; CTr 45..75° elevation; FTi -130..-120° (flexed).

Steering (O1, O2) follows DESIGN §2: O1 (left neuron) drives the right legs, O2 the left legs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from neurowalk import anatomy
from neurowalk.compiled import jit
from neurowalk.neural.cpg import PCPG_FIELDS, CpgParams, cpg_step, pcpg_step

# ---- state layout of one network (a flat float vector) -------------------------------------
CPG = 0  # 2 CPG outputs
PCPG = CPG + 2  # 2 channels × PCPG_FIELDS
IN = PCPG + 2 * PCPG_FIELDS  # input neurons: selector, S_left, S_right
PSN = IN + 3  # 12 neurons P0..P11
VRN_L = PSN + 12  # 7 neurons: X, Y, H2, H3, H4, H5, V
VRN_R = VRN_L + 7
PMN = VRN_R + 7  # 5 used pre-motor neurons: TC_R, TC_L, CTr, FTi, FTi_mid
CTR_PREV = PMN + 5  # 6 delayed CTr values of the previous step, LEGS order
STEP = CTR_PREV + 6  # step counter
STATE_SIZE = STEP + 1
N_PMN = 5

# ---- fixed wiring (dimensionless weights) ---------------------------------------------------
VRN_W = 1.7246
VRN_BIAS = -2.48285
VRN_X_GAIN = 1.75
VRN_Y_GAIN = 5.0
PMN_TC_GAIN = -2.5
PMN_CTR_GAIN, PMN_FTI_GAIN, PMN_FTI_MID_GAIN, PMN_BIAS = 5.0, -5.0, 5.0, -0.5

DEG = math.pi / 180.0
# Motor map: pre-signal range (x_lo, x_hi) → servo command (y_lo, y_hi) → angle = y·y_to_angle.
# TC rows by leg position (front, middle, hind); commands in the original's units (deg × scale).
TC_X = (-0.91, 0.91)
TC_Y = ((0.0 * 0.0143, 50.0 * 0.0143), (-30.0 * 0.0167, 20.0 * 0.0167), (-60.0 * 0.0143, -10.0 * 0.0143))
TC_ANGLE = (70.0 * DEG, 60.0 * DEG, 70.0 * DEG)  # servo half range: command ±1 ↔ ±this angle
CTR_X = (-1.0, 0.96)
CTR_Y = (0.0133 * 45.0, 0.0133 * 75.0)
CTR_ANGLE = 75.0 * DEG  # elevation = 75°·y
FTI_X = (-1.0, 1.0)
FTI_Y = (0.0182 * -130.0 + 1.3636, 0.0182 * -120.0 + 1.3636)
# FTi: flexion = 75° - 55°·y; in the controller sign (+ extension) the angle is 55°·y - 75°.
FTI_SLOPE, FTI_OFFSET = 55.0 * DEG, -75.0 * DEG


@dataclass(frozen=True, kw_only=True)
class LocomotionParams:
    """Parameters of the locomotion network (delays in control steps)."""

    cpg: CpgParams = field(default_factory=CpgParams)
    tau: int = 16  # delay between ipsilateral neighbouring legs
    tau_l: int = 48  # delay from the right side to the left side
    fti_steer_gain: float = 1.5  # front/hind FTi pre-signal × ±gain·S
    fti_mid_gain: float = -1.2  # middle FTi pre-signal gain

    def __post_init__(self) -> None:
        if self.tau < 1 or self.tau_l < 0:
            raise ValueError(f"delays must be tau >= 1, tau_l >= 0; got tau={self.tau}, tau_l={self.tau_l}")

    @property
    def buffer_length(self) -> int:
        """Length of the delay-line ring buffer (longest delay + 1)."""
        return self.tau_l + 2 * self.tau + 3

    def as_array(self) -> np.ndarray:
        """Pack for the compiled step."""
        c = self.cpg
        return np.array(
            [
                c.w_self,
                c.w_cross + c.mi,
                c.pcpg_threshold,
                self.tau,
                self.tau_l,
                self.fti_steer_gain,
                self.fti_mid_gain,
                float(c.pcpg_first_partial),
            ]
        )


@jit
def _lin(x: float, x_lo: float, x_hi: float, y_lo: float, y_hi: float) -> float:
    return y_lo + (x - x_lo) * (y_hi - y_lo) / (x_hi - x_lo)


@jit
def _clip1(y: float) -> float:
    return min(1.0, max(-1.0, y))


@jit
def motor_map(tc: np.ndarray, ctr: np.ndarray, fti: np.ndarray, out: np.ndarray) -> None:
    """Map pre-motor signals (6,) each, LEGS order, to 18 joint angles (rad) in actuator order."""
    for leg in range(6):
        pos = leg % 3  # 0 front, 1 middle, 2 hind (LEGS = R1 R2 R3 L1 L2 L3)
        y = _clip1(_lin(tc[leg], TC_X[0], TC_X[1], TC_Y[pos][0], TC_Y[pos][1]))
        out[leg] = y * TC_ANGLE[pos]
        y = _clip1(_lin(ctr[leg], CTR_X[0], CTR_X[1], CTR_Y[0], CTR_Y[1]))
        out[6 + leg] = y * CTR_ANGLE
        y = _clip1(_lin(fti[leg], FTI_X[0], FTI_X[1], FTI_Y[0], FTI_Y[1]))
        out[12 + leg] = FTI_SLOPE * y + FTI_OFFSET


@jit
def _vrn(old: np.ndarray, new: np.ndarray, base: int, x_in: float, y_in: float) -> None:
    """One VRN (7 neurons at ``base``) from the previous outputs ``old``."""
    x, y = old[base], old[base + 1]
    new[base] = math.tanh(VRN_X_GAIN * x_in)
    new[base + 1] = math.tanh(VRN_Y_GAIN * y_in)
    new[base + 2] = math.tanh(VRN_W * x + VRN_W * y + VRN_BIAS)
    new[base + 3] = math.tanh(-VRN_W * x - VRN_W * y + VRN_BIAS)
    new[base + 4] = math.tanh(VRN_W * x - VRN_W * y + VRN_BIAS)
    new[base + 5] = math.tanh(-VRN_W * x + VRN_W * y + VRN_BIAS)
    h = old[base + 2 : base + 6]
    new[base + 6] = math.tanh(0.5 * h[0] + 0.5 * h[1] - 0.5 * h[2] - 0.5 * h[3])


@jit
def presignal_step(
    x: np.ndarray, buf: np.ndarray, s_right: float, s_left: float, p: np.ndarray, pre: np.ndarray
) -> None:
    """Advance one network one control step in place and write the delayed pre-motor signals.

    Args:
        x: (STATE_SIZE,) network state. buf: (L, 5) delay-line ring buffer of PMN outputs.
        s_right: steering of the right legs (O1). s_left: steering of the left legs (O2).
        p: packed :class:`LocomotionParams`.
        pre: (3, 6) output: TC, CTr and FTi pre-signals (dimensionless, about [-1, 1]), LEGS order;
            :func:`motor_map` turns them into joint angles. A CTr value of -1 means stance.
    """
    old = x.copy()
    # CPG and its post-processing (PCPG reads the previous CPG output).
    cpg_step(x[CPG : CPG + 2], p[0], p[1])
    pcpg_step(x[PCPG : PCPG + PCPG_FIELDS], old[CPG], p[2], p[7] > 0.0)
    pcpg_step(x[PCPG + PCPG_FIELDS : PCPG + 2 * PCPG_FIELDS], old[CPG + 1], p[2], p[7] > 0.0)
    # Input neurons take this step's external values.
    x[IN], x[IN + 1], x[IN + 2] = 1.0, s_left, s_right
    # PSN, from the previous outputs.
    pc0, pc1 = old[PCPG + 5], old[PCPG + PCPG_FIELDS + 5]
    sel = old[IN]
    q = old[PSN : PSN + 12]
    x[PSN + 0] = math.tanh(1.0 - sel)
    x[PSN + 1] = math.tanh(sel)
    x[PSN + 2] = math.tanh(-5.0 * q[0] + 0.5 * pc0)
    x[PSN + 3] = math.tanh(-5.0 * q[1] + 0.5 * pc1)
    x[PSN + 4] = math.tanh(-5.0 * q[0] + 0.5 * pc1)
    x[PSN + 5] = math.tanh(-5.0 * q[1] + 0.5 * pc0)
    for i in range(4):
        x[PSN + 6 + i] = math.tanh(0.5 * q[2 + i] + 0.5)
    x[PSN + 10] = math.tanh(3.0 * q[6] + 3.0 * q[7] - 1.35)
    x[PSN + 11] = math.tanh(3.0 * q[8] + 3.0 * q[9] - 1.35)
    # VRNs: X from P11, Y from that side's steering input neuron.
    _vrn(old, x, VRN_L, q[11], old[IN + 1])
    _vrn(old, x, VRN_R, q[11], old[IN + 2])
    # Pre-motor neurons.
    x[PMN + 0] = math.tanh(PMN_TC_GAIN * old[VRN_R + 6])
    x[PMN + 1] = math.tanh(PMN_TC_GAIN * old[VRN_L + 6])
    x[PMN + 2] = math.tanh(PMN_CTR_GAIN * q[11] + PMN_BIAS)
    x[PMN + 3] = math.tanh(PMN_FTI_GAIN * q[11] + PMN_BIAS)
    x[PMN + 4] = math.tanh(PMN_FTI_MID_GAIN * q[10] + PMN_BIAS)
    # Delay lines: write this step's PMN outputs, read each leg's delayed copy.
    n = buf.shape[0]
    t = int(x[STEP])
    buf[t % n, :] = x[PMN : PMN + N_PMN]
    tau, tau_l = int(p[3]), int(p[4])
    g, g_mid = p[5], p[6]
    tc, ctr, fti = pre[0], pre[1], pre[2]
    # LEGS order R1 R2 R3 L1 L2 L3; k = 2 (front), 1 (middle), 0 (hind) neighbours from the hind leg.
    for leg in range(6):
        right = leg < 3
        k = 2 - leg % 3
        base = 0 if right else tau_l
        tc[leg] = buf[(t - base - k * tau) % n, 0 if right else 1]
        c = buf[(t - base - k * (tau + 1)) % n, 2]
        ctr[leg] = c if c >= old[CTR_PREV + leg] else -1.0
        x[CTR_PREV + leg] = c
        s = s_right if right else s_left
        if k == 1:
            fti[leg] = g_mid * buf[(t - base - tau + 1) % n, 4]
        elif k == 2:
            fti[leg] = buf[(t - base - 2 * tau) % n, 3] * (g * s)
        else:
            fti[leg] = buf[(t - base) % n, 3] * (-g * s)
    x[STEP] = t + 1


@jit
def locomotion_step(
    x: np.ndarray, buf: np.ndarray, s_right: float, s_left: float, p: np.ndarray, targets: np.ndarray
) -> None:
    """Advance one network one control step in place and write 18 leg targets (rad).

    :func:`presignal_step` followed by :func:`motor_map`; ``targets``: (>= 18,) output, actuator order.
    """
    pre = np.empty((3, 6))
    presignal_step(x, buf, s_right, s_left, p, pre)
    motor_map(pre[0], pre[1], pre[2], targets)


def initial_state(params: LocomotionParams) -> tuple[np.ndarray, np.ndarray]:
    """Start state (STATE_SIZE,) and empty delay buffer (L, 5) of one network."""
    x = np.zeros(STATE_SIZE)
    x[CPG : CPG + 2] = params.cpg.start
    return x, np.zeros((params.buffer_length, N_PMN))


class LocomotionNetwork:
    """Stateful holder of one locomotion network: steering (O1, O2) in, 19 joint targets out."""

    def __init__(self, params: LocomotionParams | None = None) -> None:
        self.params = params or LocomotionParams()
        self._p = self.params.as_array()
        self.targets = np.zeros(anatomy.N_ACTUATORS)
        self.pre = np.zeros((3, 6))
        self.reset()

    def reset(self) -> None:
        """Back to the start: CPG at (0.1, 0.1), delay lines empty."""
        self.state, self.buffer = initial_state(self.params)

    def step(self, o1: float, o2: float) -> np.ndarray:
        """One control step from steering (O1, O2); returns (19,) targets in rad (BJ = 0).

        The returned array is the network's own buffer, overwritten next step: copy to keep it.
        """
        locomotion_step(self.state, self.buffer, o1, o2, self._p, self.targets)
        return self.targets

    def step_presignals(self, o1: float, o2: float) -> np.ndarray:
        """One control step from steering (O1, O2); returns the (3, 6) TC/CTr/FTi pre-signals.

        For controllers that shape the pre-signals (local leg control) before :func:`motor_map`.
        The returned array is the network's own buffer, overwritten next step.
        """
        presignal_step(self.state, self.buffer, o1, o2, self._p, self.pre)
        return self.pre

    @property
    def cpg(self) -> np.ndarray:
        """(2,) CPG outputs."""
        return self.state[CPG : CPG + 2].copy()

    @property
    def pmn(self) -> np.ndarray:
        """(5,) pre-motor outputs: TC right, TC left, CTr, FTi (front/hind), FTi (middle)."""
        return self.state[PMN : PMN + N_PMN].copy()
