"""When has an agent found its target? The goal-pose rule, in one place, versioned.

``top_area`` (the default, the paper's): the goal poses of a target category are the poses
whose ground-truth segmentation shows the most pixels of that category: every pose whose
target area is at least the ``top_k``-th largest (5; ties are all included), among poses
that see the target at all. ``near_visible`` (ObjectNav-style, selectable): every pose that
sees at least ``min_pixels`` target pixels closer than ``max_distance`` metres.

Both are computed from frames of the goal camera, ``GOAL_CAMERA`` (independent of the
camera an agent uses, ``objsearch.sim.camera.AGENT_CAMERA``, although equal to it today),
and suites store the resulting poses, so success never drifts with renderer or agent
settings.

A protocol (``PROTOCOLS``) is the whole success rule of an episode: the kind of goal rule,
whether the agent must call STOP at a goal pose, and the step limit. ``paper`` (the paper's,
every suite before ``house-gen-v2-objectnav``): ``top_area`` goal poses, the episode ends
by itself when the agent reaches one, 1000 steps. ``objectnav`` (Habitat's ObjectNav
challenge): ``near_visible`` goal poses (at least 20 target pixels of the 64 x 64 goal
camera within 1 m), success only when the agent calls STOP at one (STOP elsewhere ends the
episode as a failure), 500 steps. A suite file records its protocol (``protocol``; absent:
``paper``).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from objsearch.sim.camera import RenderSettings

GOAL_RULE_VERSION = "goals-v1"
GOAL_CAMERA = RenderSettings(width=64, height=64, fovy=90.0, camera_height=1.0, znear=0.05, zfar=30.0, ceiling=True)
"""The camera the goal rule looks through: 64 x 64, 90 degrees vertical field of view, 1 m
above the floor. Fixed benchmark data, like ``GOAL_RULE_VERSION``: the suite files record it
(``goal_camera``) beside the goal poses it chose, and its cache key names the goal caches.
It does not follow the agent camera (``objsearch.sim.camera.AGENT_CAMERA``); changing it
means rebuilding every suite file (``objsearch suite rebuild``). Every field is given, so a
change to ``RenderSettings``' defaults leaves it alone."""
RULES = ("top_area", "near_visible")


@dataclass(frozen=True)
class GoalRule:
    """Attributes:
    kind: ``top_area`` or ``near_visible``.
    top_k: top_area: how many of the largest target areas count (ties included).
    min_pixels: near_visible: target pixels needed (at the goal camera's 64x64).
    max_distance: near_visible: those pixels' depth limit in metres.
    """

    kind: str = "top_area"
    top_k: int = 5
    min_pixels: int = 20
    max_distance: float = 1.0

    def __post_init__(self):
        if self.kind not in RULES:
            raise ValueError(f"goal rule must be one of {RULES}, not {self.kind!r}")

    def to_json(self) -> dict:
        """The rule as a JSON dict, with ``GOAL_RULE_VERSION``."""
        return {"version": GOAL_RULE_VERSION, **asdict(self)}


DEFAULT_RULE = GoalRule()


def goal_poses(semantic: np.ndarray, depth: np.ndarray, category_id: int, rule: GoalRule = DEFAULT_RULE) -> np.ndarray:
    """Pose ids that are goals for ``category_id``, given the goal camera's frames of every
    pose (``semantic`` (P, H, W) category ids, ``depth`` (P, H, W) metres). Empty if the
    category is never seen."""
    hits = semantic == category_id
    if rule.kind == "top_area":
        return _top_area(_count_per_frame(hits), rule.top_k)
    near = _count_per_frame(hits & (depth <= rule.max_distance))
    return np.flatnonzero(near >= rule.min_pixels)


def goal_poses_of(
    semantic: np.ndarray, depth: np.ndarray, category_ids, rule: GoalRule = DEFAULT_RULE
) -> dict[int, np.ndarray]:
    """``goal_poses`` of several categories, {category id: pose ids}. With ``top_area``, every
    frame's pixels are counted once for all categories (one pass over the frames, not one a
    category): the same poses."""
    category_ids = [int(c) for c in category_ids]
    semantic = np.asarray(semantic)
    if rule.kind != "top_area" or len(category_ids) < 2 or semantic.dtype != np.uint8:
        return {c: goal_poses(semantic, depth, c, rule) for c in category_ids}
    areas = np.stack([np.bincount(frame, minlength=256) for frame in semantic.reshape(len(semantic), -1)])
    return {
        c: _top_area(areas[:, c], rule.top_k) if 0 <= c < areas.shape[1] else goal_poses(semantic, depth, c, rule)
        for c in category_ids
    }


def _top_area(area: np.ndarray, top_k: int) -> np.ndarray:
    """The ``top_area`` goal poses given every pose's target area (pixels)."""
    if not area.any():
        return np.zeros(0, dtype=np.int64)
    threshold = max(1, np.sort(area)[::-1][min(top_k, len(area)) - 1])
    return np.flatnonzero(area >= threshold)


def _count_per_frame(mask: np.ndarray) -> np.ndarray:
    """True pixels of each frame of a bool (P, H, W): the values of ``.sum(axis=(1, 2))``,
    summed as bytes into the smallest integer that holds a frame's count (several times faster
    than summing bools, which casts every pixel to int64)."""
    flat = mask.reshape(len(mask), -1)
    dtype = np.uint16 if flat.shape[1] <= np.iinfo(np.uint16).max else np.int64
    return np.add.reduce(flat.view(np.uint8), axis=1, dtype=dtype)


@dataclass(frozen=True)
class Protocol:
    """How a house episode succeeds and ends.

    Attributes:
        name: ``paper`` or ``objectnav``.
        goal_rule: the rule that picks the goal poses (a suite file's rule has this kind).
        stop: the agent must call STOP (``objsearch.sim.navgraph.STOP``) at a goal pose to
            succeed; otherwise the episode ends by itself on reaching one.
        max_steps: the step limit of the suites made for it.
    """

    name: str
    goal_rule: GoalRule
    stop: bool
    max_steps: int


PROTOCOLS = {
    "paper": Protocol("paper", DEFAULT_RULE, stop=False, max_steps=1000),
    "objectnav": Protocol("objectnav", GoalRule(kind="near_visible"), stop=True, max_steps=500),
}
