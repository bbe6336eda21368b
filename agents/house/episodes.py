"""Training episodes in the houses: N episodes stepped together on observation tables.

The fast path of house training (the equivalent of ``objsearch.sim.vector.HouseVectorEnv``
without 64x64 frames): poses are global ids of an ``ObservationTables``, a step is
``next_pose[pose, action]``, success is "the pose is a goal pose of the target" (the env's
goal rule on the goal camera's frames, the same poses the suites store) and the history of
the last 4 poses is what the networks see.

Tasks are drawn as the authors' trainers draw them: a house uniformly, then a target
uniformly among that house's trainable targets, then a start from a pool sorted by minimal
steps to the nearest goal pose, of which episode i may use the nearest
``max(1, floor(N * min((i + 10) / curriculum, 1)))`` (the curriculum). Pools:

* ``search`` (main phase): poses ``min_start_steps`` to ``max_start_steps`` (6-40 by default)
  minimal steps from the goal poses, the evaluation episodes' range;
* ``approach`` (pretraining the low level): poses that see the category
  (``VISIBLE_PIXELS``) and are not goal poses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from objsearch.house.categories import CATEGORY_IDS, FIRST_OBJECT_ID
from objsearch.sim.cache import HouseCache, PredictedCache
from objsearch.sim.camera import AGENT_CAMERA, check_predictor_camera
from objsearch.sim.goals import DEFAULT_RULE, GOAL_CAMERA, goal_poses
from objsearch.sim.house_task import START_STEPS
from objsearch.sim.world import HouseRef, World
from objsearch_agents.house.tables import HISTORY, VISIBLE_PIXELS, ObservationTables, house_tables

POOLS = ("search", "approach")


@dataclass(frozen=True, eq=False)
class Pair:
    """One (house, category) task family: its goal poses and start pools (global pose ids)."""

    house: int
    category: int
    goals: np.ndarray
    pools: dict


class TrainingHouses:
    """The houses of a training run, their tables and their (house, category) tasks.

    Args:
        refs: the houses.
        targets: category names the ``search`` pool trains on (all object categories with
            goal poses are kept for ``approach``).
        cache_dir: observation caches (built if missing).
        predictor: if given, the agent observes its predictions (``PredictedCache``);
            goals are always judged on the ground truth.
        max_start_steps: the ``search`` pool's farthest start, in minimal steps to the goals.
        min_start_steps: its nearest.
        room_max_steps: step limits of single rooms by room type (a suite's
            ``room_max_steps``, as ``HouseEnv`` takes them); an episode in such a room ends at
            its type's limit if that is below the batch's ``max_steps``.

    The agent's tables come from ``AGENT_CAMERA`` frames (a predictor must be trained on
    them), goal poses from ``GOAL_CAMERA`` frames (the rule the suites use).
    """

    def __init__(
        self,
        refs: list[HouseRef],
        targets: list[str],
        cache_dir=None,
        predictor=None,
        progress: bool = True,
        max_start_steps: int = START_STEPS[1],
        min_start_steps: int = START_STEPS[0],
        room_max_steps: dict[str, int] | None = None,
    ):
        self.worlds = [World.load(ref) for ref in refs]
        no_limit = np.iinfo(np.int64).max
        limits = room_max_steps or {}
        self.step_limits = np.array([limits.get(w.spec.single_room, no_limit) for w in self.worlds], np.int64)
        self.house_ids = [w.house_id for w in self.worlds]
        self.perception_key = None if predictor is None else predictor.key  # what the agent learns to see
        per_house, self.pairs = [], []
        offset = 0
        target_ids = {CATEGORY_IDS[t] for t in targets}
        if predictor is not None:
            check_predictor_camera(predictor, AGENT_CAMERA)
        for h, world in enumerate(self.worlds):
            gt = HouseCache.open(world, AGENT_CAMERA, cache_dir, progress)
            goal = gt if GOAL_CAMERA == AGENT_CAMERA else HouseCache.open(world, GOAL_CAMERA, cache_dir, progress)
            gt_tables = house_tables(gt, world.graph.next_pose)
            if predictor is None:
                tables = gt_tables
            else:
                tables = house_tables(
                    PredictedCache.open(world, AGENT_CAMERA, predictor, cache_dir, progress), world.graph.next_pose
                )
            per_house.append(tables)
            seen = gt_tables.pixels >= VISIBLE_PIXELS  # approach starts: the category is really in view
            for cid in sorted({CATEGORY_IDS[o.category] for o in world.spec.objects}):
                goals = goal_poses(goal.semantic, goal.depth, cid, DEFAULT_RULE)
                if not len(goals):
                    continue
                dist = world.graph.shortest_steps(goals).astype(np.int64)
                pools = {}
                if cid in target_ids:
                    ok = (dist >= min_start_steps) & (dist <= max_start_steps)
                    pools["search"] = _by_distance(ok, dist) + offset
                ok = seen[:, cid] & (dist > 0) & (dist < np.iinfo(np.int32).max)
                pools["approach"] = _by_distance(ok, dist) + offset
                self.pairs.append(Pair(h, cid, goals.astype(np.int64) + offset, pools))
            offset += tables.num_poses
        self.tables = ObservationTables.concat(per_house)
        self.pair_house = np.array([pair.house for pair in self.pairs], np.int64)
        keys = [p_ix * self.tables.num_poses + pair.goals for p_ix, pair in enumerate(self.pairs)]
        self._goal_keys = np.sort(np.concatenate(keys)) if keys else np.zeros(0, np.int64)
        self.by_pool = {
            pool: np.array([i for i, p in enumerate(self.pairs) if len(p.pools.get(pool, ()))], np.int64)
            for pool in POOLS
        }
        if not len(self.by_pool["search"]):
            raise ValueError(f"none of the targets {sorted(targets)} has goal poses and starts in these houses")

    def at_goal(self, pairs: np.ndarray, poses: np.ndarray) -> np.ndarray:
        """bool (N,): ``poses[i]`` is a goal pose of task family ``pairs[i]``."""
        keys = pairs * self.tables.num_poses + poses
        ix = np.minimum(np.searchsorted(self._goal_keys, keys), len(self._goal_keys) - 1)
        return self._goal_keys[ix] == keys

    def sample(self, pool: str, episode_ix: np.ndarray, curriculum: int, rng: np.random.Generator):
        """(pairs, starts) for episodes numbered ``episode_ix``: a house uniformly, a target
        of it uniformly, a start by the curriculum."""
        k = len(episode_ix)
        candidates = self.by_pool[pool]
        houses = np.array(sorted({self.pairs[i].house for i in candidates}))
        house = houses[rng.integers(len(houses), size=k)]
        pairs = np.empty(k, np.int64)
        starts = np.empty(k, np.int64)
        frac = np.minimum((np.asarray(episode_ix) + 10) / curriculum, 1.0)
        u = rng.random(k)
        for i in range(k):
            mine = candidates[[self.pairs[c].house == house[i] for c in candidates]]
            pairs[i] = mine[rng.integers(len(mine))]
            pool_poses = self.pairs[pairs[i]].pools[pool]
            n = max(1, int(np.floor(len(pool_poses) * frac[i])))
            starts[i] = pool_poses[int(u[i] * n)]
        return pairs, starts

    def categories(self, pairs: np.ndarray) -> np.ndarray:
        return np.array([self.pairs[p].category for p in pairs], np.int64)


def _by_distance(ok: np.ndarray, dist: np.ndarray) -> np.ndarray:
    """Pose ids where ``ok``, nearest first (ties by pose id)."""
    ids = np.flatnonzero(ok)
    return ids[np.argsort(dist[ids], kind="stable")].astype(np.int64)


class EpisodeBatch:
    """N episodes on a ``TrainingHouses``: poses, 4-pose histories, steps and success."""

    def __init__(self, houses: TrainingHouses, num_envs: int, max_steps: int):
        self.houses, self.max_steps = houses, int(max_steps)
        self.limit = np.minimum(houses.step_limits, self.max_steps)  # per house
        n = int(num_envs)
        self.pose = np.zeros(n, np.int64)
        self.hist = np.zeros((n, HISTORY), np.int64)  # oldest first
        self.steps = np.zeros(n, np.int64)
        self.pair = np.zeros(n, np.int64)
        self.target = np.zeros(n, np.int64)  # category id

    def start(self, env_ids: np.ndarray, pairs: np.ndarray, starts: np.ndarray) -> None:
        self.pair[env_ids], self.pose[env_ids] = pairs, starts
        self.hist[env_ids] = starts[:, None]
        self.steps[env_ids] = 0
        self.target[env_ids] = self.houses.categories(pairs)

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Move every env; returns (success, truncated). Ended episodes keep their last pose
        until ``start`` is called for them."""
        self.pose = self.houses.tables.next_pose[self.pose, actions].astype(np.int64)
        self.hist = np.concatenate([self.hist[:, 1:], self.pose[:, None]], axis=1)
        self.steps += 1
        success = self.houses.at_goal(self.pair, self.pose)
        return success, ~success & (self.steps >= self.limit[self.houses.pair_house[self.pair]])

    def state_dict(self) -> dict:
        return {k: getattr(self, k).copy() for k in ("pose", "hist", "steps", "pair", "target")}

    def load_state_dict(self, state: dict) -> None:
        for k, v in state.items():
            setattr(self, k, np.array(v))


def object_node(category_ids: np.ndarray) -> np.ndarray:
    """GRG / sub-goal node of an object category id (ids below ``FIRST_OBJECT_ID`` have none)."""
    return np.asarray(category_ids) - FIRST_OBJECT_ID
