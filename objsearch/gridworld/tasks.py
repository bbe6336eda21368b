"""Grid-world tasks: (map, start, goal) triples, their JSONL files, and sampling them.

A task file has one JSON object a line, e.g. ``{"map": "map_0105", "start": [7, 10],
"goal": 14}``. Minimal steps are not stored: they are computed by BFS when the file is
loaded, so a file cannot disagree with its map.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import atomic_write
from objsearch.gridworld.maps import GridMap, bfs_distances

SEEN_GOALS = (0, 1, 3, 4, 6, 7, 8, 9, 11, 12, 14, 15)
UNSEEN_GOALS = (2, 5, 10, 13)
ALL_GOALS = tuple(range(16))


@dataclass(frozen=True)
class GridTask:
    """One grid-world episode specification.

    Attributes:
        map: name of the map (a key of the map directory).
        start: (row, col) start cell.
        goal: goal id (row of the map's ``goals``).
        min_steps: BFS distance from start to goal (>= 1).
    """

    map: str
    start: tuple[int, int]
    goal: int
    min_steps: int

    def to_json(self) -> dict:
        """The task as a JSON dict: map, start, goal (not min_steps)."""
        return {"map": self.map, "start": list(self.start), "goal": self.goal}


GoalDistances = Callable[[str, int], np.ndarray]
"""(map name, goal) -> (H, W) BFS distances to that goal, e.g. ``GridTables.goal_distances``."""


def make_task(
    maps: dict[str, GridMap],
    map_name: str,
    start,
    goal: int,
    source: str = "task",
    distances: GoalDistances | None = None,
) -> GridTask:
    """Check a task against its map and compute its minimal steps (a BFS, or read from
    ``distances`` when the caller has them)."""
    if map_name not in maps:
        known = ", ".join(list(maps)[:5])
        raise UserError(f"{source}: unknown map {map_name!r} (the map directory has {known}, ...)")
    grid_map = maps[map_name]
    if not isinstance(goal, (int, np.integer)) or not 0 <= goal < grid_map.num_goals:
        raise UserError(f"{source}: goal {goal!r} is not a goal id of {map_name} (0..{grid_map.num_goals - 1})")
    try:
        row, col = (int(v) for v in start)
    except (TypeError, ValueError):
        raise UserError(f"{source}: start {start!r} must be [row, col]") from None
    height, width = grid_map.shape
    if not (0 <= row < height and 0 <= col < width) or grid_map.obstacles[row, col]:
        raise UserError(f"{source}: start {[row, col]} is not a free cell of {map_name}")
    goal_cell = tuple(grid_map.goals[goal])
    dist = bfs_distances(grid_map.obstacles, goal_cell) if distances is None else distances(map_name, int(goal))
    steps = int(dist[row, col])
    if steps < 0:
        raise UserError(f"{source}: goal {goal} of {map_name} cannot be reached from start {[row, col]}")
    if steps == 0:
        raise UserError(f"{source}: start {[row, col]} is already on goal {goal}; a task needs at least one step")
    return GridTask(map=map_name, start=(row, col), goal=int(goal), min_steps=steps)


def load_tasks(
    path: str | os.PathLike, maps: dict[str, GridMap], distances: GoalDistances | None = None
) -> list[GridTask]:
    """Load a JSONL task file, checking every line against ``maps`` (``distances``: see ``make_task``)."""
    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except OSError as err:
        raise UserError(f"cannot read task file {path}: {err.strerror}") from None
    tasks = []
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        try:
            item = json.loads(line)
            map_name, start, goal = item["map"], item["start"], item["goal"]
        except (json.JSONDecodeError, TypeError, KeyError) as err:
            raise UserError(
                f'{where}: malformed task line ({err}); expected {{"map": "map_0005", "start": [7, 10], "goal": 14}}'
            ) from None
        tasks.append(make_task(maps, map_name, start, goal, source=where, distances=distances))
    if not tasks:
        raise UserError(f"task file {path} holds no tasks")
    return tasks


def save_tasks(tasks: list[GridTask], path: str | os.PathLike) -> None:
    """Write tasks as JSONL atomically (temp file, then rename)."""
    with atomic_write(path) as f:
        for task in tasks:
            f.write(json.dumps(task.to_json()) + "\n")


def sample_tasks(
    maps: dict[str, GridMap], goals: tuple[int, ...], count: int, rng: np.random.Generator
) -> list[GridTask]:
    """Sample tasks: a map and a goal uniformly, then a start uniformly among the free cells
    from which the goal is reachable (start != goal)."""
    names = sorted(maps)
    tasks = []
    while len(tasks) < count:
        name = names[rng.integers(len(names))]
        goal = int(goals[rng.integers(len(goals))])
        dist = bfs_distances(maps[name].obstacles, tuple(maps[name].goals[goal]))
        starts = np.argwhere(dist > 0)
        row, col = starts[rng.integers(len(starts))]
        tasks.append(GridTask(map=name, start=(int(row), int(col)), goal=goal, min_steps=int(dist[row, col])))
    return tasks
