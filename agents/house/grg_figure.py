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


FONT, FONT_SCALE = cv2.FONT_HERSHEY_SIMPLEX, 0.5
NODE_R = 12  # node radius, pixels


def label_box(text: str, x: int, y: int, angle: float) -> np.ndarray:
    """The four corners (x, y) of the label ``text`` of the node at (``x``, ``y``) whose ray
    from the circle's centre has direction ``angle`` (radians, image axes): the text starts
    ``NODE_R + 6`` pixels out along the ray and runs outwards, turned to read left to right
    on the circle's left half."""
    (tw, th), base = cv2.getTextSize(text, FONT, FONT_SCALE, 1)
    along = np.array([math.cos(angle), math.sin(angle)])
    across = np.array([-along[1], along[0]])
    start = np.array([x, y], float) + along * (NODE_R + 6)
    half = (th + base) / 2
    return np.array(
        [
            start - across * half,
            start + along * tw - across * half,
            start + along * tw + across * half,
            start + across * half,
        ]
    )


def _draw_label(img: np.ndarray, text: str, x: int, y: int, angle: float) -> None:
    """Draw ``text`` along its node's ray (``label_box``): rendered upright on a patch, turned, and
    laid over ``img`` darkest-wins."""
    (tw, th), base = cv2.getTextSize(text, FONT, FONT_SCALE, 1)
    patch = np.full((th + base + 4, tw + 4), 255, np.uint8)
    cv2.putText(patch, text, (2, th + 2), FONT, FONT_SCALE, 0, 1, cv2.LINE_AA)
    left = math.cos(angle) < -1e-9
    turn = angle + (math.pi if left else 0.0)  # the baseline's direction in the image
    anchor = (tw + 2, (th + base + 4) / 2) if left else (2, (th + base + 4) / 2)  # the end nearer the node
    m = cv2.getRotationMatrix2D(anchor, -math.degrees(turn), 1.0)
    target = np.array([x, y], float) + np.array([math.cos(angle), math.sin(angle)]) * (NODE_R + 6)
    m[:, 2] += target - np.array(anchor)
    turned = cv2.warpAffine(patch, m, (img.shape[1], img.shape[0]), flags=cv2.INTER_LINEAR, borderValue=255)
    np.minimum(img, turned[:, :, None], out=img)


def node_angles(count: int) -> list[float]:
    """Each node's direction from the centre, the first at the top, clockwise (image axes)."""
    return [2 * math.pi * k / max(count, 1) - math.pi / 2 for k in range(count)]


def draw(edges: list[tuple[str, str, float]], size: int = 720) -> np.ndarray:
    """BGR image of the edges' graph: nodes on a circle, each labelled along its ray outwards
    (no label crosses a node or another label)."""
    nodes = _grouped([e[:2] for e in edges])
    img = np.full((size, size, 3), 255, np.uint8)
    centre, radius = size / 2, size * 0.30  # room outside the circle for the longest names
    angles = dict(zip(nodes, node_angles(len(nodes))))
    at = {n: (int(centre + radius * math.cos(a)), int(centre + radius * math.sin(a))) for n, a in angles.items()}
    for a, b, w in edges:
        start, end = np.array(at[a], float), np.array(at[b], float)
        direction = (end - start) / max(np.linalg.norm(end - start), 1e-9)
        shade = int(200 * (1 - w))
        cv2.arrowedLine(
            img,
            tuple(int(v) for v in start + direction * (NODE_R + 2)),
            tuple(int(v) for v in end - direction * (NODE_R + 2)),
            (shade, shade, shade),
            max(1, int(round(4 * w))),
            cv2.LINE_AA,
            tipLength=0.06,
        )
    for n, (x, y) in at.items():
        cv2.circle(img, (x, y), NODE_R, (60, 150, 230), -1, cv2.LINE_AA)
        _draw_label(img, n, x, y, angles[n])
    cv2.putText(
        img,
        "edges i -> j with w_ij >= 0.5 (darker, thicker: larger)",
        (10, size - 12),
        FONT,
        0.45,
        (0, 0, 0),
        1,
        cv2.LINE_AA,
    )
    return img


if __name__ == "__main__":  # `python -m` of this module, a command until 2026-12-02: name its replacement
    raise SystemExit("python -m objsearch_agents.house.grg_figure is now: objsearch plot grg RUN [--out FILE]")
