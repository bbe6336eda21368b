"""The grid-world suite: the 20 test maps and the three fixed task lists of the paper, or a
user's own maps and task file (``--maps DIR --tasks FILE``)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path


from objsearch.eval.suites import Episode
from objsearch.gridworld import dataset
from objsearch.gridworld.batched import GridTables
from objsearch.gridworld.env import GridWorldEnv
from objsearch.gridworld.maps import GridMap, load_map_dir, shortest_path_actions
from objsearch.gridworld.tasks import GridTask, load_tasks
from objsearch.errors import UserError


@dataclass(frozen=True)
class GridPath:
    """The oracle's view of a grid-world episode."""

    grid_map: GridMap
    task: GridTask

    def shortest_path(self) -> list[int]:
        return shortest_path_actions(self.grid_map.obstacles, self.task.start, tuple(self.grid_map.goals[self.task.goal]))


class GridWorldSuite:
    """Grid world of HRL-GRG: splits ``seen-goals``, ``unseen-goals``, ``all-goals``.

    Args:
        name: its registered name, ``gridworld``.
        maps: a directory of ``map_XXXX.npz`` (with ``tasks``) instead of the packaged test maps.
        tasks: a JSONL task file; the suite then has one split named after the file's stem.
        max_steps: step limit per episode (the paper's 100).
    """

    world = "gridworld"
    options = ("maps", "tasks", "max_steps")

    def __init__(self, name: str = "gridworld", maps: str | None = None, tasks: str | None = None, max_steps: int = 100):
        if (maps is None) != (tasks is None):
            raise UserError("--maps and --tasks go together: pass a map directory and a task file, or neither")
        self.name = name
        self.maps_dir, self.tasks_file, self.max_steps = maps, tasks, int(max_steps)
        if tasks is None:
            self.episode_set_version = dataset.DATA_VERSION
            self.splits = tuple(dataset.SPLIT_GOALS)
        else:
            self.episode_set_version = f"custom:{Path(tasks).name}"
            self.splits = (Path(tasks).stem,)

    def config(self) -> dict:
        return {"maps": self.maps_dir, "tasks": self.tasks_file, "max_steps": self.max_steps}

    @cached_property
    def grid_tables(self) -> GridTables:
        """The maps' tables, built once and shared by the envs of every slot."""
        return GridTables.build(list(self.grid_maps.values()))

    @cached_property
    def grid_maps(self) -> dict[str, GridMap]:
        return dataset.test_maps() if self.maps_dir is None else load_map_dir(self.maps_dir)

    def _tasks(self, split: str) -> list[GridTask]:
        if self.tasks_file is None:
            return dataset.split_tasks(split)
        return load_tasks(self.tasks_file, self.grid_maps)

    def episodes(self, split: str) -> list[Episode]:
        episodes = []
        for i, task in enumerate(self._tasks(split)):
            episodes.append(
                Episode(
                    episode_id=i,
                    task=task,
                    goal=task.goal,
                    goal_name=f"g{task.goal}",
                    min_steps=task.min_steps,
                    describe=task.to_json(),
                    privileged=GridPath(self.grid_maps[task.map], task),
                )
            )
        return episodes

    def make_env(self) -> GridWorldEnv:
        return GridWorldEnv(
            maps=self.grid_tables,
            goals=None,
            observation="all_goals",
            max_steps=self.max_steps,
        )
