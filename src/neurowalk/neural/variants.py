"""Named variants of the whole network: the paper's text, the authors' code, and tuned learning parameters.

Where the paper's Eq. 1-6 read literally and the authors' C++ code differ, neurowalk offers both
(``docs/paper-vs-code.md`` lists the points, with the evidence):

* ``paper`` (default): DESIGN §3, Eq. 1-6 as printed; the sensory network's new outputs steer the
  locomotion network in the same control step; plastic weights start at 0.
* ``original``: the authors' code, all of it: (1) the weights learn from the activities before and
  after the update; (2) the steering reaches the locomotion network 3 control steps after the reading
  (an input identity neuron, an output identity neuron, read before the step); (3) the constructor runs
  one step with zero input, which moves the neurons but does not learn; (4) I = 1 - 2d/0.4, clipped to
  [-1, 1]; (5) the PCPG stores its first, partial phase; (6) learning starts from b = 2, q = 3; and the
  activity cut-off 0.009 and the reflex gate on US > 0.2.
* ``tuned``: the ``original`` network with learning parameters found by ``neurowalk optimize``
  (CMA-ES), shipped in ``neural/data/tuned.json`` with how they were found; present only if that file is.

A variant can carry overrides of named :class:`~neurowalk.neural.sensory.SensoryParams` fields
(:data:`TUNABLE`), e.g. from a ``--params FILE``.

A learning rule of the user's own is a variant too, named ``FILE.py:NAME``: the file's function ``NAME(state, i1,
i2, params)`` takes the place of :func:`~neurowalk.neural.sensory.sensory_step` (the same (14,) state and packed
params, updated in place; compiled where the file compiles it, e.g. with :func:`neurowalk.compiled.jit`), over the
parameters of the file's ``BASE`` variant (``paper`` where it names none).
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from neurowalk.fileio import load_ref, user_ref
from neurowalk.neural.motor import LocomotionParams
from neurowalk.neural.sensory import SensoryParams

TUNED_FILE = Path(__file__).with_name("data") / "tuned.json"
#: SensoryParams fields a params file or an optimisation may set (all numbers).
TUNABLE: tuple[str, ...] = (
    "a",
    "mu_b",
    "mu_q",
    "gamma_b",
    "gamma_q",
    "k",
    "reflex_threshold",
    "activity_cutoff",
    "us_near",
    "b_start",
    "q_start",
)


#: The authors' code's switches a params file may set too, each alone (:mod:`neurowalk.experiments.figures.ablation`):
#: the sensory network's (SensoryParams fields: booleans, and ``steer_delay`` 0, 1 or 2 control steps) and the PCPG's
#: ``pcpg_first_partial`` (boolean). With the numbers of :data:`TUNABLE` they are the 10 options by which
#: ``original`` differs from ``paper`` (:data:`CODE_OPTIONS`).
SWITCHES: tuple[str, ...] = ("input_delay", "post_learning", "steer_delay", "prime_step", "pcpg_first_partial")

#: The 10 options of the authors' code (``original``) that the paper's reading (``paper``) sets otherwise, with the
#: value of each in the two: {option: (paper, original)}; ``b_start``/``q_start`` 0 are the paper's plastic start.
CODE_OPTIONS: dict[str, tuple[float | bool | int, float | bool | int]] = {
    "activity_cutoff": (0.0, 0.009),
    "reflex_threshold": (-0.5, -0.6),
    "us_near": (0.05, 0.0),
    "input_delay": (False, True),
    "post_learning": (False, True),
    "steer_delay": (0, 2),
    "prime_step": (False, True),
    "b_start": (0.0, 2.0),
    "q_start": (0.0, 3.0),
    "pcpg_first_partial": (False, True),
}


def variant_names() -> tuple[str, ...]:
    """The variants available here: ``paper``, ``original``, and ``tuned`` where its data file is shipped."""
    return ("paper", "original", "tuned") if TUNED_FILE.is_file() else ("paper", "original")


@dataclass(frozen=True)
class Variant:
    """A named configuration of the network.

    Attributes:
        name: ``paper``, ``original``, ``tuned`` (with ``+params`` when overrides were applied).
        sensory: the sensory network's parameters.
        pcpg_first_partial: the PCPG stores its first, partial phase (the authors' code).
        overrides: the SensoryParams fields set on top of the named variant.
        rule: the sensory network's step, a user's learning rule (``FILE.py:NAME``); None: the built-in one,
            :func:`~neurowalk.neural.sensory.sensory_step`.
    """

    name: str
    sensory: SensoryParams
    pcpg_first_partial: bool = False
    overrides: Mapping[str, float | bool | int] = dataclasses.field(default_factory=dict)
    rule: Callable[..., None] | None = None

    def locomotion(self, base: LocomotionParams | None = None) -> LocomotionParams:
        """Locomotion parameters (``base``'s, default the wave gait) with this variant's PCPG."""
        b = base or LocomotionParams()
        return dataclasses.replace(b, cpg=dataclasses.replace(b.cpg, pcpg_first_partial=self.pcpg_first_partial))


def check_overrides(overrides: Mapping[str, Any], where: str = "params") -> dict[str, float | bool | int]:
    """``overrides`` as {field: value}: a :data:`TUNABLE` field a float, a :data:`SWITCHES` one a bool
    (``steer_delay`` an int 0-2); raises ValueError naming an unknown field or a bad value."""
    if not isinstance(overrides, Mapping):
        raise ValueError(f"{where} must be an object of SensoryParams fields, got {overrides!r}")
    out: dict[str, float | bool | int] = {}
    for key, value in overrides.items():
        if key == "steer_delay":
            if isinstance(value, bool) or not isinstance(value, int | float) or value not in (0, 1, 2):
                raise ValueError(f"{where}: steer_delay must be 0, 1 or 2 control steps, got {value!r}")
            out[key] = int(value)
        elif key in SWITCHES:
            if not isinstance(value, bool):
                raise ValueError(f"{where}: {key} must be true or false, got {value!r}")
            out[key] = value
        elif key not in TUNABLE:
            raise ValueError(f"{where}: unknown field {key!r}; fields: {', '.join((*TUNABLE, *SWITCHES))}")
        elif isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise ValueError(f"{where}: {key} must be a finite number, got {value!r}")
        else:
            out[key] = float(value)
    return dict(sorted(out.items()))


def get_variant(name: str = "paper", overrides: Mapping[str, Any] | None = None) -> Variant:
    """The variant ``name``, with ``overrides`` of SensoryParams fields applied (validated).

    Raises:
        ValueError: unknown variant, unknown field, or a value the parameters refuse (e.g. a negative rate).
    """
    names = variant_names()
    if user_ref(name) is not None:
        module, rule = load_ref(name, "neurowalk_rule_", ValueError)
        if not callable(rule):
            raise ValueError(f"learning rule {name!r} is a {type(rule).__name__}, not a function")
        base = getattr(module, "BASE", "paper")
        if base not in ("paper", "original"):
            raise ValueError(f"learning rule {name!r}: BASE must be 'paper' or 'original', got {base!r}")
        return dataclasses.replace(get_variant(base, overrides), name=name, rule=rule)
    if name not in names:
        raise ValueError(f"unknown variant {name!r}; expected one of {', '.join(names)}, or FILE.py:NAME")
    if name == "tuned":
        data = read_params_file(TUNED_FILE)
        base = get_variant(data.get("variant", "original"), data["params"])
        v = Variant("tuned", base.sensory, base.pcpg_first_partial, base.overrides)
    elif name == "original":
        v = Variant("original", SensoryParams.original_code(), pcpg_first_partial=True)
    else:
        v = Variant("paper", SensoryParams())
    if not overrides:
        return v
    extra = check_overrides(overrides)
    sensory: dict[str, Any] = {k: x for k, x in extra.items() if k != "pcpg_first_partial"}
    pcpg = bool(extra.get("pcpg_first_partial", v.pcpg_first_partial))
    return Variant(f"{v.name}+params", dataclasses.replace(v.sensory, **sensory), pcpg, {**v.overrides, **extra})


def read_params_file(path: Path | str) -> dict[str, Any]:
    """A params file: ``{"params": {field: value, ...}, "variant": base (optional: ``paper`` or ``original``), ...}``
    (other keys kept); its base variant as :func:`params_variant` reads it.

    Raises:
        ValueError: unreadable file, not JSON, no ``params`` object, an unknown field or a bad value (named).
    """
    try:
        data = json.loads(Path(path).read_text())
    except OSError as e:
        raise ValueError(f"cannot read params file {str(path)!r}: {e.strerror or e}") from None
    except UnicodeDecodeError as e:
        raise ValueError(f"params file {str(path)!r} is not text ({e.reason} at byte {e.start})") from None
    except json.JSONDecodeError as e:
        raise ValueError(f"params file {str(path)!r} is not JSON ({e.msg}, line {e.lineno})") from None
    except RecursionError:
        raise ValueError(f"params file {str(path)!r} is not a params file (JSON nested too deeply)") from None
    if not isinstance(data, dict) or not isinstance(data.get("params"), dict):
        raise ValueError(f"params file {str(path)!r} needs an object 'params' of SensoryParams fields")
    data["params"] = check_overrides(data["params"], f"params file {str(path)!r}")
    base = data.get("variant")
    if base is not None and base not in ("paper", "original"):
        raise ValueError(f"params file {str(path)!r}: variant must be 'paper' or 'original', got {base!r}")
    try:
        get_variant(base or "paper", data["params"])  # the parameters' own range checks
    except ValueError as e:
        raise ValueError(f"params file {str(path)!r}: {e}") from None
    return data


def params_variant(path: Path | str, data: dict[str, Any], variant: str | None) -> str | None:
    """The variant a params file's fields are set over: the file's own (an ``optimize`` best.json names the one it
    was tuned on), else ``variant`` (``--variant``; None: the default, ``paper``). ValueError where ``variant``
    contradicts the file's."""
    named = data.get("variant")
    if named is not None and variant is not None and variant != named:
        raise ValueError(f"--variant {variant} contradicts params file {str(path)!r}, which names variant {named!r}; "
                         "leave out --variant or edit the file")  # fmt: skip
    return named or variant
