"""The grid-world suite: the 20 test maps and the three fixed task lists of the paper, or a
user's own maps and task file (``--maps DIR --tasks FILE``)."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from objsearch.errors import UserError
from objsearch.eval.episode import valid_action
from objsearch.eval.suites import Episode, step_limit
from objsearch.gridworld import dataset
from objsearch.gridworld.batched import BatchedGridWorld, GridTables
from objsearch.gridworld.env import GridWorldEnv
from objsearch.gridworld.maps import GridMap, load_map_dir, shortest_path_actions
from objsearch.gridworld.tasks import GridTask, load_tasks


@dataclass(frozen=True)
class GridPath:
    """The oracle's view of a grid-world episode.

    ``distances``: the goal's BFS distances over the map (H, W), from
    ``GridTables.goal_distances``, so that the path needs no BFS of its own (the same path).
    The path is computed once per episode."""

    grid_map: GridMap
    task: GridTask
    distances: np.ndarray | None = field(default=None, compare=False, repr=False)

    def shortest_path(self) -> list[int]:
        """A shortest action sequence from the task's start to its goal (a fresh list each call)."""
        return list(self._path)

    @cached_property
    def _path(self) -> tuple[int, ...]:
        goal = tuple(self.grid_map.goals[self.task.goal])
        return tuple(shortest_path_actions(self.grid_map.obstacles, self.task.start, goal, self.distances))


class GridWorldSuite:
    """Grid world of HRL-GRG: splits ``seen-goals``, ``unseen-goals``, ``all-goals``.

    Args:
        name: its registered name, ``gridworld``.
        maps: a directory of ``map_XXXX.npz`` (with ``tasks``) instead of the packaged test maps.
        tasks: a JSONL task file; the suite then has one split named after the file's stem.
        max_steps: step limit per episode (the paper's 100).
    """

    world = "gridworld"
    protocol = "paper"  # an episode ends by itself on reaching the goal
    options = ("maps", "tasks", "max_steps")

    def __init__(
        self, name: str = "gridworld", maps: str | None = None, tasks: str | None = None, max_steps: int = 100
    ):
        if (maps is None) != (tasks is None):
            raise UserError("--maps and --tasks go together: pass a map directory and a task file, or neither")
        self.name = name
        self.maps_dir, self.tasks_file, self.max_steps = maps, tasks, step_limit(max_steps)
        if tasks is None:
            self.episode_set_version = dataset.DATA_VERSION
            self.splits = tuple(dataset.SPLIT_GOALS)
        else:
            self.episode_set_version = f"custom:{Path(tasks).name}"
            self.splits = (Path(tasks).stem,)

    def config(self) -> dict:
        """The config that rebuilds this suite: ``maps``, ``tasks``, ``max_steps``."""
        return {"maps": self.maps_dir, "tasks": self.tasks_file, "max_steps": self.max_steps}

    @cached_property
    def grid_tables(self) -> GridTables:
        """The maps' tables, built once and shared by the envs of every slot."""
        return GridTables.build(list(self.grid_maps.values()))

    @cached_property
    def grid_maps(self) -> dict[str, GridMap]:
        """The suite's maps by name: the packaged test maps, or those of the ``maps`` directory."""
        return dataset.test_maps() if self.maps_dir is None else load_map_dir(self.maps_dir)

    @cached_property
    def _tables(self) -> GridTables | None:
        """``grid_tables``, or None if the maps cannot share tables (the envs then refuse them)."""
        try:
            return self.grid_tables
        except ValueError:
            return None

    def _tasks(self, split: str) -> list[GridTask]:
        """The tasks of ``split``, their minimal steps read from the suite's tables when it has them."""
        path = dataset.DATA_DIR / "tasks" / f"{split}.jsonl" if self.tasks_file is None else self.tasks_file
        tables = self._tables
        return load_tasks(path, self.grid_maps, tables.goal_distances if tables is not None else None)

    def episodes(self, split: str) -> list[Episode]:
        """The fixed episodes of ``split``, in task-file order (ids 0, 1, ...)."""
        episodes = []
        tables = self._tables
        for i, task in enumerate(self._tasks(split)):
            distances = tables.goal_distances(task.map, task.goal) if tables is not None else None
            episodes.append(
                Episode(
                    episode_id=i,
                    task=task,
                    goal=task.goal,
                    goal_name=f"g{task.goal}",
                    min_steps=task.min_steps,
                    describe=task.to_json(),
                    privileged=GridPath(self.grid_maps[task.map], task, distances),
                )
            )
        return episodes

    def make_slots(self, num_slots: int) -> "GridSlots":
        """``num_slots`` lockstep slots stepped in one ``BatchedGridWorld`` call
        (``objsearch.eval.lockstep``): what ``num_slots`` envs of ``make_env`` would give."""
        return GridSlots(self.make_env(), num_slots)

    def make_env(self) -> GridWorldEnv:
        """A ``GridWorldEnv`` over the suite's maps, observing all goals, with the suite's step limit."""
        return GridWorldEnv(
            maps=self.grid_tables,
            goals=None,
            observation="all_goals",
            max_steps=self.max_steps,
        )


class GridSlots:
    """Lockstep slots of the grid world (the protocol of ``objsearch.eval.lockstep.EnvSlots``),
    all in one ``BatchedGridWorld``: a step of every playing slot is one call of array
    gathers, not one ``GridWorldEnv.step`` a slot. Each slot sees what ``env`` (a
    ``GridWorldEnv`` of the suite, whose tables, step limit, observation and spaces the
    slots share) would show it: the same observations, ends and successes."""

    def __init__(self, env: GridWorldEnv, num_slots: int):
        self.env = env
        world = env._world
        self.tables = world.tables
        self.world = BatchedGridWorld(
            self.tables,
            num_slots,
            goals=None,
            observation=world.observation,
            max_steps=world.max_steps,
            autoreset=False,
        )
        self.num_actions = int(env.action_space.n)
        if int(env.action_space.start) != 0:
            raise ValueError("GridSlots expects actions numbered from 0")

    def __len__(self) -> int:
        return self.world.num_envs

    def observation_space(self, i: int):
        """Slot ``i``'s observation space (the same for every slot)."""
        return self.env.observation_space

    def action_space(self, i: int):
        """Slot ``i``'s action space (the same for every slot)."""
        return self.env.action_space

    def valid(self, i: int, action) -> bool:
        """Whether ``action`` is in slot ``i``'s action space."""
        if type(action) is int:  # what Discrete(n).contains says of a plain int, without its checks
            return 0 <= action < self.num_actions
        return valid_action(self.env.action_space, action)

    def start(self, starts: dict[int, tuple[Episode, Any]]) -> dict[int, tuple[dict, dict]]:
        """Reset slots to their episodes' tasks (the seed is not needed: a task fixes the
        whole episode)."""
        if not starts:
            return {}
        ids = list(starts)
        t = self.tables
        maps, goals, cells = [], [], []
        for i in ids:
            task = starts[i][0].task
            try:
                maps.append(t.map_index(task.map))
            except ValueError:
                raise ValueError(f"task map {task.map!r} is not among this env's maps") from None
            goals.append(task.goal)
            cells.append(int(task.start[0]) * t.width + int(task.start[1]))
        obs = self.world.start(ids, maps, goals, cells)
        w = self.world
        out = {}
        for k, i in enumerate(ids):
            r, c = divmod(int(w.cell[i]), t.width)
            info = {
                "success": False,
                "steps": 0,
                "min_steps": int(w.min_steps[i]),
                "map": t.names[int(w.map_idx[i])],
                "position": (r, c),
            }
            out[i] = {"image": obs["image"][k], "goal": int(obs["goal"][k])}, info
        return out

    def step(self, actions: dict[int, Any]) -> dict[int, tuple[dict, bool, bool, dict]]:
        """One step of each slot in ``actions`` (valid actions only); ``info`` holds
        ``success`` and ``steps``."""
        ids = list(actions)
        obs, _, terminated, truncated, info = self.world.step_envs(
            ids, np.array([actions[i] for i in ids], dtype=np.int64)
        )
        images, goals = obs["image"], obs["goal"].tolist()
        terminated, truncated, steps = terminated.tolist(), truncated.tolist(), info["steps"].tolist()
        return {
            i: (
                {"image": images[k], "goal": goals[k]},
                terminated[k],
                truncated[k],
                {"success": terminated[k], "steps": steps[k]},
            )
            for k, i in enumerate(ids)
        }
