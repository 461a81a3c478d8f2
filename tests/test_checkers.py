"""check_body and check_engine on every built-in; a body or engine breaking the contract gets one line naming what."""

from __future__ import annotations

import numpy as np
import pytest

from neurowalk import EpisodeConfig, make_arena, make_body
from neurowalk.body.amosii import AmosII
from neurowalk.body.check import BodyContractError, check_body
from neurowalk.body.registry import BODIES, body_xml
from neurowalk.observation import Observation
from neurowalk.sim.batch import MujocoBatchWorlds
from neurowalk.sim.check import EngineContractError, check_engine
from neurowalk.sim.cpu_loop import CpuLoop
from neurowalk.sim.engines import ENGINES, PLANAR


@pytest.mark.parametrize("name", sorted(BODIES))
def test_every_built_in_body_keeps_the_contract(name):
    check_body(make_body(name, make_arena("box")))


def test_a_user_mjcf_robot_and_many_worlds_keep_it(tmp_path):
    path = tmp_path / "robot.xml"
    path.write_text(body_xml("wheeled"))
    check_body(make_body(f"mjcf:{path}", make_arena("corner")))
    check_body(MujocoBatchWorlds([EpisodeConfig(arena="box", steps=5, seed=s) for s in range(2)]))


class _ThreeEyes(AmosII):
    def observe(self) -> Observation:
        obs = super().observe()
        return Observation(us_distance=np.append(obs.us_distance, 1.0), foot_contact=obs.foot_contact)


class _Unseeded(AmosII):
    def reset(self, rng: np.random.Generator) -> None:
        super().reset(np.random.default_rng())  # ignores the run's Generator


class _Frozen(AmosII):
    def advance(self) -> None:
        pass


@pytest.mark.parametrize(
    ("cls", "says"),
    [
        (_ThreeEyes, "distances of shape (1, 2), got (1, 3)"),
        (_Unseeded, "not deterministic"),
        (_Frozen, "time must go forward"),
    ],
)
def test_a_body_that_breaks_the_contract_gets_one_line_naming_what(cls, says):
    with pytest.raises(BodyContractError) as e:
        check_body(cls(make_arena("box")))
    assert says in str(e.value) and "\n" not in str(e.value) and str(e.value).startswith("body 'amosii': ")


@pytest.mark.parametrize("name", [n for n in ENGINES if n != "warp"])
def test_every_cpu_engine_keeps_the_contract(name):
    check_engine(ENGINES[name])


def test_the_planar_engine_keeps_it():
    check_engine(PLANAR)


class _Reversed(CpuLoop):
    def run(self, configs, options):
        return super().run(configs, options)[::-1]


def test_an_engine_that_breaks_the_contract_gets_one_line_naming_what():
    with pytest.raises(EngineContractError) as e:
        check_engine(_Reversed())
    assert str(e.value) == "engine 'mujoco': episode 0 is not config 0's: run() must keep the configs' order"
