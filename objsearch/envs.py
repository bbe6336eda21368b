"""Registration of objsearch's Gymnasium environments (string entry points: nothing heavy
is imported until an environment is made), and the action check the envs share.

* ``ObjSearch/GridWorld-v0``: the paper's grid world (``objsearch.gridworld.env.GridWorldEnv``).
* ``ObjSearch/House-v1``: sampled tasks in MuJoCo houses (``objsearch.sim.env.HouseEnv``).
  ``ObjSearch/House-v0`` keeps the observation keys v0 was released with (``rgb``,
  ``depth``, ``semantic``, ``target``; ``objsearch.sim.env_v0``): old ids keep working.
* ``ObjSearch/Suite-v1``: a suite's fixed episodes, in the order ``objsearch-eval`` plays
  them (``objsearch.eval.suite_env.SuiteEnv``; ``suite=`` and ``split=`` name them), and
  ``ObjSearch/<suite>-v1`` for every shipped suite (``gridworld`` and the files of
  ``objsearch/sim/data``), the same env with ``suite=`` given, as the design asks (one id a
  shipped suite): ``gymnasium.make("ObjSearch/house-large-v1", split="test")``.

Every env's docstring has a Version History; a change to what an id gives is a new version.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import gymnasium

ENVS = {
    "ObjSearch/GridWorld-v0": {"entry_point": "objsearch.gridworld.env:GridWorldEnv"},
    "ObjSearch/House-v0": {
        "entry_point": "objsearch.sim.env_v0:HouseEnvV0",
        "vector_entry_point": "objsearch.sim.env_v0:HouseVectorEnvV0",
    },
    "ObjSearch/House-v1": {
        "entry_point": "objsearch.sim.env:HouseEnv",
        # gymnasium.make_vec(..., vectorization_mode="vector_entry_point"): the batched cached env
        "vector_entry_point": "objsearch.sim.vector:HouseVectorEnv",
    },
    "ObjSearch/Suite-v1": {"entry_point": "objsearch.eval.suite_env:SuiteEnv"},
}
# The shipped suites by their files (read without importing objsearch.sim, which imports MuJoCo;
# tests/sim/test_shipped_suite_files.py checks that the files are the shipped suites).
SHIPPED_SUITE_NAMES = ("gridworld", *sorted(p.stem for p in (Path(__file__).parent / "sim" / "data").glob("*.json")))
for _name in SHIPPED_SUITE_NAMES:
    ENVS[f"ObjSearch/{_name}-v1"] = {"entry_point": "objsearch.eval.suite_env:SuiteEnv", "kwargs": {"suite": _name}}


def register_envs() -> None:
    """Register every objsearch environment id with Gymnasium; safe to call twice."""
    for env_id, entry_points in ENVS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, **entry_points)


def check_action(space: gymnasium.spaces.Discrete, action, names: Sequence[str]) -> int:
    """``action`` as an int if ``space`` contains it (a Python or numpy integer in range, as
    Gymnasium's ``Discrete.contains`` says), else a ValueError naming it and the valid actions:
    ``1.5``, ``"1"``, ``None`` or an array are refused, not rounded or cast."""
    if not space.contains(action):
        first, last = int(space.start), int(space.start + space.n - 1)
        raise ValueError(
            f"invalid action {action!r} ({type(action).__name__}); expected an integer in {first}..{last} "
            f"({', '.join(f'{first + i} {name}' for i, name in enumerate(names))})"
        )
    return int(action)
