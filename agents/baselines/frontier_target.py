"""What one episode of ``frontier`` knows of its target (``TargetMemory``), and when it calls STOP.

* **Voxels.** Pixels of the target's id (at least ``min_target_pixels`` in a frame) become
  points, kept in ``VOXEL`` voxels: where the approach goes (``frontier.py``, step 3).
* **Votes** (predicted perception): every frame's object labels of the places within
  ``vote_range``, counted per voxel as the target's or another object's.
* **STOP** (suites of the ObjectNav protocol, where ``task.stop_action`` is set): the frame
  shows the goal rule's ``min_pixels`` target pixels (``task.goal_rule``, scaled to the agent
  camera's resolution) at most ``max_distance`` metres deep. With rendered depth that is all; on
  predicted perception the STOP is earned: ``stop_margin`` nearer, from ``stop_views`` cells, on
  a place that the frames read as the target (``stop_share`` of its votes). docs/frontier.md
  measures each rule on validation splits.
"""

from __future__ import annotations

from collections import Counter

import numpy as np

from objsearch.eval.agent import AgentTask
from objsearch.house.categories import FIRST_OBJECT_ID
from objsearch.sim.goals import GOAL_CAMERA
from objsearch_agents.baselines.frontier_geometry import CELL, VOXEL, unique_voxels, voxel_keys


def stop_test(task: AgentTask) -> tuple[int, float] | None:
    """When to call STOP: (target pixels, metres) where the protocol needs STOP
    (``task.stop_action``), from its ``near_visible`` goal rule, its ``min_pixels`` (counted
    on the goal camera's frame) scaled to the agent camera's frame; None without STOP."""
    if task.stop_action is None:
        return None
    rule = task.goal_rule or {}
    if rule.get("kind") != "near_visible":
        raise ValueError(f"the frontier agent calls STOP by the near_visible goal rule, not {rule.get('kind')!r}")
    scale = task.camera["width"] * task.camera["height"] / (GOAL_CAMERA.width * GOAL_CAMERA.height)
    return int(np.ceil(rule["min_pixels"] * scale)), float(rule["max_distance"])


class TargetMemory:
    """One episode's target: its voxels, the votes about them, where it passed the STOP test."""

    def __init__(self, task: AgentTask, config):
        self.config, self.camera = config, task.camera
        self.target = -1
        self.voxels = np.zeros((0, 3), np.int32)  # voxels (i, j, k) of VOXEL metres from the map's origin, sorted
        self.votes = (Counter(), Counter())  # voxel key -> pixels labelled the target, labelled another object
        self.stop_action, self.stop_test = task.stop_action, stop_test(task)
        self.sightings: list[tuple[tuple[int, int], np.ndarray]] = []  # (cell, centre) of frames passing it so far

    def add_frame(self, p: dict, semantic: np.ndarray, exact: bool) -> None:
        """Add one frame's target pixels (``p``: its points, ``frontier_geometry.project``) to the
        voxels, and, unless depth was seen to be rendered (``exact``), its labels to the votes."""
        cfg = self.config
        x, y, height, rng, valid = p["x"], p["y"], p["height"], p["range"], p["valid"]
        if not exact and self.stop_test is not None and cfg.stop_share > 0:
            voting = valid & (semantic >= FIRST_OBJECT_ID) & (rng < cfg.vote_range)
            keys = voxel_keys(x[voting], y[voting], height[voting])
            target = semantic[voting] == self.target
            for votes, mine in zip(self.votes, (target, ~target)):
                k, n = np.unique(keys[mine], return_counts=True)
                votes.update(dict(zip(k.tolist(), n.tolist())))
        hits = valid & (semantic == self.target)
        if hits.sum() >= cfg.min_target_pixels:
            vox = np.floor(np.stack([x[hits] * (CELL / VOXEL), y[hits] * (CELL / VOXEL), height[hits] / VOXEL], 1))
            self.voxels = unique_voxels(np.concatenate([self.voxels, vox.astype(np.int32)]))

    def sees_goal(self, cell, p: dict, semantic: np.ndarray, depth: np.ndarray, earned: bool) -> bool:
        """Whether to STOP: the frame passes the STOP test (``stop_test``: enough target pixels
        near). Unless the STOP is ``earned`` (a frame showed predicted depth, none rendered) that
        is all; then the target is confirmed first: the test asks for ``stop_pixels`` times the
        pixels within ``stop_margin`` less depth, on a place the votes read as the target
        (``stop_share``), and must have passed from ``stop_views`` cells on the same target (the
        passing pixels' centres within ``stop_match``)."""
        if self.stop_test is None:
            return False
        pixels, distance = self.stop_test
        cfg = self.config
        if earned:
            pixels, distance = int(np.ceil(pixels * cfg.stop_pixels)), distance - cfg.stop_margin
        near = (semantic == self.target) & (depth <= distance)
        if int(near.sum()) < pixels:
            return False
        if not earned or cfg.stop_views <= 1:
            return True
        if cfg.stop_share > 0:
            keys = np.unique(voxel_keys(p["x"][near], p["y"][near], p["height"][near])).tolist()
            mine, other = (sum(votes[k] for k in keys) for votes in self.votes)
            if mine < cfg.stop_share * (mine + other):
                return False
        here = (int(cell[0]), int(cell[1]))
        centre = np.array([p["x"][near].mean(), p["y"][near].mean()]) * CELL
        self.sightings.append((here, centre))
        match = cfg.stop_match**2
        cells = {c for c, at in self.sightings if ((at - centre) ** 2).sum() <= match}
        return len(cells) >= cfg.stop_views
