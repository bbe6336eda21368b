"""The house GRG as the paper's Figure 5: a few object categories as nodes and the edges
with weight >= 0.5 between them ("does the sink lead to the mirror?").

    objsearch plot grg agents/checkpoints/house-single/hrl_grg --out grg.png

Nodes: the categories on the strongest edges (at most ``limit``), on a circle; an arrow
i -> j for each edge of weight >= ``threshold``, darker and thicker for larger weights. The
command prints the edge list too. Loading and writing are ``objsearch_agents.grg_plot``'s,
shared with the grid-world figure.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from objsearch.house.categories import CATEGORY_NAMES, FIRST_OBJECT_ID
from objsearch_agents.house.tables import NUM_OBJECTS


def strongest_edges(weights: np.ndarray, threshold: float = 0.5, limit: int = 24) -> list[tuple[str, str, float]]:
    """(from, to, weight) of the strongest edges between object categories, weight >= threshold."""
    w = np.array(weights[:NUM_OBJECTS, :NUM_OBJECTS], float)
    np.fill_diagonal(w, 0.0)
    order = np.argsort(-w, axis=None, kind="stable")[:limit]
    name = lambda node: CATEGORY_NAMES[int(node) + FIRST_OBJECT_ID]
    return [
        (name(i), name(j), float(w[i, j])) for i, j in zip(*np.unravel_index(order, w.shape)) if w[i, j] >= threshold
    ]


def _grouped(pairs: list[tuple[str, str]]) -> list[str]:
    """The nodes of ``pairs``, connected ones next to each other on the circle (fewer crossings)."""
    order: list[str] = []
    remaining = list(pairs)
    while remaining:
        group = set(remaining[0])
        grew = True
        while grew:
            grew = False
            for a, b in remaining:
                if (a in group) != (b in group):
                    group |= {a, b}
                    grew = True
        order += [n for n in dict.fromkeys(n for pair in remaining for n in pair) if n in group and n not in order]
        remaining = [p for p in remaining if p[0] not in group]
    return order


def draw(edges: list[tuple[str, str, float]], size: int = 720) -> np.ndarray:
    """BGR image of the edges' graph."""
    nodes = _grouped([e[:2] for e in edges])
    img = np.full((size, size, 3), 255, np.uint8)
    centre, radius = size / 2, size * 0.36
    at = {
        n: (
            int(centre + radius * math.cos(2 * math.pi * k / max(len(nodes), 1) - math.pi / 2)),
            int(centre + radius * math.sin(2 * math.pi * k / max(len(nodes), 1) - math.pi / 2)),
        )
        for k, n in enumerate(nodes)
    }
    for a, b, w in edges:
        start, end = np.array(at[a], float), np.array(at[b], float)
        direction = (end - start) / max(np.linalg.norm(end - start), 1e-9)
        shade = int(200 * (1 - w))
        cv2.arrowedLine(
            img,
            tuple(int(v) for v in start + direction * 14),
            tuple(int(v) for v in end - direction * 14),
            (shade, shade, shade),
            max(1, int(round(4 * w))),
            cv2.LINE_AA,
            tipLength=0.06,
        )
    for n, (x, y) in at.items():
        cv2.circle(img, (x, y), 12, (60, 150, 230), -1, cv2.LINE_AA)
        (tw, th), _ = cv2.getTextSize(n, cv2.FONT_HERSHEY_SIMPLEX, 0.5, 1)
        dx = -tw - 16 if x < centre else 16
        cv2.putText(img, n, (x + dx, y + th // 2), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    cv2.putText(
        img,
        "edges i -> j with w_ij >= 0.5 (darker, thicker: larger)",
        (10, size - 12),
        cv2.FONT_HERSHEY_SIMPLEX,
        0.45,
        (0, 0, 0),
        1,
        cv2.LINE_AA,
    )
    return img


if __name__ == "__main__":  # `python -m` of this module, a command until 2026-12-02: name its replacement
    raise SystemExit("python -m objsearch_agents.house.grg_figure is now: objsearch plot grg RUN [--out FILE]")
