"""Evaluation suites: fixed, versioned episode sets and the env that plays them.

``SUITES`` is the one registry of suite names: every list of suites (the CLI's help and
checks, ``objsearch suite list``, the leaderboard) comes from it. It holds the grid world
and the shipped house suites, whose names are declared with their builders
(``objsearch.sim.suites.SUITE_NAMES``); besides them, the path of a suite file made by
``objsearch suite make`` (``*.json``) names a house suite. Other suites join it with
``register_suite(name, cls)``, or from an installed package through the entry-point group
``objsearch.suites`` (``name = "package.module:SuiteClass"``), read in every process as
agents' are. Adding a suite: ``docs/add_a_suite.md``.

A suite class provides:

* ``world``: ``gridworld`` or ``house``, the world agents declare they run in;
* ``protocol``: how an episode succeeds, ``paper`` (it ends by itself on reaching the goal)
  or ``objectnav`` (the agent must call STOP at the goal; ``objsearch.sim.goals.PROTOCOLS``),
  recorded in results; the leaderboard ranks a suite's entries, so never two protocols together;
* ``options``: the names of the config it accepts (``make_suite(name, **config)`` refuses
  others; the CLI's suite flags are checked against them);
* ``__init__(name, **config)``; ``name``, ``episode_set_version`` and ``splits`` (names,
  in report order);
* ``episodes(split) -> list[Episode]``: the fixed episodes of a split;
* ``make_env() -> gymnasium.Env`` whose ``reset(options={"task": episode.task})`` starts
  the episode and whose ``info["success"]`` says whether it ended in success (the one
  definition of success, owned by the env);
* ``config() -> dict``: the config that rebuilds it (``make_suite(name, **config)``).

Classes are imported only when a suite is used. Through these, any suite is also one
Gymnasium env, ``ObjSearch/Suite-v1`` (``objsearch.eval.suite_env``), which plays its
episodes in the harness's order.
"""

from __future__ import annotations

import difflib
import importlib
from dataclasses import dataclass, field
from importlib.metadata import entry_points
from typing import Any

from objsearch.errors import UserError
from objsearch.sim.suites import SUITE_NAMES as HOUSE_SUITES

HOUSE_SUITE = "objsearch.eval.suites.house:HouseSuite"
GROUP = "objsearch.suites"
SUITES = {
    "gridworld": "objsearch.eval.suites.gridworld:GridWorldSuite",
    **dict.fromkeys(HOUSE_SUITES, HOUSE_SUITE),
}
#: The suites registered in this process by ``register_suite`` (handed to worker processes).
REGISTERED: dict[str, str] = {}
SUITE_FILE = HOUSE_SUITE  # the class of a suite file (a path ending in .json)
DEFAULT_SUITE = "house-single"  # what objsearch-eval runs without --suite: the main job
WORLDS = ("gridworld", "house")


def register_suite(name: str, suite: type | str, *, check: bool = True) -> None:
    """Make ``name`` a suite: ``suite`` is a suite class (see above) or its ``"module:Class"``.

    The name then works everywhere a shipped suite's does (``objsearch.evaluate``,
    ``make_suite``, worker processes of this evaluation). Registering a name again with the
    same class is allowed; a name taken by another suite is an error. A package makes its
    suites known to every process, and to the command line, with an entry point in the
    group ``objsearch.suites`` instead."""
    if not isinstance(suite, (str, type)):
        raise UserError(f"register_suite: suite {suite!r} for {name!r} must be a class or a 'module:Class' string")
    target = suite if isinstance(suite, str) else f"{suite.__module__}:{suite.__qualname__}"
    if not isinstance(name, str) or not name or name.endswith(".json"):
        raise UserError(f"register_suite: suite name {name!r} must be a non-empty string not ending in .json")
    if ":" not in target:
        raise UserError(f"register_suite: suite {suite!r} for {name!r} must be a class or a 'module:Class' string")
    if check:  # a caller's own registration is checked now, not at the first episode (entry points stay lazy)
        try:
            cls = suite if isinstance(suite, type) else _import(target)
        except (ImportError, AttributeError) as err:
            raise UserError(
                f"register_suite: cannot import {target} for {name!r} ({err}); check the module:Class"
            ) from None
        missing = [a for a in ("world", "protocol", "options", "episodes", "make_env", "config") if not hasattr(cls, a)]
        if not isinstance(cls, type) or missing:
            raise UserError(
                f"register_suite: {target} for {name!r} is not a suite class (it lacks {', '.join(missing) or 'a class'}); "
                "docs/add_a_suite.md lists what a suite provides"
            )
    if SUITES.get(name, target) != target:
        raise UserError(
            f"register_suite: suite name {name!r} is taken by {SUITES[name]}; register {target} under another name"
        )
    SUITES[name] = REGISTERED[name] = target


def _register_installed() -> None:
    for ep in entry_points(group=GROUP):
        register_suite(ep.name, ep.value, check=False)


_register_installed()


def is_suite_file(name: str) -> bool:
    """Whether ``name`` is the path of a suite file rather than a registered name."""
    return name not in SUITES and name.endswith(".json")


def suite_world(name: str) -> str:
    """The world a suite's episodes play in, ``gridworld`` or ``house``: its class's
    ``world`` (agents declare the worlds they run in with ``worlds()``)."""
    return suite_class(name).world


def standard_seeds(name: str) -> tuple[int, ...]:
    """The seeds a full (ranked) evaluation of suite ``name`` plays: a house suite file's
    ``seeds`` where it records them (the large-house tier: one, its 300 long episodes carry the
    statistics), else the paper's ``PAPER_SEEDS``; without building the suite."""
    from objsearch.eval.config import PAPER_SEEDS

    if suite_class(name).world != "house":
        return PAPER_SEEDS
    from objsearch.sim.suites import load_suite_file

    return tuple(load_suite_file(name).get("seeds", PAPER_SEEDS))


def suite_protocol(name: str) -> str:
    """How a suite's episodes succeed, ``paper`` or ``objectnav`` (its class's ``protocol``;
    a house suite's is its file's), without building the suite."""
    cls = suite_class(name)
    if cls.world != "house":
        return cls.protocol
    from objsearch.sim.suites import load_suite_file
    from objsearch.sim.suites import suite_protocol as file_protocol

    return file_protocol(load_suite_file(name)).name


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


def step_limit(value) -> int:
    """A suite's ``max_steps`` option: an integer >= 1 (a Python or numpy integer, or a float
    with no fraction), else ``UserError``: ``2.5`` is not silently 2, nor ``True`` 1."""
    import numbers

    whole = isinstance(value, numbers.Integral) or (isinstance(value, float) and value.is_integer())
    if isinstance(value, bool) or not whole or value < 1:
        raise UserError(f"max_steps {value!r}: the step limit is an integer >= 1 (e.g. max_steps=100)")
    return int(value)


def _import(target: str) -> type:
    module_name, _, cls_name = target.partition(":")
    return getattr(importlib.import_module(module_name), cls_name)


def suite_class(name: str) -> type:
    """The class of the suite ``name``, a registered name or a suite file (imported on demand)."""
    if is_suite_file(name):
        return _import(SUITE_FILE)
    if name not in SUITES:
        close = difflib.get_close_matches(name, list(SUITES), n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise UserError(
            f"unknown suite {name!r}; {hint}known suites: {', '.join(SUITES)}, "
            "or a suite file (.json) made by objsearch suite make"
        )
    return _import(SUITES[name])


def suites_taking(option: str) -> list[str]:
    """The suites whose class accepts the config ``option`` (suite files listed as one)."""
    names = [name for name in SUITES if option in suite_class(name).options]
    return names + (["suite files (.json)"] if option in _import(SUITE_FILE).options else [])


def make_suite(name: str, **config):
    """Build the suite ``name`` with its config (e.g. ``maps``/``tasks`` for the grid world);
    a config key the suite's ``options`` lack is an error naming the suites that take it."""
    cls = suite_class(name)
    for option in config:
        if option not in cls.options:
            raise UserError(
                f"suite {name!r} takes no option {option!r} (it takes {', '.join(cls.options)}); "
                f"{option!r} is an option of {', '.join(suites_taking(option)) or 'no suite'}"
            )
    return cls(name, **config)


def check_splits(suite, splits: list[str] | None) -> list[str]:
    """The splits to run: all of the suite's if none given; unknown names are an error.

    The one place an evaluation's splits are resolved, so the one place that refuses an
    evaluation with nothing to play: a suite whose ``splits`` is empty, and chosen splits that
    hold no episodes, are a ``UserError`` naming the suite and the fix, never results with no
    episodes (which would read as a finished run) nor an error from ``summarize``."""
    name = getattr(suite, "name", None) or type(suite).__name__
    available = list(getattr(suite, "splits", None) or ())
    if not available:
        raise UserError(
            f"suite {name!r} has no splits (its splits is {getattr(suite, 'splits', None)!r}): nothing to play; "
            "a suite lists at least one split, each with episodes (docs/add_a_suite.md)"
        )
    if not splits:
        splits = available
    for split in splits:
        if split not in available:
            close = difflib.get_close_matches(split, available, n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise UserError(f"unknown split {split!r} of suite {name!r}; {hint}splits: {', '.join(available)}")
    empty = [split for split in splits if not suite.episodes(split)]
    if empty:
        others = [split for split in available if split not in empty and suite.episodes(split)]
        fix = (
            f"choose splits that have episodes ({', '.join(others)})"
            if others
            else "give the suite's episodes(split) at least one episode per split (docs/add_a_suite.md)"
        )
        raise UserError(
            f"split{'s' if len(empty) > 1 else ''} {', '.join(map(repr, empty))} of suite {name!r} "
            f"{'hold' if len(empty) > 1 else 'holds'} no episodes: nothing to play; {fix}"
        )
    return list(splits)
