"""The grid world as one batched numpy simulator: N environments stepped in one call.

Everything per map is precomputed once into tables (next cell for every cell and action,
BFS distances from every goal, the whole 7x7 observation seen from every cell), so a step is
a handful of array gathers whatever N is. ``GridWorldEnv`` (the Gymnasium env) is this
simulator with N = 1; training code uses it directly with large N.

Dynamics (the paper's section 4.1, as the authors' code runs it): actions up, down, left, right; a move
into an obstacle or off the map leaves the agent in place; reward 1 and termination when
the agent stands on the episode's goal; truncation after ``max_steps`` steps. The window is
centred on the agent, not rotated, and cells outside the map read as obstacle.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from objsearch.gridworld.maps import MOVES, GridMap

WINDOW = 7
HALF = WINDOW // 2
NUM_ACTIONS = 4
ACTION_NAMES = ("up", "down", "left", "right")
OBSERVATIONS = ("goal", "all_goals")


@dataclass(frozen=True, eq=False)
class GridTables:
    """Per-map lookup tables for a list of equally sized maps (cells are flat: r * W + c).

    Attributes:
        names: map names, index = map index.
        height, width, num_goals: shared by all maps.
        free: bool (M, HW), True where the cell is free.
        next_cell: int32 (M, HW, 4), the cell each action leads to.
        goal_cells: int32 (M, G), the cell of every goal.
        goal_dist: int16 (M, G, HW), minimal steps from every cell to every goal (-1 = none).
        windows: uint8 (M, HW, 1 + G, 7, 7), the full observation seen from every cell:
            channel 0 obstacles, channel 1 + g goal g's cell (about 0.2 MB per map).
    """

    names: tuple[str, ...]
    height: int
    width: int
    num_goals: int
    free: np.ndarray
    next_cell: np.ndarray
    goal_cells: np.ndarray
    goal_dist: np.ndarray
    windows: np.ndarray

    @classmethod
    def build(cls, maps: Sequence[GridMap]) -> "GridTables":
        """The tables of ``maps`` (BFS distances, observation windows); ValueError if maps differ in shape or goals."""
        if not maps:
            raise ValueError("GridTables needs at least one map")
        height, width = maps[0].shape
        num_goals = maps[0].num_goals
        for m in maps:
            if m.shape != (height, width) or m.num_goals != num_goals:
                raise ValueError(
                    f"map {m.name} is {m.shape} with {m.num_goals} goals; all maps of one world must match "
                    f"{(height, width)} with {num_goals} goals"
                )
        obstacles = np.stack([m.obstacles for m in maps]).astype(bool)  # (M, H, W)
        num_maps, cells = len(maps), height * width
        rows, cols = np.divmod(np.arange(cells), width)

        next_cell = np.empty((num_maps, cells, NUM_ACTIONS), dtype=np.int32)
        for a, (dr, dc) in enumerate(MOVES):
            nr, nc = rows + dr, cols + dc
            inside = (nr >= 0) & (nr < height) & (nc >= 0) & (nc < width)
            target = np.where(inside, nr * width + nc, 0)
            blocked = ~inside[None, :] | obstacles.reshape(num_maps, cells)[:, target]
            next_cell[:, :, a] = np.where(blocked, np.arange(cells)[None, :], target[None, :])

        goal_cells = np.stack([m.goals[:, 0] * width + m.goals[:, 1] for m in maps]).astype(np.int32)
        free = ~obstacles.reshape(num_maps, cells)

        # BFS from every goal of every map at once, one frontier expansion per distance.
        free_2d = ~obstacles[:, None]  # (M, 1, H, W)
        frontier = np.zeros((num_maps, num_goals, height, width), dtype=bool)
        goal_rows, goal_cols = np.divmod(goal_cells, width)
        frontier[np.arange(num_maps)[:, None], np.arange(num_goals)[None, :], goal_rows, goal_cols] = True
        visited = frontier.copy()
        goal_dist = np.where(frontier, 0, -1).astype(np.int16)
        distance = 0
        while frontier.any():
            distance += 1
            reached = np.zeros_like(frontier)
            reached[:, :, 1:, :] |= frontier[:, :, :-1, :]
            reached[:, :, :-1, :] |= frontier[:, :, 1:, :]
            reached[:, :, :, 1:] |= frontier[:, :, :, :-1]
            reached[:, :, :, :-1] |= frontier[:, :, :, 1:]
            frontier = reached & free_2d & ~visited
            visited |= frontier
            goal_dist[frontier] = distance
        goal_dist = goal_dist.reshape(num_maps, num_goals, cells)

        layers = np.zeros((num_maps, 1 + num_goals, height, width), dtype=np.uint8)
        layers[np.arange(num_maps)[:, None], 1 + np.arange(num_goals)[None, :], goal_rows, goal_cols] = 1
        padded = np.pad(layers, ((0, 0), (0, 0), (HALF, HALF), (HALF, HALF)))
        # channel 0 is obstacles, and cells off the map read as obstacle
        padded[:, 0] = np.pad(obstacles, ((0, 0), (HALF, HALF), (HALF, HALF)), constant_values=True)
        views = np.lib.stride_tricks.sliding_window_view(padded, (WINDOW, WINDOW), axis=(2, 3))  # (M, C, H, W, 7, 7)
        windows = np.ascontiguousarray(views.transpose(0, 2, 3, 1, 4, 5)).reshape(
            num_maps, cells, 1 + num_goals, WINDOW, WINDOW
        )

        return cls(
            names=tuple(m.name for m in maps),
            height=height,
            width=width,
            num_goals=num_goals,
            free=free,
            next_cell=next_cell,
            goal_cells=goal_cells,
            goal_dist=goal_dist,
            windows=windows,
        )

    def map_index(self, name: str) -> int:
        """Index of the map named ``name`` (ValueError if absent)."""
        return self.names.index(name)

    def goal_distances(self, name: str, goal: int) -> np.ndarray:
        """(H, W) minimal steps from every cell of map ``name`` to its goal ``goal`` (-1 = none):
        ``maps.bfs_distances`` of that goal, read from ``goal_dist``."""
        return self.goal_dist[self.map_index(name), goal].reshape(self.height, self.width)


class BatchedGridWorld:
    """``num_envs`` grid-world episodes stepped together.

    Args:
        maps: the maps episodes are drawn from (or a prebuilt ``GridTables``).
        num_envs: batch size N.
        goals: goal ids episodes are drawn from when ``reset`` gets no explicit tasks.
        observation: ``"goal"`` gives 2 channels (obstacles, the episode goal's cell);
            ``"all_goals"`` gives 1 + G channels (obstacles, then one channel per goal id).
        max_steps: episodes are truncated after this many steps.
        autoreset: if True, an episode that ends in ``step`` is replaced at once by a freshly
            sampled one, and the returned observation is the new episode's first.
        rng: the Generator for sampling maps, goals and starts.

    Observations are dicts of arrays: ``image`` uint8 (N, C, 7, 7) and ``goal`` int64 (N,).
    """

    def __init__(
        self,
        maps: Sequence[GridMap] | GridTables,
        num_envs: int,
        goals: Sequence[int] | None = None,
        observation: str = "goal",
        max_steps: int = 100,
        autoreset: bool = True,
        rng: np.random.Generator | None = None,
    ):
        if observation not in OBSERVATIONS:
            raise ValueError(f"observation must be one of {OBSERVATIONS}, not {observation!r}")
        self.tables = maps if isinstance(maps, GridTables) else GridTables.build(maps)
        self.num_envs = int(num_envs)
        self.goals = np.asarray(goals if goals is not None else range(self.tables.num_goals), dtype=np.int64)
        self.observation = observation
        self.max_steps = int(max_steps)
        self.autoreset = autoreset
        self.rng = rng if rng is not None else np.random.default_rng()
        self.num_channels = 2 if observation == "goal" else 1 + self.tables.num_goals
        n = self.num_envs
        self.map_idx = np.zeros(n, dtype=np.int64)
        self.goal = np.zeros(n, dtype=np.int64)
        self.cell = np.zeros(n, dtype=np.int64)
        self.steps = np.zeros(n, dtype=np.int64)
        self.min_steps = np.zeros(n, dtype=np.int64)
        self._arange = np.arange(n)

    # -- episodes ---------------------------------------------------------------------
    def sample_tasks(self, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Draw (map index, goal, start cell) for ``count`` episodes: map and goal uniform,
        start uniform among the cells from which the goal is reachable (start != goal)."""
        t = self.tables
        maps = self.rng.integers(len(t.names), size=count)
        goals = self.goals[self.rng.integers(len(self.goals), size=count)]
        starts = np.empty(count, dtype=np.int64)
        pending = np.arange(count)
        while len(pending):  # rejection sampling; about half the cells qualify
            cand = self.rng.integers(t.height * t.width, size=len(pending))
            ok = t.goal_dist[maps[pending], goals[pending], cand] > 0
            starts[pending[ok]] = cand[ok]
            pending = pending[~ok]
        return maps, goals, starts

    def reset(self, env_ids=None, maps=None, goals=None, starts=None) -> dict[str, np.ndarray]:
        """Start new episodes in ``env_ids`` (default: all) and return the observations of
        all envs. With ``maps``/``goals``/``starts`` (map indices, goal ids, flat start
        cells) the episodes are those; otherwise they are sampled."""
        env_ids = self._arange if env_ids is None else np.asarray(env_ids, dtype=np.int64)
        if maps is None:
            maps, goals, starts = self.sample_tasks(len(env_ids))
        self._start(env_ids, maps, goals, starts)
        return self.observe()

    def start(self, env_ids, maps, goals, starts) -> dict[str, np.ndarray]:
        """Start the given episodes (map indices, goal ids, flat start cells) in ``env_ids``
        and return the observations of those envs only (rows in ``env_ids``' order); the
        other envs are left as they are."""
        env_ids = np.asarray(env_ids, dtype=np.int64)
        self._start(env_ids, maps, goals, starts)
        return self.observe(env_ids)

    def _start(self, env_ids: np.ndarray, maps, goals, starts) -> None:
        self.map_idx[env_ids] = maps
        self.goal[env_ids] = goals
        self.cell[env_ids] = starts
        self.steps[env_ids] = 0
        self.min_steps[env_ids] = self.tables.goal_dist[self.map_idx[env_ids], self.goal[env_ids], self.cell[env_ids]]

    def step(self, actions) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray, dict[str, np.ndarray]]:
        """Move every env by one action.

        Returns ``(obs, reward, terminated, truncated, info)`` with arrays of length N;
        ``info`` holds ``success``, ``steps`` and ``min_steps`` of the episodes as they were
        at this step (before any autoreset).
        """
        actions = np.asarray(actions, dtype=np.int64)
        t = self.tables
        self.cell = t.next_cell[self.map_idx, self.cell, actions].astype(np.int64)
        self.steps += 1
        success = self.cell == t.goal_cells[self.map_idx, self.goal]
        truncated = ~success & (self.steps >= self.max_steps)
        info = {"success": success, "steps": self.steps.copy(), "min_steps": self.min_steps.copy()}
        done = success | truncated
        if self.autoreset and done.any():
            self.reset(np.flatnonzero(done))
        return self.observe(), success.astype(np.float32), success, truncated, info

    def step_envs(
        self, env_ids, actions
    ) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray, dict[str, np.ndarray]]:
        """Move only the envs ``env_ids`` (distinct), each by its action in ``actions``; the
        others stay as they are (their step counts too). Returns what ``step`` does, with
        arrays of length ``len(env_ids)`` in ``env_ids``' order. No autoreset: the episodes
        that ended wait for ``start`` or ``reset``."""
        ids = np.asarray(env_ids, dtype=np.int64)
        actions = np.asarray(actions, dtype=np.int64)
        t = self.tables
        maps = self.map_idx[ids]
        cell = t.next_cell[maps, self.cell[ids], actions].astype(np.int64)
        steps = self.steps[ids] + 1
        self.cell[ids] = cell
        self.steps[ids] = steps
        success = cell == t.goal_cells[maps, self.goal[ids]]
        truncated = ~success & (steps >= self.max_steps)
        info = {"success": success, "steps": steps, "min_steps": self.min_steps[ids]}
        return self.observe(ids), success.astype(np.float32), success, truncated, info

    # -- observations -----------------------------------------------------------------
    def observe(self, env_ids=None) -> dict[str, np.ndarray]:
        """The observations of all envs, or of ``env_ids`` (rows in their order)."""
        if env_ids is None:
            map_idx, cell, goal = self.map_idx, self.cell, self.goal
        else:
            ids = np.asarray(env_ids, dtype=np.int64)
            map_idx, cell, goal = self.map_idx[ids], self.cell[ids], self.goal[ids]
        windows = self.tables.windows
        if self.observation == "goal":
            channels = np.stack([np.zeros_like(goal), 1 + goal], axis=1)  # (N, 2)
            image = windows[map_idx[:, None], cell[:, None], channels]
        else:
            image = windows[map_idx, cell]
        return {"image": image, "goal": goal.copy()}

    def positions(self) -> np.ndarray:
        """(N, 2) row, col of every agent."""
        return np.stack(np.divmod(self.cell, self.tables.width), axis=1)
