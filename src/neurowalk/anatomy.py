"""Names and canonical orders of AMOSII's parts: the one place that spells them.

Legs are ``R1 R2 R3 L1 L2 L3`` (1 = front, 3 = hind, as in the paper's Fig. 7). Joints are ``TC``
(thoraco-coxal, + forward), ``CTr`` (coxa-trochanteral, + elevation), ``FTi`` (femur-tibia,
+ extension) and the backbone ``BJ`` (+ up). Every joint angle in neurowalk is in radians and in
this "controller" sign convention, whatever the body.

The 19 actuators are ordered ``TR1 TR2 TR3 TL1 TL2 TL3 CR1 ... FL3 BJ``: joint group, then side,
then leg from front to hind (the original code's motor order, with 1-based leg numbers).
"""

from __future__ import annotations

SIDES: tuple[str, ...] = ("R", "L")
LEGS: tuple[str, ...] = ("R1", "R2", "R3", "L1", "L2", "L3")
LEG_JOINTS: tuple[str, ...] = ("TC", "CTr", "FTi")
BACKBONE: str = "BJ"

# One-letter prefix of each joint group in actuator names (TR1 = TC joint of leg R1).
_PREFIX: dict[str, str] = {"TC": "T", "CTr": "C", "FTi": "F"}


def actuator_name(joint: str, leg: str) -> str:
    """Actuator name of ``joint`` on ``leg``, e.g. ``actuator_name("CTr", "L3") == "CL3"``."""
    if joint not in _PREFIX:
        raise ValueError(f"unknown leg joint {joint!r}; expected one of {LEG_JOINTS}")
    if leg not in LEGS:
        raise ValueError(f"unknown leg {leg!r}; expected one of {LEGS}")
    return f"{_PREFIX[joint]}{leg}"


ACTUATORS: tuple[str, ...] = (*(actuator_name(j, leg) for j in LEG_JOINTS for leg in LEGS), BACKBONE)
"""The 19 actuator names in actuator order: TR1 TR2 TR3 TL1 TL2 TL3 CR1 ... FL3 BJ."""

N_ACTUATORS: int = len(ACTUATORS)  # 19
N_LEG_JOINTS: int = N_ACTUATORS - 1  # 18

ACTUATOR_INDEX: dict[str, int] = {name: i for i, name in enumerate(ACTUATORS)}


def joint_index(joint: str, leg: str) -> int:
    """Index of ``joint`` of ``leg`` in the actuator order (0..17)."""
    return ACTUATOR_INDEX[actuator_name(joint, leg)]


BJ_INDEX: int = ACTUATOR_INDEX[BACKBONE]  # 18

# Index arrays by joint group, each in LEGS order (R1 R2 R3 L1 L2 L3): shape (6,).
TC_INDICES: tuple[int, ...] = tuple(joint_index("TC", leg) for leg in LEGS)
CTR_INDICES: tuple[int, ...] = tuple(joint_index("CTr", leg) for leg in LEGS)
FTI_INDICES: tuple[int, ...] = tuple(joint_index("FTi", leg) for leg in LEGS)

# Leg position along the body: 0 = front, 1 = middle, 2 = hind.
LEG_POSITION: dict[str, int] = {leg: int(leg[1]) - 1 for leg in LEGS}
LEG_SIDE: dict[str, str] = {leg: leg[0] for leg in LEGS}

# Sensory network: neuron 1 = left (left ultrasonic sensor, I1, O1), neuron 2 = right (I2, O2).
US_SENSORS: tuple[str, ...] = ("US_L", "US_R")
