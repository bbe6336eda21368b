"""What the grid-world networks see of an observation, the 17-channel 7x7 window (obstacles, then
one channel per goal): the goals in view and under the agent, the candidate sub-goals, and the
inputs of the low level and of the candidates' scores. Shared by the policy
(``gridworld.policy``) and the grid world's adapter and losses (``gridworld.world``)."""

from __future__ import annotations

import numpy as np

CENTRE = 3


def visible_goals(images: np.ndarray) -> np.ndarray:
    """bool (N, G): goals in the 7x7 window (including the one under the agent)."""
    return images[:, 1:].any(axis=(2, 3))


def goals_under_agent(images: np.ndarray) -> np.ndarray:
    """bool (N, G): the goal the agent stands on."""
    return images[:, 1:, CENTRE, CENTRE].astype(bool)


def candidates(images: np.ndarray) -> np.ndarray:
    """bool (N, G+1): visible goals not under the agent, and the "random" node (always)."""
    vis = visible_goals(images) & ~goals_under_agent(images)
    return np.concatenate([vis, np.ones((len(images), 1), dtype=bool)], axis=1)


def goal_input(images: np.ndarray, node: np.ndarray) -> np.ndarray:
    """uint8 (N, 2, 7, 7): obstacles and the channel of goal ``node`` (zeros for "random")."""
    n, channels = len(images), images.shape[1]
    out = np.zeros((n, 2, *images.shape[2:]), dtype=np.uint8)
    out[:, 0] = images[:, 0]
    real = node < channels - 1
    out[real, 1] = images[np.flatnonzero(real), 1 + node[real]]
    return out


def candidate_inputs(images: np.ndarray, weights: np.ndarray, rows: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """float32 (P, 2, 7, 7): for each pair (``rows[p]``, ``nodes[p]``) of an image and a
    candidate node, (obstacles, the node's channel times its weight ``weights[row, node]``).
    "random" has no cell: its channel is all ones times its weight. Only the pairs asked
    for are built (a batch scores ~5 of its 17 nodes)."""
    channels = images.shape[1]
    out = np.empty((len(rows), 2, *images.shape[2:]), dtype=np.float32)
    out[:, 0] = images[rows, 0]
    w = weights[rows, nodes]
    real = nodes < channels - 1
    out[real, 1] = images[rows[real], 1 + nodes[real]] * w[real, None, None]
    out[~real, 1] = w[~real, None, None]
    return out
