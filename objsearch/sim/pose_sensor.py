"""The ``pose`` observation of the house envs: the agent's position and heading relative to the
episode's start, as Habitat's GPS+compass gives it (x metres forward, y metres to the left of
the start pose, the heading in radians counter-clockwise from the start heading, in (-pi, pi]);
``relative_pose`` for arrays of poses, ``relative_pose_of`` for one (the env's every step)."""

from __future__ import annotations

import numpy as np

from objsearch.sim.navgraph import GRID, PoseGraph


def relative_pose(graph: PoseGraph, start, pose) -> np.ndarray:
    """The ``pose`` observation: float32 (..., 3) of (x forward, y left, heading) of pose ids
    ``pose`` relative to pose ids ``start`` (metres, radians counter-clockwise in (-pi, pi])."""
    start, pose = np.asarray(start), np.asarray(pose)
    d = (graph.cells[pose // 4] - graph.cells[start // 4])[..., ::-1] * GRID  # (dx, dy) in the world
    yaw = (start % 4) * (np.pi / 2)
    c, s = np.cos(yaw), np.sin(yaw)
    turn = (pose % 4 - start % 4) % 4
    heading = np.where(turn == 3, -np.pi / 2, turn * (np.pi / 2))
    return np.stack([c * d[..., 0] + s * d[..., 1], -s * d[..., 0] + c * d[..., 1], heading], axis=-1).astype(
        np.float32
    )


# ``relative_pose``'s cos and sin of the 4 start headings and its heading of the 4 turns, computed
# once by its own numpy expressions: the scalar path below then gives its very bits
# (tests/sim/test_env_fast_paths.py checks every start heading and turn).
COS_SIN = tuple((float(np.cos(h * (np.pi / 2))), float(np.sin(h * (np.pi / 2)))) for h in np.arange(4))
TURN_HEADINGS = tuple(float(x) for x in np.where(np.arange(4) == 3, -np.pi / 2, np.arange(4) * (np.pi / 2)))


def relative_pose_of(start: tuple[int, int, int], pose: tuple[int, int, int]) -> tuple[float, float, float]:
    """``relative_pose`` of one pose in Python floats: ``np.float32`` of each is exactly its
    value. ``start`` and ``pose`` are (row, col, heading) (``PoseGraph.pose_of``); scalar
    arithmetic in the same order as numpy's, so no tiny arrays are made (the env's every step)."""
    row0, col0, h0 = start
    row, col, h = pose
    c, s = COS_SIN[h0]
    dx, dy = (col - col0) * GRID, (row - row0) * GRID
    return (c * dx + s * dy, -s * dx + c * dy, TURN_HEADINGS[(h - h0) % 4])
