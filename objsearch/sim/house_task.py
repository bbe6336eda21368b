"""A house episode's task (``HouseTask``), where sampled episodes start (``draw_start``: anywhere
``START_STEPS`` from the goal, or near the house's entrance, ``entrance_poses``) and the checks of
the step limits the house envs take (``check_max_steps``, ``check_room_max_steps``)."""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from objsearch.errors import UserError
from objsearch.house.rooms import ROOM_TYPES
from objsearch.sim.navgraph import GRID
from objsearch.sim.world import World

START_STEPS = (6, 40)  # sampled starts: minimal steps to the nearest goal pose in this range
# Where sampled starts are drawn: among all poses, or near the house's entrance (``draw_start``).
STARTS = ("anywhere", "entrance")
ENTRANCE_STEPS = 8  # "entrance" starts: at most this many steps from the entrance pose (``entrance_poses``)


def entrance_poses(world: World, steps: int = ENTRANCE_STEPS) -> np.ndarray:
    """Bool mask over the pose graph: the poses at most ``steps`` navgraph steps from the
    entrance pose (the 4 headings of the free cell nearest ``spec.entrance_point()``, 1 m
    inside the entrance door). UserError for a house without an entrance (``house-gen-1``)."""
    point = world.spec.entrance_point()
    if point is None:
        raise UserError(
            f"house {world.house_id} (generator {world.spec.generator_version}) has no entrance, so starts "
            "cannot be drawn near it; use house-gen-2 houses (HouseRef(seed=S, generator='house-gen-2')), "
            "or starts='anywhere'"
        )
    graph = world.graph
    centres = (graph.cells[:, ::-1] + 0.5) * GRID  # (x, y) of every free cell
    cell = int(np.argmin(((centres - np.asarray(point)) ** 2).sum(axis=1)))
    dist = graph.shortest_steps([cell * 4 + h for h in range(4)])
    return (dist >= 0) & (dist <= steps)


def draw_start(dist: np.ndarray, rng: np.random.Generator, near: np.ndarray | None = None) -> int | None:
    """A start pose drawn uniformly with ``rng``, given ``dist``, the minimal steps of every pose
    to the goal poses.

    ``near=None`` (starts "anywhere"): among the poses ``START_STEPS`` from the goals.
    ``near`` (a bool mask over poses, e.g. ``entrance_poses``): among the near poses
    ``START_STEPS`` from the goals; if there is none (the goals are far from the entrance),
    among the near poses farther than ``START_STEPS[1]`` (``min_steps`` then exceeds the
    window); if there is none either (goals unreachable from there, or right at the
    entrance), None: the caller draws another house and target.
    """
    window = (dist >= START_STEPS[0]) & (dist <= START_STEPS[1])
    if near is not None:
        inside = window & near
        window = inside if inside.any() else near & (dist > START_STEPS[1])
    starts = np.flatnonzero(window)
    if len(starts) == 0:
        return None
    return int(starts[rng.integers(len(starts))])


def check_max_steps(value) -> int:
    """``max_steps`` as an int if it is an integer >= 1 (a Python or numpy integer, or a float
    with no fraction); else ``ValueError`` naming it: ``-5``, ``0``, ``2.5``, ``True`` or ``"100"``
    are not step limits (``gymnasium.make("ObjSearch/House-v1", max_steps=-5)`` says so, not a ``Box``)."""
    whole = isinstance(value, numbers.Integral) or (isinstance(value, float) and value.is_integer())
    if isinstance(value, bool) or not whole or value < 1:
        raise ValueError(
            f"max_steps={value!r}: the step limit of an episode is an integer >= 1 (e.g. max_steps=1000, the default)"
        )
    return int(value)


def check_room_max_steps(room_max_steps: dict[str, int] | None) -> dict[str, int]:
    """``room_max_steps`` (room type -> step limit) checked: types of ``ROOM_TYPES``, positive
    integer limits; ValueError otherwise. None: {}."""
    out = {}
    for room, limit in (room_max_steps or {}).items():
        if room not in ROOM_TYPES:
            raise ValueError(f"room_max_steps: unknown room type {room!r}; use one of {', '.join(ROOM_TYPES)}")
        if isinstance(limit, bool) or not isinstance(limit, (int, np.integer)) or limit < 1:
            raise ValueError(f"room_max_steps[{room!r}] must be a positive integer, not {limit!r}")
        out[room] = int(limit)
    return out


@dataclass(frozen=True)
class HouseTask:
    """One episode: a house, a start pose, a target category and its goal poses.

    Attributes:
        house: house id (a key of the env's houses).
        start: (row, col, heading) on the house's pose graph.
        target: category name.
        goals: goal poses (row, col, heading) from the goal rule.
        min_steps: minimal actions from start to success: the moves to the nearest goal
            pose, and the STOP there where the env has ``stop_action``.
    """

    house: str
    start: tuple[int, int, int]
    target: str
    goals: tuple[tuple[int, int, int], ...]
    min_steps: int

    def to_json(self) -> dict:
        """The task as a JSON dict: house, start, target, min_steps (not the goals)."""
        return {"house": self.house, "start": list(self.start), "target": self.target, "min_steps": self.min_steps}
