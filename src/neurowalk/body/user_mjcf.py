"""``--body mjcf:FILE.xml``: a user's MuJoCo robot, driven by the same networks.

The convention a file must follow (checked when the run is configured; each missing piece is named):

- It compiles in MuJoCo and holds the robot and the floor; neurowalk adds the arena's obstacles to its worldbody
  (as boxes, the arena's own sizes, places and friction), so meshes and includes resolve from the file's folder.
- The robot's root body has a free joint, the model's first joint (``qpos[0:7]``); at reset it is put at the
  arena's start (x, y, yaw), its height and every other joint from the keyframe named by option ``key`` (default:
  the file's first keyframe, else ``qpos0``).
- Two ``rangefinder`` sensors, the left and the right ultrasonic sensor: ``US_L`` and ``US_R`` (AMOSII's names), or
  those named by options ``left`` and ``right``. Readings beyond option ``range`` (m, default 0.4, AMOSII's) are no
  echo; the noise is AMOSII's coloured noise. Place them as AMOSII's (about ±35° outward, at the front) for the
  networks' distance scale to mean the same.
- Option ``drive``: ``wheels`` or ``legs`` (default: ``legs`` where the file has AMOSII's 19 actuator names, else
  ``wheels``).
- ``wheels``, differential drive: two ``velocity`` actuators, the right and the left wheel, ``wheel_R`` and
  ``wheel_L`` (as ``neurowalk export-model --body wheeled`` writes them), or those named by options
  ``right_motor`` and ``left_motor``. Steering drives them as on the built-in wheeled robot: right from O1, left
  from O2, target -O x ``speed`` rad/s (option ``speed``; default the actuators' control limit), so (-1, -1) is
  forward.
- ``legs``, a six-legged robot: position actuators with AMOSII's 19 names (:data:`neurowalk.anatomy.ACTUATORS`),
  each on one joint; the locomotion network's joint targets (rad) drive them, as on AMOSII (``neurowalk
  export-model`` writes such a file). Observations carry those joints' angles; foot contacts read zero (no
  climbing controls).

Options are given as ``--body-opt KEY=VALUE`` (spec key ``body_opts``).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from neurowalk import anatomy
from neurowalk.arenas.spec import ArenaSpec
from neurowalk.body.noise import ColoredNoise
from neurowalk.body.physics import set_control_rate
from neurowalk.body.wheeled_body import Wheeled
from neurowalk.observation import Observation

PREFIX = "mjcf:"
NAMES = {"left": "US_L", "right": "US_R", "right_motor": "wheel_R", "left_motor": "wheel_L", "key": "", "drive": ""}
DRIVES = ("wheels", "legs")
NUMBERS = {"range": (0.4, 0.001, 100.0), "speed": (math.nan, 1e-6, 1e6)}  # default, low, high


def check_opts(body: str, opts: dict[str, Any]) -> dict[str, Any]:
    """The options of ``mjcf:FILE`` checked, and the file checked against the convention (module text).

    Raises:
        ValueError: naming the unknown option, the bad value, the missing file or the missing piece of the model.
    """
    out = parse_opts(body, opts)
    _Layout(_compile(body, None), {**_defaults(), **out}, body)  # raises on a file that breaks the convention
    return out


def parse_opts(body: str, opts: dict[str, Any]) -> dict[str, Any]:
    """The options of ``mjcf:FILE`` as names and numbers (ValueError naming a bad one); the file is not read."""
    out: dict[str, Any] = {}
    for key, value in opts.items():
        if key in NAMES:
            if not isinstance(value, str) or not value or (key == "drive" and value not in DRIVES):
                what = " or ".join(DRIVES) if key == "drive" else "a name"
                raise ValueError(f"body option {key} of {body!r} must be {what}, got {value!r}")
            out[key] = value
        elif key in NUMBERS:
            _, low, high = NUMBERS[key]
            try:
                number = float(value)
            except (TypeError, ValueError):
                number = math.nan
            if isinstance(value, bool) or not low <= number <= high:
                raise ValueError(
                    f"body option {key} of {body!r} must be a number in [{low:g}, {high:g}], got {value!r}"
                )
            out[key] = number
        else:
            raise ValueError(f"unknown option {key!r} of body {body!r}; its options: {', '.join([*NAMES, *NUMBERS])}")
    return out


def _defaults() -> dict[str, Any]:
    return {**NAMES, **{k: v[0] for k, v in NUMBERS.items()}}


def _compile(body: str, arena: ArenaSpec | None) -> mujoco.MjModel:
    path = Path(body[len(PREFIX) :])
    if not path.is_file():
        raise ValueError(f"body {body!r}: no such file {str(path)!r}")
    try:
        spec = mujoco.MjSpec.from_file(str(path))
        for i, b in enumerate(arena.boxes if arena is not None else []):
            g = spec.worldbody.add_geom(
                name=f"obstacle_{i}",
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=[b.sx / 2, b.sy / 2, b.h / 2],
                pos=[b.x, b.y, b.h / 2],
                quat=[math.cos(b.yaw / 2), 0.0, 0.0, math.sin(b.yaw / 2)],
            )
            g.rgba, g.friction = [0.55, 0.45, 0.35, 1.0], [0.4, 0.005, 0.0001]
        return spec.compile()
    except Exception as e:  # MuJoCo's parser and compiler raise ValueError or its own errors: one message
        raise ValueError(f"body {body!r}: MuJoCo cannot load it: {str(e).splitlines()[0] if str(e) else e!r}") from None


class _Layout:
    """The ids the convention asks for, found in a compiled model (ValueError naming what is missing)."""

    def __init__(self, m: mujoco.MjModel, opts: dict[str, Any], body: str) -> None:
        if m.njnt == 0 or m.jnt_type[0] != mujoco.mjtJoint.mjJNT_FREE:
            raise ValueError(f"body {body!r}: the model's first joint must be the robot's free joint (qpos[0:7])")
        self.root = int(m.jnt_bodyid[0])
        self.us = []
        for side in ("left", "right"):
            name, i = opts[side], mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SENSOR, opts[side])
            if i < 0 or m.sensor_type[i] != mujoco.mjtSensor.mjSENS_RANGEFINDER:
                rf = mujoco.mjtSensor.mjSENS_RANGEFINDER
                found = [m.sensor(j).name for j in range(m.nsensor) if m.sensor_type[j] == rf]
                raise ValueError(
                    f"body {body!r}: no rangefinder sensor {name!r} (the {side} ultrasonic sensor; "
                    f"rangefinders in the file: {found or 'none'}); name it with --body-opt {side}=NAME"
                )
            self.us.append(int(m.sensor_adr[i]))
        ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, a) for a in anatomy.ACTUATORS]
        self.drive = opts["drive"] or ("legs" if min(ids) >= 0 else "wheels")
        if self.drive == "legs":  # AMOSII's 19 actuators: the locomotion network's joint targets
            missing = [a for a, i in zip(anatomy.ACTUATORS, ids, strict=True) if i < 0]
            if missing:
                raise ValueError(
                    f"body {body!r}: drive=legs needs AMOSII's 19 actuator names; missing: {', '.join(missing)}"
                )
            self.motors = ids
            self.qidx = np.array([m.jnt_qposadr[m.actuator_trnid[i, 0]] for i in ids])
            self.speed = math.nan
        else:
            self._wheels(m, opts, body)
        self.key = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_KEY, opts["key"]) if opts["key"] else (0 if m.nkey else -1)
        if opts["key"] and self.key < 0:
            raise ValueError(f"body {body!r}: no keyframe {opts['key']!r}")

    def _wheels(self, m: mujoco.MjModel, opts: dict[str, Any], body: str) -> None:
        self.motors = []
        for side in ("right_motor", "left_motor"):
            name, i = opts[side], mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, opts[side])
            if i < 0:
                found = [m.actuator(j).name for j in range(m.nu)]
                raise ValueError(
                    f"body {body!r}: no actuator {name!r} (the {side.split('_')[0]} wheel; actuators in "
                    f"the file: {found or 'none'}); name it with --body-opt {side}=NAME"
                )
            self.motors.append(i)
        speed = opts["speed"]
        if math.isnan(speed):
            limited = all(m.actuator_ctrllimited[i] for i in self.motors)
            if not limited:
                raise ValueError(
                    f"body {body!r}: the wheel actuators have no control limit; give the wheel speed "
                    "at full steering with --body-opt speed=RAD_PER_S"
                )
            speed = float(min(m.actuator_ctrlrange[i, 1] for i in self.motors))
        self.speed = speed


class UserMjcf(Wheeled):
    """A user's robot: differential drive or AMOSII's legs (see the module text for the file's convention).

    Args:
        body: ``mjcf:PATH``. arena: where it drives. opts: the options (module text).
        control_hz: control rate (Hz); the file's timestep is fitted to it (``set_control_rate``).
        noise: strength of the coloured ultrasonic noise.
    """

    name = "mjcf"
    action = "steering"

    def __init__(
        self,
        body: str,
        arena: ArenaSpec,
        opts: dict[str, Any] | None = None,
        *,
        control_hz: float = 10.0,
        noise: float = 0.02,
    ) -> None:
        options = {**_defaults(), **parse_opts(body, opts or {})}  # the file is checked by _Layout below
        self.name, self.arena, self.options = body, arena, options
        self.model = _compile(body, arena)
        self.data = mujoco.MjData(self.model)
        self.control_hz = control_hz
        self.n_substeps = set_control_rate(self.model, control_hz)
        lay = _Layout(self.model, options, body)
        self._us_adr, self._us_range, self._unit = tuple(lay.us), float(options["range"]), 1.0
        self._omega_max, self._chassis, self._key = lay.speed, lay.root, lay.key
        self._noise = ColoredNoise(2, strength=noise)
        self.action = "targets" if lay.drive == "legs" else "steering"
        if lay.drive == "legs":
            self._motors, self._qidx = np.array(lay.motors), lay.qidx  # _qidx: the control loop records the joints
        else:
            self._right, self._left = lay.motors

    def apply(self, action: np.ndarray) -> None:
        """``wheels``: the steering pair (O1, O2); ``legs``: the 19 joint targets (rad, actuator order)."""
        if self.action == "steering":
            super().apply(action)
            return
        a = np.asarray(action, dtype=float)
        if a.shape != (anatomy.N_ACTUATORS,) or not np.all(np.isfinite(a)):
            raise ValueError(f"joint targets must be {anatomy.N_ACTUATORS} finite numbers, got shape {a.shape}")
        self.data.ctrl[self._motors] = a

    def observe(self) -> Observation:
        """As the wheeled robot's; with ``legs``, the joint angles (rad, actuator order) too."""
        obs = super().observe()
        if self.action == "targets":
            obs.joint_angles[:] = self.data.qpos[self._qidx]
        return obs

    def true_joint_angles(self) -> np.ndarray:
        """(19,) the joint angles (rad) with ``legs``; zeros with ``wheels``."""
        return self.data.qpos[self._qidx].copy() if self.action == "targets" else super().true_joint_angles()
