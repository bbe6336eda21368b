"""``ObjSearch/House-v1``: find an object category in a generated MuJoCo house (``House-v0``:
``objsearch.sim.env_v0``)."""

from __future__ import annotations

import os
from typing import Any, Sequence

import gymnasium
import numpy as np
from gymnasium import spaces

from objsearch.envs import check_action
from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.cache import HouseCache, PredictedCache, Predictor, quantize_depth
from objsearch.sim.camera import AGENT_CAMERA, RenderSettings, check_predictor_camera
from objsearch.sim.goals import DEFAULT_RULE, GOAL_CAMERA, GoalRule, goal_poses_of
from objsearch.sim.house_task import (  # noqa: F401  (ENTRANCE_STEPS, START_STEPS: imported from here too)
    ENTRANCE_STEPS,
    START_STEPS,
    STARTS,
    HouseTask,
    check_max_steps,
    check_room_max_steps,
    draw_start,
    entrance_poses,
)
from objsearch.sim.navgraph import ACTIONS, GRID, NUM_MOVE_ACTIONS, STOP
from objsearch.sim.pose_sensor import COS_SIN, TURN_HEADINGS, relative_pose, relative_pose_of  # noqa: F401  (imported from here too)
from objsearch.sim.world import HouseRef, World

MODES = ("cached", "live")
OBSERVATIONS = ("gt", "predicted")
NUM_CATEGORY_IDS = max(CATEGORY_IDS.values()) + 1


MOVES = (0, 3, 4, 5)  # the actions that translate (ahead, back, left, right); a blocked one sets ``collided``


class HouseEnv(gymnasium.Env):
    """Goal-driven object search in a procedurally generated MuJoCo house.

    ## Description
    The agent stands at a pose of the house's pose graph (0.25 m cells, 4 headings;
    ``objsearch.sim.navgraph``) and must reach a goal pose of its target category: a pose
    whose view is filled by the target (``objsearch.sim.goals``). It sees an egocentric
    camera at 1 m height.

    ## Observation Space
    ``Dict(rgb=Box(uint8, (H, W, 3)), depth=Box(float32, (H, W)) metres to the mm (zfar where
    nothing is hit),
    semantic=Box(uint8, (H, W)) category ids, target=Discrete(C), pose=Box(float32, (3,)),
    collided=Discrete(2))`` with H, W from ``settings`` (64 x 64 by default). ``depth`` is
    planar: the distance along the camera's optical axis, not along the pixel's ray.
    ``semantic`` holds the ids of ``objsearch.house.categories.CATEGORY_IDS``, the structure
    classes included (wall 1, floor 2, door 3, ceiling 4: every room has a ceiling), and
    ``target`` is the target category's id in that same table. ``pose`` is the agent's
    position and heading relative to the episode's start, as Habitat's GPS+compass gives
    it: x metres forward and y metres to the left of the start pose, and the heading in
    radians counter-clockwise from the start heading, in (-pi, pi]. ``collided`` is 1 when
    the last action was a move that was blocked (the agent stayed where it was), else 0.
    The camera's parameters (image size, horizontal and vertical field of view, focal
    lengths, height, clipping range) are the reset ``info["camera"]``
    (``RenderSettings.intrinsics``); the harness gives them to agents as ``task.camera``.
    The reset ``info`` also says how to succeed: ``stop_action`` (6, the action the agent
    must call at a goal pose, with ``stop_action=True``; else None) and ``goal_rule``
    (``GoalRule.to_json``: the rule that made the goal poses); the harness gives them to
    agents as ``task.stop_action`` and ``task.goal_rule``.

    ## Action Space
    ``Discrete(6)``: move ahead, rotate left, rotate right, move back, move left, move right
    (0.25 m, 90 degrees); ``Discrete(7)`` with ``stop_action=True`` (6 = STOP).

    ## Rewards
    1 when the episode succeeds, else 0.

    ## Starting State
    The task passed as ``reset(options={"task": HouseTask})``, or a sampled one: a house,
    a target category present in it, and a start 6-40 steps from its nearest goal pose
    (``starts="anywhere"``), or one near the house's entrance (``starts="entrance"``,
    ``draw_start``; ``house-gen-2`` houses only).

    ## Episode End
    Terminated on success: on reaching a goal pose, or with ``stop_action`` on STOP (success
    iff at a goal pose; ``min_steps`` then counts the STOP). Truncated after the episode's
    step limit (``step_limit``): ``max_steps`` (1000, the paper's), or, in a single room
    (``HouseSpec.single_room``) of a type ``room_max_steps`` lists, that type's limit where it is
    lower (the ``rooms`` suite: 100 steps, 200 in living rooms).

    ## Arguments
    ``houses``: HouseRefs, or loaded ``World``s (envs that play side by side share them)
    (default: the house of generator seed 0). ``mode``: ``cached``
    (every pose pre-rendered, read from the cache files; ``objsearch.sim.cache``) or ``live`` (render
    each step); both give identical observations. ``settings``: the agent's camera
    (default ``objsearch.sim.camera.AGENT_CAMERA``; goal poses always come from
    ``objsearch.sim.goals.GOAL_CAMERA``). ``cache_dir``.
    ``goal_rule``. ``room_max_steps``: step limits of single rooms by room type (``ROOM_TYPES``),
    under the cap ``max_steps``. ``targets``: categories sampled episodes may ask for. ``starts``: where
    sampled episodes start, ``anywhere`` (default) or ``entrance`` (within ``ENTRANCE_STEPS``
    steps of the entrance; a house without one is a ``UserError`` on reset).
    ``observation``: ``gt`` (rendered ground truth) or ``predicted``: ``semantic`` and
    ``depth`` come from ``predictor`` (e.g. ``objsearch.perception.inference.Predictor``)
    applied to the RGB (trained on frames of ``settings``, else ``CameraMismatchError``),
    pre-computed for every pose in cached mode
    (``objsearch.sim.cache.PredictedCache``); ``rgb`` and success stay ground truth.

    ## Version History
    * v1: the ``pose`` and ``collided`` observation keys. They were first added to v0 in
      place; ``ObjSearch/House-v0`` (``objsearch.sim.env_v0.HouseEnvV0``) gives v0's four keys
      again. Everything else is as v0 is now (below).
    * v0: initial release (pose graph navgraph-v1, goal rule goals-v1): observation keys
      ``rgb``, ``depth``, ``semantic``, ``target``. Added later, with defaults that keep the
      tasks, observations and records as they were: ``observation="predicted"``,
      ``starts="entrance"``, ``room_max_steps``, the reset ``info["camera"]``,
      ``info["stop_action"]`` and ``info["goal_rule"]``; with ``stop_action``, ``min_steps``
      counts the STOP (before, only the moves; no suite used it then).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 4}

    def __init__(
        self,
        houses: Sequence[HouseRef | World] | None = None,
        mode: str = "cached",
        settings: RenderSettings = AGENT_CAMERA,
        max_steps: int = 1000,
        stop_action: bool = False,
        cache_dir: str | None = None,
        goal_rule: GoalRule = DEFAULT_RULE,
        targets: Sequence[str] | None = None,
        render_mode: str | None = None,
        observation: str = "gt",
        predictor: Predictor | None = None,
        starts: str = "anywhere",
        room_max_steps: dict[str, int] | None = None,
    ):
        if mode not in MODES:
            raise ValueError(f"mode must be one of {MODES}, not {mode!r}")
        if observation not in OBSERVATIONS:
            raise ValueError(f"observation must be one of {OBSERVATIONS}, not {observation!r}")
        if starts not in STARTS:
            raise ValueError(f"starts must be one of {STARTS}, not {starts!r}")
        self.starts = starts
        if observation == "predicted" and predictor is None:
            raise ValueError(
                "observation='predicted' needs a predictor (objsearch.perception.inference.Predictor.from_checkpoint)"
            )
        if observation == "predicted":
            check_predictor_camera(predictor, settings, "this HouseEnv's camera (settings)")
        self.observation, self.predictor = observation, predictor
        self.refs = list(houses) if houses else [HouseRef(seed=0)]
        self.mode, self.settings, self.max_steps = mode, settings, check_max_steps(max_steps)
        self.room_max_steps = check_room_max_steps(room_max_steps)
        if cache_dir is not None and not isinstance(cache_dir, (str, os.PathLike)):
            raise ValueError(f"cache_dir={cache_dir!r} is not a folder; pass a path (str or pathlib.Path) or None")
        self.stop_action, self.cache_dir, self.goal_rule = bool(stop_action), cache_dir, goal_rule
        self.targets = tuple(targets) if targets else None
        self.render_mode = render_mode
        h, w = settings.height, settings.width
        reach = self.max_steps * GRID
        self.observation_space = spaces.Dict(
            {
                "rgb": spaces.Box(0, 255, (h, w, 3), dtype=np.uint8),
                "depth": spaces.Box(0.0, settings.zfar, (h, w), dtype=np.float32),
                "semantic": spaces.Box(0, 255, (h, w), dtype=np.uint8),
                "target": spaces.Discrete(NUM_CATEGORY_IDS),
                # an episode cannot take the agent farther than max_steps cells from its start
                "pose": spaces.Box(
                    np.array([-reach, -reach, -np.pi], np.float32),
                    np.array([reach, reach, np.pi], np.float32),
                    dtype=np.float32,
                ),
                "collided": spaces.Discrete(2),
            }
        )
        self.action_space = spaces.Discrete(NUM_MOVE_ACTIONS + (1 if stop_action else 0))
        self._num_actions = int(self.action_space.n)  # step's fast check of a Python int
        self._loaded: dict[int, World] = {}  # index in refs -> house
        self._worlds: dict[str, World] = {}  # house id -> house
        self._sources: dict[str, Any] = {}  # live mode: house id -> HouseRenderer
        # cached mode: only the current house's caches are held (the previous house's are released
        # when another starts; envs of one process share a house's files: cache.open_layers)
        self._source_now = None  # the current house's frames: HouseCache (cached) or HouseRenderer (live)
        self._labels_now = None  # cached mode: the current house's semantic and depth (see _labels)
        self._goals: dict[tuple, np.ndarray] = {}  # (house, target) -> goal pose ids
        self._steps_to: dict[tuple, np.ndarray] = {}  # (house, goal ids) -> steps from every pose
        self._steps_lists: dict[tuple, list] = {}  # the same as Python lists (step's info)
        self._read = None  # cached mode: pose -> the current house's (rgb, depth, semantic) frames
        self._near: dict[str, np.ndarray] = {}  # house id -> entrance_poses (starts="entrance")
        self._world: World | None = None
        self._done = True

    # -- houses -----------------------------------------------------------------------
    def _load(self, index: int) -> World:
        if index not in self._loaded:
            ref = self.refs[index]
            world = ref if isinstance(ref, World) else World.load(ref)
            self._loaded[index] = self._worlds[world.house_id] = world
        return self._loaded[index]

    def world(self, house_id: str) -> World:
        """The loaded house ``house_id`` (houses load on first use)."""
        for index in range(len(self.refs)):
            if house_id in self._worlds:
                break
            self._load(index)
        if house_id not in self._worlds:
            raise ValueError(f"house {house_id!r} is not among this env's houses")
        return self._worlds[house_id]

    def _source(self, world: World):
        """The house's frames: its ``HouseCache`` (cached mode; not kept here) or its renderer (live)."""
        if self.mode == "cached":
            return HouseCache.open(world, self.settings, self.cache_dir)
        if world.house_id not in self._sources:
            from objsearch.sim.renderer import HouseRenderer

            self._sources[world.house_id] = HouseRenderer(world.model, self.settings)
        return self._sources[world.house_id]

    def _labels(self, world: World):
        """Where cached ``semantic`` and ``depth`` come from: the house's cache, or (predicted
        mode) the network's predictions of its RGB (not kept here)."""
        if self.observation != "predicted":
            return self._source(world)
        return PredictedCache.open(world, self.settings, self.predictor, self.cache_dir)

    def _attach(self, world: World) -> None:
        """Make ``world`` the house observed; in cached mode, the previous house's caches are
        let go (closed once no env of the process holds them), and so are the distances
        memoised in other houses (computed again if one comes back)."""
        source = self._source_now
        if self.mode == "cached" and getattr(source, "meta", {}).get("house_id") == world.house_id:
            return  # the same house again (a cache folder is one house's)
        self._source_now = self._labels_now = self._read = None  # released before the next house's are opened
        self._steps_to = {key: dist for key, dist in self._steps_to.items() if key[0] == world.house_id}
        self._steps_lists = {key: dist for key, dist in self._steps_lists.items() if key[0] == world.house_id}
        self._source_now = self._source(world)
        if self.mode == "cached":
            labels = self._labels_now = self._labels(world)
            if labels is self._source_now:  # one read a step gives all three
                self._read = labels.reader(("rgb", "depth", "semantic"))
            else:
                read_rgb, read_labels = self._source_now.reader(("rgb",)), labels.reader(("depth", "semantic"))
                self._read = lambda pose: read_rgb(pose) + read_labels(pose)

    def goal_pose_ids(self, world: World, target: str) -> np.ndarray:
        """Goal poses of ``target`` by the goal rule (renders the goal camera's cache)."""
        key = (world.house_id, target)
        if key not in self._goals:
            cache = HouseCache.open(world, GOAL_CAMERA, self.cache_dir)  # shared; let go after
            # every category of the house at once (one pass over the frames): the others are asked for next
            names = sorted({o.category for o in world.spec.objects} | {target})
            found = goal_poses_of(cache.semantic, cache.depth, [CATEGORY_IDS[c] for c in names], self.goal_rule)
            for name in names:
                self._goals[(world.house_id, name)] = found[CATEGORY_IDS[name]]
        return self._goals[key]

    def steps_to(self, world: World, goal_ids) -> np.ndarray:
        """Minimal steps from every pose to the goal poses (memoised per goal set)."""
        key = (world.house_id, tuple(int(g) for g in goal_ids))
        if key not in self._steps_to:
            self._steps_to[key] = world.graph.shortest_steps(list(key[1]))
        return self._steps_to[key]

    def _steps_list(self, world: World, goal_ids) -> list[int]:
        """``steps_to`` as a Python list (memoised the same way)."""
        key = (world.house_id, tuple(int(g) for g in goal_ids))
        if key not in self._steps_lists:
            self._steps_lists[key] = self.steps_to(world, goal_ids).tolist()
        return self._steps_lists[key]

    def step_limit(self, world: World) -> int:
        """The step limit of an episode in ``world``: ``max_steps``, or the limit ``room_max_steps``
        gives a single room of its type where that is lower (``max_steps`` caps every episode)."""
        return min(self.max_steps, self.room_max_steps.get(world.spec.single_room, self.max_steps))

    def sample_task(self, rng: np.random.Generator) -> HouseTask:
        """A house, a target present in it, and a start ``START_STEPS`` from its goals, drawn
        by ``draw_start`` (near the entrance with ``starts="entrance"``)."""
        for _ in range(100):
            world = self._load(int(rng.integers(len(self.refs))))
            present = sorted({o.category for o in world.spec.objects})
            candidates = [c for c in present if self.targets is None or c in self.targets]
            if not candidates:
                continue
            target = candidates[rng.integers(len(candidates))]
            goals = self.goal_pose_ids(world, target)
            if len(goals) == 0:
                continue
            dist = self.steps_to(world, goals)
            near = None
            if self.starts == "entrance":
                if world.house_id not in self._near:
                    self._near[world.house_id] = entrance_poses(world)
                near = self._near[world.house_id]
            start = draw_start(dist, rng, near)
            if start is None:
                continue
            graph = world.graph
            return HouseTask(
                house=world.house_id,
                start=graph.pose_of(start),
                target=target,
                goals=tuple(graph.pose_of(g) for g in goals),
                min_steps=int(dist[start]) + self.stop_action,
            )
        raise RuntimeError("could not sample a task: no target with goal poses and starts in range")

    # -- gymnasium API ----------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        """Start an episode: ``options["task"]`` (a ``HouseTask``), or one sampled with the env's rng.

        Returns (observation, info). Raises ValueError if the task's ``min_steps`` disagrees with the pose graph.
        """
        super().reset(seed=seed)
        task = (options or {}).get("task") or self.sample_task(self.np_random)
        world = self.world(task.house)
        graph = world.graph
        self._world, self._task = world, task
        goal_ids = sorted(graph.pose_id(*g) for g in task.goals)
        self._goal_set = frozenset(goal_ids)
        self._dist = self._steps_list(world, goal_ids)
        self._pose = self._start_pose = graph.pose_id(*task.start)
        self._collided = 0
        # step's scalar paths: Python lists and floats, no numpy scalars or tiny arrays
        self._pose_tuples = graph.pose_tuples
        row0, col0, h0 = graph.pose_of(self._start_pose)
        c, s = COS_SIN[h0]
        self._origin = (row0, col0, h0, c, s, -s)
        moves = self._dist[self._pose]
        if moves < 0 or moves + self.stop_action != task.min_steps:
            stop = " and the STOP" if self.stop_action else ""
            found = (
                "no goal pose is reachable" if moves < 0 else f"{moves + self.stop_action} (moves to the goal{stop})"
            )
            raise ValueError(f"task in {task.house} says {task.min_steps} minimal steps, the pose graph says {found}")
        self._next, self._stride = graph.next_pose_flat, graph.next_pose.shape[1]
        self._target_id = CATEGORY_IDS[task.target]
        self._attach(world)
        self._steps, self._done, self._limit = 0, False, self.step_limit(world)
        rules = {"stop_action": STOP if self.stop_action else None, "goal_rule": self.goal_rule.to_json()}
        return self._observe(), {**self._info(False), "camera": self.settings.intrinsics(), **rules}

    def step(self, action):
        """Take one action; returns (observation, reward, terminated, truncated, info).

        The reward is 1.0 on success, else 0.0. Raises ValueError for an invalid action and RuntimeError after the
        episode ended.
        """
        if self._done:
            raise RuntimeError("step() called on a finished episode; call reset() first")
        if type(action) is not int or not 0 <= action < self._num_actions:  # a Python int in range: as it is
            action = check_action(self.action_space, action, ACTIONS[: self.action_space.n])
        before = self._pose
        pose = self._pose = self._next[before * self._stride + action]
        self._collided = int(pose == before and action in MOVES)
        self._steps += 1
        at_goal = pose in self._goal_set
        success = (action == STOP and at_goal) if self.stop_action else at_goal
        terminated = success or (self.stop_action and action == STOP)
        truncated = not terminated and self._steps >= self._limit
        self._done = terminated or truncated
        return self._observe(), float(success), terminated, truncated, self._info(success)

    def render(self):
        """The current RGB view (H, W, 3) uint8 in ``rgb_array`` mode, else None."""
        if self.render_mode == "rgb_array" and self._world is not None:
            return np.array(self._observe()["rgb"])
        return None

    def close(self):
        """Close the env's frame sources (renderers) and let go of its caches; the episode is over."""
        for source in self._sources.values():
            if hasattr(source, "close"):
                source.close()
        self._sources.clear()
        # a cache is shared: closed when its last user lets go
        self._source_now = self._labels_now = self._read = None
        self._done = True

    def __getstate__(self):
        state = dict(self.__dict__)
        state["_sources"], state["_source_now"], state["_labels_now"], state["_read"] = {}, None, None, None
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        if self._world is not None:
            self._attach(self._world)

    # -- helpers ----------------------------------------------------------------------
    @property
    def pose(self) -> tuple[int, int, int]:
        """The agent's current pose (row, col, heading) on the pose graph."""
        return self._world.graph.pose_of(self._pose)

    def _observe(self) -> dict[str, Any]:
        p = self._pose
        # relative_pose_of(start, pose), inlined: the env's every step
        row0, col0, h0, c, s, minus_s = self._origin
        row, col, h = self._pose_tuples[p]
        dx, dy = (col - col0) * GRID, (row - row0) * GRID
        pose = np.array((c * dx + s * dy, minus_s * dx + c * dy, TURN_HEADINGS[(h - h0) % 4]), np.float32)
        if self.mode == "cached":
            # read from the file, not mapped: new arrays (the caller owns what it is given,
            # Gymnasium's contract), and memory does not grow with the poses visited
            rgb, depth, semantic = self._read(p)
            return {
                "rgb": rgb,
                "depth": depth,
                "semantic": semantic,
                "target": self._target_id,
                "pose": pose,
                "collided": self._collided,
            }
        state = {"target": self._target_id, "pose": pose, "collided": self._collided}
        frames = self._source_now.render(self._world.graph.world_poses([self._pose]))
        semantic, depth = frames.semantic, frames.depth
        if self.observation == "predicted":
            semantic, depth = self.predictor.predict(frames.rgb)
        return {"rgb": frames.rgb[0], "depth": quantize_depth(depth[0]), "semantic": semantic[0], **state}

    def _info(self, success: bool) -> dict[str, Any]:
        return {
            "success": success,
            "steps": self._steps,
            "min_steps": self._task.min_steps,
            "house": self._task.house,
            "pose": self._pose_tuples[self._pose],
            "steps_to_goal": self._dist[self._pose],
        }
