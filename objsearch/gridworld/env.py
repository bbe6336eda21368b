"""``ObjSearch/GridWorld-v0``: the HRL-GRG grid world as a Gymnasium environment."""

from __future__ import annotations

import os
from typing import Any, Sequence

import gymnasium
import numpy as np
from gymnasium import spaces

from objsearch.envs import check_action
from objsearch.gridworld.batched import ACTION_NAMES, NUM_ACTIONS, OBSERVATIONS, WINDOW, BatchedGridWorld, GridTables
from objsearch.gridworld.maps import GridMap, load_map_dir
from objsearch.gridworld.tasks import SEEN_GOALS, GridTask


class GridWorldEnv(gymnasium.Env):
    """Partially observable goal search on 16x16 grid maps (Ye et al., CVPR 2021, sec. 4.1).

    ## Description
    The agent starts on a free cell of a map with 16 goals and must walk onto the goal it
    is given. It sees only the 7x7 window centred on itself. The goals of a map are placed
    in two chains (g0..g7, g8..g15), each goal within 3 cells of its predecessor, so goals
    that are seen together hint at where the others are.

    ## Observation Space
    ``Dict(image=Box(0, 1, (C, 7, 7), uint8), goal=Discrete(16))``. ``image`` channel 0 is
    obstacles (cells outside the map read 1). With ``observation="goal"`` (C = 2) channel 1
    marks the episode goal's cell if it is in view; with ``observation="all_goals"``
    (C = 17) channel 1 + i marks goal i. ``goal`` is the id of the episode's goal.

    ## Action Space
    ``Discrete(4)``: 0 up, 1 down, 2 left, 3 right. A move into an obstacle leaves the agent
    where it is.

    ## Rewards
    1 on the step the agent reaches the goal, else 0.

    ## Starting State
    A map and a goal drawn uniformly (from ``maps`` and ``goals``) and a start drawn
    uniformly among the free cells from which the goal can be reached, or the task passed
    as ``reset(options={"task": GridTask})``.

    ## Episode End
    Terminated when the agent stands on the goal; truncated after ``max_steps`` (100) steps.

    ## Info
    ``success``, ``steps``, ``min_steps`` (BFS distance from the start), ``map`` (name),
    ``position`` (row, col).

    ## Arguments
    ``maps``: a directory of ``map_XXXX.npz`` files, a list of ``GridMap``, their built
    ``GridTables`` (envs that play side by side share them), or None for the packaged
    training maps. ``goals``: goal ids to draw from (default: the 12 training
    goals; None: all of them). ``observation``: ``"goal"`` or ``"all_goals"``. ``max_steps``: 100.

    ## Version History
    * v0: initial release (maps ``gridworld-v1``).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 8}

    def __init__(
        self,
        maps: str | os.PathLike | Sequence[GridMap] | GridTables | None = None,
        goals: Sequence[int] | None = SEEN_GOALS,
        observation: str = "goal",
        max_steps: int = 100,
        render_mode: str | None = None,
    ):
        if maps is None:
            from objsearch.gridworld.dataset import train_maps

            maps = list(train_maps().values())
        elif isinstance(maps, (str, os.PathLike)):
            maps = list(load_map_dir(maps).values())
        if observation not in OBSERVATIONS:
            raise ValueError(f"observation must be one of {OBSERVATIONS}, not {observation!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']}, not {render_mode!r}")
        self.render_mode = render_mode
        tables = maps if isinstance(maps, GridTables) else GridTables.build(list(maps))
        self._world = BatchedGridWorld(
            tables, 1, goals=goals, observation=observation, max_steps=max_steps, autoreset=False
        )
        self.observation_space = spaces.Dict(
            {
                "image": spaces.Box(0, 1, (self._world.num_channels, WINDOW, WINDOW), dtype=np.uint8),
                "goal": spaces.Discrete(tables.num_goals),
            }
        )
        self.action_space = spaces.Discrete(NUM_ACTIONS)
        self._done = True

    @property
    def tables(self) -> GridTables:
        """The maps' ``GridTables`` the env steps on."""
        return self._world.tables

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        """Start an episode: ``options["task"]`` (a ``GridTask``) or a random map, goal, start; returns (obs, info)."""
        super().reset(seed=seed)
        self._world.rng = self.np_random
        task = (options or {}).get("task")
        if task is None:
            obs = self._world.reset()
        else:
            obs = self._world.reset(maps=[self._map_index(task)], goals=[task.goal], starts=[self._cell(task.start)])
        self._done = False
        return self._obs(obs), self._info(success=False)

    def step(self, action):
        """Take one action; returns (obs, reward, terminated, truncated, info).

        Raises ValueError for an action outside the action space and RuntimeError after the episode ended.
        """
        if self._done:
            raise RuntimeError("step() called on a finished episode; call reset() first")
        action = check_action(self.action_space, action, ACTION_NAMES)
        obs, reward, terminated, truncated, _ = self._world.step(np.array([action]))
        self._done = bool(terminated[0] or truncated[0])
        return (
            self._obs(obs),
            float(reward[0]),
            bool(terminated[0]),
            bool(truncated[0]),
            self._info(bool(terminated[0])),
        )

    def render(self):
        """The map as an RGB image (16 px a cell) in ``rgb_array`` mode, else None.

        Free cells light grey, obstacles dark grey, goals blue, the episode's goal green, the agent red.
        """
        if self.render_mode != "rgb_array":
            return None
        t, w = self.tables, self._world
        m = int(w.map_idx[0])
        image = np.where(t.free[m].reshape(t.height, t.width)[..., None], 235, 60).astype(np.uint8).repeat(3, axis=2)
        goal_rows, goal_cols = np.divmod(t.goal_cells[m], t.width)
        image[goal_rows, goal_cols] = (120, 170, 240)
        gr, gc = divmod(int(t.goal_cells[m, w.goal[0]]), t.width)
        image[gr, gc] = (40, 180, 60)
        r, c = w.positions()[0]
        image[r, c] = (220, 40, 40)
        return np.kron(image, np.ones((16, 16, 1), dtype=np.uint8))

    def close(self):
        """End the current episode (the env holds no other resources)."""
        self._done = True

    # -- helpers ----------------------------------------------------------------------
    def _map_index(self, task: GridTask) -> int:
        try:
            return self.tables.map_index(task.map)
        except ValueError:
            raise ValueError(f"task map {task.map!r} is not among this env's maps") from None

    def _cell(self, start) -> int:
        return int(start[0]) * self.tables.width + int(start[1])

    @staticmethod
    def _obs(obs: dict[str, np.ndarray]) -> dict[str, Any]:
        return {"image": obs["image"][0], "goal": int(obs["goal"][0])}

    def _info(self, success: bool) -> dict[str, Any]:
        w = self._world
        r, c = w.positions()[0]
        return {
            "success": success,
            "steps": int(w.steps[0]),
            "min_steps": int(w.min_steps[0]),
            "map": self.tables.names[int(w.map_idx[0])],
            "position": (int(r), int(c)),
        }
