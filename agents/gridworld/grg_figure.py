"""The grid-world GRG as the paper's Figure 4: goals on a circle in id order (the two chains
g0..g7 and g8..g15 side by side); an arrow i -> j for each goal's strongest out-edges,
darker and thicker for larger weights; and how well the graph recovers its goal chains.

    objsearch plot grg agents/checkpoints/gridworld/hrl_grg --out grg.png

Loading and writing are ``objsearch_agents.grg_plot``'s, shared with the house figure
(``house.grg_figure``).
"""

from __future__ import annotations

import math

import cv2
import numpy as np

GRID_GOALS = 16
CHAINS = (tuple(range(0, 8)), tuple(range(8, 16)))
UNSEEN = (2, 5, 10, 13)


def chain_recovery(weights: np.ndarray, chains=CHAINS, top: int = 2) -> float:
    """Fraction of goals whose chain neighbour (predecessor or successor) is among their
    ``top`` strongest out-edges (self-edges and the back-up node ignored)."""
    goals = [g for chain in chains for g in chain]
    w = weights[np.ix_(goals, goals)].astype(float)
    np.fill_diagonal(w, -np.inf)
    index = {g: i for i, g in enumerate(goals)}
    hits = 0
    for chain in chains:
        for pos, goal in enumerate(chain):
            neighbours = {index[chain[p]] for p in (pos - 1, pos + 1) if 0 <= p < len(chain)}
            strongest = set(np.argsort(-w[index[goal]], kind="stable")[:top].tolist())
            hits += bool(neighbours & strongest)
    return hits / len(goals)


def draw_graph(weights: np.ndarray, edges_per_node: int = 2, size: int = 640) -> np.ndarray:
    """BGR image of the graph over the 16 goals (node i at angle i * 360 / 16)."""
    goals = 16
    img = np.full((size, size, 3), 255, np.uint8)
    centre, radius = size / 2, size * 0.38
    at = [
        (
            int(centre + radius * math.cos(2 * math.pi * i / goals - math.pi / 2)),
            int(centre + radius * math.sin(2 * math.pi * i / goals - math.pi / 2)),
        )
        for i in range(goals)
    ]
    w = weights[:goals, :goals].astype(float).copy()
    np.fill_diagonal(w, 0.0)
    for i in range(goals):
        for j in np.argsort(-w[i], kind="stable")[:edges_per_node]:
            if w[i, j] <= 0:
                continue
            shade = int(200 * (1 - w[i, j]))
            start, end = np.array(at[i], float), np.array(at[j], float)
            direction = (end - start) / max(np.linalg.norm(end - start), 1e-9)
            tip = end - direction * 22  # stop at the node's rim
            cv2.arrowedLine(
                img,
                tuple(int(v) for v in start + direction * 22),
                tuple(int(v) for v in tip),
                (shade, shade, shade),
                max(1, int(round(4 * w[i, j]))),
                cv2.LINE_AA,
                tipLength=0.08,
            )
    for i, (x, y) in enumerate(at):
        colour = (60, 150, 230) if i < 8 else (80, 180, 90)
        cv2.circle(img, (x, y), 20, colour, -1, cv2.LINE_AA)
        cv2.circle(img, (x, y), 20, (0, 0, 0), 3 if i in UNSEEN else 1, cv2.LINE_AA)
        label = f"g{i}"
        (tw, th), _ = cv2.getTextSize(label, cv2.FONT_HERSHEY_SIMPLEX, 0.5, 1)
        cv2.putText(img, label, (x - tw // 2, y + th // 2), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    cv2.putText(
        img,
        f"chain neighbour among the 2 strongest out-edges: {chain_recovery(weights):.0%} of goals",
        (10, size - 12),
        cv2.FONT_HERSHEY_SIMPLEX,
        0.45,
        (0, 0, 0),
        1,
        cv2.LINE_AA,
    )
    cv2.putText(
        img, "bold rim: goals never trained on", (10, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1, cv2.LINE_AA
    )
    return img
