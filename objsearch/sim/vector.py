"""``HouseVectorEnv``: N cached house episodes stepped together with array operations.

The fast path for training on pre-rendered observations: transitions, success and
observations of all N episodes are array gathers (per house), not N Python calls. Tasks
are sampled as ``HouseEnv`` samples them (same houses, targets, goal rule and start
range). Episodes that end are reset in the same ``step`` call (Gymnasium's same-step
autoreset): the returned observation is the new episode's first, and ``info`` holds the
ended episode's ``success``, ``steps`` and ``min_steps`` (arrays over the N envs, valid
where ``terminated | truncated``). Each episode ends at its own step limit
(``HouseEnv.step_limit``: ``max_steps``, lower in single rooms under ``room_max_steps``).
"""

from __future__ import annotations

import gymnasium
import numpy as np
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.env import MOVES, HouseEnv, relative_pose


class HouseVectorEnv(gymnasium.vector.VectorEnv):
    """``num_envs`` cached ``ObjSearch/House-v1`` episodes; keyword arguments as ``HouseEnv``
    (``mode`` is always ``cached``, so ``observation="predicted"`` reads the predicted
    cache; the STOP variant is not supported here)."""

    metadata = {"autoreset_mode": AutoresetMode.SAME_STEP}

    def __init__(self, num_envs: int, **env_kwargs):
        if env_kwargs.pop("mode", "cached") != "cached" or env_kwargs.get("stop_action"):
            raise ValueError(
                "HouseVectorEnv steps cached observations without STOP; use HouseEnv for live rendering or STOP"
            )
        self.env = HouseEnv(mode="cached", **env_kwargs)
        self.num_envs = int(num_envs)
        self.single_observation_space = self.env.observation_space
        self.single_action_space = self.env.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.max_steps = self.env.max_steps
        n = self.num_envs
        self.house = np.zeros(n, dtype=np.int64)  # index into self._houses
        self.pose = np.zeros(n, dtype=np.int64)
        self.start_pose = np.zeros(n, dtype=np.int64)
        self.collided = np.zeros(n, dtype=np.int64)
        self.steps = np.zeros(n, dtype=np.int64)
        self.min_steps = np.zeros(n, dtype=np.int64)
        self.limit = np.zeros(n, dtype=np.int64)  # each episode's step limit
        self.target = np.zeros(n, dtype=np.int64)
        self._goal_rows = np.zeros(n, dtype=np.int64)  # row of self._at_goal for each env
        self._houses: list[str] = []
        self._caches: list = []  # per house: rgb source
        self._labels: list = []  # per house: semantic and depth source (ground truth or predicted)
        self._next: list[np.ndarray] = []
        self._graphs: list = []
        self._limits: list[int] = []  # per house: its episodes' step limit
        self._at_goal: list[np.ndarray] = []  # per (house, target): bool over that house's poses
        self._goal_keys: dict[tuple[str, str], int] = {}
        self._rng = np.random.default_rng()

    def _house_index(self, house_id: str) -> int:
        if house_id not in self._houses:
            world = self.env.world(house_id)
            self._houses.append(house_id)
            self._caches.append(self.env._source(world))
            self._labels.append(self.env._labels(world))
            self._next.append(world.graph.next_pose)
            self._graphs.append(world.graph)
            self._limits.append(self.env.step_limit(world))
        return self._houses.index(house_id)

    def _start(self, i: int) -> None:
        task = self.env.sample_task(self._rng)
        h = self._house_index(task.house)
        graph = self.env.world(task.house).graph
        key = (task.house, task.target)
        if key not in self._goal_keys:
            mask = np.zeros(graph.num_poses, dtype=bool)
            mask[[graph.pose_id(*g) for g in task.goals]] = True
            self._goal_keys[key] = len(self._at_goal)
            self._at_goal.append(mask)
        self.house[i], self.pose[i] = h, graph.pose_id(*task.start)
        self.start_pose[i], self.collided[i] = self.pose[i], 0
        self.steps[i], self.min_steps[i], self.limit[i] = 0, task.min_steps, self._limits[h]
        self.target[i], self._goal_rows[i] = CATEGORY_IDS[task.target], self._goal_keys[key]

    def _observe(self) -> dict[str, np.ndarray]:
        obs = {
            "rgb": np.empty((self.num_envs, *self.single_observation_space["rgb"].shape), np.uint8),
            "depth": np.empty((self.num_envs, *self.single_observation_space["depth"].shape), np.float32),
            "semantic": np.empty((self.num_envs, *self.single_observation_space["semantic"].shape), np.uint8),
            "target": self.target.copy(),
            "pose": np.empty((self.num_envs, 3), np.float32),
            "collided": self.collided.copy(),
        }
        for h in np.unique(self.house):
            envs = np.flatnonzero(self.house == h)
            poses, labels = self.pose[envs], self._labels[h]
            obs["pose"][envs] = relative_pose(self._graphs[h], self.start_pose[envs], poses)
            obs["rgb"][envs], obs["depth"][envs], obs["semantic"][envs] = (
                self._caches[h].rgb[poses],
                labels.depth[poses],
                labels.semantic[poses],
            )
        return obs

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start a sampled task in every env (``seed`` reseeds the task rng); returns (obs, {})."""
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        for i in range(self.num_envs):
            self._start(i)
        return self._observe(), {}

    def step(self, actions):
        """Step every env; returns (obs, reward, terminated, truncated, info) arrays of shape (num_envs,).

        An env ends on reaching a goal pose (success, reward 1.0) or at its step limit, and restarts at once with a new
        task; ``info`` holds ``success``, ``steps`` and ``min_steps`` of the step taken.
        """
        actions = np.asarray(actions, dtype=np.int64)
        success = np.zeros(self.num_envs, dtype=bool)
        for h in np.unique(self.house):
            envs = np.flatnonzero(self.house == h)
            before = self.pose[envs]
            self.pose[envs] = self._next[h][before, actions[envs]]
            self.collided[envs] = (self.pose[envs] == before) & np.isin(actions[envs], MOVES)
        for row in np.unique(self._goal_rows):
            envs = np.flatnonzero(self._goal_rows == row)
            success[envs] = self._at_goal[row][self.pose[envs]]
        self.steps += 1
        truncated = ~success & (self.steps >= self.limit)
        info = {"success": success, "steps": self.steps.copy(), "min_steps": self.min_steps.copy()}
        for i in np.flatnonzero(success | truncated):
            self._start(int(i))
        return self._observe(), success.astype(np.float32), success, truncated, info

    def close_extras(self, **kwargs):
        """Close the wrapped ``HouseEnv``."""
        self.env.close()
