"""Evaluation suites: fixed, versioned episode sets and the env that plays them.

A suite provides:

* ``name``, ``episode_set_version`` and ``splits`` (names, in report order);
* ``episodes(split) -> list[Episode]``: the fixed episodes of a split;
* ``make_env() -> gymnasium.Env`` whose ``reset(options={"task": episode.task})`` starts
  the episode and whose ``info["success"]`` says whether it ended in success (the one
  definition of success, owned by the env);
* ``config() -> dict``: the arguments that rebuild it (``make_suite(name, **config)``);
* ``world``: ``gridworld`` or ``house``, the world agents declare they run in.

Suites are looked up lazily by name in ``SUITES``.
"""

from __future__ import annotations

import difflib
import importlib
from dataclasses import dataclass, field
from typing import Any

from objsearch.errors import UserError

SUITES = {
    "gridworld": "objsearch.eval.suites.gridworld:GridWorldSuite",
    "house-single": "objsearch.eval.suites.house:HouseSingleSuite",
    "house-multi": "objsearch.eval.suites.house:HouseMultiSuite",
    "house-gen": "objsearch.eval.suites.house:HouseGenSuite",
}
DEFAULT_SUITE = "gridworld"
WORLDS = ("gridworld", "house")


def suite_world(name: str) -> str:
    """The world a suite's episodes play in, ``gridworld`` or ``house``: its class's
    ``world`` (agents declare the worlds they run in with ``worlds()``)."""
    return suite_class(name).world


@dataclass(frozen=True)
class Episode:
    """One episode of a split.

    Attributes:
        episode_id: index within the split.
        task: what the suite's env is reset with.
        goal: the goal's id; ``goal_name`` its label in reports.
        min_steps: shortest-path length from the start to success.
        describe: JSON-ready fields copied into the episode's record (map, start, ...).
        privileged: ground truth for the oracle (``shortest_path() -> list[action]``).
    """

    episode_id: int
    task: Any
    goal: int
    goal_name: str
    min_steps: int
    describe: dict = field(default_factory=dict)
    privileged: Any = field(default=None, repr=False, compare=False)


def suite_class(name: str) -> type:
    """The class of the suite ``name`` (imported on demand)."""
    if name not in SUITES:
        close = difflib.get_close_matches(name, list(SUITES), n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise UserError(f"unknown suite {name!r}; {hint}known suites: {', '.join(SUITES)}")
    module_name, _, cls_name = SUITES[name].partition(":")
    return getattr(importlib.import_module(module_name), cls_name)


def make_suite(name: str, **config):
    """Build the suite ``name`` with its config (e.g. ``maps``/``tasks`` for the grid world)."""
    return suite_class(name)(**config)


def check_splits(suite, splits: list[str] | None) -> list[str]:
    """The splits to run: all of the suite's if none given; unknown names are an error."""
    if not splits:
        return list(suite.splits)
    for split in splits:
        if split not in suite.splits:
            close = difflib.get_close_matches(split, list(suite.splits), n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise UserError(f"unknown split {split!r} of suite {suite.name!r}; {hint}splits: {', '.join(suite.splits)}")
    return splits
