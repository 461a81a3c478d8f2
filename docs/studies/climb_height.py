"""How high a step does AMOSII climb with the plastic network, with and without its backbone joint control?

A study file (``neurowalk study docs/studies/climb_height.py``): the robot walks at one step across its path (arena
``steps``, its edge 0.5 m ahead), the plastic network steering, for 300 s of simulated time, at each height from 0.04
to 0.12 m in 1 cm steps, 10 seeds each. Two module sets, as the command line names them: ``--climb`` (leg reflexes
and backbone joint control: the step is recognised as climbable and the front segment leans over it) and
``--reflexes`` (the leg reflexes alone: no backbone control, so no step detection either; the network avoids a step
its ultrasonic sensors see). A run climbs when the trunk centre gets 0.3 m onto the platform (the run stops there).

The committed result is ``docs/studies/climb-height/`` (``--out docs/studies/climb-height``); the paper's robot
climbs steps up to 11 cm with the backbone joint control (Fig. 10, section 3.3).
"""

import matplotlib.pyplot as plt
import numpy as np

from neurowalk import EpisodeConfig, Plan, Study

HEIGHTS = tuple(round(0.04 + 0.01 * k, 2) for k in range(9))  # m: 0.04 ... 0.12
QUICK_HEIGHTS = (0.06, 0.12)  # m
MODULES = {"--climb": {"reflexes": True, "backbone": True}, "--reflexes": {"reflexes": True}}
WORDS = {"--climb": "reflexes and backbone control", "--reflexes": "reflexes, no backbone control"}
PAPER_M = 0.11  # m: the highest step the paper's robot climbs with its backbone joint control
SECONDS = 300.0  # s of simulated time per run (3000 control steps at 10 Hz)


def runs(s):
    base = EpisodeConfig(arena="steps", controller="plastic", steps=round(SECONDS * 10), until="escaped")
    for name, modules in MODULES.items():
        for h in QUICK_HEIGHTS if s.quick else HEIGHTS:
            for k in range(s.n(full=10, quick=2)):
                yield Plan((name, h), base.replace(seed=s.seed + k, **modules, **{"arena_opts.height": h}))


def measure(s, results):
    heights = QUICK_HEIGHTS if s.quick else HEIGHTS
    out = {"heights_m": list(heights), "seeds": s.n(full=10, quick=2), "seconds": SECONDS, "paper_m": PAPER_M}
    for name in MODULES:
        climbed = [[r.exit_step is not None for r in results[name, h]] for h in heights]
        rates = [sum(c) / len(c) for c in climbed]
        every = [h for h, c in zip(heights, climbed, strict=True) if all(c)]
        times = [[r.exit_s for r in results[name, h] if r.exit_step is not None] for h in heights]
        out[name] = {
            "climbed": [sum(c) for c in climbed],
            "rate": rates,
            "median_time_s": [float(np.median(t)) if t else None for t in times],
            "highest_every_seed_m": max(every, default=None),
            # the largest rise of the rate from a lower height to a higher one (0: never climbed more often higher)
            "largest_rise": max(
                [0.0] + [rates[j] - rates[i] for i in range(len(rates)) for j in range(i + 1, len(rates))]
            ),
        }
    return out


def plot(result):
    s = result.summary
    cm = np.array(s["heights_m"]) * 100
    fig, ax = plt.subplots(figsize=(8, 4), layout="constrained")
    styles = ({"marker": "o"}, {"marker": "s", "ls": "--"})
    for name, style in zip(MODULES, styles, strict=True):
        d = s[name]
        best = d["highest_every_seed_m"]
        every = f"every seed up to {best * 100:g} cm" if best is not None else "no height every seed"
        ax.plot(cm, d["rate"], label=f"{name} ({WORDS[name]}):\n{every}", ms=8, mfc="none", mew=1.5, **style)
    ax.axvline(s["paper_m"] * 100, color="0.4", lw=1, ls=":")
    ax.annotate(f"the paper: up to {s['paper_m'] * 100:g} cm\nwith backbone control", (s["paper_m"] * 100, 0.75),
                xytext=(-6, 0), textcoords="offset points", ha="right", va="center", color="0.3")  # fmt: skip
    title = f"AMOSII at a single step, the plastic network steering ({s['seconds']:g} s a run)"
    ax.set(xlabel="step height (cm)", ylabel=f"climbed (share of {s['seeds']} seeds)", ylim=(-0.04, 1.04), title=title)
    ax.set_xticks(cm)
    ax.legend(loc="center", bbox_to_anchor=(0.5, 0.3))
    return fig


study = Study("climb-height", "share of seeds that climb a single step, by its height", plot=plot, runs=runs,
              measure=measure)  # fmt: skip
